// SPDX-License-Identifier: GPL-3.0-or-later
#include "AnalyticSurfaces.h"

#include <gtest/gtest.h>

#include <random>

using namespace ctk;

TEST(AnalyticSurfaces, SphereOctantLiesOnTheUnitSphere)
{
  const std::array<Vec2, 3> A = SphereOctantDomain();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int s = 0; s < 500; ++s)
  {
    Vec3 t(U(rng), U(rng), U(rng));
    t /= t.sum();
    const Vec2 X = t[0] * A[0] + t[1] * A[1] + t[2] * A[2];
    const SurfacePoint p = EvaluateAnalyticSurface(AnalyticSurface::SphereOctant, X.x(), X.y());
    EXPECT_NEAR(p.F.norm(), 1.0, 1e-14);
    // Tangent vectors are orthogonal to the radius.
    EXPECT_NEAR(p.F.dot(p.Fu), 0.0, 1e-13);
    EXPECT_NEAR(p.F.dot(p.Fv), 0.0, 1e-13);
    EXPECT_GE(p.F.minCoeff(), -1e-15);
  }
  const Vec3 corners[3] = { Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  for (int i = 0; i < 3; ++i)
  {
    const SurfacePoint p = EvaluateAnalyticSurface(AnalyticSurface::SphereOctant, A[i].x(), A[i].y());
    EXPECT_NEAR((p.F - corners[i]).norm(), 0.0, 1e-15);
  }
}

TEST(AnalyticSurfaces, DerivativesMatchFiniteDifferences)
{
  for (AnalyticSurface s : { AnalyticSurface::Plane, AnalyticSurface::Quadratic,
         AnalyticSurface::FarinCubic, AnalyticSurface::Franke, AnalyticSurface::SineWave,
         AnalyticSurface::SphereOctant })
  {
    for (const Vec2 X : { Vec2(0.3, 0.2), Vec2(0.55, 0.41), Vec2(0.71, 0.12) })
    {
      const double h = 1e-6;
      const SurfacePoint p = EvaluateAnalyticSurface(s, X.x(), X.y());
      const Vec3 du = (EvaluateAnalyticSurface(s, X.x() + h, X.y()).F -
                        EvaluateAnalyticSurface(s, X.x() - h, X.y()).F) /
        (2 * h);
      const Vec3 dv = (EvaluateAnalyticSurface(s, X.x(), X.y() + h).F -
                        EvaluateAnalyticSurface(s, X.x(), X.y() - h).F) /
        (2 * h);
      EXPECT_NEAR((p.Fu - du).norm(), 0.0, 1e-7) << ToString(s);
      EXPECT_NEAR((p.Fv - dv).norm(), 0.0, 1e-7) << ToString(s);
    }
  }
}

TEST(AnalyticSurfaces, RefinedTriangleMeshCounts)
{
  const std::array<Vec2, 3> A = SphereOctantDomain();
  for (int l = 0; l <= 5; ++l)
  {
    const ParameterMesh m = RefinedTriangleMesh(A[0], A[1], A[2], l);
    EXPECT_EQ(m.NumberOfTriangles(), Id(1) << (2 * l));
    double area = 0.0;
    for (Id t = 0; t < m.NumberOfTriangles(); ++t)
    {
      const double a = SignedArea2(m.UV[m.Triangles[3 * t]], m.UV[m.Triangles[3 * t + 1]],
        m.UV[m.Triangles[3 * t + 2]]);
      EXPECT_GT(a, 0.0);
      area += a;
    }
    EXPECT_NEAR(area, SignedArea2(A[0], A[1], A[2]), 1e-12);
  }
}
