// SPDX-License-Identifier: GPL-3.0-or-later
// Facts of the study, measured on the kernel's output: precision, interpolation, C0/C1 across every
// micro- and macro-edge (Rule A), invariance to affine reparameterisation.
#include "CubicCloughTocher.h"
#include "RuleA.h"
#include "SplineMeasures.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <random>

using namespace ctk;
using namespace ctk_test;

namespace
{
struct Variant
{
  Construction Method;
  BoundaryMode Boundary;
};

const Variant LocalAndSplitLineVariants[] = {
  { Construction::CTo, BoundaryMode::Perpendicular },
  { Construction::CTi, BoundaryMode::Perpendicular },
  { Construction::CTi, BoundaryMode::Midpoint },
  { Construction::CTi, BoundaryMode::GradientPerpendicular },
  { Construction::CTi, BoundaryMode::GradientToSplitPoint },
  { Construction::MGo, BoundaryMode::Perpendicular },
  { Construction::MGi, BoundaryMode::Midpoint },
  { Construction::MGi, BoundaryMode::GradientPerpendicular },
  { Construction::MGi, BoundaryMode::GradientToSplitPoint },
};

const SplitPointRule AllSplitPoints[] = { SplitPointRule::Bary, SplitPointRule::Inc2,
  SplitPointRule::Inc3 };

} // namespace

TEST(CubicCloughTocher, QuadraticPrecisionForEveryVariant)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    for (AnalyticSurface s : { AnalyticSurface::Plane, AnalyticSurface::Quadratic })
    {
      const SampledMesh mesh = Sample(name, pm, s);
      for (const Variant& v : LocalAndSplitLineVariants)
      {
        for (SplitPointRule sp : AllSplitPoints)
        {
          const SplineOptions o{ v.Method, sp, v.Boundary, 0 };
          EXPECT_LT(MaxError(mesh, BuildOrFail(mesh, o), s, false), 1e-13) << Describe(mesh, o);
        }
      }
    }
  }
}

TEST(CubicCloughTocher, MidEdgeGradientsGiveCubicPrecision)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::FarinCubic);
    for (const Variant& v : LocalAndSplitLineVariants)
    {
      // MGi uses the boundary mid-edge gradients whatever the boundary mode.
      const bool everywhere = v.Method == Construction::MGo || v.Method == Construction::MGi;
      for (SplitPointRule sp : AllSplitPoints)
      {
        const SplineOptions o{ v.Method, sp, v.Boundary, 0 };
        const double err = MaxError(mesh, BuildOrFail(mesh, o), AnalyticSurface::FarinCubic, false);
        if (everywhere)
        {
          EXPECT_LT(err, 1e-13) << Describe(mesh, o);
        }
        else
        {
          // Quadratic precision only: the cubic is visibly not reproduced.
          EXPECT_GT(err, 1e-10) << Describe(mesh, o);
        }
      }
    }
  }
}

TEST(CubicCloughTocher, InterpolatesPositionsAndGradients)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::Franke);
    for (const Variant& v : LocalAndSplitLineVariants)
    {
      const SplineOptions o{ v.Method, SplitPointRule::Inc3, v.Boundary, 0 };
      const CubicSpline spline = BuildOrFail(mesh, o);
      for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
      {
        for (int i = 0; i < 3; ++i)
        {
          const Id p = mesh.Triangles[3 * t + i];
          const Vec2 U(mesh.UV[2 * p], mesh.UV[2 * p + 1]);
          const ParametricJet j = EvaluateSpline(mesh, spline, t, U, 1);
          const double scale = 1.0 + Vec3(&mesh.F[3 * p]).norm();
          ASSERT_LT((j.Value - Vec3(&mesh.F[3 * p])).norm(), 1e-14 * scale) << Describe(mesh, o);
          ASSERT_LT((j.Du - Vec3(&mesh.Fu[3 * p])).norm(), 1e-12 * scale) << Describe(mesh, o);
          ASSERT_LT((j.Dv - Vec3(&mesh.Fv[3 * p])).norm(), 1e-12 * scale) << Describe(mesh, o);
        }
      }
    }
  }
}

