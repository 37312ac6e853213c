// SPDX-License-Identifier: GPL-3.0-or-later
#include "SurfaceCurvatures.h"

#include <Eigen/Eigenvalues> // for GeneralizedSelfAdjointEigenSolver

namespace ctk
{
SurfaceCurvatures CurvaturesFromJet(const ParametricJet& jet)
{
  SurfaceCurvatures k;
  const Vec3 cross = jet.Du.cross(jet.Dv);
  k.Normal = cross.normalized();
  Eigen::Matrix2d& I = k.First;
  Eigen::Matrix2d& II = k.Second;
  I << jet.Du.dot(jet.Du), jet.Du.dot(jet.Dv), jet.Du.dot(jet.Dv), jet.Dv.dot(jet.Dv);
  II << jet.Duu.dot(k.Normal), jet.Duv.dot(k.Normal), jet.Duv.dot(k.Normal),
    jet.Dvv.dot(k.Normal);
  // det I = |x_r x x_s|^2 exactly, without cancellation.
  const double detI = cross.squaredNorm();
  k.Gauss = II.determinant() / detI;
  k.Mean = -(I(0, 0) * II(1, 1) - 2 * I(0, 1) * II(0, 1) + I(1, 1) * II(0, 0)) / (2 * detI);
  // Principal curvatures and directions: II v = lambda I v with kappa = -lambda, so the smallest
  // lambda gives the largest curvature. The symmetric eigenproblem stays accurate at umbilics,
  // where H +- sqrt(H^2 - K) would lose half the digits.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> eig(II, I);
  k.Max = -eig.eigenvalues()[0];
  k.Min = -eig.eigenvalues()[1];
  const Eigen::Vector2d vMax = eig.eigenvectors().col(0), vMin = eig.eigenvectors().col(1);
  k.MaxDirection = (vMax.x() * jet.Du + vMax.y() * jet.Dv).normalized();
  k.MinDirection = (vMin.x() * jet.Du + vMin.y() * jet.Dv).normalized();
  return k;
}

SurfaceCurvatures BezierTriangleCurvatures(
  int n, const Vec3* P, const double* weights, const Vec3& t)
{
  // The patch's own parametrisation (r, s): domain (0,0), (1,0), (0,1).
  const Vec2 R0(0, 0), R1(1, 0), R2(0, 1);
  const ParametricJet exact = EvaluateOverDomain(n, P, weights, R0, R1, R2, t, 2);
  if (!IsSingularTangentPlane(exact.Du, exact.Dv))
  {
    return CurvaturesFromJet(exact);
  }
  SurfaceCurvatures k =
    CurvaturesFromJet(EvaluateOverDomain(n, P, weights, R0, R1, R2, NudgeInside(t), 2));
  k.Limit = true;
  return k;
}

} // namespace ctk
