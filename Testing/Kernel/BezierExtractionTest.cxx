// SPDX-License-Identifier: GPL-3.0-or-later
// Bézier extraction: the operators reproduce the construction, every basis function is C1 across
// every edge, the value basis functions sum to one, and the dimension is the study's.
#include "BezierExtraction.h"
#include "SplineMeasures.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

using namespace ctk;
using namespace ctk_test;

namespace
{
const SplineOptions Cases[] = {
  { Construction::CTo, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 },
  { Construction::CTi, SplitPointRule::Inc3, BoundaryMode::Midpoint, 0 },
  { Construction::CTi, SplitPointRule::Inc2, BoundaryMode::GradientPerpendicular, 0 },
  { Construction::Fa, SplitPointRule::Bary, BoundaryMode::Perpendicular, 0 },
  { Construction::FO, SplitPointRule::Inc3, BoundaryMode::Midpoint, 0 },
  { Construction::Ka, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 },
  { Construction::KaG, SplitPointRule::Inc3, BoundaryMode::GradientToSplitPoint, 0 },
  { Construction::MGo, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 },
  { Construction::MGi, SplitPointRule::Inc3, BoundaryMode::GradientToSplitPoint, 0 },
  { Construction::Kashyap, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 },
};

// Control points of the spline from the operators and a DOF vector, written into a copy of the
// spline's layout (every cell writes its points; shared points must agree).
CubicSpline Assemble(const SampledMesh& mesh, const CubicSpline& layoutOf, const BezierExtraction& x,
  const std::vector<Vec3>& dofs, double* disagreement)
{
  constexpr int M = BezierExtraction::MaxElementDofs;
  CubicSpline s = layoutOf;
  std::vector<int> written(s.ControlPoints.size(), 0);
  *disagreement = 0.0;
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    const MacroElementIds ids = GetMacroElementIds(s.Layout, mesh.Topology, mesh.Triangles.data(), t);
    for (int k = 0; k < 3; ++k)
    {
      const std::array<Id, 10> net = MicroTriangleNet(ids, k);
      const Id* cd = &x.CellDofs[(3 * t + k) * M];
      const double* op = &x.CellOperators[(3 * t + k) * 10 * M];
      for (int a = 0; a < 10; ++a)
      {
        Vec3 p = Vec3::Zero();
        for (int j = 0; j < M && cd[j] >= 0; ++j)
        {
          p += op[a * M + j] * dofs[cd[j]];
        }
        if (written[net[a]]++)
        {
          *disagreement = std::max(*disagreement, (p - s.ControlPoints[net[a]]).norm());
        }
        s.ControlPoints[net[a]] = p;
      }
    }
  }
  return s;
}
} // namespace

TEST(BezierExtraction, OperatorsReproduceEveryConstruction)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::Franke);
    for (const SplineOptions& o : Cases)
    {
      const CubicSpline direct = BuildOrFail(mesh, o);
      BezierExtraction x;
      ASSERT_TRUE(BuildBezierExtraction(mesh.Data(), mesh.Topology, o, x).Ok) << Describe(mesh, o);
      double disagreement = 0.0;
      const CubicSpline viaOperators =
        Assemble(mesh, direct, x, DegreesOfFreedom(mesh.Data(), mesh.Topology, x), &disagreement);
      double worst = 0.0;
      for (size_t p = 0; p < direct.ControlPoints.size(); ++p)
      {
        worst = std::max(worst, (direct.ControlPoints[p] - viaOperators.ControlPoints[p]).norm());
      }
      EXPECT_LT(worst, 1e-13) << Describe(mesh, o);
      EXPECT_LT(disagreement, 1e-13) << Describe(mesh, o);
    }
  }
}

TEST(BezierExtraction, DimensionIsTheStudys)
{
  const SampledMesh mesh = Sample("jittered", JitteredGrid(4, 0.3, 9u), AnalyticSurface::Franke);
  const Id nV = static_cast<Id>(mesh.UV.size() / 2), nE = static_cast<Id>(mesh.Topology.Edges.size());
  const Id nB = mesh.Topology.NumberOfBoundaryEdges();
  for (const SplineOptions& o : Cases)
  {
    BezierExtraction x;
    ASSERT_TRUE(BuildBezierExtraction(mesh.Data(), mesh.Topology, o, x).Ok);
    Id expected = 3 * nV;
    if (o.Method == Construction::MGo || o.Method == Construction::MGi)
    {
      expected += nE; // the full CT space, 3 n_v + n_e
    }
    else if (UsesEdgeGradients(o))
    {
      expected += nB;
    }
    EXPECT_EQ(x.NumberOfDofs, expected) << Describe(mesh, o);
  }
}

TEST(BezierExtraction, BasisFunctionsAreC1AndValueFunctionsSumToOne)
{
  const SampledMesh mesh = Sample("jittered", JitteredGrid(3, 0.3, 4u), AnalyticSurface::Franke);
  for (const SplineOptions& o : Cases)
  {
    const CubicSpline layout = BuildOrFail(mesh, o);
    BezierExtraction x;
    ASSERT_TRUE(BuildBezierExtraction(mesh.Data(), mesh.Topology, o, x).Ok);
    double disagreement = 0.0;
    // Every basis function, scalar in x (y and z stay zero), is C1 across every edge.
    double worst[2] = { 0.0, 0.0 };
    for (Id j = 0; j < x.NumberOfDofs; ++j)
    {
      std::vector<Vec3> unit(x.NumberOfDofs, Vec3::Zero());
      unit[j].x() = 1.0;
      const CubicSpline basis = Assemble(mesh, layout, x, unit, &disagreement);
      ASSERT_LT(disagreement, 1e-14);
      const std::array<double, 3> jumps = MaxJumps(mesh, basis);
      worst[0] = std::max(worst[0], jumps[0]);
      worst[1] = std::max(worst[1], jumps[1]);
    }
    EXPECT_LT(worst[0], 1e-14) << Describe(mesh, o);
    EXPECT_LT(worst[1], 1e-12) << Describe(mesh, o);
    // Partition of unity: value DOFs 1, derivatives and edge DOFs 0.
    std::vector<Vec3> ones(x.NumberOfDofs, Vec3::Zero());
    for (Id v = 0; v < static_cast<Id>(mesh.UV.size() / 2); ++v)
    {
      ones[3 * v] = Vec3::Ones();
    }
    const CubicSpline sum = Assemble(mesh, layout, x, ones, &disagreement);
    for (const Vec3& p : sum.ControlPoints)
    {
      ASSERT_LT((p - Vec3::Ones()).norm(), 1e-13) << Describe(mesh, o);
    }
  }
}

TEST(BezierExtraction, RefusesIterations)
{
  const SampledMesh mesh = Sample("grid", RegularGridMesh(2, GridDiagonal::Forward), AnalyticSurface::Plane);
  BezierExtraction x;
  const SplineOptions o{ Construction::CTi, SplitPointRule::Bary, BoundaryMode::Midpoint, 2 };
  const BuildStatus st = BuildBezierExtraction(mesh.Data(), mesh.Topology, o, x);
  EXPECT_FALSE(st.Ok);
  EXPECT_NE(st.Message.find("iterations"), std::string::npos);
}
