// SPDX-License-Identifier: GPL-3.0-or-later
// Facts of the study, measured on the kernel's output: precision, interpolation, C0/C1 across every
// micro- and macro-edge (Rule A), invariance to affine reparameterisation.
#include "CubicCloughTocher.h"
#include "RuleA.h"
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

CubicSpline Build(const SampledMesh& mesh, const SplineOptions& o)
{
  CubicSpline spline;
  const BuildStatus st = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, o, spline);
  EXPECT_TRUE(st.Ok) << st.Message;
  return spline;
}

std::string Describe(const SampledMesh& m, const SplineOptions& o)
{
  return m.Name + " " + ToString(o.Method) + "/" + ToString(o.SplitPoint) + "/" +
    ToString(o.Boundary);
}

// Largest |spline - surface| over random points of every macro-triangle (functional surfaces:
// the spline's (x, y) must also equal (u, v)).
double MaxError(const SampledMesh& mesh, const CubicSpline& spline, AnalyticSurface s)
{
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double err = 0.0;
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    Vec2 A[3];
    for (int i = 0; i < 3; ++i)
    {
      const Id v = mesh.Triangles[3 * t + i];
      A[i] = Vec2(mesh.UV[2 * v], mesh.UV[2 * v + 1]);
    }
    for (int k = 0; k < 12; ++k)
    {
      Vec3 b(U(rng), U(rng), U(rng));
      b /= b.sum();
      const Vec2 X = b[0] * A[0] + b[1] * A[1] + b[2] * A[2];
      const Vec3 exact = EvaluateAnalyticSurface(s, X.x(), X.y()).F;
      err = std::max(err, (EvaluateSpline(mesh, spline, t, X, 0).Value - exact).norm());
    }
  }
  return err;
}

// Largest C0 and C1 jumps over all micro-edges and interior macro-edges.
std::array<double, 3> MaxJumps(const SampledMesh& mesh, const CubicSpline& spline)
{
  auto net = [&](Id t, int k, Vec3* P, Vec2* A) {
    const MacroElementIds ids =
      GetMacroElementIds(spline.Layout, mesh.Topology, mesh.Triangles.data(), t);
    const std::array<Id, 10> n = MicroTriangleNet(ids, k);
    for (int a = 0; a < 10; ++a)
    {
      P[a] = spline.ControlPoints[n[a]];
    }
    // Domain corners: the canonical net's exponent-3 points.
    A[0] = spline.DomainPoints[n[0]];
    A[1] = spline.DomainPoints[n[6]];
    A[2] = spline.DomainPoints[n[9]];
  };
  std::array<double, 3> worst{ 0.0, 0.0, 0.0 };
  auto check = [&](Id ta, int ka, Id tb, int kb) {
    Vec3 PA[10], PB[10];
    Vec2 A[3], B[3];
    net(ta, ka, PA, A);
    net(tb, kb, PB, B);
    double j[3];
    RuleAJumps(3, PA, A, PB, B, 2, j);
    for (int r = 0; r < 3; ++r)
    {
      worst[r] = std::max(worst[r], j[r]);
    }
  };
  const Id nT = static_cast<Id>(mesh.Triangles.size() / 3);
  for (Id t = 0; t < nT; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      check(t, k, t, (k + 1) % 3); // micro-edge (U_{k+2}, Z)
    }
  }
  for (Id e = 0; e < static_cast<Id>(mesh.Topology.Edges.size()); ++e)
  {
    const auto& et = mesh.Topology.EdgeTriangles[e];
    if (et[1] < 0)
    {
      continue;
    }
    const auto& el = mesh.Topology.EdgeLocalIndex[e];
    check(et[0], (el[0] + 2) % 3, et[1], (el[1] + 2) % 3);
  }
  return worst;
}
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
          EXPECT_LT(MaxError(mesh, Build(mesh, o), s), 1e-13) << Describe(mesh, o);
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
      const bool everywhere = v.Method == Construction::MGo ||
        (v.Method == Construction::MGi && v.Boundary != BoundaryMode::Midpoint);
      for (SplitPointRule sp : AllSplitPoints)
      {
        const SplineOptions o{ v.Method, sp, v.Boundary, 0 };
        const double err = MaxError(mesh, Build(mesh, o), AnalyticSurface::FarinCubic);
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
      const CubicSpline spline = Build(mesh, o);
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
          const SplineOptions o{ v.Method, sp, v.Boundary, 0 };
          const std::array<double, 3> j = MaxJumps(mesh, Build(mesh, o));
          EXPECT_LT(j[0], 1e-14) << Describe(mesh, o);
          EXPECT_LT(j[1], 1e-13) << Describe(mesh, o);
          // Not C2: the check can see a jump when there is one.
          EXPECT_GT(j[2], 1e-9) << Describe(mesh, o);
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
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (const Case& c : cases)
  {
    const CubicSpline sa = Build(a, c.Options), sb = Build(b, c.Options);
    double dev = 0.0;
    for (Id t = 0; t < static_cast<Id>(pm.Triangles.size() / 3); ++t)
    {
      for (int k = 0; k < 10; ++k)
      {
        Vec3 w(U(rng), U(rng), U(rng));
        w /= w.sum();
        Vec2 X = Vec2::Zero();
        for (int i = 0; i < 3; ++i)
        {
          X += w[i] * pm.UV[pm.Triangles[3 * t + i]];
        }
        const Vec2 Y = affine.A * X + affine.t;
        dev = std::max(dev,
          (EvaluateSpline(a, sa, t, X, 0).Value - EvaluateSpline(b, sb, t, Y, 0).Value).norm());
      }
    }
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
  const CubicSpline serial = Build(mesh, o);
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
