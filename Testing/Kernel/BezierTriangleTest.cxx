// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierTriangle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace ctk;

namespace
{
std::vector<Vec3> RandomNet(int n, std::mt19937& rng)
{
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<Vec3> P(BezierPointCount(n));
  for (Vec3& p : P)
  {
    p = Vec3(U(rng), U(rng), U(rng));
  }
  return P;
}

Vec3 RandomBarycentric(std::mt19937& rng, double lo = 0.0)
{
  std::uniform_real_distribution<double> U(lo, 1.0);
  Vec3 t(U(rng), U(rng), U(rng));
  return t / t.sum();
}
} // namespace

TEST(BezierTriangle, ConstantAndLinearPrecision)
{
  for (int n = 1; n <= 6; ++n)
  {
    // Control points at the domain points reproduce the (affine) domain map exactly.
    const Vec2 A[3] = { Vec2(0.2, -0.1), Vec2(1.3, 0.4), Vec2(0.1, 0.9) };
    std::vector<Vec3> P;
    for (const auto& e : BezierExponents(n))
    {
      const Vec2 d = (e[0] * A[0] + e[1] * A[1] + e[2] * A[2]) / n;
      P.emplace_back(d.x(), d.y(), 2.0);
    }
    std::mt19937 rng(n);
    for (int s = 0; s < 20; ++s)
    {
      const Vec3 t = RandomBarycentric(rng);
      const Vec2 X = t[0] * A[0] + t[1] * A[1] + t[2] * A[2];
      const ParametricJet j = EvaluateOverDomain(n, P.data(), nullptr, A[0], A[1], A[2], t, 2);
      EXPECT_NEAR((j.Value - Vec3(X.x(), X.y(), 2.0)).norm(), 0.0, 1e-14);
      EXPECT_NEAR((j.Du - Vec3(1, 0, 0)).norm(), 0.0, 1e-13);
      EXPECT_NEAR((j.Dv - Vec3(0, 1, 0)).norm(), 0.0, 1e-13);
      EXPECT_NEAR(j.Duu.norm() + j.Duv.norm() + j.Dvv.norm(), 0.0, 1e-12);
    }
  }
}

TEST(BezierTriangle, EvaluationIsDiagonalBlossom)
{
  std::mt19937 rng(3);
  for (int n = 1; n <= MaxDegree; ++n)
  {
    const std::vector<Vec3> P = RandomNet(n, rng);
    const Vec3 t = RandomBarycentric(rng, -0.3);
    std::vector<Vec3> args(n, t);
    const Vec3 a = EvaluateBezierTriangle(n, P.data(), nullptr, t).Value;
    EXPECT_NEAR((a - Blossom(n, P.data(), args.data())).norm(), 0.0, 1e-12) << "degree " << n;
  }
}

TEST(BezierTriangle, DerivativesMatchFiniteDifferences)
{
  std::mt19937 rng(5);
  const Vec2 A[3] = { Vec2(0.0, 0.0), Vec2(2.0, 0.3), Vec2(0.4, 1.5) };
  for (int n = 1; n <= 5; ++n)
  {
    for (int rational = 0; rational < 2; ++rational)
    {
      const std::vector<Vec3> P = RandomNet(n, rng);
      std::vector<double> w(P.size());
      std::uniform_real_distribution<double> W(0.5, 2.0);
      for (double& x : w)
      {
        x = W(rng);
      }
      const double* wp = rational ? w.data() : nullptr;
      const Vec3 t = RandomBarycentric(rng, 0.1);
      const Vec2 X = t[0] * A[0] + t[1] * A[1] + t[2] * A[2];
      auto at = [&](const Vec2& Y) {
        return EvaluateOverDomain(n, P.data(), wp, A[0], A[1], A[2], Barycentric(A[0], A[1], A[2], Y), 2);
      };
      const ParametricJet j = at(X);
      const double h = 1e-5;
      const ParametricJet ju = at(X + Vec2(h, 0)), jum = at(X - Vec2(h, 0));
      const ParametricJet jv = at(X + Vec2(0, h)), jvm = at(X - Vec2(0, h));
      EXPECT_NEAR((j.Du - (ju.Value - jum.Value) / (2 * h)).norm(), 0.0, 1e-7);
      EXPECT_NEAR((j.Dv - (jv.Value - jvm.Value) / (2 * h)).norm(), 0.0, 1e-7);
      EXPECT_NEAR((j.Duu - (ju.Du - jum.Du) / (2 * h)).norm(), 0.0, 1e-6);
      EXPECT_NEAR((j.Duv - (jv.Du - jvm.Du) / (2 * h)).norm(), 0.0, 1e-6);
      EXPECT_NEAR((j.Dvv - (jv.Dv - jvm.Dv) / (2 * h)).norm(), 0.0, 1e-6);
    }
  }
}

TEST(BezierTriangle, SubTriangleReproducesThePolynomial)
{
  std::mt19937 rng(11);
  for (int n = 1; n <= 6; ++n)
  {
    const std::vector<Vec3> P = RandomNet(n, rng);
    const Vec3 c0 = RandomBarycentric(rng), c1 = RandomBarycentric(rng), c2(0.2, -0.4, 1.2);
    std::vector<Vec3> Q(P.size());
    SubTriangle(n, P.data(), c0, c1, c2, Q.data());
    for (int s = 0; s < 10; ++s)
    {
      const Vec3 b = RandomBarycentric(rng);
      const Vec3 t = b[0] * c0 + b[1] * c1 + b[2] * c2;
      EXPECT_NEAR((EvaluateBezierTriangle(n, Q.data(), nullptr, b).Value -
                    EvaluateBezierTriangle(n, P.data(), nullptr, t).Value)
                    .norm(),
        0.0, 1e-12);
    }
  }
}

