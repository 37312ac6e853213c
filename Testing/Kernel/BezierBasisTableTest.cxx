// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierBasisTable.h"

#include <gtest/gtest.h>

#include <random>

using namespace ctk;

namespace
{
// A level-L lattice (corners and edges included) plus random inner points.
std::vector<Vec3> TablePoints(int L, std::mt19937& rng)
{
  std::vector<Vec3> t;
  for (int i = 0; i <= L; ++i)
  {
    for (int j = 0; i + j <= L; ++j)
    {
      t.emplace_back(double(L - i - j) / L, double(i) / L, double(j) / L);
    }
  }
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int s = 0; s < 20; ++s)
  {
    const double a = U(rng);
    const double b = U(rng);
    const double c = U(rng);
    t.push_back(Vec3(a, b, c) / (a + b + c));
  }
  return t;
}

// Bitwise equality: the table must give the very doubles of the pointwise evaluation.
void ExpectSame(const Vec3& a, const Vec3& b)
{
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(a[k], b[k]);
  }
}
} // namespace

TEST(BezierBasisTable, SameDoublesAsPointwiseEvaluation)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0), W(0.5, 2.0);
  for (int n = 1; n <= MaxDegree; ++n)
  {
    const std::vector<Vec3> t = TablePoints(8, rng);
    const BezierBasisTable table(n, t);
    ASSERT_EQ(table.NumberOfPoints(), static_cast<int>(t.size()));
    for (const bool rational : { false, true })
    {
      std::vector<Vec3> P(BezierPointCount(n)), R(P.size());
      std::vector<double> w(P.size());
      for (size_t i = 0; i < P.size(); ++i)
      {
        const double x = U(rng), y = U(rng), z = U(rng);
        P[i] = Vec3(1e3 + x, y, z); // far from the origin: the relative net matters
        w[i] = W(rng);
      }
      const double* wp = rational ? w.data() : nullptr;
      RelativeNet(n, P.data(), R.data());
      std::vector<Eigen::Vector4d> H(P.size()), HR(P.size());
      HomogeneousNet(n, P.data(), wp, H.data());
      HomogeneousNet(n, R.data(), wp, HR.data());
      for (int p = 0; p < table.NumberOfPoints(); ++p)
      {
        ExpectSame(table.Value(H.data(), p), EvaluateBezierTriangle(n, P.data(), wp, t[p]).Value);
        ExpectSame(table.Normal(HR.data(), R.data(), wp, p), PatchNormal(n, R.data(), wp, t[p]));
      }
    }
  }
}

TEST(BezierBasisTable, SingularCornerTakesTheLimitFromInside)
{
  // A cubic net whose corner 0 row collapses: no tangent plane at corner 0.
  std::vector<Vec3> P(BezierPointCount(3));
  for (const auto& e : BezierExponents(3))
  {
    const double u = (e[1] + e[2]) / 3.0, v = e[2] / 3.0;
    P[BezierIndex(3, e[0], e[1])] = Vec3(u * std::cos(v), u * std::sin(v), u * u);
  }
  P[BezierIndex(3, 2, 1)] = P[BezierIndex(3, 3, 0)];
  P[BezierIndex(3, 2, 0)] = P[BezierIndex(3, 3, 0)];
  std::vector<Eigen::Vector4d> H(P.size());
  HomogeneousNet(3, P.data(), nullptr, H.data());
  const BezierBasisTable table(3, { Vec3(1, 0, 0) });
  const Vec3 normal = table.Normal(H.data(), P.data(), nullptr, 0);
  EXPECT_NEAR(normal.norm(), 1.0, 1e-12);
  ExpectSame(normal, PatchNormal(3, P.data(), nullptr, Vec3(1, 0, 0)));
}
