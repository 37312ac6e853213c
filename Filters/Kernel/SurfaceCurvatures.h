// SPDX-License-Identifier: GPL-3.0-or-later
// Differential geometry of a parametric surface x(r, s) at one point: the first and second
// fundamental forms, the unit normal, Gaussian, mean and principal curvatures and the principal
// directions, from exact derivatives (no tessellation). Pure maths: no VTK.
//
// Sign convention: with n = (x_r x x_s) / |x_r x x_s| and L = x_rr . n, M = x_rs . n,
// N = x_ss . n, H = -(E N - 2 F M + G L) / (2 (E G - F^2)), so that H > 0 where the surface bends
// away from its normal: a sphere whose normal points outwards has H = +1/R, K = 1/R^2. The
// principal curvatures use the same sign (their mean is H, their product K), Max >= Min.
#ifndef CTSplines_Kernel_SurfaceCurvatures_h
#define CTSplines_Kernel_SurfaceCurvatures_h

#include "BezierTriangle.h"

namespace ctk
{
struct SurfaceCurvatures
{
  /// First fundamental form [E F; F G] (E = x_r . x_r, F = x_r . x_s, G = x_s . x_s).
  Eigen::Matrix2d First = Eigen::Matrix2d::Zero();
  /// Second fundamental form [L M; M N] with respect to Normal.
  Eigen::Matrix2d Second = Eigen::Matrix2d::Zero();
  /// Unit normal (x_r x x_s) / |x_r x x_s|.
  Vec3 Normal = Vec3::Zero();
  double Gauss = 0, Mean = 0, Max = 0, Min = 0;
  /// Unit tangent principal directions of Max and Min (their sign is arbitrary).
  Vec3 MaxDirection = Vec3::Zero(), MinDirection = Vec3::Zero();
  /// True when the tangent plane was singular at the requested point (e.g. a collapsed corner)
  /// and the values are the limit from inside, taken at NudgeInside(t).
  bool Limit = false;
};

/// Curvatures from the derivatives of x(r, s) (a ParametricJet of order 2, r = u, s = v). The
/// tangent plane must be regular (x_r x x_s != 0); otherwise the values are not finite.
SurfaceCurvatures CurvaturesFromJet(const ParametricJet& jet);

/// Curvatures of the degree-n Bézier triangle P (canonical order; weights nullptr when
/// polynomial) at barycentric t, in the patch's own parametrisation t = (1 - r - s, r, s); the
/// fundamental forms refer to (r, s). Where the tangent plane is singular (IsSingularTangentPlane),
/// the limit from inside (Limit is set). Curvatures do not depend on the position of the net:
/// pass a RelativeNet for accuracy on small patches far from the origin.
SurfaceCurvatures BezierTriangleCurvatures(
  int n, const Vec3* P, const double* weights, const Vec3& t);

} // namespace ctk

#endif
