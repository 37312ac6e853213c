// SPDX-License-Identifier: GPL-3.0-or-later
// Curvatures of Bézier triangles against closed forms (paraboloid, cylinder, sphere), their
// invariance under rigid motions and affine reparametrisations of the domain, and the limit at
// a singular corner.
#include "AnalyticSurfaces.h"
#include "SurfaceCurvatures.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

using namespace ctk;

namespace
{
struct Net
{
  int Degree = 0;
  std::vector<Vec3> Points;
  std::vector<double> Weights; // empty: polynomial
  const double* W() const { return Weights.empty() ? nullptr : Weights.data(); }
};

double Bernstein(int n, const std::array<int, 3>& e, const Vec3& t)
{
  double f = std::tgamma(n + 1.0);
  for (int a = 0; a < 3; ++a)
  {
    f *= std::pow(t[a], e[a]) / std::tgamma(e[a] + 1.0);
  }
  return f;
}

// The degree-n (rational) net over the parameter triangle (V0, V1, V2) that interpolates the
// homogeneous map h(u, v) = (w x, w) at the domain points: exact when h is a polynomial of
// degree <= n.
Net Interpolate(int n, const std::array<Vec2, 3>& V, bool rational,
  const std::function<Eigen::Vector4d(const Vec2&)>& h)
{
  const std::vector<std::array<int, 3>> exps = BezierExponents(n);
  const int m = static_cast<int>(exps.size());
  Eigen::MatrixXd M(m, m), values(m, 4);
  for (int a = 0; a < m; ++a)
  {
    const Vec3 t = Vec3(exps[a][0], exps[a][1], exps[a][2]) / n;
    for (int b = 0; b < m; ++b)
    {
      M(a, b) = Bernstein(n, exps[b], t);
    }
    values.row(a) = h(t[0] * V[0] + t[1] * V[1] + t[2] * V[2]).transpose();
  }
  const Eigen::MatrixXd H = M.partialPivLu().solve(values);
  Net net;
  net.Degree = n;
  for (int a = 0; a < m; ++a)
  {
    net.Points.push_back(H.row(a).head<3>().transpose() / H(a, 3));
    if (rational)
    {
      net.Weights.push_back(H(a, 3));
    }
  }
  return net;
}

SurfaceCurvatures At(const Net& net, const Vec3& t)
{
  return BezierTriangleCurvatures(net.Degree, net.Points.data(), net.W(), t);
}

const std::array<Vec2, 3> GraphDomain = { Vec2(-0.4, -0.3), Vec2(0.5, -0.2), Vec2(0.1, 0.6) };
// z = (a x^2 + 2 b x y + c y^2) / 2 + d x + e y.
constexpr double Qa = 1.3, Qb = -0.4, Qc = 0.7, Qd = 0.2, Qe = -0.5;

Net Paraboloid(int n, double d = Qd, double e = Qe)
{
  // Exactly a quadratic: interpolated at degree 2, then degree-elevated to n.
  Net net = Interpolate(2, GraphDomain, false, [d, e](const Vec2& p) {
    const double x = p.x(), y = p.y();
    const double z = 0.5 * (Qa * x * x + 2 * Qb * x * y + Qc * y * y) + d * x + e * y;
    return Eigen::Vector4d(x, y, z, 1);
  });
  for (int k = 2; k < n; ++k)
  {
    std::vector<Vec3> up(BezierPointCount(k + 1));
    ElevateDegree(k, net.Points.data(), up.data());
    net.Points = up;
    net.Degree = k + 1;
  }
  return net;
}

Vec3 RandomBarycentric(std::mt19937& rng, double lo = 0.05)
{
  std::uniform_real_distribution<double> U(lo, 1.0);
  const Vec3 t(U(rng), U(rng), U(rng));
  return t / t.sum();
}

// Normal curvature (our sign) in the tangent direction d: -II(v) / I(v) with d = [x_r x_s] v.
double NormalCurvature(const Net& net, const Vec3& t, const Vec3& d)
{
  const ParametricJet j = EvaluateOverDomain(
    net.Degree, net.Points.data(), net.W(), Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), t, 2);
  Eigen::Matrix<double, 3, 2> D;
  D << j.Du, j.Dv;
  const Eigen::Vector2d v = D.colPivHouseholderQr().solve(d);
  const SurfaceCurvatures k = CurvaturesFromJet(j);
  return -v.dot(k.Second * v) / v.dot(k.First * v);
}
} // namespace

