// SPDX-License-Identifier: GPL-3.0-or-later
// Checks of a construction's input and output that every caller of the kernel gets: the input
// is usable (finite, far from overflow, a planar parameter domain without zero-area or folded
// triangles) and the output is finite. Each failure names the offending vertex, triangle or
// edge.
#ifndef CTSplines_Kernel_SplineDataValidation_h
#define CTSplines_Kernel_SplineDataValidation_h

#include "CubicCloughTocher.h"

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
/// - UV, F, Fu, Fv and the optional arrays are finite and below MaxInputMagnitude (NaN groups
///   of BoundaryCurvePoints mean "none"; skipped when data.ValuesChecked); given split points
///   lie inside their triangles;
/// - no parameter triangle has zero area (relative 1e-13 of the domain's squared diagonal);
/// - no fold: across every interior edge the two opposite vertices lie on opposite sides of the
///   edge in (u, v), whatever the triangles' vertex order.
/// The triangle checks visit the triangles in `order` (a locality order, LocalityOrder.h; empty:
/// their own) and report the lowest failing triangle or edge either way, chunked by parallelFor.
BuildStatus ValidateSplineData(const SplineData& data, const MeshTopology& topology,
  const std::vector<Id>& order = std::vector<Id>(), const ParallelFor& parallelFor = SerialFor);

/// Checks that every control point is finite; otherwise names the lowest triangle whose
/// macro-element holds a non-finite point. Layout: #V vertex points, pointsPerEdge per edge,
/// then pointsPerTriangle per triangle.
BuildStatus CheckFiniteControlPoints(const std::vector<Vec3>& points, const MeshTopology& topology,
  const Id* triangles, Id numberOfVertices, int pointsPerEdge, int pointsPerTriangle);

} // namespace ctk

#endif
