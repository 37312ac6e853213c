// SPDX-License-Identifier: GPL-3.0-or-later
// Fang and Mann's quartic Clough-Tocher interpolant ("A Quartic Clough-Tocher Interpolant",
// section 4 and Fig. 11), applied to 3D control points: the cubic-precision interpolant (FO) is
// degree-raised, then each round adjusts the free macro-boundary point c2 (section 4.2, eq. 15),
// applies exterior fairing (eq. 7, then eq. 11) and C1 smoothing (section 4.3).
//
// Labels of the paper's figures, identified by domain points (spec section 3b). Across the
// macro-edge P1 P2 the left micro-triangle is L = (S, P1, P2), the right one R = (S', P2, P1);
// with the kernel's micro net over (P1, P2, S) and exponents (a, b, c) of (P1, P2, S):
//   P1 c1 c2 c3 P2 = (4,0,0) (3,1,0) (2,2,0) (1,3,0) (0,4,0)        row 0, on the macro-edge
//   l6 l7 l8 l9    = (3,0,1) (2,1,1) (1,2,1) (0,3,1)                row 1
//   l3 l4 l5       = (2,0,2) (1,1,2) (0,2,2)                        row 2
//   l1 l2          = (1,0,3) (0,1,3)                                row 3, then S = (0,0,4)
// R is mirrored (r1 at (P2 + 3S')/4, r9 at (3P1 + S')/4). l6, l9, c1, c3 are fixed by the
// vertex data; l3, l1 (and l5, l2) lie on the inner edges; l4, l7, l8 are interior points.
// Eq. (7) sets l7, l8, r7, r8 from the two middle C1 conditions and the two outer C2 conditions
// (a square system); eq. (8) ties r4 to l4 (the middle C2 condition) and eq. (11) picks l4 that
// minimises the C3 residuals; eq. (12)-(15) pick c2 minimising those C3 residuals when l4, r4
// move least. Every step is solved from its Rule A definition (AffineLeastSquares.h).
#ifndef CTSplines_Kernel_QuarticCloughTocher_h
#define CTSplines_Kernel_QuarticCloughTocher_h

#include "CubicCloughTocher.h"

namespace ctk
{
/// Shared control points of a quartic CT spline: one per vertex, three per macro-edge (from the
/// edge's smaller vertex id), nineteen per macro-triangle (S, three per inner edge, three
/// interior points per micro-triangle). Total #V + 3 #E + 19 #T.
struct QuarticSplineLayout
{
  Id NumberOfVertices = 0;
  Id NumberOfEdges = 0;
  Id NumberOfTriangles = 0;
  static constexpr int PointsPerTriangle = 19;

  Id NumberOfPoints() const
  {
    return NumberOfVertices + 3 * NumberOfEdges + PointsPerTriangle * NumberOfTriangles;
  }
  /// Point m = 1..3 steps from vertex `from` along edge e.
  Id EdgePoint(const MeshTopology& topo, Id e, Id from, int m) const
  {
    return NumberOfVertices + 3 * e + (topo.Edges[e][0] == from ? m - 1 : 3 - m);
  }
  Id TriangleBase(Id t) const { return NumberOfVertices + 3 * NumberOfEdges + PointsPerTriangle * t; }
};

/// Point ids of micro-triangle k of macro-triangle t, canonical order over (U_{k+1}, U_{k+2}, Z).
std::array<Id, 15> QuarticMicroNet(
  const QuarticSplineLayout& layout, const MeshTopology& topo, const Id* triangles, Id t, int k);

struct QuarticSpline
{
  QuarticSplineLayout Layout;
  OverwriteVector<Vec3> ControlPoints; // as CubicSpline's
  OverwriteVector<Vec2> DomainPoints;
  OverwriteVector<Vec3> SplitTau;
};

/// Stages reported to an observer: after degree raising, and in each round after the boundary
/// adjustment, after exterior fairing and after C1 smoothing.
enum class QuarticStage
{
  DegreeRaised,
  BoundaryAdjusted,
  ExteriorFaired,
  Smoothed
};
using QuarticObserver = std::function<void(QuarticStage, int round, const QuarticSpline&)>;

/// Builds the quartic spline with options.Iterations rounds (0: the degree-raised cubic-precision
/// interpolant). options.Method is ignored (the start is FO); split point and boundary mode apply
/// to the start. Boundary macro-edges keep their degree-raised points.
BuildStatus BuildQuarticCloughTocher(const SplineData& data, const MeshTopology& topology,
  const SplineOptions& options, QuarticSpline& spline, const ParallelFor& parallelFor = SerialFor,
  const QuarticObserver& observer = nullptr);

} // namespace ctk

#endif
