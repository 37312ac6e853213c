// SPDX-License-Identifier: GPL-3.0-or-later
// Facts of the study, measured on the kernel's output: precision, interpolation, C0/C1 across every
// micro- and macro-edge (Rule A), invariance to affine reparameterisation.
#include "CubicCloughTocher.h"
#include "LocalityOrder.h"
#include "RuleA.h"
#include "SplineDataValidation.h"
#include "SplineMeasures.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
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

// The mesh with its vertices and triangles renumbered at random (no locality order left); the
// vertex order within each triangle is kept.
SampledMesh Shuffled(const SampledMesh& m, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<Id> vertex(m.NumberOfVertices()), triangle(m.NumberOfTriangles());
  std::iota(vertex.begin(), vertex.end(), Id(0));
  std::iota(triangle.begin(), triangle.end(), Id(0));
  std::shuffle(vertex.begin(), vertex.end(), rng);
  std::shuffle(triangle.begin(), triangle.end(), rng);
  SampledMesh out = m;
  for (Id v = 0; v < m.NumberOfVertices(); ++v)
  {
    std::copy_n(&m.UV[2 * v], 2, &out.UV[2 * vertex[v]]);
    std::copy_n(&m.F[3 * v], 3, &out.F[3 * vertex[v]]);
    std::copy_n(&m.Fu[3 * v], 3, &out.Fu[3 * vertex[v]]);
    std::copy_n(&m.Fv[3 * v], 3, &out.Fv[3 * vertex[v]]);
  }
  for (Id t = 0; t < m.NumberOfTriangles(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      out.Triangles[3 * triangle[t] + l] = vertex[m.Triangles[3 * t + l]];
    }
    std::copy_n(&m.EdgeGradients[18 * t], 18, &out.EdgeGradients[18 * triangle[t]]);
  }
  EXPECT_TRUE(BuildMeshTopology(out.NumberOfVertices(), out.NumberOfTriangles(),
    out.Triangles.data(), out.Topology).Ok);
  return out;
}

TEST(CubicCloughTocher, LocalityOrderGivesTheSameBits)
{
  // Large enough for the locality order (LocalityOrder.h), numbered at random.
  const int n = 128;
  ASSERT_GE(2 * n * n, MinTrianglesForLocalityOrder);
  const SampledMesh mesh =
    Shuffled(Sample("jittered", JitteredGrid(n, 0.15, 11u), AnalyticSurface::Franke), 3u);
  ASSERT_FALSE(TriangleLocalityOrder(mesh.NumberOfVertices(), mesh.NumberOfTriangles(),
    mesh.Triangles.data(), mesh.UV.data()).empty());
  auto chunks = [](Id n, const std::function<void(Id, Id)>& body) {
    for (Id b = n; b > 0; b -= 1000)
    {
      body(std::max<Id>(0, b - 1000), b); // back to front
    }
  };
  for (const Construction c : { Construction::CTo, Construction::CTi, Construction::MGi,
         Construction::Fa, Construction::KaG, Construction::Kashyap })
  {
    SplineOptions o{ c, SplitPointRule::Inc3, BoundaryMode::Midpoint, 1 };
    o.LocalityOrder = false;
    const CubicSpline natural = BuildOrFail(mesh, o);
    o.LocalityOrder = true;
    CubicSpline local;
    const BuildStatus st = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, o, local, chunks);
    ASSERT_TRUE(st.Ok) << ToString(c) << ": " << st.Message;
    ASSERT_EQ(natural.ControlPoints.size(), local.ControlPoints.size());
    EXPECT_EQ(0, std::memcmp(natural.ControlPoints.data(), local.ControlPoints.data(),
                   natural.ControlPoints.size() * sizeof(Vec3))) << ToString(c);
    EXPECT_EQ(0, std::memcmp(natural.DomainPoints.data(), local.DomainPoints.data(),
                   natural.DomainPoints.size() * sizeof(Vec2))) << ToString(c);
  }
}

