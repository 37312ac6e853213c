// SPDX-License-Identifier: GPL-3.0-or-later
// Bézier extraction of the C1 Clough-Tocher spline space (for isogeometric analysis): every cubic
// construction without iterations is linear in its data, so each micro-triangle's Bernstein
// ordinates are C_e d_e, with d_e the element's global degrees of freedom:
//   vertex v: 3v (value), 3v + 1 (d/du), 3v + 2 (d/dv);
//   edge e carrying mid-edge data: 3 #V + (its rank among such edges): the directional derivative
//   at the edge midpoint along the construction's unit v_eps (EdgeDirection), i.e. g_eps . v_eps.
// Every edge carries one for MGo and MGi (dimension 3 #V + #E, the full CT space); boundary edges
// do for KaG and the gradient boundary modes; none otherwise (3 #V, the reduced space).
// C_e is found by probing the construction with unit data on the triangle and its neighbours
// (the only data it reads), with the split points of the real data held fixed.
#ifndef CTSplines_Kernel_BezierExtraction_h
#define CTSplines_Kernel_BezierExtraction_h

#include "CubicCloughTocher.h"

namespace ctk
{
struct BezierExtraction
{
  /// Largest number of degrees of freedom of one macro-triangle: six vertices and three edges.
  static constexpr int MaxElementDofs = 21;
  Id NumberOfDofs = 0;
  /// Per edge: its degree of freedom, or -1.
  std::vector<Id> EdgeDofs;
  /// Per edge carrying a degree of freedom: the unit direction v_eps in the parameter plane.
  std::vector<Vec2> EdgeDirections;
  /// Per micro-triangle 3t + k: MaxElementDofs global ids (-1 padded) ...
  std::vector<Id> CellDofs;
  /// ... and the 10 x MaxElementDofs operator, row-major, rows in the canonical order of
  /// MicroTriangleNet (ordinate a = sum_j C[a][j] d[CellDofs[j]]).
  std::vector<double> CellOperators;
};

/// Degrees of freedom of given data (applied per coordinate: #DOF by 3): positions, derivatives
/// and g_eps . v_eps of the (averaged) mid-edge gradients.
std::vector<Vec3> DegreesOfFreedom(
  const SplineData& data, const MeshTopology& topology, const BezierExtraction& extraction);

/// Builds the extraction operators. data supplies the geometry (UV, F for Inc3 split points,
/// EdgeGradients only for presence); constructions with Iterations > 0 are not linear-local
/// and are refused, as are Kashyap (with rounds) and the quartic scheme.
BuildStatus BuildBezierExtraction(const SplineData& data, const MeshTopology& topology,
  const SplineOptions& options, BezierExtraction& extraction, const ParallelFor& parallelFor = SerialFor);

} // namespace ctk

#endif
