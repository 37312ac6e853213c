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

} // namespace ctk