// The graph of a quadratic, degree-elevated: K, H and the principal curvatures are the closed
// forms of a graph z = f(x, y) at every point, to round-off; at the apex the principal
// directions are the Hessian's eigenvectors.
TEST(SurfaceCurvatures, ExactOnParaboloid)
{
  std::mt19937 rng(5);
  for (int n = 2; n <= 7; ++n)
  {
    const Net net = Paraboloid(n);
    for (int s = 0; s < 20; ++s)
    {
      const Vec3 t = RandomBarycentric(rng, 0.0);
      const Vec2 p = t[0] * GraphDomain[0] + t[1] * GraphDomain[1] + t[2] * GraphDomain[2];
      const double fx = Qa * p.x() + Qb * p.y() + Qd, fy = Qb * p.x() + Qc * p.y() + Qe;
      const double W2 = 1 + fx * fx + fy * fy;
      const double K = (Qa * Qc - Qb * Qb) / (W2 * W2);
      // The normal points up (the domain is counter-clockwise): the graph bends towards it.
      const double H =
        -((1 + fy * fy) * Qa - 2 * fx * fy * Qb + (1 + fx * fx) * Qc) / (2 * std::pow(W2, 1.5));
      const SurfaceCurvatures k = At(net, t);
      EXPECT_FALSE(k.Limit);
      EXPECT_NEAR(k.Gauss, K, 1e-12) << "n " << n;
      EXPECT_NEAR(k.Mean, H, 1e-12) << "n " << n;
      EXPECT_NEAR(k.Max, H + std::sqrt(H * H - K), 1e-12) << "n " << n;
      EXPECT_NEAR(k.Min, H - std::sqrt(H * H - K), 1e-12) << "n " << n;
      EXPECT_NEAR((k.Normal - Vec3(-fx, -fy, 1) / std::sqrt(W2)).norm(), 0, 1e-13);
      // The kernel's other home of the normal gives the same one.
      EXPECT_NEAR((k.Normal - PatchNormal(n, net.Points.data(), nullptr, t)).norm(), 0, 1e-15);
      // Principal directions: unit tangents, orthogonal, with normal curvatures Max and Min.
      EXPECT_NEAR(k.MaxDirection.norm(), 1, 1e-14);
      EXPECT_NEAR(k.MaxDirection.dot(k.Normal), 0, 1e-13);
      EXPECT_NEAR(k.MaxDirection.dot(k.MinDirection), 0, 1e-12);
      EXPECT_NEAR(NormalCurvature(net, t, k.MaxDirection), k.Max, 1e-11);
      EXPECT_NEAR(NormalCurvature(net, t, k.MinDirection), k.Min, 1e-11);
    }
  }
  // Apex (gradient zero at the origin): K = det Hess, H = -trace / 2, and the direction of the
  // largest curvature (ours is -lambda) is the Hessian's eigenvector of its smallest eigenvalue.
  const Net net = Paraboloid(4, 0.0, 0.0);
  const Vec3 apex = Barycentric(GraphDomain[0], GraphDomain[1], GraphDomain[2], Vec2(0, 0));
  const SurfaceCurvatures k = At(net, apex);
  EXPECT_NEAR(k.Gauss, Qa * Qc - Qb * Qb, 1e-13);
  EXPECT_NEAR(k.Mean, -(Qa + Qc) / 2, 1e-13);
  Eigen::Matrix2d hessian;
  hessian << Qa, Qb, Qb, Qc;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> hess(hessian);
  EXPECT_NEAR(k.Max, -hess.eigenvalues()[0], 1e-13);
  EXPECT_NEAR(k.Min, -hess.eigenvalues()[1], 1e-13);
  const Eigen::Vector2d e0 = hess.eigenvectors().col(0), e1 = hess.eigenvectors().col(1);
  EXPECT_NEAR(std::abs(k.MaxDirection.dot(Vec3(e0.x(), e0.y(), 0))), 1, 1e-13);
  EXPECT_NEAR(std::abs(k.MinDirection.dot(Vec3(e1.x(), e1.y(), 0))), 1, 1e-13);
  // Fundamental forms in the patch's own (r, s): x_r = (V1 - V0, 0), x_s = (V2 - V0, 0) at the
  // apex, so I = D^T D and II = D^T Hess D with D the domain's edge matrix.
  Eigen::Matrix2d D;
  D << GraphDomain[1] - GraphDomain[0], GraphDomain[2] - GraphDomain[0];
  EXPECT_NEAR((k.First - D.transpose() * D).norm(), 0, 1e-14);
  EXPECT_NEAR((k.Second - D.transpose() * hessian * D).norm(), 0, 1e-13);
}

