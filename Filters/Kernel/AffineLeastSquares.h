// SPDX-License-Identifier: GPL-3.0-or-later
// The least-squares steps of the constructions all have one unknown point X and vector residuals
// that are affine in X with scalar coefficients (control points are affine combinations with
// weights from the domain), r_m(X) = r_m(0) + alpha_m X. Instead of transcribing closed forms,
// the kernel evaluates the residuals from their definition at X = 0 and X = (1, 1, 1), reads off
// alpha_m, and solves the one scalar normal equation.
#ifndef CTSplines_Kernel_AffineLeastSquares_h
#define CTSplines_Kernel_AffineLeastSquares_h

#include "BezierTriangle.h"

#include <Eigen/QR>

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
/// The same for K unknown points X_0..X_{K-1} (K <= 4) and `count` residuals (count <= 16):
/// least-squares solution of the (scalar) count x K system, exact when it is square and regular.
template <int K, typename Residuals>
void SolveAffineSystem(Residuals&& residuals, int count, Vec3* X)
{
  Vec3 r0[16], r1[16];
  Vec3 probe[K];
  for (int k = 0; k < K; ++k)
  {
    probe[k] = Vec3::Zero();
  }
  residuals(probe, r0);
  Eigen::Matrix<double, Eigen::Dynamic, K> M(count, K);
  Eigen::Matrix<double, Eigen::Dynamic, 3> rhs(count, 3);
  for (int m = 0; m < count; ++m)
  {
    rhs.row(m) = -r0[m].transpose();
  }
  for (int k = 0; k < K; ++k)
  {
    probe[k] = Vec3::Ones();
    residuals(probe, r1);
    probe[k] = Vec3::Zero();
    for (int m = 0; m < count; ++m)
    {
      M(m, k) = r1[m].x() - r0[m].x();
    }
  }
  const Eigen::Matrix<double, K, 3> sol = M.colPivHouseholderQr().solve(rhs);
  for (int k = 0; k < K; ++k)
  {
    X[k] = sol.row(k).transpose();
  }
}
} // namespace ctk

#endif
