// SPDX-License-Identifier: GPL-3.0-or-later
// The least-squares steps of the constructions all have one unknown point X and vector residuals
// that are affine in X with scalar coefficients (control points are affine combinations with
// weights from the domain), r_m(X) = r_m(0) + alpha_m X. Instead of transcribing closed forms,
// the kernel evaluates the residuals from their definition at X = 0 and X = (1, 1, 1), reads off
// alpha_m, and solves the one scalar normal equation.
#ifndef CTSplines_Kernel_AffineLeastSquares_h
#define CTSplines_Kernel_AffineLeastSquares_h

#include "BezierTriangle.h"

namespace ctk
{
/// residuals(X, out) writes `count` residuals (count <= 8) for the unknown X.
/// Least squares (sumToZero false): X minimising sum |r_m(X)|^2.
/// sumToZero true: X solving sum r_m(X) = 0 (as the Foley-Opitz/Mann eq. 22 does).
template <typename Residuals>
Vec3 SolveAffineResiduals(Residuals&& residuals, int count, bool sumToZero = false)
{
  Vec3 r0[8], r1[8];
  residuals(Vec3::Zero(), r0);
  residuals(Vec3::Ones(), r1);
  Vec3 num = Vec3::Zero();
  double den = 0.0;
  for (int m = 0; m < count; ++m)
  {
    const double alpha = r1[m].x() - r0[m].x();
    const double w = sumToZero ? 1.0 : alpha;
    num += w * r0[m];
    den += w * alpha;
  }
  return -num / den;
}
} // namespace ctk

#endif
