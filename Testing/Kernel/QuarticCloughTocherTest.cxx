// SPDX-License-Identifier: GPL-3.0-or-later
// Fang-Mann's quartic scheme: quadratic precision, C1 everywhere after every round, C2 across
// macro-edges right after exterior fairing (the paper's statement), and the paper's Table 1
// setting printed beside its figures.
#include "QuarticCloughTocher.h"
#include "RuleA.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

using namespace ctk;
using namespace ctk_test;

namespace
{
struct QuarticNet
{
  Vec3 P[15];
  Vec2 A[3];
};

QuarticNet Net(const SampledMesh& mesh, const QuarticSpline& s, Id t, int k)
{
  QuarticNet n;
  const std::array<Id, 15> ids = QuarticMicroNet(s.Layout, mesh.Topology, mesh.Triangles.data(), t, k);
  for (int a = 0; a < 15; ++a)
  {
    n.P[a] = s.ControlPoints[ids[a]];
  }
  n.A[0] = s.DomainPoints[ids[BezierIndex(4, 4, 0)]];
  n.A[1] = s.DomainPoints[ids[BezierIndex(4, 0, 4)]];
  n.A[2] = s.DomainPoints[ids[BezierIndex(4, 0, 0)]];
  return n;
}

// Largest C0..C2 jumps across micro-edges (micro) and interior macro-edges (macro).
struct Jumps
{
  double Micro[3] = { 0, 0, 0 }, Macro[3] = { 0, 0, 0 };
};

Jumps MeasureJumps(const SampledMesh& mesh, const QuarticSpline& s)
{
  Jumps J;
  auto check = [&](Id ta, int ka, Id tb, int kb, double* worst) {
    const QuarticNet a = Net(mesh, s, ta, ka), b = Net(mesh, s, tb, kb);
    double j[3];
    RuleAJumps(4, a.P, a.A, b.P, b.A, 2, j);
    for (int r = 0; r < 3; ++r)
    {
      worst[r] = std::max(worst[r], j[r]);
    }
  };
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      check(t, k, t, (k + 1) % 3, J.Micro);
    }
  }
  for (Id e = 0; e < static_cast<Id>(mesh.Topology.Edges.size()); ++e)
  {
    const auto& et = mesh.Topology.EdgeTriangles[e];
    if (et[1] >= 0)
    {
      const auto& el = mesh.Topology.EdgeLocalIndex[e];
      check(et[0], (el[0] + 2) % 3, et[1], (el[1] + 2) % 3, J.Macro);
    }
  }
  return J;
}

Vec3 Evaluate(const SampledMesh& mesh, const QuarticSpline& s, Id t, const Vec2& X)
{
  for (int k = 0; k < 3; ++k)
  {
    const QuarticNet n = Net(mesh, s, t, k);
    const Vec3 b = Barycentric(n.A[0], n.A[1], n.A[2], X);
    if (b.minCoeff() >= -1e-12 || k == 2)
    {
      return EvaluateBezierTriangle(4, n.P, nullptr, b).Value;
    }
  }
  return Vec3::Zero();
}

// Max and RMS of |spline - surface| (z only for functional data) over a dense grid in [0,1]^2.
template <typename Eval>
std::pair<double, double> GridErrors(const SampledMesh& mesh, Eval&& eval, AnalyticSurface f, int n)
{
  double mx = 0.0, sum = 0.0;
  long count = 0;
  for (Id t = 0; t < static_cast<Id>(mesh.Triangles.size() / 3); ++t)
  {
    Vec2 U[3];
    for (int i = 0; i < 3; ++i)
    {
      U[i] = Vec2(mesh.UV[2 * mesh.Triangles[3 * t + i]], mesh.UV[2 * mesh.Triangles[3 * t + i] + 1]);
    }
    for (int a = 0; a <= n; ++a)
    {
      for (int b = 0; a + b <= n; ++b)
      {
        const Vec2 X = U[0] + (double(a) * (U[1] - U[0]) + double(b) * (U[2] - U[0])) / n;
        const double d = std::abs(eval(t, X).z() - EvaluateAnalyticSurface(f, X.x(), X.y()).F.z());
        mx = std::max(mx, d);
        sum += d * d;
        ++count;
      }
    }
  }
  return { mx, std::sqrt(sum / count) };
}
} // namespace

