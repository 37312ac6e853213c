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

/// Closed forms of Rule A for two cubics whose domains share an edge exactly (the same
/// coordinates). The blossom is linear in the ordinates and multi-affine in its arguments, so
/// with e_a A's vertex a and x a point in A's barycentric coordinates:
/// - row 1, b(e_a, e_b, x) = sum_k x_k P_{e_a + e_b + e_k};
/// - row 2, b(e_a, x, x) = sum_{|f| = 2} 2!/f! x^f P_{f + e_a}, the quadratic sub-net at corner a
///   evaluated at x, in which the central ordinate P_111 has the weight 2 x_b x_c
///   ({a, b, c} = {0, 1, 2}).

namespace detail
{
// Canonical cubic index of the ordinate with exponents e_a + e_b + e_c.
constexpr int CubicIndexOf(int a, int b, int c)
{
  const int i = (a == 0) + (b == 0) + (c == 0), j = (a == 1) + (b == 1) + (c == 1);
  return BezierIndex(3, i, j);
}
constexpr int CubicCentreIndex = BezierIndex(3, 1, 1);
// Row 2: f = 200 020 002 110 101 011 (|f| = 2), as pairs (p, q) of vertices.
constexpr int Row2P[6] = { 0, 1, 2, 0, 0, 1 };
constexpr int Row2Q[6] = { 0, 1, 2, 1, 2, 2 };
// The indices of the two rows, tabulated: the vertices are known at run time only, and the
// index arithmetic cost more than the sums.
struct CubicRuleAIndices
{
  int Row1[3][3][3]; // CubicIndexOf(a, b, k)
  int Row2[3][6];    // CubicIndexOf(a, Row2P[f], Row2Q[f])
};
constexpr CubicRuleAIndices MakeCubicRuleAIndices()
{
  CubicRuleAIndices t{};
  for (int a = 0; a < 3; ++a)
  {
    for (int b = 0; b < 3; ++b)
    {
      for (int k = 0; k < 3; ++k)
      {
        t.Row1[a][b][k] = CubicIndexOf(a, b, k);
      }
    }
    for (int f = 0; f < 6; ++f)
    {
      t.Row2[a][f] = CubicIndexOf(a, Row2P[f], Row2Q[f]);
    }
  }
  return t;
}
inline constexpr CubicRuleAIndices CubicRuleAIndexTable = MakeCubicRuleAIndices();
} // namespace detail

namespace detail
{
template <int A, int B>
inline Vec3 CubicRuleARow1(const Vec3* PA, const Vec3& centre, const Vec3& x)
{
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
  {
    const int idx = CubicRuleAIndexTable.Row1[A][B][k];
    sum += x[k] * (idx == CubicCentreIndex ? centre : PA[idx]);
  }
  return sum;
}
template <int A>
inline Vec3 CubicRuleARow2(const Vec3* PA, const Vec3& x, double& centreWeight)
{
  Vec3 sum = Vec3::Zero();
  for (int f = 0; f < 6; ++f)
  {
    const int p = Row2P[f], q = Row2Q[f], idx = CubicRuleAIndexTable.Row2[A][f];
    const double w = (p == q ? 1.0 : 2.0) * x[p] * x[q];
    if (idx == CubicCentreIndex)
    {
      centreWeight = w;
    }
    else
    {
      sum += w * PA[idx];
    }
  }
  return sum;
}
} // namespace detail

/// Row 1: b(e_a, e_b, x) of the cubic net PA with `centre` standing for its P_111 (a may equal b).
/// The vertices select a specialisation, whose indices are constants.
inline Vec3 CubicRuleARow1(const Vec3* PA, const Vec3& centre, int a, int b, const Vec3& x)
{
  using detail::CubicRuleARow1;
  switch (3 * a + b)
  {
    case 0: return CubicRuleARow1<0, 0>(PA, centre, x);
    case 1: return CubicRuleARow1<0, 1>(PA, centre, x);
    case 2: return CubicRuleARow1<0, 2>(PA, centre, x);
    case 3: return CubicRuleARow1<1, 0>(PA, centre, x);
    case 4: return CubicRuleARow1<1, 1>(PA, centre, x);
    case 5: return CubicRuleARow1<1, 2>(PA, centre, x);
    case 6: return CubicRuleARow1<2, 0>(PA, centre, x);
    case 7: return CubicRuleARow1<2, 1>(PA, centre, x);
    default: return CubicRuleARow1<2, 2>(PA, centre, x);
  }
}

/// Row 2: b(e_a, x, x) of the cubic net PA without its P_111 term, whose weight goes to
/// centreWeight.
inline Vec3 CubicRuleARow2(const Vec3* PA, int a, const Vec3& x, double& centreWeight)
{
  using detail::CubicRuleARow2;
  return a == 0 ? CubicRuleARow2<0>(PA, x, centreWeight)
                : (a == 1 ? CubicRuleARow2<1>(PA, x, centreWeight) : CubicRuleARow2<2>(PA, x, centreWeight));
}

/// The edge that a cubic net over B shares with one over A: A's vertices a, b at its ends, and
/// x, B's off-edge vertex in A's barycentric coordinates.
struct SharedCubicEdge
{
  int A = 0, B = 1;
  Vec3 X = Vec3::Zero();
};

/// The one-unknown step of Fa (eq. 20-21), FO (eq. 22) and Ka (eq. 23) in closed form. The
/// residuals of B's two row-2 ordinates r_s = PB_s - b_A(e_s, x, x) are affine in A's central
/// point X: r_s = K_s - w_s X (CubicRuleARow2). Returns the X with r_1 + r_2 = 0 (sumToZero,
/// X = (K_1 + K_2) / (w_1 + w_2)) or least |r_1|^2 + |r_2|^2 (X = sum w_s K_s / sum w_s^2), as
/// RuleAResiduals with SolveAffineResiduals would; PA's own central point is ignored. B must
/// share exactly two vertices of A (equal coordinates, any order; NaN otherwise); edge receives
/// them for the row-1 tie.
Vec3 SolveCubicRuleARow2(const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B,
  bool sumToZero, SharedCubicEdge& edge);

/// Smallest joint movement of an ordinate X of A (index `index` in PA) and the ordinate Xbar of a
/// neighbour that is tied to it by Rule A, Xbar = A's blossom at `args` (barycentric w.r.t. A):
/// minimises |X - X0|^2 + |Xbar - Xbar0|^2 on the tie, where X, Xbar hold X0, Xbar0 on entry.
/// PA[index] is set to the new X.
void MoveLeastOntoTie(int n, Vec3* PA, int index, const Vec3* args, Vec3& X, Vec3& Xbar);

} // namespace ctk

#endif
