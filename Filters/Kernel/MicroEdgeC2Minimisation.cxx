// SPDX-License-Identifier: GPL-3.0-or-later
#include "MicroEdgeC2Minimisation.h"

#include "AffineLeastSquares.h"
#include "RuleA.h"

#include <algorithm>

namespace ctk
{
void MinimiseMicroEdgeC2Jump(
  const Vec3* PM, const Vec2* AM, const Vec3* PMbar, const Vec2* AMbar, Vec3& C, Vec3& Cbar)
{
  Vec3 net[10];
  std::copy(PM, PM + 10, net);
  // Row 2 of Mbar holds no central point, so the residuals depend on C only; with Cbar tied to C
  // by the C1 condition, they measure the C2 jump (Rule A).
  auto residuals = [&](const Vec3& X, Vec3* out) {
    net[CubicCentre] = X;
    RuleAResiduals(3, net, AM, PMbar, AMbar, 2, out);
  };
  C = SolveAffineResiduals(residuals, 2);
  net[CubicCentre] = C;
  Cbar = TiedCubicCentre(net, AM, AMbar);
}

} // namespace ctk
