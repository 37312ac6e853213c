// SPDX-License-Identifier: GPL-3.0-or-later
// Rule A of the spec: smoothness of two polynomial Bézier triangles across their shared edge.
// B's ordinates within r rows of the shared edge must equal A's polynomial, extended by
// blossoming, at the same domain points. The size of the mismatch in row r is the C^r jump.
#ifndef CTSplines_Kernel_RuleA_h
#define CTSplines_Kernel_RuleA_h

#include "BezierTriangle.h"

namespace ctk
{
/// Jumps across the edge shared by A (degree-n net PA over domain A[0..2]) and B (degree-n net
/// PB over domain B[0..2]), for orders 0..maxOrder (maxOrder <= n): jumps[r] is the largest
/// distance between an ordinate of B whose exponent of B's off-edge vertex is r and A's blossom
/// at the same domain point. C^r holds iff jumps[0..r] vanish. Nets in canonical order; the
/// off-edge vertex of B is the one farthest from A's vertices.
void RuleAJumps(int n, const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B, int maxOrder,
  double* jumps);

} // namespace ctk

#endif
