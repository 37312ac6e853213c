// SPDX-License-Identifier: GPL-3.0-or-later
#include "MicroEdgeC2Minimisation.h"

#include "RuleA.h"

namespace ctk
{
void MinimiseMicroEdgeC2Jump(
  const Vec3* PM, const Vec2* AM, const Vec3* PMbar, const Vec2* AMbar, Vec3& C, Vec3& Cbar)
{
  // Fa, eq. (20)-(21) (spec errata): Mbar's row-2 ordinates hold no central point, so the two C2
  // residuals r_s = PMbar_s - b_M(U_s, Zbar, Zbar) are affine in C alone (Rule A, RuleA.h):
  // r_s = K_s - 2 beta_t beta_2 C ({s, t} the edge, beta = Zbar in M's coordinates), and the
  // least sum of squares is C = sum w_s K_s / sum w_s^2. Cbar is then tied to C by the C1
  // condition (row 1): Cbar = b_M(U_0, U_1, Zbar) = beta_0 T_01 + beta_1 T_10 + beta_2 C.
  SharedCubicEdge edge;
  C = SolveCubicRuleARow2(PM, AM, PMbar, AMbar, false, edge);
  Cbar = CubicRuleARow1(PM, C, edge.A, edge.B, edge.X);
}

void FaMicroEdgeCentres(const MacroPatchAtEdge& T, const MacroPatchAtEdge& Tbar, bool sameDirection,
  const Vec3& x, Vec3& C, Vec3& Cbar)
{
  // M's net is T's macro-patch subdivided, its centre m_111 = b(U_i, U_j, Z) replaced by C; M's
  // blossom at points of M's coordinates is the macro-patch's at their images (e_i, e_j, tau), so
  // b_M(U_s, x, x) = b(e_s, y, y) + w_s (C - m_111), y = x_0 e_i + x_1 e_j + x_2 tau, w_s the
  // weight of m_111 (MinimiseMicroEdgeC2Jump). Mbar's row-2 ordinates are Tbar's
  // b(e_s', taubar, taubar). The least squares of the two residuals then give
  // C = m_111 + sum w_s (Mbar_s - b(e_s, y, y)) / sum w_s^2, and the C1 tie (row 1)
  // Cbar = x_0 T_ij + x_1 T_ji + x_2 C.
  const int i = T.L, j = (T.L + 1) % 3;
  const Vec3* P = T.Net;
  const Vec3& Q = P[CubicCentre];
  const Vec3& Qbar = Tbar.Net[CubicCentre];
  Vec3 y = x[2] * T.Tau;
  y[i] += x[0];
  y[j] += x[1];
  const int vertex[2] = { i, j };
  const int vertexBar[2] = { sameDirection ? Tbar.L : (Tbar.L + 1) % 3,
    sameDirection ? (Tbar.L + 1) % 3 : Tbar.L };
  const double w[2] = { 2.0 * x[1] * x[2], 2.0 * x[0] * x[2] };
  Vec3 num = Vec3::Zero();
  for (int s = 0; s < 2; ++s)
  {
    // b(e_s, y, y) and Tbar's b(e_s', taubar, taubar), their central points' weights q, qbar
    // (set by the calls, so read after them).
    double q = 0.0, qbar = 0.0;
    const Vec3 b = CubicRuleARow2(P, vertex[s], y, q);
    const Vec3 bbar = CubicRuleARow2(Tbar.Net, vertexBar[s], Tbar.Tau, qbar);
    num += w[s] * (bbar + qbar * Qbar - b - q * Q);
  }
  C = CubicRuleARow1(P, Q, i, j, T.Tau) + num / (w[0] * w[0] + w[1] * w[1]);
  const auto& row1 = detail::CubicRuleAIndexTable.Row1;
  Cbar = x[0] * P[row1[i][i][j]] + x[1] * P[row1[j][j][i]] + x[2] * C;
}

} // namespace ctk
