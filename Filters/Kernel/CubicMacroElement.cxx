// SPDX-License-Identifier: GPL-3.0-or-later
#include "CubicMacroElement.h"

#include "InnerEdgeC1Smoothing.h"
#include "RuleA.h"

#include <limits>

namespace ctk
{
MacroElementIds GetMacroElementIds(
  const CubicSplineLayout& layout, const MeshTopology& topo, const Id* triangles, Id t)
{
  MacroElementIds ids;
  const Id* p = triangles + 3 * t;
  for (int i = 0; i < 3; ++i)
  {
    ids.V[i] = layout.Vertex(p[i]);
    ids.I1[i] = layout.TrianglePoint(t, CubicSplineLayout::I1(i));
    ids.I2[i] = layout.TrianglePoint(t, CubicSplineLayout::I2(i));
    ids.C[i] = layout.TrianglePoint(t, CubicSplineLayout::C(i));
    ids.T[i][i] = -1;
  }
  const std::array<Id, 3>& edges = topo.TriangleEdges[t];
  for (int l = 0; l < 3; ++l)
  {
    const int i = l, j = (l + 1) % 3;
    // layout.EdgePoint without reading topo.Edges (a cache miss per edge): edges are stored as
    // (smaller, larger) vertex id.
    const Id first = layout.NumberOfVertices + 2 * edges[l];
    const Id nearI = p[i] < p[j] ? 0 : 1;
    ids.T[i][j] = first + nearI;
    ids.T[j][i] = first + (1 - nearI);
  }
  ids.S = layout.TrianglePoint(t, CubicSplineLayout::S);
  return ids;
}

std::array<Vec3, 10> MacroNet(const MacroElementIds& ids, const Vec3* P, const Vec3& Q)
{
  // Exponents 300 210 201 120 111 102 030 021 012 003.
  return { P[ids.V[0]], P[ids.T[0][1]], P[ids.T[0][2]], P[ids.T[1][0]], Q, P[ids.T[2][0]],
    P[ids.V[1]], P[ids.T[1][2]], P[ids.T[2][1]], P[ids.V[2]] };
}

Vec3 QuadraticPrecisionQ(const MacroElementIds& ids, const Vec3* P)
{
  return (P[ids.T[0][1]] + P[ids.T[1][0]] + P[ids.T[1][2]] + P[ids.T[2][1]] + P[ids.T[2][0]] +
           P[ids.T[0][2]]) /
    4.0 -
    (P[ids.V[0]] + P[ids.V[1]] + P[ids.V[2]]) / 6.0;
}

void MacroPatchMicroNet(
  const Vec3* macro, int l, const Vec3& tau, Vec3* PM, int firstRow, int lastRow)
{
  const int i = l, j = (l + 1) % 3, k = (l + 2) % 3;
  const Vec3& Q = macro[BezierIndex(3, 1, 1)];
  auto corner = [macro](int a, int b) {
    return macro[detail::CubicRuleAIndexTable.Row1[a][a][b]]; // e_a + e_a + e_b
  };
  auto row2 = [&](int a) {
    double w = 0.0;
    const Vec3 b = CubicRuleARow2(macro, a, tau, w);
    return Vec3(b + w * Q);
  };
  auto wanted = [&](int row) { return row >= firstRow && row <= lastRow; };
  const Vec3 nan = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  // Exponents 300 210 201 120 111 102 030 021 012 003 over (U_i, U_j, Z).
  if (wanted(0))
  {
    PM[0] = corner(i, i);
    PM[1] = corner(i, j);
    PM[3] = corner(j, i);
    PM[6] = corner(j, j);
  }
  else
  {
    PM[0] = PM[1] = PM[3] = PM[6] = nan;
  }
  if (wanted(1))
  {
    PM[2] = CubicRuleARow1(macro, Q, i, i, tau);
    PM[4] = CubicRuleARow1(macro, Q, i, j, tau);
    PM[7] = CubicRuleARow1(macro, Q, j, j, tau);
  }
  else
  {
    PM[2] = PM[4] = PM[7] = nan;
  }
  PM[5] = PM[8] = PM[9] = nan;
  if (wanted(2) || wanted(3))
  {
    PM[5] = row2(i);
    PM[8] = row2(j);
  }
  if (wanted(3))
  {
    PM[9] = tau[i] * PM[5] + tau[j] * PM[8] + tau[k] * row2(k); // b(Z, Z, Z)
  }
  if (!wanted(2))
  {
    PM[5] = PM[8] = nan;
  }
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
