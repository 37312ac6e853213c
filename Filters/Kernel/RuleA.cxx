// SPDX-License-Identifier: GPL-3.0-or-later
#include "RuleA.h"

#include <algorithm>
#include <limits>

namespace ctk
{
namespace
{
// B's off-edge vertex: the one farthest from A's vertices.
int OffEdgeVertex(const Vec2* A, const Vec2* B)
{
  int opposite = 0;
  double farthest = -1.0;
  for (int b = 0; b < 3; ++b)
  {
    double nearest = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
    {
      nearest = std::min(nearest, (B[b] - A[a]).squaredNorm());
    }
    if (nearest > farthest)
    {
      farthest = nearest;
      opposite = b;
    }
  }
  return opposite;
}

// Calls visit(row, canonical index, residual) for every ordinate of B in rows <= maxRow.
template <typename Visit>
void ForEachResidual(int n, const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B,
  int maxRow, int onlyRow, Visit&& visit)
{
  const int opposite = OffEdgeVertex(A, B);
  Vec3 bary[3];
  for (int b = 0; b < 3; ++b)
  {
    bary[b] = Barycentric(A[0], A[1], A[2], B[b]);
  }
  Vec3 args[MaxDegree];
  int idx = 0;
  for (int row = 0; row <= n; ++row)
  {
    const int i = n - row;
    for (int k = 0; k <= row; ++k, ++idx)
    {
      const int e[3] = { i, row - k, k };
      const int r = e[opposite];
      if (r > maxRow || (onlyRow >= 0 && r != onlyRow))
      {
        continue;
      }
      int a = 0;
      for (int v = 0; v < 3; ++v)
      {
        for (int s = 0; s < e[v]; ++s)
        {
          args[a++] = bary[v];
        }
      }
      visit(r, PB[idx] - Blossom(n, PA, args));
    }
  }
}
} // namespace

void RuleAJumps(int n, const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B, int maxOrder,
  double* jumps)
{
  std::fill(jumps, jumps + maxOrder + 1, 0.0);
  ForEachResidual(n, PA, A, PB, B, maxOrder, -1,
    [&](int r, const Vec3& res) { jumps[r] = std::max(jumps[r], res.norm()); });
}

int RuleAResiduals(int n, const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B, int row,
  Vec3* residuals)
{
  int count = 0;
  ForEachResidual(
    n, PA, A, PB, B, row, row, [&](int, const Vec3& res) { residuals[count++] = res; });
  return count;
}

Vec3 TiedCubicCentre(const Vec3* PA, const Vec2* A, const Vec2* B)
{
  Vec3 args[3];
  for (int b = 0; b < 3; ++b)
  {
    args[b] = Barycentric(A[0], A[1], A[2], B[b]);
  }
  return Blossom(3, PA, args);
}

Vec3 SolveCubicRuleARow2(const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B,
  bool sumToZero, SharedCubicEdge& edge)
{
  // A's vertex at each of B's vertices (-1: B's off-edge vertex).
  int match[3];
  int off = 0, shared = 0;
  for (int b = 0; b < 3; ++b)
  {
    match[b] = B[b] == A[0] ? 0 : (B[b] == A[1] ? 1 : (B[b] == A[2] ? 2 : -1));
    off = match[b] < 0 ? b : off;
    shared += match[b] >= 0 ? 1 : 0;
  }
  if (shared != 2)
  {
    return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  edge.X = Barycentric(A[0], A[1], A[2], B[off]);
  // B's row-2 ordinates, in B's canonical order: exponent 2 at `off`, 1 at an edge vertex.
  Vec3 num = Vec3::Zero();
  double den = 0.0;
  int s = 0;
  for (int b = 0; b < 3; ++b)
  {
    if (b == off)
    {
      continue;
    }
    (s++ == 0 ? edge.A : edge.B) = match[b];
    int e[3] = { 0, 0, 0 };
    e[off] = 2;
    e[b] = 1;
    double w = 0.0;
    const Vec3 K = PB[BezierIndex(3, e[0], e[1])] - CubicRuleARow2(PA, match[b], edge.X, w);
    num += (sumToZero ? 1.0 : w) * K;
    den += sumToZero ? w : w * w;
  }
  return num / den;
}

void MoveLeastOntoTie(int n, Vec3* PA, int index, const Vec3* args, Vec3& X, Vec3& Xbar)
{
  // Xbar = a X + b with a scalar a (the blossom is affine in each ordinate).
  PA[index] = Vec3::Zero();
  const Vec3 b = Blossom(n, PA, args);
  PA[index] = Vec3::Ones();
  const double a = Blossom(n, PA, args).x() - b.x();
  X = (X + a * (Xbar - b)) / (1.0 + a * a);
  Xbar = a * X + b;
  PA[index] = X;
}

} // namespace ctk