TEST(CubicCloughTocher, C1AcrossEveryMicroAndMacroEdge)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    for (AnalyticSurface s : { AnalyticSurface::Franke, AnalyticSurface::SineWave })
    {
      const SampledMesh mesh = Sample(name, pm, s);
      for (const Variant& v : LocalAndSplitLineVariants)
      {
        for (SplitPointRule sp : AllSplitPoints)
        {
          ExpectC1ButNotC2(mesh, { v.Method, sp, v.Boundary, 0 });
        }
      }
    }
  }
}

TEST(CubicCloughTocher, AffineInvarianceOfCTiAndMGi)
{
  const ParameterMesh pm = JitteredGrid(5, 0.3, 23u);
  Affine affine;
  affine.A << 2.0, 0.7, -0.3, 0.5;
  affine.t = Vec2(0.3, -1.0);
  const SampledMesh a = Sample("jittered", pm, AnalyticSurface::Franke);
  const SampledMesh b = Sample("jittered-affine", pm, AnalyticSurface::Franke, affine);

  struct Case
  {
    SplineOptions Options;
    bool Invariant;
  };
  const Case cases[] = {
    { { Construction::CTi, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 }, true },
    { { Construction::CTi, SplitPointRule::Inc3, BoundaryMode::Midpoint, 0 }, true },
    { { Construction::MGi, SplitPointRule::Bary, BoundaryMode::GradientToSplitPoint, 0 }, true },
    { { Construction::MGi, SplitPointRule::Inc3, BoundaryMode::Midpoint, 0 }, true },
    { { Construction::CTi, SplitPointRule::Inc2, BoundaryMode::Midpoint, 0 }, false },
    { { Construction::CTi, SplitPointRule::Bary, BoundaryMode::Perpendicular, 0 }, false },
    { { Construction::CTo, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 }, false },
    { { Construction::MGo, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 }, false },
  };
  for (const Case& c : cases)
  {
    const double dev = MaxDeviation(a, BuildOrFail(a, c.Options), b, BuildOrFail(b, c.Options), affine);
    if (c.Invariant)
    {
      EXPECT_LT(dev, 1e-12) << Describe(a, c.Options);
    }
    else
    {
      EXPECT_GT(dev, 1e-4) << Describe(a, c.Options);
    }
  }
}

TEST(CubicCloughTocher, ResultDoesNotDependOnHowWorkIsSplit)
{
  const SampledMesh mesh = Sample("jittered", JitteredGrid(6, 0.3, 5u), AnalyticSurface::Franke);
  const SplineOptions o{ Construction::MGi, SplitPointRule::Inc3, BoundaryMode::GradientToSplitPoint, 0 };
  const CubicSpline serial = BuildOrFail(mesh, o);
  CubicSpline chunked;
  auto chunks = [](Id n, const std::function<void(Id, Id)>& body) {
    for (Id b = n; b > 0; b -= 3)
    {
      body(std::max<Id>(0, b - 3), b); // back to front, in chunks of three
    }
  };
  ASSERT_TRUE(BuildCubicCloughTocher(mesh.Data(), mesh.Topology, o, chunked, chunks).Ok);
  ASSERT_EQ(serial.ControlPoints.size(), chunked.ControlPoints.size());
  for (size_t p = 0; p < serial.ControlPoints.size(); ++p)
  {
    ASSERT_EQ(serial.ControlPoints[p], chunked.ControlPoints[p]) << p;
  }
}

TEST(CubicCloughTocher, ReportsWhatItCannotDo)
{
  const SampledMesh mesh = Sample("grid", RegularGridMesh(2, GridDiagonal::Forward), AnalyticSurface::Plane);
  CubicSpline spline;
  SplineData data = mesh.Data();
  data.EdgeGradients = nullptr;
  SplineOptions o{ Construction::MGi, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 };
  BuildStatus st = BuildCubicCloughTocher(data, mesh.Topology, o, spline);
  EXPECT_FALSE(st.Ok);
  EXPECT_NE(st.Message.find("mid-edge gradients"), std::string::npos) << st.Message;
  o.Method = Construction::CTi;
  o.Boundary = BoundaryMode::GradientToSplitPoint;
  EXPECT_FALSE(BuildCubicCloughTocher(data, mesh.Topology, o, spline).Ok);
  o.Boundary = BoundaryMode::Midpoint;
  EXPECT_TRUE(BuildCubicCloughTocher(data, mesh.Topology, o, spline).Ok);
}
