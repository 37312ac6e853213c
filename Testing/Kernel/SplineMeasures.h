// SPDX-License-Identifier: GPL-3.0-or-later
// Measurements on a kernel spline shared by the construction tests: error against the sampled
// surface, C0/C1/C2 jumps over all edges (Rule A), deviation under reparameterisation.
#ifndef CTSplines_Testing_SplineMeasures_h
#define CTSplines_Testing_SplineMeasures_h

#include "RuleA.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <random>

namespace ctk_test
{
inline CubicSpline BuildOrFail(const SampledMesh& mesh, const SplineOptions& o)
{
  CubicSpline spline;
  const BuildStatus st = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, o, spline);
  EXPECT_TRUE(st.Ok) << st.Message;
  return spline;
}

inline std::string Describe(const SampledMesh& m, const SplineOptions& o)
{
  return m.Name + " " + ToString(o.Method) + "/" + ToString(o.SplitPoint) + "/" +
    ToString(o.Boundary) + "/IM" + std::to_string(o.Iterations);
}

inline Vec2 VertexUV(const SampledMesh& mesh, Id t, int i)
{
  const Id v = mesh.Triangles[3 * t + i];
  return Vec2(mesh.UV[2 * v], mesh.UV[2 * v + 1]);
}

/// Largest |spline - surface| over random points of the macro-triangles (all, or only those with
/// no boundary edge).
inline double MaxError(
  const SampledMesh& mesh, const CubicSpline& spline, AnalyticSurface s, bool interiorOnly)
{
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double err = 0.0;
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    if (interiorOnly &&
      (mesh.Topology.Neighbor(t, 0) < 0 || mesh.Topology.Neighbor(t, 1) < 0 ||
        mesh.Topology.Neighbor(t, 2) < 0))
    {
      continue;
    }
    for (int k = 0; k < 12; ++k)
    {
      Vec3 b(U(rng), U(rng), U(rng));
      b /= b.sum();
      const Vec2 X = b[0] * VertexUV(mesh, t, 0) + b[1] * VertexUV(mesh, t, 1) + b[2] * VertexUV(mesh, t, 2);
      const Vec3 exact = EvaluateAnalyticSurface(s, X.x(), X.y()).F;
      err = std::max(err, (EvaluateSpline(mesh, spline, t, X, 0).Value - exact).norm());
    }
  }
  return err;
}

/// Largest C0, C1, C2 jumps over all micro-edges and interior macro-edges.
inline std::array<double, 3> MaxJumps(const SampledMesh& mesh, const CubicSpline& spline)
{
  auto net = [&](Id t, int k, Vec3* P, Vec2* A) {
    const MacroElementIds ids =
      GetMacroElementIds(spline.Layout, mesh.Topology, mesh.Triangles.data(), t);
    const std::array<Id, 10> n = MicroTriangleNet(ids, k);
    for (int a = 0; a < 10; ++a)
    {
      P[a] = spline.ControlPoints[n[a]];
    }
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
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      check(t, k, t, (k + 1) % 3);
    }
  }
  for (Id e = 0; e < static_cast<Id>(mesh.Topology.Edges.size()); ++e)
  {
    const auto& et = mesh.Topology.EdgeTriangles[e];
    if (et[1] >= 0)
    {
      const auto& el = mesh.Topology.EdgeLocalIndex[e];
      check(et[0], (el[0] + 2) % 3, et[1], (el[1] + 2) % 3);
    }
  }
  return worst;
}

/// C0 and C1 to round-off across every edge, and a visible C2 jump (so the check can see one).
inline void ExpectC1ButNotC2(const SampledMesh& mesh, const SplineOptions& o)
{
  const std::array<double, 3> j = MaxJumps(mesh, BuildOrFail(mesh, o));
  EXPECT_LT(j[0], 1e-14) << Describe(mesh, o);
  EXPECT_LT(j[1], 1e-13) << Describe(mesh, o);
  EXPECT_GT(j[2], 1e-9) << Describe(mesh, o);
}

/// Largest distance between spline a at X and spline b at A X + t, over random X.
inline double MaxDeviation(const SampledMesh& a, const CubicSpline& sa, const SampledMesh& b,
  const CubicSpline& sb, const Affine& affine)
{
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double dev = 0.0;
  for (Id t = 0; t < static_cast<Id>(a.Triangles.size() / 3); ++t)
  {
    for (int k = 0; k < 10; ++k)
    {
      Vec3 w(U(rng), U(rng), U(rng));
      w /= w.sum();
      const Vec2 X = w[0] * VertexUV(a, t, 0) + w[1] * VertexUV(a, t, 1) + w[2] * VertexUV(a, t, 2);
      const Vec2 Y = affine.A * X + affine.t;
      dev = std::max(dev, (EvaluateSpline(a, sa, t, X, 0).Value - EvaluateSpline(b, sb, t, Y, 0).Value).norm());
    }
  }
  return dev;
}
} // namespace ctk_test

#endif
