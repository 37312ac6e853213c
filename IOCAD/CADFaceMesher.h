// SPDX-License-Identifier: GPL-3.0-or-later
// Interior triangulation of one face's parameter domain (study section 4, second stage): a
// constrained Delaunay triangulation (CGAL) of the boundary loops, refined by inserting interior
// points only (boundary segments are never split, so neighbours keep sharing their nodes) until
// the CTo/Bary spline's error at triangle centroids and edge midpoints is below the tolerance,
// then until the spline the stitcher makes is.
// No OpenCASCADE here: the surface comes in as a callback.
#ifndef CTSplines_IOCAD_CADFaceMesher_h
#define CTSplines_IOCAD_CADFaceMesher_h

#include "CADBRepSampling.h"

#include "CubicCloughTocher.h"

#include <functional>

namespace ctcad
{
/// Surface point P and derivatives Ds, Dt at (s, t).
using SurfaceFunction =
  std::function<void(double s, double t, double P[3], double Ds[3], double Dt[3])>;

struct FaceMeshOptions
{
  double Tolerance = 0;     // absolute
  double AspectRatio = 0;   // bound on the 3D aspect ratio (1 = equilateral); 0 = none
  double MaxEdgeLength = 0; // absolute bound on 3D edge lengths; 0 = none
  /// Bound in degrees on the angle between the spline's normals and the surface's (like
  /// OpenCASCADE's angular deflection); 0 = none.
  double AngularTolerance = 0;
  int MaxRounds = 60;
  long MaxTriangles = 500000;
  /// After the CTo rounds, check the spline the stitcher makes (this construction, following
  /// the shared edge cubics) on the whole face and refine until it is within the tolerances at
  /// the CheckLevel lattice of every micro-triangle (DeviationPoints; the boundary macro-edges,
  /// which the face cannot refine, are the edge sampling's).
  bool CheckConstruction = false;
  int CheckLevel = 4;
  /// With CheckConstruction: a face that Spline.Method leaves over the tolerances when nothing
  /// more can be inserted (or a cap is reached) is checked with every other stitchable
  /// construction on its final mesh, and takes the one least over them if that is less than
  /// Spline.Method's and turns the normals neither from the surface's nor, at tangent spans,
  /// from the shared tangent planes (FaceMesh::FallbackConstruction; the stitcher builds the
  /// face with it).
  bool FallbackConstructions = true;
  ctk::SplineOptions Spline;
};

struct FaceMesh
{
  std::vector<std::array<double, 2>> UV;
  /// Points and derivatives for stitching (at boundary nodes the consistent ones of
  /// InterfaceTangentPlanes.h), and the surface's own derivatives.
  std::vector<Point3> F, Fs, Ft;
  std::vector<Point3> SurfaceFs, SurfaceFt;
  std::vector<Id> GlobalNode; // -1 for interior points
  std::vector<std::array<Id, 3>> Triangles; // counter-clockwise in the parameter plane
  /// Per local edge (p0,p1), (p1,p2), (p2,p0): the loop segment it is, or nullptr; and whether
  /// the segment runs the other way (its Near0 is then near the edge's second point).
  std::vector<std::array<const LoopSegment*, 3>> Segments;
  std::vector<std::array<bool, 3>> SegmentFlipped;
  int Rounds = 0;
  int CheckRounds = 0; // rounds that checked the stitched spline
  bool Converged = false;
  /// Last round's largest error: of the stitched spline at its check points when checked, else
  /// the CTo estimate at centroids, micro-triangle centres and interior edge midpoints; and the
  /// largest angle between the normals (degrees) there, measured with an AngularTolerance.
  double MaxEstimatedError = 0;
  double MaxEstimatedAngle = 0;
  /// Why refinement stopped short of the tolerances (empty when converged).
  std::string StopReason;
  /// The construction the face takes where Spline.Method could not bring it within the
  /// tolerances and this one does better (FallbackConstructions), else -1; MaxEstimatedError,
  /// MaxEstimatedAngle and Converged are then its, and ChosenError and ChosenStopReason what
  /// Spline.Method had reached.
  int FallbackConstruction = -1;
  double ChosenError = 0;
  std::string ChosenStopReason;
  std::string Error;
};

/// Runs body(f) for every f in [0, n), on up to one thread per core, f taken in turn (faces are
/// independent once their loops exist; each evaluates only its own surface adaptor). body must
/// let nothing escape (see RunGuarded).
void ForEachFaceInParallel(int n, const std::function<void(int)>& body);

/// Deviation of a spline from its CAD surface: distances (absolute) and the angles between the
/// normals (degrees; not where either normal is degenerate, at poles, nor at the face's cusp
/// nodes, counted in CuspNodes: see MeasureDeviation).
struct Deviation
{
  double MaxDistance = 0, SumSquaredDistance = 0;
  double MaxAngle = 0, SumSquaredAngle = 0;
  long Count = 0, AngleCount = 0, CuspNodes = 0;
  void Add(const Deviation& o);
};

/// The points at which the deviation of a macro-triangle split at splitTau is measured: the
/// barycentric lattice with `level` subdivisions of each of its micro-triangles (interior,
/// macro-edges, inner edges, vertices and split point), every point once, as macro barycentric
/// coordinates. Points on local macro-edge l (vertices l, l+1) are left out where skipEdge[l].
void DeviationPoints(const ctk::Vec3& splitTau, int level, const std::array<bool, 3>& skipEdge,
  std::vector<ctk::Vec3>& points);

/// The distance between a spline point (jet of order >= 1 when `normals`) and the surface at
/// parameter X, and the angle between their normals in degrees (-1 where either is
/// degenerate; not computed without `normals`). False, with error, when not finite.
bool PointDeviation(const SurfaceFunction& surface, const ctk::Vec2& X,
  const ctk::ParametricJet& jet, bool normals, double& distance, double& angle,
  std::string& error);

/// Measures macro-triangle t of a cubic spline (vertex parameters in spline.DomainPoints)
/// against its surface at `points` (macro barycentric coordinates) into d. False with error.
/// With `worst`, also the point where the deviation is largest relative to the tolerances:
/// max(distance / tolerance, angle / angularTolerance), the angle counting only with normals.
bool MeasureTriangle(const ctk::CubicSpline& spline, const ctk::MeshTopology& topo,
  const ctk::Id* triangles, ctk::Id t, const std::vector<ctk::Vec3>& points,
  const SurfaceFunction& surface, bool normals, Deviation& d, std::string& error,
  ctk::Vec3* worst = nullptr, double tolerance = 1, double angularTolerance = 1);

/// The mid-edge gradient (f_u then f_v) the stitched spline uses on a boundary span: the
/// surface's, projected to the span's shared tangent plane where the interface is restored to G1.
void StitchEdgeGradient(const LoopSegment& seg, double gradient[6]);

/// Meshes one face given its loops (in its oriented parameter plane), the 3D points of the
/// global boundary nodes and its surface. Returns false with mesh.Error on failure.
bool MeshFace(const std::vector<FaceLoop>& loops, const std::vector<Point3>& nodePoints,
  const SurfaceFunction& surface, const FaceMeshOptions& options, FaceMesh& mesh);

} // namespace ctcad

#endif