// A quarter of the cylinder x^2 + y^2 = R^2 as a rational cubic triangle (the rational
// quadratic arc times a linear height): K = 0, H = 1/(2R), principal curvatures 1/R along the
// arc and 0 along the axis, with the outward normal of the patch's orientation.
TEST(SurfaceCurvatures, ExactOnRationalCylinder)
{
  const double R = 2.0, w1 = std::sqrt(0.5);
  const std::array<Vec2, 3> domain = { Vec2(0, 0), Vec2(1, 0), Vec2(0, 1) };
  const Net net = Interpolate(3, domain, true, [=](const Vec2& p) {
    const double s = p.x(), b0 = (1 - s) * (1 - s), b1 = 2 * s * (1 - s), b2 = s * s;
    const double w = b0 + w1 * b1 + b2;
    const double wx = R * (b0 + w1 * b1), wy = R * (w1 * b1 + b2);
    return Eigen::Vector4d(wx, wy, w * p.y(), w);
  });
  std::mt19937 rng(11);
  for (int s = 0; s < 30; ++s)
  {
    const Vec3 t = RandomBarycentric(rng, 0.0);
    const SurfaceCurvatures k = At(net, t);
    const Vec3 x = EvaluateBezierTriangle(3, net.Points.data(), net.W(), t).Value;
    ASSERT_NEAR(std::hypot(x.x(), x.y()), R, 1e-13);
    const Vec3 radial = Vec3(x.x(), x.y(), 0) / R;
    EXPECT_NEAR(k.Gauss, 0, 1e-13);
    EXPECT_NEAR(k.Mean, 1 / (2 * R), 1e-13);
    EXPECT_NEAR(k.Max, 1 / R, 1e-13);
    EXPECT_NEAR(k.Min, 0, 1e-13);
    EXPECT_NEAR((k.Normal - radial).norm(), 0, 1e-13);
    EXPECT_NEAR(std::abs(k.MinDirection.z()), 1, 1e-12);
    EXPECT_NEAR(std::abs(k.MaxDirection.dot(Vec3(-radial.y(), radial.x(), 0))), 1, 1e-12);
  }
}

