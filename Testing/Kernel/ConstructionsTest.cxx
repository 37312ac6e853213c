// SPDX-License-Identifier: GPL-3.0-or-later
// The construction table states facts of every construction; these tests hold each row to them
// (precision, affine invariance, interpolation) through BuildCloughTocher and EvaluateSpline, so
// a wrong row or a construction that changes fails here.
#include "CloughTocherSpline.h"
#include "SplineInput.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace ctk_test;

namespace
{
CloughTocherSpline BuildOrFail(const SampledMesh& mesh, Construction c, int iterations = 0)
{
  const SplineOptions o{ c, SplitPointRule::Bary, BoundaryMode::Midpoint, iterations };
  CloughTocherSpline spline;
  const BuildStatus st = BuildCloughTocher(mesh.Data(), mesh.Topology, o, spline);
  EXPECT_TRUE(st.Ok) << ToString(c) << ": " << st.Message;
  return spline;
}

bool IsInterior(const SampledMesh& mesh, Id t)
{
  return mesh.Topology.Neighbor(t, 0) >= 0 && mesh.Topology.Neighbor(t, 1) >= 0 &&
    mesh.Topology.Neighbor(t, 2) >= 0;
}

Vec3 RandomTau(std::mt19937& rng)
{
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Vec3 tau(U(rng), U(rng), U(rng));
  return tau / tau.sum();
}

/// Largest |spline - surface| over random points of the (interior) macro-triangles.
double MaxError(const SampledMesh& mesh, const CloughTocherSpline& spline, AnalyticSurface s,
  bool interiorOnly)
{
  std::mt19937 rng(5);
  double err = 0;
  for (Id t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (interiorOnly && !IsInterior(mesh, t))
    {
      continue;
    }
    for (int q = 0; q < 8; ++q)
    {
      const Vec3 tau = RandomTau(rng);
      const Id* tri = mesh.Triangles.data() + 3 * t;
      Vec2 X = Vec2::Zero();
      for (int i = 0; i < 3; ++i)
      {
        X += tau[i] * Vec2(mesh.UV[2 * tri[i]], mesh.UV[2 * tri[i] + 1]);
      }
      const Vec3 exact = EvaluateAnalyticSurface(s, X.x(), X.y()).F;
      const Vec3 ours =
        EvaluateSpline(spline, mesh.Topology, mesh.Triangles.data(), t, tau).Value;
      err = std::max(err, (ours - exact).norm());
    }
  }
  return err;
}
} // namespace

TEST(Constructions, TableIsConsistent)
{
  std::set<std::string> names;
  for (int i = 0; i < NumberOfConstructions; ++i)
  {
    const ConstructionInfo& row = ConstructionTable()[i];
    EXPECT_EQ(static_cast<int>(row.Method), i);
    EXPECT_TRUE(names.insert(row.Name).second) << row.Name;
    Construction found;
    ASSERT_TRUE(FindConstruction(row.Name, found)) << row.Name;
    EXPECT_EQ(found, row.Method);
    EXPECT_STREQ(ToString(row.Method), row.Name);
    EXPECT_TRUE(row.Degree == 3 || row.Degree == 4) << row.Name;
    EXPECT_EQ(CanBeStitched(row.Method), row.TakesBoundaryCurves);
    EXPECT_EQ(RequiredGhostRings(row.Method, 0), row.Local ? 0 : 2) << row.Name;
    EXPECT_EQ(RequiredGhostRings(row.Method, 3), 5) << row.Name;
    // Only the edge-based constructions compare the neighbour's data by a macro-edge rule.
    EXPECT_TRUE(row.EdgeRule == MacroEdgeRule::None || row.EdgeBased) << row.Name;
  }
  Construction c;
  EXPECT_FALSE(FindConstruction("Farin", c));
  EXPECT_FALSE(IsConstruction(NumberOfConstructions));
  EXPECT_FALSE(IsConstruction(-1));
  EXPECT_STREQ(ToString(static_cast<Construction>(42)), "Unknown");
}

// Quadratic data are reproduced everywhere by every construction; cubic data exactly where the
// table says the construction has cubic precision, and not at all by the others.
TEST(Constructions, PrecisionIsWhatTheTableStates)
{
  const ParameterMesh pm = JitteredGrid(5, 0.3, 11u);
  const SampledMesh quadratic = Sample("jittered", pm, AnalyticSurface::Quadratic);
  const SampledMesh cubic = Sample("jittered", pm, AnalyticSurface::FarinCubic);
  for (const ConstructionInfo& row : ConstructionTable())
  {
    ASSERT_GE(row.Precision, 2) << row.Name;
    EXPECT_LT(MaxError(quadratic, BuildOrFail(quadratic, row.Method, 2), AnalyticSurface::Quadratic,
                false),
      1e-12)
      << row.Name;
    // The fairing schemes' precision is that of their rounds (with none they are FO); IM steps
    // would spread the boundary error of the cubic-precision ones inwards (tested elsewhere).
    const CloughTocherSpline s =
      BuildOrFail(cubic, row.Method, row.IterationsAreFairingRounds ? 2 : 0);
    const bool everywhere = std::string(row.PrecisionWhere).rfind("everywhere", 0) == 0;
    const double interior = MaxError(cubic, s, AnalyticSurface::FarinCubic, true);
    const double all = MaxError(cubic, s, AnalyticSurface::FarinCubic, false);
    if (row.Precision >= 3)
    {
      EXPECT_LT(everywhere ? all : interior, 1e-12) << row.Name;
      if (!everywhere)
      {
        EXPECT_GT(all, 1e-6) << row.Name << ": exact on boundary triangles too";
      }
    }
    else
    {
      EXPECT_GT(interior, 1e-6) << row.Name << " reproduces a cubic";
    }
  }
}