TEST(QuarticCloughTocher, QuadraticPrecisionAndC1AfterEveryRound)
{
  for (const auto& entry : MeshSuite())
  {
    // A named copy: lambdas may not capture structured bindings in C++17 (clang rejects it).
    const std::string& name = entry.first;
    for (AnalyticSurface surface : { AnalyticSurface::Quadratic, AnalyticSurface::Franke })
    {
      const SampledMesh mesh = Sample(name, entry.second, surface);
      for (SplitPointRule sp : { SplitPointRule::Bary, SplitPointRule::Inc3 })
      {
        SplineOptions o{ Construction::FO, sp, BoundaryMode::Midpoint, 3 };
        QuarticSpline s;
        ASSERT_TRUE(BuildQuarticCloughTocher(mesh.Data(), mesh.Topology, o, s, SerialFor,
          [&](QuarticStage stage, int round, const QuarticSpline& cur) {
            const Jumps J = MeasureJumps(mesh, cur);
            // Edges whose eq. (7) is ill-conditioned (S' near a line S P, on irregular meshes)
            // are left unfaired, so the C2 claim is checked on the regular meshes.
            if (stage == QuarticStage::ExteriorFaired && name != "jittered")
            {
              // The paper: after exterior fairing the patches meet C2 across macro-edges.
              EXPECT_LT(J.Macro[1], 1e-12) << name << " round " << round;
              EXPECT_LT(J.Macro[2], 1e-11) << name << " round " << round;
            }
            if (stage == QuarticStage::Smoothed || stage == QuarticStage::DegreeRaised)
            {
              EXPECT_LT(J.Micro[0] + J.Macro[0], 1e-14) << name;
              EXPECT_LT(J.Micro[1], 1e-12) << name << " round " << round;
              EXPECT_LT(J.Macro[1], 1e-12) << name << " round " << round;
            }
          })
                      .Ok);
        if (surface == AnalyticSurface::Quadratic)
        {
          auto eval = [&](Id t, const Vec2& X) { return Evaluate(mesh, s, t, X); };
          EXPECT_LT(GridErrors(mesh, eval, surface, 4).first, 1e-12) << name;
        }
      }
    }
  }
}

TEST(QuarticCloughTocher, FangMannTable1Setting)
{
  // Franke's function on a 5 x 5 grid of [0, 1]^2 (both diagonal choices). The paper reports
  // max 0.0754 / 0.0752 / 0.0690 and RMS 0.0172 / 0.0166 / 0.0170 (cubic precision, Kashyap,
  // quartic); its sampling of the error is not stated, so the figures are printed side by side
  // and only their size is asserted.
  for (GridDiagonal d : { GridDiagonal::Forward, GridDiagonal::Backward })
  {
    const SampledMesh mesh = Sample("grid5", RegularGridMesh(4, d), AnalyticSurface::Franke);
    QuarticSpline degreeRaised, quartic;
    SplineOptions o{ Construction::FO, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 };
    ASSERT_TRUE(BuildQuarticCloughTocher(mesh.Data(), mesh.Topology, o, degreeRaised).Ok);
    o.Iterations = 5;
    ASSERT_TRUE(BuildQuarticCloughTocher(mesh.Data(), mesh.Topology, o, quartic).Ok);
    CubicSpline kashyap;
    SplineOptions ko{ Construction::Kashyap, SplitPointRule::Bary, BoundaryMode::Midpoint, 5 };
    ASSERT_TRUE(BuildCubicCloughTocher(mesh.Data(), mesh.Topology, ko, kashyap).Ok);
    const auto e0 = GridErrors(
      mesh, [&](Id t, const Vec2& X) { return Evaluate(mesh, degreeRaised, t, X); }, AnalyticSurface::Franke, 24);
    const auto ek = GridErrors(
      mesh, [&](Id t, const Vec2& X) { return EvaluateSpline(mesh, kashyap, t, X, 0).Value; }, AnalyticSurface::Franke, 24);
    const auto e1 = GridErrors(
      mesh, [&](Id t, const Vec2& X) { return Evaluate(mesh, quartic, t, X); }, AnalyticSurface::Franke, 24);
    std::printf("Franke 5x5 (%s diagonal): cubic precision max %.4f rms %.4f (paper 0.0754 / 0.0172); "
                "Kashyap max %.4f rms %.4f (paper 0.0752 / 0.0166); "
                "quartic max %.4f rms %.4f (paper 0.0690 / 0.0170)\n",
      d == GridDiagonal::Forward ? "forward" : "backward", e0.first, e0.second, ek.first, ek.second,
      e1.first, e1.second);
    EXPECT_LT(ek.first, 0.3);
    EXPECT_GT(e0.first, 0.01);
    EXPECT_LT(e0.first, 0.3);
    EXPECT_LT(e1.first, 0.3);
    EXPECT_LT(e1.second, 0.1);
  }
}

