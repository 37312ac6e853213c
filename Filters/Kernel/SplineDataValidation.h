// SPDX-License-Identifier: GPL-3.0-or-later
// Checks of a construction's input and output that every caller of the kernel gets: the input
// is usable (finite, far from overflow, a planar parameter domain without zero-area or folded
// triangles) and the output is finite. Each failure names the offending vertex, triangle or
// edge.
#ifndef CTSplines_Kernel_SplineDataValidation_h
#define CTSplines_Kernel_SplineDataValidation_h

#include "BezierTriangle.h"
#include "CubicCloughTocher.h"

#include <atomic>
#include <cmath>

namespace ctk
{
/// Input values (positions, derivatives, (u, v), gradients) must stay below this magnitude: the
/// constructions form products and squared distances of them, far from overflow at 1e100.
constexpr double MaxInputMagnitude = 1e100;
/// Finite and below MaxInputMagnitude (false for NaN).
inline bool IsUsableValue(double x)
{
  return std::abs(x) < MaxInputMagnitude;
}
inline bool IsUsablePoint(const Vec3& p)
{
  return IsUsableValue(p.x()) && IsUsableValue(p.y()) && IsUsableValue(p.z());
}
/// Whether any of the six values g[0..5] that a triangle gives an edge (f_u then f_v at its
/// midpoint, SplineData::EdgeGradients) is not usable. The cubic constructions check the ones
/// they read with it (the Bézier extraction reads no others): the boundary-edge constructions
/// read few, and MGo's and MGi's single pass over them is the check.
inline bool UnusableEdgeGradients(const double* g)
{
  bool usable = true;
  for (int k = 0; k < 6; ++k)
  {
    usable &= IsUsableValue(g[k]);
  }
  return !usable;
}
/// The failure naming triangle t of data, one of whose mid-edge gradients read by a construction
/// is not usable (UnusableEdgeGradients), and that value.
BuildStatus EdgeGradientFailure(const SplineData& data, Id t);
/// Bulk checks of raw arrays (a source read in place), out of line so that each loop is
/// vectorised on its own (inlined into a large caller, GCC left them scalar):
/// whether all n values are usable (IsUsableValue) and, with `positive`, > 0;
bool AllUsableValues(const double* values, Id n, bool positive = false);
/// whether all n (u, v) pairs uv[2 i], uv[2 i + 1] are usable, and their box [lo, hi];
bool AllUsablePairs(const double* uv, Id n, Vec2& lo, Vec2& hi);
/// whether all n ids lie in [0, nPoints) (nPoints > 0); defined for int, long and long long.
template <typename IdT>
bool AllIdsInRange(const IdT* ids, Id n, Id nPoints);

/// A parameter domain whose diagonal is below this is rejected (barycentric coordinates would
/// divide by underflowing areas).
constexpr double MinDomainDiagonal = 1e-100;

/// Checks data (and its topology) before any construction:
/// - UV, F, Fu, Fv and BoundaryCurvePoints are finite and below MaxInputMagnitude (NaN groups
///   of BoundaryCurvePoints mean "none"; skipped when data.ValuesChecked; the mid-edge
///   gradients are checked where they are read, UnusableEdgeGradients); given split points
///   lie inside their triangles; the domain is not too small (CheckDomainSize);
/// - no parameter triangle is degenerate (IsDegenerateTriangle);
/// - no interior edge is folded (IsFoldedEdge).
/// The triangle checks visit the triangles in `order` (a locality order, LocalityOrder.h; empty:
/// their own) and report the lowest failing triangle or edge either way, chunked by parallelFor.
BuildStatus ValidateSplineData(const SplineData& data, const MeshTopology& topology,
  const std::vector<Id>& order = std::vector<Id>(), const ParallelFor& parallelFor = SerialFor);

/// The checks of ValidateSplineData before the per-triangle and per-edge ones, which a
/// construction may run in its own first passes (the cubic builder: its split points and
/// Step 1), then report with DomainFailure. diag2: the domain's squared diagonal.
BuildStatus ValidateSplineValues(const SplineData& data, const MeshTopology& topology,
  const ParallelFor& parallelFor, double& diag2);
/// The (u, v) box's squared diagonal diag2, or a failure when its diagonal is below
/// MinDomainDiagonal.
BuildStatus CheckDomainSize(const SplineData& data, const ParallelFor& parallelFor, double& diag2);
/// Twice the signed area of triangle t in (u, v).
inline double SignedAreaUV(const SplineData& data, Id t)
{
  const Id* p = data.Triangles + 3 * t;
  const double* uv = data.UV;
  return SignedArea2(Vec2(uv[2 * p[0]], uv[2 * p[0] + 1]), Vec2(uv[2 * p[1]], uv[2 * p[1] + 1]),
    Vec2(uv[2 * p[2]], uv[2 * p[2] + 1]));
}
/// Whether a triangle of doubled signed area area2 has zero area, relative 1e-13 of diag2.
inline bool IsDegenerateArea(double area2, double diag2)
{
  return !(std::abs(area2) > 1e-13 * diag2);
}
/// Whether triangle t has zero area in (u, v) (IsDegenerateArea).
inline bool IsDegenerateTriangle(const SplineData& data, Id t, double diag2)
{
  return IsDegenerateArea(SignedAreaUV(data, t), diag2);
}
/// Whether interior edge e is folded: its two opposite vertices lie on the same side of it in
/// (u, v), whatever the triangles' vertex order. Boundary edges never are.
inline bool IsFoldedEdge(const SplineData& data, const MeshTopology& topology, Id e)
{
  if (topology.IsBoundaryEdge(e))
  {
    return false;
  }
  const double* uv = data.UV;
  const Id a = topology.Edges[e][0], b = topology.Edges[e][1];
  const Vec2 A(uv[2 * a], uv[2 * a + 1]), B(uv[2 * b], uv[2 * b + 1]);
  double side[2];
  for (int s = 0; s < 2; ++s)
  {
    const Id t = topology.EdgeTriangles[e][s];
    const Id o = data.Triangles[3 * t + (topology.EdgeLocalIndex[e][s] + 2) % 3];
    side[s] = SignedArea2(A, B, Vec2(uv[2 * o], uv[2 * o + 1]));
  }
  return (side[0] > 0) == (side[1] > 0);
}
/// The signs of the triangles' areas in (u, v), reported from any thread. No edge can fold when
/// every interior edge's triangles run along it in opposite directions
/// (MeshTopology::ConsistentlyOriented) and the areas, none degenerate, all have one sign: their
/// signs are then far above round-off, and the fold check (IsFoldedEdge) cannot fail.
class AreaSigns
{
public:
  void Report(double area2)
  {
    std::atomic<bool>& seen = area2 > 0 ? this->Positive : this->Negative;
    if (!seen.load(std::memory_order_relaxed))
    {
      seen.store(true, std::memory_order_relaxed);
    }
  }
  /// Whether the fold check is needed on `topology` after every triangle was reported.
  bool FoldsPossible(const MeshTopology& topology) const
  {
    return !topology.ConsistentlyOriented || (this->Positive.load() && this->Negative.load());
  }

private:
  std::atomic<bool> Positive{ false }, Negative{ false };
};
/// The failure naming the lowest degenerate triangle, else the lowest folded edge, or success.
BuildStatus DomainFailure(const SplineData& data, const MeshTopology& topology,
  const LowestId& degenerate, const LowestId& folded);

/// Checks that every control point is finite; otherwise names the lowest triangle whose
/// macro-element holds a non-finite point. Layout: #V vertex points, pointsPerEdge per edge,
/// then pointsPerTriangle per triangle.
BuildStatus CheckFiniteControlPoints(const OverwriteVector<Vec3>& points,
  const MeshTopology& topology, const Id* triangles, Id numberOfVertices, int pointsPerEdge,
  int pointsPerTriangle);

} // namespace ctk

#endif
