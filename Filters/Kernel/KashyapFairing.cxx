// SPDX-License-Identifier: GPL-3.0-or-later
#include "KashyapFairing.h"

#include "MicroEdgeC2Minimisation.h"
#include "RuleA.h"

#include <algorithm>

namespace ctk
{
void KashyapInteriorFairing(const MacroElementIds& ids, const Vec3& tau, Vec3* points)
{
  Vec3 base[3];
  Vec3 num = Vec3::Zero();
  double den = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    base[k] = tau[i] * points[ids.T[i][j]] + tau[j] * points[ids.T[j][i]];
    num += tau[k] * (points[ids.C[k]] - base[k]);
    den += tau[k] * tau[k];
  }
  const Vec3 Q = num / den;
  for (int k = 0; k < 3; ++k)
  {
    points[ids.C[k]] = base[k] + tau[k] * Q;
  }
}

void RestoreMacroEdgeC1(const Vec3* PM, const Vec2* AM, const Vec2* AMbar, Vec3& C, Vec3& Cbar)
{
  // Cbar = a C + b (Rule A row 1); minimise |C - C0|^2 + |a C + b - Cbar0|^2.
  Vec3 net[10];
  std::copy(PM, PM + 10, net);
  net[CubicCentre] = Vec3::Zero();
  const Vec3 b = TiedCubicCentre(net, AM, AMbar);
  net[CubicCentre] = Vec3::Ones();
  const double a = TiedCubicCentre(net, AM, AMbar).x() - b.x();
  C = (C + a * (Cbar - b)) / (1.0 + a * a);
  Cbar = a * C + b;
}

} // namespace ctk