TEST(QuarticCloughTocher, StopsInsteadOfDivergingOnIrregularMeshes)
{
  // On strongly irregular meshes the rounds of Fig. 11 can amplify each other; the scheme then
  // stops (and says so) and the result stays a bounded C1 spline close to the data.
  const SampledMesh mesh = Sample("jittered", JitteredGrid(6, 0.45, 5u), AnalyticSurface::Franke);
  const SplineOptions o{ Construction::FO, SplitPointRule::Bary, BoundaryMode::Midpoint, 8 };
  QuarticSpline s;
  const BuildStatus st = BuildQuarticCloughTocher(mesh.Data(), mesh.Topology, o, s);
  ASSERT_TRUE(st.Ok) << st.Message;
  EXPECT_NE(st.Message.find("diverges"), std::string::npos) << st.Message;
  double largest = 0.0;
  for (const Vec3& p : s.ControlPoints)
  {
    largest = std::max(largest, std::abs(p.z()));
  }
  EXPECT_LT(largest, 3.0); // Franke's range is [0, 1.22]
  const Jumps J = MeasureJumps(mesh, s);
  EXPECT_LT(J.Micro[1], 1e-12);
  EXPECT_LT(J.Macro[1], 1e-12);
  // A regular mesh runs every round.
  const SampledMesh regular = Sample("grid", RegularGridMesh(5, GridDiagonal::Alternating), AnalyticSurface::Franke);
  QuarticSpline r;
  EXPECT_TRUE(BuildQuarticCloughTocher(regular.Data(), regular.Topology, o, r).Message.empty());
}

// As for the cubic constructions (CubicConstructions.EachTrianglesVertexOrderIsNoInput): every
// triangle rotated by t % 3 and every other triple reversed gives the same quartic spline.
TEST(QuarticCloughTocher, EachTrianglesVertexOrderIsNoInput)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const ParameterMesh permuted = WithTrianglesReordered(pm);
    const SampledMesh a = Sample(name, pm, AnalyticSurface::Franke);
    const SampledMesh b = Sample(name, permuted, AnalyticSurface::Franke);
    const SplineOptions o{ Construction::FO, SplitPointRule::Inc3, BoundaryMode::Midpoint, 3 };
    QuarticSpline sa, sb;
    ASSERT_TRUE(BuildQuarticCloughTocher(a.Data(), a.Topology, o, sa).Ok) << name;
    ASSERT_TRUE(BuildQuarticCloughTocher(b.Data(), b.Topology, o, sb).Ok) << name;
    double worst = 0.0;
    for (Id t = 0; t < pm.NumberOfTriangles(); ++t)
    {
      const Vec2 U0 = pm.UV[pm.Triangles[3 * t]], U1 = pm.UV[pm.Triangles[3 * t + 1]],
                 U2 = pm.UV[pm.Triangles[3 * t + 2]];
      for (const Vec3& w : { Vec3(0.2, 0.3, 0.5), Vec3(0.7, 0.15, 0.15), Vec3(0.05, 0.5, 0.45) })
      {
        const Vec2 X = w[0] * U0 + w[1] * U1 + w[2] * U2;
        worst = std::max(worst, (Evaluate(a, sa, t, X) - Evaluate(b, sb, t, X)).norm());
      }
    }
    EXPECT_LT(worst, 1e-12) << name;
  }
}