TEST(BezierTriangle, DegreeElevationKeepsThePolynomial)
{
  std::mt19937 rng(13);
  for (int n = 1; n < MaxDegree; ++n)
  {
    const std::vector<Vec3> P = RandomNet(n, rng);
    std::vector<Vec3> Q(BezierPointCount(n + 1));
    ElevateDegree(n, P.data(), Q.data());
    for (int s = 0; s < 10; ++s)
    {
      const Vec3 t = RandomBarycentric(rng);
      EXPECT_NEAR((EvaluateBezierTriangle(n + 1, Q.data(), nullptr, t).Value -
                    EvaluateBezierTriangle(n, P.data(), nullptr, t).Value)
                    .norm(),
        0.0, 1e-12);
    }
  }
}

TEST(BezierTriangle, VtkOrderIsAPermutationWithCornersAndEdgesFirst)
{
  for (int n = 1; n <= MaxDegree; ++n)
  {
    std::vector<int> order = VtkBezierTriangleOrder(n);
    ASSERT_EQ(static_cast<int>(order.size()), BezierPointCount(n));
    const auto exps = BezierExponents(n);
    EXPECT_EQ(exps[order[0]][0], n);
    EXPECT_EQ(exps[order[1]][1], n);
    EXPECT_EQ(exps[order[2]][2], n);
    for (int s = 1; s < n; ++s)
    {
      // Edge 0 -> 1 runs from vertex 0 to vertex 1.
      EXPECT_EQ(exps[order[2 + s]][1], s);
      EXPECT_EQ(exps[order[2 + s]][2], 0);
    }
    std::sort(order.begin(), order.end());
    for (int a = 0; a < BezierPointCount(n); ++a)
    {
      EXPECT_EQ(order[a], a);
    }
  }
}

// The compile-time order (the spline filter's cells of degree 3 and 4) is the run-time one; its
// last cubic point is the centre, exponents (1, 1, 1), as VTK numbers it.
TEST(BezierTriangle, CompileTimeVtkOrderIsTheRunTimeOne)
{
  static_assert(VtkBezierTriangleOrderOf<3>()[9] == BezierIndex(3, 1, 1), "cubic centre last");
  const auto cubic = VtkBezierTriangleOrderOf<3>();
  const auto quartic = VtkBezierTriangleOrderOf<4>();
  EXPECT_EQ(std::vector<int>(cubic.begin(), cubic.end()), VtkBezierTriangleOrder(3));
  EXPECT_EQ(std::vector<int>(quartic.begin(), quartic.end()), VtkBezierTriangleOrder(4));
}

TEST(BezierTriangle, BarycentricGradientIsExact)
{
  const Vec2 A0(0.1, 0.2), A1(1.5, -0.3), A2(0.7, 1.1);
  const Eigen::Matrix<double, 3, 2> G = BarycentricGradient(A0, A1, A2);
  const Vec2 X(0.4, 0.3), d(0.3, -0.7);
  const Vec3 diff = Barycentric(A0, A1, A2, X + d) - Barycentric(A0, A1, A2, X);
  EXPECT_NEAR((G * d - diff).norm(), 0.0, 1e-14);
}

// A polynomial net (weights nullptr, evaluated without homogeneous points) gives the bits of the
// same net with all weights 1 (the homogeneous evaluation), at every degree and order: the
// probe's and the tessellator's results do not depend on which a source spells.
TEST(BezierTriangle, PolynomialNetHasTheBitsOfUnitWeights)
{
  std::mt19937 rng(11);
  const Vec2 A[3] = { Vec2(0.2, -0.1), Vec2(1.3, 0.4), Vec2(0.1, 0.9) };
  for (int n = 0; n <= MaxDegree; ++n)
  {
    const std::vector<Vec3> P = RandomNet(n, rng);
    const std::vector<double> ones(P.size(), 1.0);
    for (int s = 0; s < 20; ++s)
    {
      const Vec3 t = RandomBarycentric(rng, -0.2);
      for (int order = 0; order <= 2; ++order)
      {
        const BezierJet a = EvaluateBezierTriangle(n, P.data(), nullptr, t, order);
        const BezierJet b = EvaluateBezierTriangle(n, P.data(), ones.data(), t, order);
        ASSERT_EQ(a.Value, b.Value) << "degree " << n << " order " << order;
        for (int k = 0; k < 3; ++k)
        {
          ASSERT_EQ(a.DT[k], b.DT[k]) << "degree " << n << " order " << order;
        }
        for (int k = 0; k < 6; ++k)
        {
          ASSERT_EQ(a.DTT[k], b.DTT[k]) << "degree " << n << " order " << order;
        }
        const ParametricJet x = EvaluateOverDomain(n, P.data(), nullptr, A[0], A[1], A[2], t, order);
        const ParametricJet y =
          EvaluateOverDomain(n, P.data(), ones.data(), A[0], A[1], A[2], t, order);
        ASSERT_EQ(x.Value, y.Value);
        ASSERT_EQ(x.Du, y.Du);
        ASSERT_EQ(x.Dvv, y.Dvv);
      }
    }
  }
}
