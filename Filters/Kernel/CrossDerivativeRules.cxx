// SPDX-License-Identifier: GPL-3.0-or-later
#include "CrossDerivativeRules.h"

namespace ctk
{
Vec3 MidEdgeGradientCentre(const EdgeRows& r, const Vec2& Ui, const Vec2& Uj, const Vec2& Z,
  const Vec3& gu, const Vec3& gv, const Vec2& w)
{
  // w in barycentric differences of (U_i, U_j, Z): a = grad(tau) . w, a0 + a1 + a2 = 0.
  const Eigen::Matrix<double, 3, 2> G = BarycentricGradient(Ui, Uj, Z);
  const Vec3 a = G * w;
  // D_w p(1/2, 1/2, 0) = 3 [ 1/4 (a0 V_i + a1 T_ij + a2 I_i1) + 1/2 (a0 T_ij + a1 T_ji + a2 C)
  //                         + 1/4 (a0 T_ji + a1 V_j + a2 I_j1) ]; solve for C.
  const Vec3 target = w.x() * gu + w.y() * gv;
  const Vec3 known = 0.25 * (a[0] * r.Vi + a[1] * r.Tij + a[2] * r.Ii1) +
    0.5 * (a[0] * r.Tij + a[1] * r.Tji) + 0.25 * (a[0] * r.Tji + a[1] * r.Vj + a[2] * r.Ij1);
  return (target / 3.0 - known) / (0.5 * a[2]);
}

} // namespace ctk