// The rational quartic sphere octant (unit sphere): umbilic everywhere, K = H = 1, up to its
// corners.
TEST(SurfaceCurvatures, ExactOnRationalSphereOctant)
{
  std::array<Vec3, 15> P;
  std::array<double, 15> w;
  SphereOctantNet(P, w);
  std::vector<Vec3> ts = { Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.5, 0.5, 0),
    Vec3(1, 1, 1) / 3 };
  std::mt19937 rng(2);
  for (int s = 0; s < 20; ++s)
  {
    ts.push_back(RandomBarycentric(rng, 0.0));
  }
  for (const Vec3& t : ts)
  {
    const SurfaceCurvatures k = BezierTriangleCurvatures(4, P.data(), w.data(), t);
    const Vec3 x = EvaluateBezierTriangle(4, P.data(), w.data(), t).Value;
    EXPECT_NEAR(k.Gauss, 1, 1e-12) << t.transpose();
    EXPECT_NEAR(k.Mean, 1, 1e-12) << t.transpose();
    EXPECT_NEAR(k.Max, 1, 1e-12) << t.transpose();
    EXPECT_NEAR(k.Min, 1, 1e-12) << t.transpose();
    EXPECT_NEAR((k.Normal - x).norm(), 0, 1e-12) << t.transpose();
  }
}

// Rigid motions change nothing but the normal and the directions, which move with the surface;
// a scaling by lambda divides the curvatures by lambda (K by lambda^2). Polynomial and rational.
TEST(SurfaceCurvatures, InvariantUnderRigidMotions)
{
  std::array<Vec3, 15> sphere;
  std::array<double, 15> w;
  SphereOctantNet(sphere, w);
  Net octant;
  octant.Degree = 4;
  octant.Points.assign(sphere.begin(), sphere.end());
  octant.Weights.assign(w.begin(), w.end());
  const Eigen::Matrix3d Q =
    Eigen::Quaterniond(Eigen::Vector4d(0.3, -0.5, 0.7, 0.4).normalized()).toRotationMatrix();
  const Vec3 shift(12.5, -3.0, 40.0);
  std::mt19937 rng(3);
  for (const Net& net : { Paraboloid(3), Paraboloid(5), octant })
  {
    for (double scale : { 1.0, 3.0 })
    {
      Net moved = net;
      for (Vec3& p : moved.Points)
      {
        p = scale * (Q * p) + shift;
      }
      // Curvatures do not depend on the position of the net: evaluate from its RelativeNet.
      std::vector<Vec3> relative(moved.Points.size());
      RelativeNet(moved.Degree, moved.Points.data(), relative.data());
      moved.Points = relative;
      for (int s = 0; s < 10; ++s)
      {
        const Vec3 t = RandomBarycentric(rng);
        const SurfaceCurvatures a = At(net, t), b = At(moved, t);
        EXPECT_NEAR(b.Gauss * scale * scale, a.Gauss, 1e-12 * std::abs(a.Gauss) + 1e-13);
        EXPECT_NEAR(b.Mean * scale, a.Mean, 1e-12 * std::abs(a.Mean) + 1e-13);
        EXPECT_NEAR(b.Max * scale, a.Max, 1e-12 * std::abs(a.Max) + 1e-13);
        EXPECT_NEAR(b.Min * scale, a.Min, 1e-12 * std::abs(a.Min) + 1e-13);
        EXPECT_NEAR((b.Normal - Q * a.Normal).norm(), 0, 1e-13);
        if (a.Max - a.Min > 1e-6) // directions are defined away from umbilics
        {
          EXPECT_NEAR(std::abs(b.MaxDirection.dot(Q * a.MaxDirection)), 1, 1e-12);
          EXPECT_NEAR(std::abs(b.MinDirection.dot(Q * a.MinDirection)), 1, 1e-12);
        }
      }
    }
  }
}