TEST(CubicCloughTocher, RenumberedMeshGivesEveryTriangleTheSameBits)
{
  // The filter's locality output order (issue #12): the input renumbered (triangles by Morton
  // key, vertices by first use), built, and compared per macro-triangle with the input's order.
  const int n = 128;
  const SampledMesh mesh =
    Shuffled(Sample("jittered", JitteredGrid(n, 0.15, 11u), AnalyticSurface::Franke), 5u);
  const LocalityRenumbering r = MakeLocalityRenumbering(
    mesh.NumberOfVertices(), mesh.NumberOfTriangles(), mesh.Triangles.data(), mesh.UV.data());
  ASSERT_EQ(r.Triangles, TriangleLocalityOrder(mesh.NumberOfVertices(), mesh.NumberOfTriangles(),
    mesh.Triangles.data(), mesh.UV.data()));
  ASSERT_EQ(static_cast<Id>(r.Vertices.size()), mesh.NumberOfVertices());
  SampledMesh renumbered = mesh;
  renumbered.Renumber(r);
  // Vertices by first use: the renumbered triangles meet new vertex ids in increasing order.
  Id next = 0;
  for (const Id v : renumbered.Triangles)
  {
    ASSERT_LE(v, next);
    next = std::max(next, v + 1);
  }
  for (Id k = 0; k < mesh.NumberOfTriangles(); ++k)
  {
    for (int l = 0; l < 3; ++l)
    {
      const Id v = renumbered.Triangles[3 * k + l];
      ASSERT_EQ(r.Vertices[v], mesh.Triangles[3 * r.Triangles[k] + l]);
      ASSERT_EQ(renumbered.UV[2 * v], mesh.UV[2 * r.Vertices[v]]);
      ASSERT_EQ(renumbered.Fu[3 * v + 2], mesh.Fu[3 * r.Vertices[v] + 2]);
    }
    // The edge gradients stay in place, reached through the row map.
    ASSERT_EQ(EdgeGradientsOf(renumbered.View(), k)[17], mesh.EdgeGradients[18 * r.Triangles[k] + 17]);
  }
  // The edges' two triangles in the input's order: Rule A, the fairing and IM read them so.
  ASSERT_TRUE(BuildMeshTopology(renumbered.NumberOfVertices(), renumbered.NumberOfTriangles(),
    renumbered.Triangles.data(), renumbered.Topology, SerialFor, r.Triangles.data()).Ok);
  SplineInput back = renumbered;
  back.Renumber(r, true);
  EXPECT_EQ(back.Triangles, mesh.Triangles);
  EXPECT_EQ(back.UV, mesh.UV);
  EXPECT_EQ(back.EdgeGradients, mesh.EdgeGradients);
  for (Id t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    ASSERT_EQ(back.EdgeGradientRows[t], t);
  }

  for (int c = 0; c < NumberOfConstructions; ++c)
  {
    if (Info(static_cast<Construction>(c)).Degree != 3)
    {
      continue;
    }
    // One IM step or fairing round.
    SplineOptions o{ static_cast<Construction>(c), SplitPointRule::Inc3, BoundaryMode::Midpoint, 1 };
    const CubicSpline natural = BuildOrFail(mesh, o);
    const CubicSpline local = BuildOrFail(renumbered, o);
    ASSERT_EQ(natural.ControlPoints.size(), local.ControlPoints.size());
    Id differing = 0;
    for (Id k = 0; k < mesh.NumberOfTriangles(); ++k)
    {
      const Id t = r.Triangles[k];
      for (int m = 0; m < 3; ++m)
      {
        const auto a = MicroTriangleNet(
          GetMacroElementIds(natural.Layout, mesh.Topology, mesh.Triangles.data(), t), m);
        const auto b = MicroTriangleNet(GetMacroElementIds(local.Layout, renumbered.Topology,
                                          renumbered.Triangles.data(), k), m);
        for (size_t i = 0; i < a.size(); ++i)
        {
          differing += std::memcmp(natural.ControlPoints[a[i]].data(),
                         local.ControlPoints[b[i]].data(), sizeof(Vec3)) != 0 ||
            std::memcmp(natural.DomainPoints[a[i]].data(), local.DomainPoints[b[i]].data(),
              sizeof(Vec2)) != 0;
        }
      }
    }
    EXPECT_EQ(differing, 0) << ToString(o.Method);
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

TEST(CubicCloughTocher, RenumberingAndValidationDoNotDependOnTheSplit)
{
  const int n = 128;
  const SampledMesh mesh =
    Shuffled(Sample("jittered", JitteredGrid(n, 0.15, 11u), AnalyticSurface::Franke), 7u);
  const Id nV = mesh.NumberOfVertices(), nT = mesh.NumberOfTriangles();
  const LocalityRenumbering r =
    MakeLocalityRenumbering(nV, nT, mesh.Triangles.data(), mesh.UV.data());
  ASSERT_FALSE(r.IsIdentity());
  SplineInput renumbered = mesh;
  renumbered.Renumber(r);
  // Renumbered vertex k carries input vertex r.Vertices[k]'s rows (the definition, against the
  // one-pass gather of PermuteRowsTogether).
  for (size_t k = 0; k < r.Vertices.size(); ++k)
  {
    const size_t v = static_cast<size_t>(r.Vertices[k]);
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_EQ(renumbered.F[3 * k + c], mesh.F[3 * v + c]) << "vertex " << k;
      ASSERT_EQ(renumbered.Fu[3 * k + c], mesh.Fu[3 * v + c]) << "vertex " << k;
      ASSERT_EQ(renumbered.Fv[3 * k + c], mesh.Fv[3 * v + c]) << "vertex " << k;
      ASSERT_TRUE(c == 2 || renumbered.UV[2 * k + c] == mesh.UV[2 * v + c]) << "vertex " << k;
    }
  }
  // Two zero-area triangles: vertex b moved onto its neighbour a's (u, v).
  SplineInput degenerate = mesh;
  const Id a = mesh.Triangles[3 * (nT / 2)], b = mesh.Triangles[3 * (nT / 2) + 1];
  std::copy_n(&mesh.UV[2 * a], 2, &degenerate.UV[2 * b]);
  const BuildStatus serialCheck = ValidateSplineData(degenerate.View(), mesh.Topology);
  ASSERT_FALSE(serialCheck.Ok);
  for (const auto& [threads, chunk] : { std::pair<int, Id>{ 2, 4999 }, { 3, 777 } })
  {
    const ParallelFor split = ThreadedFor(threads, chunk);
    const LocalityRenumbering s =
      MakeLocalityRenumbering(nV, nT, mesh.Triangles.data(), mesh.UV.data(), split);
    EXPECT_EQ(s.Triangles, r.Triangles) << threads << " threads";
    EXPECT_EQ(s.Vertices, r.Vertices) << threads << " threads";
    SplineInput there = mesh;
    there.Renumber(r, false, split);
    EXPECT_EQ(there.Triangles, renumbered.Triangles);
    // The filter's route: one gather of the triangles, the same renumbering and data.
    SplineInput direct = mesh;
    const LocalityRenumbering q = direct.RenumberToLocalityOrder(split);
    EXPECT_EQ(q.Triangles, r.Triangles);
    EXPECT_EQ(q.Vertices, r.Vertices);
    EXPECT_EQ(direct.Triangles, renumbered.Triangles);
    EXPECT_EQ(direct.UV, renumbered.UV);
    EXPECT_EQ(direct.F, renumbered.F);
    EXPECT_EQ(direct.Fu, renumbered.Fu);
    EXPECT_EQ(direct.Fv, renumbered.Fv);
    EXPECT_EQ(direct.EdgeGradientRows, renumbered.EdgeGradientRows);
    EXPECT_EQ(there.UV, renumbered.UV);
    EXPECT_EQ(there.Fv, renumbered.Fv);
    EXPECT_EQ(there.EdgeGradients, renumbered.EdgeGradients);
    there.Renumber(r, true, split);
    EXPECT_EQ(there.Triangles, mesh.Triangles);
    EXPECT_EQ(there.UV, mesh.UV);
    EXPECT_EQ(there.F, mesh.F);
    EXPECT_EQ(there.Fu, mesh.Fu);
    EXPECT_EQ(there.Fv, mesh.Fv);
    const BuildStatus check = ValidateSplineData(degenerate.View(), mesh.Topology, {}, split);
    EXPECT_EQ(check.Message, serialCheck.Message) << threads << " threads";
  }
}

TEST(LocalityOrder, VerticesByFirstUseOnEveryThreadCount)
{
  // Against the definition, one corner after another: a triangle with a repeated vertex id and
  // points that no triangle uses (they follow by id), on 1-3 threads.
  const int n = 128;
  const SampledMesh mesh =
    Shuffled(Sample("jittered", JitteredGrid(n, 0.15, 11u), AnalyticSurface::Franke), 9u);
  const Id nT = mesh.NumberOfTriangles(), w = mesh.NumberOfVertices(), nV = w + 5;
  std::vector<Id> triangles(mesh.Triangles.begin(), mesh.Triangles.end());
  std::vector<double> uv(mesh.UV.begin(), mesh.UV.end());
  uv.insert(uv.end(), { 0.5, 0.5, 0.25, 0.75, 0.75, 0.25, 0.1, 0.1, 0.9, 0.9 });
  // New points w and w + 1 used only by these two triangles, each twice, so that the repeat
  // follows their first use: (a, w, w) and (w + 1, b, w + 1).
  triangles[3 * 4321 + 1] = triangles[3 * 4321 + 2] = w;
  triangles[3 * 1234] = triangles[3 * 1234 + 2] = w + 1;
  const std::vector<Id> order = TriangleLocalityOrder(nV, nT, triangles.data(), uv.data());
  ASSERT_EQ(static_cast<Id>(order.size()), nT);
  std::vector<Id> expected;
  std::vector<bool> seen(nV, false);
  for (const Id t : order)
  {
    for (int l = 0; l < 3; ++l)
    {
      const Id v = triangles[3 * t + l];
      if (!seen[v])
      {
        seen[v] = true;
        expected.push_back(v);
      }
    }
  }
  for (Id v = 0; v < nV; ++v)
  {
    if (!seen[v])
    {
      expected.push_back(v);
    }
  }
  ASSERT_TRUE(seen[w] && seen[w + 1]);
  ASSERT_GE(static_cast<Id>(std::count(seen.begin(), seen.end(), false)), 3);
  for (const auto& [threads, chunk] : { std::pair<int, Id>{ 1, nT }, { 2, 4999 }, { 3, 777 } })
  {
    const LocalityRenumbering r =
      MakeLocalityRenumbering(nV, nT, triangles.data(), uv.data(), ThreadedFor(threads, chunk));
    EXPECT_EQ(r.Triangles, order) << threads << " threads";
    EXPECT_TRUE(std::equal(r.Vertices.begin(), r.Vertices.end(), expected.begin(), expected.end()))
      << threads << " threads";
  }
  // Every vertex used, then the last corners repeat them: the branch-free pass writes them into its spare
  // slot (an overflow without it, which ASan and the sanitizer CI job catch).
  const std::vector<Id> twice = { 0, 1, 2, 2, 1, 0, 1, 2, 0 };
  const OverwriteVector<Id> all = VerticesByFirstUse(3, 3, twice.data());
  EXPECT_EQ(std::vector<Id>(all.begin(), all.end()), (std::vector<Id>{ 0, 1, 2 }));
  const OverwriteVector<Id> none = VerticesByFirstUse(2, 0, nullptr);
  EXPECT_EQ(std::vector<Id>(none.begin(), none.end()), (std::vector<Id>{ 0, 1 }));
  EXPECT_TRUE(VerticesByFirstUse(0, 0, nullptr).empty());
  // An id out of range: no order (the topology's validation names it), nothing moved.
  for (const Id bad : { nV, Id(-1) })
  {
    triangles[3 * 777 + 1] = bad;
    EXPECT_TRUE(TriangleLocalityOrder(nV, nT, triangles.data(), uv.data()).empty()) << bad;
    SplineInput input = mesh;
    input.Triangles[3 * 777 + 1] = bad < 0 ? bad : mesh.NumberOfVertices();
    const SplineInput before = input;
    EXPECT_TRUE(input.RenumberToLocalityOrder(ThreadedFor(2, 4999)).IsIdentity()) << bad;
    EXPECT_EQ(input.Triangles, before.Triangles);
    EXPECT_EQ(input.UV, before.UV);
  }
}

TEST(LocalityOrder, RowsPermutedTogetherAsByDefinition)
{
  // Arrays of ids and values, widths 1, 3 and 18 (run-time), and an empty one, permuted in one
  // pass: renumbered row k is row from[k], on 1-3 threads; the way back restores every array.
  const Id n = 20011;
  std::vector<Id> from(static_cast<size_t>(n));
  std::iota(from.begin(), from.end(), Id(0));
  std::shuffle(from.begin(), from.end(), std::mt19937_64(3u));
  std::vector<Id> ids(static_cast<size_t>(n));
  OverwriteVector<double> triples(static_cast<size_t>(3 * n)), wide(static_cast<size_t>(18 * n));
  std::iota(ids.begin(), ids.end(), Id(100));
  std::iota(triples.begin(), triples.end(), 0.5);
  std::iota(wide.begin(), wide.end(), -7.25);
  const std::vector<Id> ids0 = ids;
  const OverwriteVector<double> triples0 = triples, wide0 = wide;
  for (const auto& [threads, chunk] : { std::pair<int, Id>{ 1, n }, { 2, 4999 }, { 3, 777 } })
  {
    OverwriteVector<double> none;
    PermuteRowsTogether<1, 3, 0, 3>(
      from, false, ThreadedFor(threads, chunk), 18, ids, triples, wide, none);
    EXPECT_TRUE(none.empty());
    for (Id k = 0; k < n; ++k)
    {
      const size_t i = static_cast<size_t>(from[k]), j = static_cast<size_t>(k);
      ASSERT_EQ(ids[j], ids0[i]) << "row " << k << ", " << threads << " threads";
      ASSERT_TRUE(std::equal(&triples0[3 * i], &triples0[3 * i + 3], &triples[3 * j]))
        << "row " << k;
      ASSERT_TRUE(std::equal(&wide0[18 * i], &wide0[18 * i + 18], &wide[18 * j])) << "row " << k;
    }
    PermuteRowsTogether<1, 3, 0, 3>(
      from, true, ThreadedFor(threads, chunk), 18, ids, triples, wide, none);
    EXPECT_EQ(ids, ids0) << threads << " threads";
    EXPECT_EQ(triples, triples0) << threads << " threads";
    EXPECT_EQ(wide, wide0) << threads << " threads";
    // One array at a time, PermuteRows' width 18 as the run-time copy.
    PermuteRows(wide, 18, from, false, ThreadedFor(threads, chunk));
    EXPECT_TRUE(std::equal(&wide0[18 * static_cast<size_t>(from[5])],
      &wide0[18 * static_cast<size_t>(from[5]) + 18], &wide[18 * 5]));
    PermuteRows(wide, 18, from, true, ThreadedFor(threads, chunk));
    EXPECT_EQ(wide, wide0) << threads << " threads";
  }
}

TEST(LocalityOrder, RadixSortIsStableOnEveryThreadCount)
{
  // Five blocks of the sort's 2^16 values; keys from a few values (ties keep the input order)
  // to the full 32 bits (every pass moves values), and keys below 2^11 (two passes skipped).
  std::mt19937_64 random(5u);
  for (const std::uint64_t keyRange : { std::uint64_t(7), std::uint64_t(2048), std::uint64_t(1) << 32 })
  {
    OverwriteVector<std::uint64_t> values(300001);
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      values[i] = ((random() % keyRange) << 32) | i;
    }
    OverwriteVector<std::uint64_t> expected = values;
    std::stable_sort(expected.begin(), expected.end(),
      [](std::uint64_t a, std::uint64_t b) { return (a >> 32) < (b >> 32); });
    OverwriteVector<std::uint64_t> serial = values;
    SortByUpperHalf(serial);
    EXPECT_EQ(serial, expected) << "keys below " << keyRange;
    for (const auto& [threads, chunk] : { std::pair<int, Id>{ 2, 4999 }, { 3, 70001 } })
    {
      OverwriteVector<std::uint64_t> split = values;
      SortByUpperHalf(split, ThreadedFor(threads, chunk));
      EXPECT_EQ(split, expected) << "keys below " << keyRange << ", " << threads << " threads";
    }
  }
}
