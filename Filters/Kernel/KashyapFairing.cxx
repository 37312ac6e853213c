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
  Vec3 net[10];
  std::copy(PM, PM + 10, net);
  Vec3 args[3];
  for (int b = 0; b < 3; ++b)
  {
    args[b] = Barycentric(AM[0], AM[1], AM[2], AMbar[b]);
  }
  MoveLeastOntoTie(3, net, CubicCentre, args, C, Cbar);
}

} // namespace ctk
