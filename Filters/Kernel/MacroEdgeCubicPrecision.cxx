// SPDX-License-Identifier: GPL-3.0-or-later
#include "MacroEdgeCubicPrecision.h"

#include "AffineLeastSquares.h"
#include "MicroEdgeC2Minimisation.h"
#include "RuleA.h"

#include <algorithm>

namespace ctk
{
Vec3 MacroEdgeQ(MacroEdgeRule rule, const Vec3* macroT, const Vec2* A, const Vec3* macroTbar,
  const Vec2* B)
{
  Vec3 net[10];
  std::copy(macroT, macroT + 10, net);
  auto residuals = [&](const Vec3& X, Vec3* out) {
    net[CubicCentre] = X;
    RuleAResiduals(3, net, A, macroTbar, B, 2, out);
  };
  return SolveAffineResiduals(residuals, 2, rule == MacroEdgeRule::ZeroResidualSum);
}

} // namespace ctk
