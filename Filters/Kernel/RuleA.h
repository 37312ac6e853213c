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

/// The residuals behind RuleAJumps for one row r: for each ordinate of B whose exponent of B's
/// off-edge vertex is r (in B's canonical order), B's ordinate minus A's blossom at its domain
/// point. Returns the number of residuals written (n + 1 - r).
int RuleAResiduals(int n, const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B, int row,
  Vec3* residuals);

/// The central ordinate (1, 1, 1) of the cubic over B that joins A's cubic with C1 across their
/// shared edge (Rule A, row 1): A's blossom at B's three vertices.
Vec3 TiedCubicCentre(const Vec3* PA, const Vec2* A, const Vec2* B);

/// Smallest joint movement of an ordinate X of A (index `index` in PA) and the ordinate Xbar of a
/// neighbour that is tied to it by Rule A, Xbar = A's blossom at `args` (barycentric w.r.t. A):
/// minimises |X - X0|^2 + |Xbar - Xbar0|^2 on the tie, where X, Xbar hold X0, Xbar0 on entry.
/// PA[index] is set to the new X.
void MoveLeastOntoTie(int n, Vec3* PA, int index, const Vec3* args, Vec3& X, Vec3& Xbar);

} // namespace ctk

#endif