// The same tau of the same triangle is the same surface point after an affine
// reparameterisation exactly when the table says the construction is invariant.
TEST(Constructions, AffineInvarianceIsWhatTheTableStates)
{
  const ParameterMesh pm = JitteredGrid(5, 0.3, 31u);
  Affine affine;
  affine.A << 0.4, -1.1, 0.9, 0.6;
  affine.t = Vec2(-2.0, 0.5);
  const SampledMesh a = Sample("jittered", pm, AnalyticSurface::Franke);
  const SampledMesh b = Sample("jittered-affine", pm, AnalyticSurface::Franke, affine);
  for (const ConstructionInfo& row : ConstructionTable())
  {
    const CloughTocherSpline sa = BuildOrFail(a, row.Method, 2), sb = BuildOrFail(b, row.Method, 2);
    std::mt19937 rng(3);
    double dev = 0;
    for (Id t = 0; t < a.NumberOfTriangles(); ++t)
    {
      const Vec3 tau = RandomTau(rng);
      dev = std::max(dev,
        (EvaluateSpline(sa, a.Topology, a.Triangles.data(), t, tau).Value -
          EvaluateSpline(sb, b.Topology, b.Triangles.data(), t, tau).Value)
          .norm());
    }
    if (row.AffineInvariant)
    {
      EXPECT_LT(dev, 1e-12) << row.Name;
    }
    else
    {
      EXPECT_GT(dev, 1e-5) << row.Name;
    }
  }
}

// EvaluateSpline: the data are interpolated (positions and gradients at the vertices), and the
// micro-triangle it picks is the one the point lies in.
TEST(Constructions, EvaluateSplineInterpolatesTheVertexData)
{
  const SampledMesh mesh = Sample("jittered", JitteredGrid(4, 0.3, 7u), AnalyticSurface::Franke);
  for (Construction c : { Construction::CTi, Construction::KaG, Construction::Quartic })
  {
    const CloughTocherSpline s = BuildOrFail(mesh, c, 1);
    for (Id t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      for (int i = 0; i < 3; ++i)
      {
        const Id v = mesh.Triangles[3 * t + i];
        const ParametricJet jet = EvaluateSpline(
          s, mesh.Topology, mesh.Triangles.data(), t, Vec3(Vec3::Unit(i)), 1);
        for (int d = 0; d < 3; ++d)
        {
          EXPECT_NEAR(jet.Value[d], mesh.F[3 * v + d], 1e-13) << ToString(c);
          EXPECT_NEAR(jet.Du[d], mesh.Fu[3 * v + d], 1e-11) << ToString(c);
          EXPECT_NEAR(jet.Dv[d], mesh.Fv[3 * v + d], 1e-11) << ToString(c);
        }
      }
    }
  }
}

TEST(Constructions, LocateMicroTriangleInvertsMacroBarycentric)
{
  std::mt19937 rng(9);
  for (int q = 0; q < 200; ++q)
  {
    const Vec3 split = RandomTau(rng);
    const int k = q % 3;
    const Vec3 w = RandomTau(rng);
    const MicroPoint m = LocateMicroTriangle(split, MacroBarycentric(split, k, w));
    EXPECT_EQ(m.K, k);
    EXPECT_LT((m.W - w).norm(), 1e-14);
    EXPECT_NEAR(m.W.sum(), 1.0, 1e-15);
  }
}

TEST(Constructions, BuildersRejectWhatTheyDoNotBuild)
{
  const SampledMesh mesh = Sample("grid", RegularGridMesh(2, GridDiagonal::Forward), AnalyticSurface::Plane);
  CubicSpline cubic;
  const SplineOptions quartic{ Construction::Quartic, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 };
  const BuildStatus st = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, quartic, cubic);
  EXPECT_FALSE(st.Ok);
  EXPECT_NE(st.Message.find("Quartic"), std::string::npos) << st.Message;
  CloughTocherSpline any;
  SplineOptions unknown = quartic;
  unknown.Method = static_cast<Construction>(NumberOfConstructions);
  EXPECT_FALSE(BuildCloughTocher(mesh.Data(), mesh.Topology, unknown, any).Ok);
  ASSERT_TRUE(BuildCloughTocher(mesh.Data(), mesh.Topology, quartic, any).Ok);
  EXPECT_EQ(any.Degree, 4);
  EXPECT_EQ(any.ControlPoints().size(), static_cast<size_t>(any.Quartic.Layout.NumberOfPoints()));
}

TEST(Constructions, SplineInputNamesTheArrayOfWrongSize)
{
  SampledMesh mesh = Sample("grid", RegularGridMesh(2, GridDiagonal::Forward), AnalyticSurface::Plane);
  EXPECT_TRUE(mesh.Validate(mesh.Topology).Ok);
  EXPECT_NE(mesh.View().EdgeGradients, nullptr);
  EXPECT_EQ(mesh.View().BoundaryCurvePoints, nullptr);
  mesh.Fv.pop_back();
  BuildStatus st = mesh.Validate(mesh.Topology);
  EXPECT_FALSE(st.Ok);
  EXPECT_NE(st.Message.find("Fv"), std::string::npos) << st.Message;
  mesh.Fv.push_back(0.0);
  mesh.EdgeGradients.resize(5);
  st = mesh.Validate(mesh.Topology);
  EXPECT_NE(st.Message.find("EdgeGradients"), std::string::npos) << st.Message;
  mesh.EdgeGradients.clear();
  EXPECT_TRUE(mesh.Validate(mesh.Topology).Ok);
  // The kernel's checks come with it: a folded triangle (vertex moved across its opposite edge).
  mesh.UV[2 * 4] = 2.0;
  st = mesh.Validate(mesh.Topology);
  EXPECT_FALSE(st.Ok);
}
