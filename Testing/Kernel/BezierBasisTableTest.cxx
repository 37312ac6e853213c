// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierBasisTable.h"

#include <gtest/gtest.h>

#include <algorithm>
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
  std::uniform_real_distribution<double> U(0.0);
  for (int s = 0; s < 20; ++s)
  {
    const double a = U(rng);
    const double b = U(rng);
    const double c = U(rng);
    t.push_back(Vec3(a, b, c) / (a + b + c));
  }
  return t;
}

// Equality to round-off (the batched derivative sums group the terms differently): a few
// hundred ulps for degree 10 nets of well-conditioned patches.
void ExpectClose(const Vec3& a, const Vec3& b)
{
  EXPECT_LE((a - b).norm(), 1e-12) << a.transpose() << " vs " << b.transpose();
}

void ExpectSame(const Vec3& a, const Vec3& b)
{
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(a[k], b[k]);
  }
}

// Positions, normals and weight sums of the table's points [begin, end) at once.
void Evaluate(const BezierBasisTable& table, const ScalarNet& net, int begin, int end,
  std::vector<Vec3>& x, std::vector<Vec3>& normal, std::vector<double>& W)
{
  BezierBasisTable::BlockArray xb[3], nb[3];
  double wb[BezierBasisTable::Block];
  table.Evaluate(net, begin, end, xb, nb, wb);
  for (int q = 0; q < end - begin; ++q)
  {
    x.emplace_back(xb[0][q], xb[1][q], xb[2][q]);
    normal.emplace_back(nb[0][q], nb[1][q], nb[2][q]);
    W.push_back(wb[q]);
  }
}
} // namespace

TEST(BezierBasisTable, BatchedEvaluationMatchesPointwiseToRoundOff)
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
      ScalarNet net;
      net.Load(n, P.data(), wp);
      // Blocks of every size up to Block, as the tessellator's runs of owned points.
      std::vector<Vec3> x, normal;
      std::vector<double> sums;
      for (int begin = 0, size = 1; begin < table.NumberOfPoints(); begin += size, ++size)
      {
        size = std::min(size, BezierBasisTable::Block);
        Evaluate(table, net, begin, std::min(begin + size, table.NumberOfPoints()), x, normal, sums);
      }
      for (int p = 0; p < table.NumberOfPoints(); ++p)
      {
        ExpectSame(x[p], EvaluateBezierTriangle(n, P.data(), wp, t[p]).Value);
        ExpectClose(normal[p], PatchNormal(n, R.data(), wp, t[p]));
        std::vector<double> B(P.size());
        Bernstein(n, t[p], B.data());
        double sum = 0;
        for (size_t i = 0; i < P.size(); ++i)
        {
          sum += B[i] * (rational ? w[i] : 1.0);
        }
        EXPECT_EQ(sums[p], sum);
      }
      if (rational)
      {
        continue;
      }
      // Data ordinates: Combine over the denominators is the polynomial's value, to the bit.
      BezierBasisTable::BlockArray v[2];
      std::vector<double> f(2 * MaxBezierPoints);
      for (size_t i = 0; i < P.size(); ++i)
      {
        f[i] = P[i].y();
        f[MaxBezierPoints + i] = P[i].z();
      }
      table.Combine(f.data(), 2, 0, std::min(table.NumberOfPoints(), 64), v);
      for (int p = 0; p < std::min(table.NumberOfPoints(), 64); ++p)
      {
        const Vec3 value = EvaluateBezierTriangle(n, P.data(), nullptr, t[p]).Value;
        EXPECT_EQ(v[0][p] / sums[p], value.y());
        EXPECT_EQ(v[1][p] / sums[p], value.z());
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
  ScalarNet net;
  net.Load(3, P.data(), nullptr);
  const BezierBasisTable table(3, { Vec3(0.5, 0.5, 0), Vec3(1, 0, 0) });
  std::vector<Vec3> x, normal;
  std::vector<double> W;
  Evaluate(table, net, 0, 2, x, normal, W);
  EXPECT_NEAR(normal[1].norm(), 1.0, 1e-12);
  ExpectClose(normal[1], PatchNormal(3, net.R, nullptr, Vec3(1, 0, 0)));
  ExpectClose(normal[0], PatchNormal(3, net.R, nullptr, Vec3(0.5, 0.5, 0)));
}
