// SPDX-License-Identifier: GPL-3.0-or-later
// Study Fig. 10: the sphere octant (rational quartic patch) interpolated on the refined
// equilateral domain, levels 1..5; the error is the distance to the unit sphere, |‖p‖ - 1|, at
// dense samples. Observed orders log2(e_l / e_{l+1}) approach 3 for CTo, FO, Ka (limited by the
// boundary) and 4 for MGo and KaG (mid-edge gradients).
#include "SplineMeasures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace
{
using namespace ctk_test;

// Largest |‖p‖ - 1| at the points (i, j, k)/n of every macro-triangle.
double SphereError(const SampledMesh& mesh, const CubicSpline& spline, int n)
{
  double err = 0.0;
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    for (int i = 0; i <= n; ++i)
    {
      for (int j = 0; i + j <= n; ++j)
      {
        const double b0 = double(i) / n, b1 = double(j) / n, b2 = 1.0 - b0 - b1;
        const Vec2 X = b0 * VertexUV(mesh, t, 0) + b1 * VertexUV(mesh, t, 1) + b2 * VertexUV(mesh, t, 2);
        err = std::max(err, std::abs(EvaluateSpline(mesh, spline, t, X, 0).Value.norm() - 1.0));
      }
    }
  }
  return err;
}

std::vector<double> Errors(Construction c)
{
  const std::array<Vec2, 3> A = SphereOctantDomain();
  std::vector<double> errors;
  for (int level = 1; level <= 5; ++level)
  {
    const SampledMesh mesh = Sample("octant", RefinedTriangleMesh(A[0], A[1], A[2], level),
      AnalyticSurface::SphereOctant);
    SplineOptions o;
    o.Method = c;
    errors.push_back(SphereError(mesh, BuildOrFail(mesh, o), 9));
  }
  return errors;
}

void ExpectOrder(Construction c, double lastOrderAbove)
{
  const std::vector<double> e = Errors(c);
  std::string line = std::string(ToString(c)) + ":";
  for (size_t l = 0; l + 1 < e.size(); ++l)
  {
    char buf[64];
    std::snprintf(buf, sizeof buf, " %.3e (%.2f)", e[l], std::log2(e[l] / e[l + 1]));
    line += buf;
  }
  std::printf("%s %.3e\n", line.c_str(), e.back());
  for (size_t l = 0; l + 1 < e.size(); ++l)
  {
    EXPECT_LT(e[l + 1], e[l]) << line;
  }
  EXPECT_GT(std::log2(e[e.size() - 2] / e.back()), lastOrderAbove) << line;
}
} // namespace

TEST(SphereOctantConvergence, CToIsThirdOrder)
{
  ExpectOrder(Construction::CTo, 2.8);
}

TEST(SphereOctantConvergence, FOIsThirdOrder)
{
  ExpectOrder(Construction::FO, 2.8);
}

TEST(SphereOctantConvergence, KaIsThirdOrder)
{
  ExpectOrder(Construction::Ka, 2.8);
}

TEST(SphereOctantConvergence, MGoIsFourthOrder)
{
  ExpectOrder(Construction::MGo, 3.7);
}

TEST(SphereOctantConvergence, KaGIsFourthOrder)
{
  ExpectOrder(Construction::KaG, 3.7);
}
