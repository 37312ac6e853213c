// SPDX-License-Identifier: GPL-3.0-or-later
// The cubic C1 Clough-Tocher spline of a parametrised triangle mesh (study section 3): Step 1
// (eq. 11-12), Step 2 by the chosen construction, Step 3 (eq. 13-14), on shared control points.
//
// Constructions (Constructions.h has their table): CTo, CTi (eq. 15-17), MGo, MGi (eq. 24-25),
// Fa (eq. 18-21), FO (eq. 22), Ka (eq. 23), KaG (Ka with mid-edge gradients on boundary edges)
// and Kashyap's cubic fairing scheme (quartic paper section 3); Quartic is QuarticCloughTocher.h's; boundary edges of the non-local ones follow BoundaryMode
// (section 3.8). Iterations: IM steps (section 3.7) after any construction but Kashyap, for
// which it counts exterior + interior fairing rounds.
#ifndef CTSplines_Kernel_CubicCloughTocher_h
#define CTSplines_Kernel_CubicCloughTocher_h

#include "Constructions.h"
#include "CubicMacroElement.h"
#include "LargeArrays.h" // for OverwriteVector
#include "MeshTopology.h"
#include "ParallelFor.h"
#include "PointRanges.h"
#include "SplitPoint.h"

#include <atomic>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace ctk
{

enum class BoundaryMode
{
  Perpendicular = 0,        // eq. (15) with eq. (16)
  Midpoint = 1,             // eq. (15) with lambda = 1/2
  GradientPerpendicular = 2, // eq. (25), v_eps perpendicular to the edge
  GradientToSplitPoint = 3  // eq. (25), v_eps from Z to the edge midpoint
};

const char* ToString(BoundaryMode m);

/// Input of a spline construction; arrays are row-major and owned by the caller.
struct SplineData
{
  Id NumberOfVertices = 0;
  Id NumberOfTriangles = 0;
  const Id* Triangles = nullptr; // #T by 3 vertex ids
  const double* UV = nullptr;    // #V by 2 parameter values
  const double* F = nullptr;     // #V by 3 positions
  const double* Fu = nullptr;    // #V by 3 derivatives d/du
  const double* Fv = nullptr;    // #V by 3 derivatives d/dv
  /// Optional #T by 18: for local edges (p0,p1), (p1,p2), (p2,p0), f_u then f_v at the edge
  /// midpoint. Where both triangles of an edge give one, their mean is used on both sides.
  const double* EdgeGradients = nullptr;
  /// Optional #T: triangle t's row of EdgeGradients (default t), so that a renumbered mesh can
  /// read its caller's rows in place (the VTK filter's cell data, never copied nor permuted).
  const Id* EdgeGradientRows = nullptr;
  /// Optional #T barycentric coordinates of the split points; when given they replace
  /// SplineOptions::SplitPoint (the Bézier extraction probes data with the split points of the
  /// real data, since Inc3 depends on positions).
  const Vec3* SplitTau = nullptr;
  /// Optional #T by 18: prescribed inner control points of boundary macro-edges (a curve the
  /// spline must follow, e.g. the shared B-rep edge cubic of watertight stitching, study
  /// section 4). For local edge l of triangle t: the point near p_l, then the one near
  /// p_{l+1}. NaN (all six values) leaves the edge to eq. (11); interior edges are ignored.
  /// Step 1's inner ring, the boundary rule and Step 3 then follow the prescribed curve, so
  /// every macro-patch stays C1 inside; C1 across interior macro-edges at a boundary vertex
  /// needs the points to agree with the vertex derivatives (eq. 11).
  const double* BoundaryCurvePoints = nullptr;
  /// Set by a caller that has checked every value of UV, F, Fu, Fv and BoundaryCurvePoints as
  /// ValidateSplineData does (vtkCloughTocherSplineFilter, while copying its input): the values
  /// are then not read a second time, serially, before the construction. EdgeGradients are
  /// checked by the constructions where they read them (UnusableEdgeGradients), either way.
  bool ValuesChecked = false;
};

/// The 18 mid-edge gradient values of triangle t (SplineData::EdgeGradients must be set).
inline const double* EdgeGradientsOf(const SplineData& d, Id t)
{
  return d.EdgeGradients + 18 * (d.EdgeGradientRows ? d.EdgeGradientRows[t] : t);
}

struct SplineOptions
{
  Construction Method = Construction::CTi;
  SplitPointRule SplitPoint = SplitPointRule::Bary;
  BoundaryMode Boundary = BoundaryMode::Midpoint;
  int Iterations = 0; // IM steps, or fairing rounds for Kashyap
  /// Visit the triangles in a locality order (LocalityOrder.h) on large meshes; the result is
  /// the same either way, bit for bit. Off by default: on CGAL-numbered random Delaunay meshes
  /// (1e6 triangles) it measured 1.5x slower than the input's order, the triangle-indexed arrays
  /// being then reached at random. vtkCloughTocherSplineFilter renumbers the mesh instead
  /// (SplineInput::RenumberToLocalityOrder, BuildMeshTopology by rank; issue #12).
  bool LocalityOrder = false;
  /// Also give the ranges of the points built (CubicSpline::ControlPointRanges and
  /// DomainPointRanges), scanned block by block in the passes that write them, while they are in
  /// the cache: for a caller that stores them, as vtkCloughTocherSplineFilter does in its output
  /// arrays. Off, no build pays for the scan (the quartic's first cubic, IOCAD's faces, Bézier
  /// extraction).
  bool ScanRanges = false;
  /// With ScanRanges, also keep the ranges of each block scanned (CubicSpline::BlockRanges): for
  /// a caller that keeps some of the points only (vtkCloughTocherSplineFilter drops those that
  /// only ghost cells use) and needs the ranges of what it keeps.
  bool ScanBlockRanges = false;
};

/// The boundary rule in force: KaG and MGi turn a non-gradient mode into GradientToSplitPoint.
BoundaryMode EffectiveBoundaryMode(const SplineOptions& options);

/// Whether the options read SplineData::EdgeGradients (on all edges or on boundary edges).
bool UsesEdgeGradients(const SplineOptions& options);

struct CubicSpline
{
  CubicSplineLayout Layout;
  // Layout.NumberOfPoints() each; the VTK filter's output adopts them.
  OverwriteVector<Vec3> ControlPoints;
  OverwriteVector<Vec2> DomainPoints; // parameter-space domain point of every control point
  OverwriteVector<Vec3> SplitTau;    // #T barycentric coordinates of Z
  // The ranges of ControlPoints and DomainPoints as built, with SplineOptions::ScanRanges: each
  // block of points scanned in the pass that writes its last values (Components 0: not scanned,
  // as without the option, after IM steps, Kashyap's fairing or with a locality order of the
  // kernel's own). Stale once the points change.
  PointRanges ControlPointRanges, DomainPointRanges;
  // With SplineOptions::ScanBlockRanges as well, the ranges of each block of points scanned, in
  // no particular order; together they cover every point once (empty when not scanned).
  std::vector<PointBlockRanges> BlockRanges;
};

struct BuildStatus
{
  bool Ok = true;
  std::string Message;
  std::vector<MessageId> Ids; // the triangles and vertices Message names
};

/// Builds the spline. topology must come from BuildMeshTopology on data.Triangles. Results are
/// independent of how parallelFor splits the work.
BuildStatus BuildCubicCloughTocher(const SplineData& data, const MeshTopology& topology,
  const SplineOptions& options, CubicSpline& spline, const ParallelFor& parallelFor = SerialFor);

} // namespace ctk

#endif
