// SPDX-License-Identifier: GPL-3.0-or-later
#include "RuleA.h"

#include <algorithm>
#include <limits>

namespace ctk
{
void RuleAJumps(int n, const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B, int maxOrder,
  double* jumps)
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
  // B's vertices in A's barycentric coordinates.
  Vec3 bary[3];
  for (int b = 0; b < 3; ++b)
  {
    bary[b] = Barycentric(A[0], A[1], A[2], B[b]);
  }
  for (int r = 0; r <= maxOrder; ++r)
  {
    jumps[r] = 0.0;
  }
  Vec3 args[MaxDegree];
  int idx = 0;
  for (int row = 0; row <= n; ++row)
  {
    const int i = n - row;
    for (int k = 0; k <= row; ++k, ++idx)
    {
      const int j = row - k;
      const int e[3] = { i, j, k };
      const int r = e[opposite];
      if (r > maxOrder)
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
      jumps[r] = std::max(jumps[r], (PB[idx] - Blossom(n, PA, args)).norm());
    }
  }
}

} // namespace ctk
