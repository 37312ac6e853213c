// SPDX-License-Identifier: GPL-3.0-or-later
#include "MacroEdgeCubicPrecision.h"

#include "RuleA.h"

namespace ctk
{
Vec3 MacroEdgeQ(MacroEdgeRule rule, const Vec3* macroT, const Vec2* A, const Vec3* macroTbar,
  const Vec2* B, SharedCubicEdge& edge)
{
  // With U3 = Tbar's off-edge vertex = t0 U0 + t1 U1 + t2 U2 and the shared edge (U0, U1), the
  // residuals T30 - b(U3, U3, U0) and T31 - b(U3, U3, U1) are K - 2 t1 t2 Q and K' - 2 t0 t2 Q
  // (Rule B of the spec); FO (eq. 22) zeroes their sum, Ka (eq. 23) their squares' sum.
  return SolveCubicRuleARow2(
    macroT, A, macroTbar, B, rule == MacroEdgeRule::ZeroResidualSum, edge);
}

} // namespace ctk
