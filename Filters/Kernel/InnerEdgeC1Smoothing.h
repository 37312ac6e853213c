// SPDX-License-Identifier: GPL-3.0-or-later
// C1 across the inner edges of a Clough-Tocher macro-triangle of any degree n: Step 3 of the study
// (eq. 13-14) for cubics, C1 smoothing of the quartic paper (section 4.3) for quartics.
//
// Along the inner edge (U_i, Z), the point E_i[m] at ((n - m) U_i + m Z)/n, m = 2 .. n-1, is the
// affine combination tau_i E_i[m-1] + tau_{i+1} X + tau_{i+2} Y of its predecessor and the two
// points beside the edge at ((n - m) U_i + (m - 1) Z + U_{i+1})/n and (... + U_{i+2})/n (Rule A:
// the weights are Z's barycentric coordinates). Then S = sum tau_i E_i[n-1].
#ifndef CTSplines_Kernel_InnerEdgeC1Smoothing_h
#define CTSplines_Kernel_InnerEdgeC1Smoothing_h

#include "BezierTriangle.h"

namespace ctk
{
/// netIds(k) returns the point ids (canonical order, degree n) of micro-triangle k over
/// (U_{k+1}, U_{k+2}, Z); points are updated in place.
template <typename NetIds, typename Point>
void SmoothInnerEdgesC1(int n, const Vec3& tau, NetIds&& netIds, Point* points)
{
  const auto n0 = netIds(0), n1 = netIds(1), n2 = netIds(2);
  const decltype(n0)* nets[3] = { &n0, &n1, &n2 };
  for (int i = 0; i < 3; ++i)
  {
    // T_{i+2} = (U_i, U_{i+1}, Z) holds the inner edge (U_i, Z) as its b = 0 side;
    // T_{i+1} = (U_{i+2}, U_i, Z) as its a = 0 side.
    const auto& left = *nets[(i + 2) % 3];
    const auto& right = *nets[(i + 1) % 3];
    for (int m = 2; m <= n - 1; ++m)
    {
      const Point prev = points[left[BezierIndex(n, n - m + 1, 0)]];
      const Point x = points[left[BezierIndex(n, n - m, 1)]];
      const Point y = points[right[BezierIndex(n, 1, n - m)]];
      points[left[BezierIndex(n, n - m, 0)]] = tau[i] * prev + tau[(i + 1) % 3] * x + tau[(i + 2) % 3] * y;
    }
  }
  // S from the last inner-edge points: E_i[n-1] is (1, 0, n-1) in T_{i+2}.
  const Point s = tau[0] * points[(*nets[2])[BezierIndex(n, 1, 0)]] +
    tau[1] * points[(*nets[0])[BezierIndex(n, 1, 0)]] + tau[2] * points[(*nets[1])[BezierIndex(n, 1, 0)]];
  points[n0[BezierIndex(n, 0, 0)]] = s;
}
} // namespace ctk

#endif
