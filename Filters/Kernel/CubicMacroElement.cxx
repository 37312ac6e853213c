// SPDX-License-Identifier: GPL-3.0-or-later
#include "CubicMacroElement.h"

#include "InnerEdgeC1Smoothing.h"

namespace ctk
{
std::array<Vec3, 10> MacroNet(const MacroElementIds& ids, const Vec3* P, const Vec3& Q)
{
  // Exponents 300 210 201 120 111 102 030 021 012 003.
  return { P[ids.V[0]], P[ids.T[0][1]], P[ids.T[0][2]], P[ids.T[1][0]], Q, P[ids.T[2][0]],
    P[ids.V[1]], P[ids.T[1][2]], P[ids.T[2][1]], P[ids.V[2]] };
}

Vec3 QuadraticPrecisionQ(const Vec3* m)
{
  // (sum of the six T) / 4 - (sum of the three V) / 6, exponents as in MacroNet.
  return (m[1] + m[2] + m[3] + m[5] + m[7] + m[8]) / 4.0 - (m[0] + m[6] + m[9]) / 6.0;
}

void ComputeInnerRing1(const MacroElementIds& ids, const Vec3& tau, Vec3* points)
{
  for (int i = 0; i < 3; ++i)
  {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    points[ids.I1[i]] =
      tau[i] * points[ids.V[i]] + tau[j] * points[ids.T[i][j]] + tau[k] * points[ids.T[i][k]];
  }
}

void ComputeInnerRing2AndSplitPoint(const MacroElementIds& ids, const Vec3& tau, Vec3* points)
{
  // I_i2 = tau_i I_i1 + tau_j C_k + tau_k C_j, S = sum tau_i I_i2: the n = 3 case.
  SmoothInnerEdgesC1(3, tau, [&ids](int k) { return MicroTriangleNet(ids, k); }, points);
}

} // namespace ctk