// The same surface over a sub-triangle (an affine map of the barycentric domain): equal
// curvatures, fundamental forms transformed by the Jacobian J of (r, s) with respect to the new
// parameters, I' = J^T I J and II' = J^T II J. A reversed orientation flips the normal and the
// signs of H and the principal curvatures (Max' = -Min).
TEST(SurfaceCurvatures, InvariantUnderAffineReparametrisation)
{
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> U(-0.2, 0.2);
  for (int n : { 2, 3, 6 })
  {
    Net net = Paraboloid(n);
    for (Vec3& p : net.Points)
    {
      p += Vec3(U(rng), U(rng), U(rng)); // a general (non-quadric) polynomial patch
    }
    // Sub-triangle corners in barycentric coordinates; the second set reverses the orientation,
    // the third reaches outside the domain (the polynomial's extension).
    const std::array<std::array<Vec3, 3>, 3> corners = { {
      { Vec3(0.7, 0.2, 0.1), Vec3(0.1, 0.8, 0.1), Vec3(0.2, 0.1, 0.7) },
      { Vec3(0.7, 0.2, 0.1), Vec3(0.2, 0.1, 0.7), Vec3(0.1, 0.8, 0.1) },
      { Vec3(1.2, -0.1, -0.1), Vec3(-0.1, 1.2, -0.1), Vec3(-0.1, -0.1, 1.2) },
    } };
    for (const auto& c : corners)
    {
      Net sub = net;
      SubTriangle(n, net.Points.data(), c[0], c[1], c[2], sub.Points.data());
      Eigen::Matrix2d J;
      J << c[1][1] - c[0][1], c[2][1] - c[0][1], c[1][2] - c[0][2], c[2][2] - c[0][2];
      const double orientation = J.determinant() > 0 ? 1 : -1;
      for (int s = 0; s < 10; ++s)
      {
        const Vec3 tSub = RandomBarycentric(rng);
        const Vec3 t = tSub[0] * c[0] + tSub[1] * c[1] + tSub[2] * c[2];
        const SurfaceCurvatures a = At(net, t), b = At(sub, tSub);
        EXPECT_NEAR(b.Gauss, a.Gauss, 1e-11) << "n " << n;
        EXPECT_NEAR(b.Mean, orientation * a.Mean, 1e-11) << "n " << n;
        EXPECT_NEAR(b.Max, orientation > 0 ? a.Max : -a.Min, 1e-11) << "n " << n;
        EXPECT_NEAR(b.Min, orientation > 0 ? a.Min : -a.Max, 1e-11) << "n " << n;
        EXPECT_NEAR((b.Normal - orientation * a.Normal).norm(), 0, 1e-12);
        EXPECT_NEAR((b.First - J.transpose() * a.First * J).norm(), 0, 1e-12);
        EXPECT_NEAR((b.Second - orientation * J.transpose() * a.Second * J).norm(), 0, 1e-11);
      }
    }
  }
}

// A collapsed corner (its first edge ordinate on the corner: x_r = 0 there) gives the limit
// from inside: finite, flagged, equal to the values just inside; regular points are not moved.
TEST(SurfaceCurvatures, SingularCornerGivesLimitFromInside)
{
  Net net = Paraboloid(3);
  net.Points[BezierIndex(3, 2, 1)] = net.Points[BezierIndex(3, 3, 0)];
  const Vec3 corner(1, 0, 0);
  const ParametricJet j = EvaluateOverDomain(
    3, net.Points.data(), nullptr, Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), corner, 2);
  ASSERT_TRUE(IsSingularTangentPlane(j.Du, j.Dv));
  const SurfaceCurvatures k = At(net, corner);
  EXPECT_TRUE(k.Limit);
  for (double v : { k.Gauss, k.Mean, k.Max, k.Min, k.Normal.norm(), k.MaxDirection.norm() })
  {
    EXPECT_TRUE(std::isfinite(v));
  }
  EXPECT_NEAR(k.Normal.norm(), 1, 1e-12);
  const SurfaceCurvatures inside = At(net, NudgeInside(corner));
  EXPECT_FALSE(inside.Limit);
  EXPECT_EQ(k.Gauss, inside.Gauss);
  EXPECT_EQ(k.Mean, inside.Mean);
  EXPECT_EQ(k.Normal, inside.Normal);
  EXPECT_NEAR((k.Normal - PatchNormal(3, net.Points.data(), nullptr, corner)).norm(), 0, 1e-15);
  // The other corners are regular.
  EXPECT_FALSE(At(net, Vec3(0, 1, 0)).Limit);
  EXPECT_FALSE(At(net, Vec3(0, 0, 1)).Limit);
}
