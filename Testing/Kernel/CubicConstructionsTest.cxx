// SPDX-License-Identifier: GPL-3.0-or-later
// The non-local constructions of the study (Fa, FO, Ka, KaG), the IM iteration and Kashyap's
// fairing scheme: precision, C1, invariance and IM's convergence, measured on the output.
#include "AffineLeastSquares.h"
#include "CubicCloughTocher.h"
#include "MacroEdgeCubicPrecision.h"
#include "MicroEdgeC2Minimisation.h"
#include "RuleA.h"
#include "SplineMeasures.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace ctk;
using namespace ctk_test;

namespace
{
struct Variant
{
  Construction Method;
  BoundaryMode Boundary;
  int Iterations;
};

const Variant NonLocalVariants[] = {
  { Construction::Fa, BoundaryMode::Midpoint, 0 },
  { Construction::Fa, BoundaryMode::Perpendicular, 0 },
  { Construction::FO, BoundaryMode::Midpoint, 0 },
  { Construction::FO, BoundaryMode::GradientPerpendicular, 0 },
  { Construction::Ka, BoundaryMode::Midpoint, 0 },
  { Construction::Ka, BoundaryMode::Perpendicular, 0 },
  { Construction::KaG, BoundaryMode::GradientToSplitPoint, 0 },
  { Construction::KaG, BoundaryMode::GradientPerpendicular, 0 },
  { Construction::Kashyap, BoundaryMode::Midpoint, 3 },
  { Construction::CTi, BoundaryMode::Midpoint, 3 },
  { Construction::CTo, BoundaryMode::Midpoint, 2 },
  { Construction::Ka, BoundaryMode::GradientToSplitPoint, 4 },
};

SplineOptions Options(const Variant& v, SplitPointRule sp = SplitPointRule::Bary)
{
  return { v.Method, sp, v.Boundary, v.Iterations };
}
} // namespace

TEST(CubicConstructions, QuadraticPrecision)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::Quadratic);
    for (const Variant& v : NonLocalVariants)
    {
      for (SplitPointRule sp : { SplitPointRule::Bary, SplitPointRule::Inc2, SplitPointRule::Inc3 })
      {
        const SplineOptions o = Options(v, sp);
        const CubicSpline spline = BuildOrFail(mesh, o);
        EXPECT_LT(MaxError(mesh, spline, AnalyticSurface::Quadratic, false), 1e-13) << Describe(mesh, o);
      }
    }
  }
}

TEST(CubicConstructions, CubicPrecisionOfFOAndKaOnInteriorTriangles)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::FarinCubic);
    for (Construction c : { Construction::FO, Construction::Ka })
    {
      for (SplitPointRule sp : { SplitPointRule::Bary, SplitPointRule::Inc3 })
      {
        const SplineOptions o{ c, sp, BoundaryMode::Midpoint, 0 };
        const CubicSpline spline = BuildOrFail(mesh, o);
        EXPECT_LT(MaxError(mesh, spline, AnalyticSurface::FarinCubic, true), 1e-13) << Describe(mesh, o);
        // Boundary triangles use the quadratic-precision boundary rule: visibly not exact.
        EXPECT_GT(MaxError(mesh, spline, AnalyticSurface::FarinCubic, false), 1e-10) << Describe(mesh, o);
      }
    }
    // Fa has quadratic precision only, even inside (on irregular meshes; regular ones are
    // symmetric enough for its C2 minimisation to find the cubic).
    const SplineOptions fa{ Construction::Fa, SplitPointRule::Bary, BoundaryMode::Midpoint, 0 };
    if (name == "jittered")
    {
      EXPECT_GT(MaxError(mesh, BuildOrFail(mesh, fa), AnalyticSurface::FarinCubic, true), 1e-10);
    }
  }
}

TEST(CubicConstructions, KaGIsExactEverywhereWithMidEdgeGradients)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::FarinCubic);
    for (BoundaryMode b : { BoundaryMode::GradientToSplitPoint, BoundaryMode::GradientPerpendicular,
           BoundaryMode::Midpoint /* KaG overrides a non-gradient mode */ })
    {
      const SplineOptions o{ Construction::KaG, SplitPointRule::Inc3, b, 0 };
      EXPECT_LT(MaxError(mesh, BuildOrFail(mesh, o), AnalyticSurface::FarinCubic, false), 1e-12)
        << Describe(mesh, o);
    }
  }
}

TEST(CubicConstructions, C1AcrossEveryEdgeIncludingAfterIterations)
{
  for (const auto& [name, pm] : MeshSuite())
  {
    const SampledMesh mesh = Sample(name, pm, AnalyticSurface::Franke);
    for (const Variant& v : NonLocalVariants)
    {
      for (SplitPointRule sp : { SplitPointRule::Bary, SplitPointRule::Inc2, SplitPointRule::Inc3 })
      {
        ExpectC1ButNotC2(mesh, Options(v, sp));
      }
    }
  }
}

// How a triangle lists its vertices is no input of any construction: every triangle rotated by
// t % 3 and, every other triple, reversed (so that interior edges also run the same way in both
// of their triangles, the case the edge-based rules read from the vertex ids) gives the same
// spline to round-off, evaluated at the same parameter points.
TEST(CubicConstructions, EachTrianglesVertexOrderIsNoInput)
{
  std::vector<Variant> variants(std::begin(NonLocalVariants), std::end(NonLocalVariants));
  for (Construction c : { Construction::CTo, Construction::CTi, Construction::MGo, Construction::MGi })
  {
    variants.push_back({ c, BoundaryMode::Midpoint, 0 });
  }
  for (const auto& [name, pm] : MeshSuite())
  {
    const ParameterMesh permuted = WithTrianglesReordered(pm);
    const SampledMesh a = Sample(name, pm, AnalyticSurface::Franke);
    const SampledMesh b = Sample(name, permuted, AnalyticSurface::Franke);
    const Vec3 at[3] = { Vec3(0.2, 0.3, 0.5), Vec3(0.7, 0.15, 0.15), Vec3(0.05, 0.5, 0.45) };
    for (const Variant& v : variants)
    {
      const SplineOptions o = Options(v, SplitPointRule::Inc2);
      const CubicSpline sa = BuildOrFail(a, o), sb = BuildOrFail(b, o);
      double worst = 0.0;
      for (Id t = 0; t < pm.NumberOfTriangles(); ++t)
      {
        for (const Vec3& w : at)
        {
          const Vec2 X = w[0] * VertexUV(a, t, 0) + w[1] * VertexUV(a, t, 1) + w[2] * VertexUV(a, t, 2);
          const ParametricJet ja = EvaluateSpline(a, sa, t, X), jb = EvaluateSpline(b, sb, t, X);
          worst = std::max({ worst, (ja.Value - jb.Value).norm(), (ja.Du - jb.Du).norm(),
            (ja.Dv - jb.Dv).norm() });
        }
      }
      EXPECT_LT(worst, 1e-12) << Describe(a, o);
    }
  }
}

TEST(CubicConstructions, AffineInvariance)
{
  const ParameterMesh pm = JitteredGrid(5, 0.3, 31u);
  Affine affine;
  affine.A << 0.4, -1.1, 0.9, 0.6;
  affine.t = Vec2(-2.0, 0.5);
  const SampledMesh a = Sample("jittered", pm, AnalyticSurface::Franke);
  const SampledMesh b = Sample("jittered-affine", pm, AnalyticSurface::Franke, affine);
  for (Construction c : { Construction::Fa, Construction::FO, Construction::Ka, Construction::KaG,
         Construction::Kashyap })
  {
    for (SplitPointRule sp : { SplitPointRule::Bary, SplitPointRule::Inc3, SplitPointRule::Inc2 })
    {
      for (int iterations : { 0, 3 })
      {
        const SplineOptions o{ c, sp, BoundaryMode::GradientToSplitPoint, iterations };
        const double dev = MaxDeviation(a, BuildOrFail(a, o), b, BuildOrFail(b, o), affine);
        if (sp == SplitPointRule::Inc2)
        {
          EXPECT_GT(dev, 1e-5) << Describe(a, o);
        }
        else
        {
          EXPECT_LT(dev, 1e-12) << Describe(a, o) << " iterations " << iterations;
        }
      }
    }
  }
}

TEST(CubicConstructions, IMConvergesToTheCubicWithExactBoundaryGradients)
{
  // Farin's cubic, boundary edges fixed by exact mid-edge gradients: IM drives the
  // quadratic-precision constructions to the cubic, leaves KaG exact. (CTo and MGo are local
  // and take no boundary mode.)
  const SampledMesh mesh = Sample("jittered", JitteredGrid(4, 0.25, 3u), AnalyticSurface::FarinCubic);
  for (Construction c : { Construction::CTi, Construction::Fa })
  {
    const SplineOptions o0{ c, SplitPointRule::Bary, BoundaryMode::GradientToSplitPoint, 0 };
    SplineOptions o20 = o0, o40 = o0;
    o20.Iterations = 20;
    o40.Iterations = 40;
    const double e0 = MaxError(mesh, BuildOrFail(mesh, o0), AnalyticSurface::FarinCubic, false);
    const double e20 = MaxError(mesh, BuildOrFail(mesh, o20), AnalyticSurface::FarinCubic, false);
    const double e40 = MaxError(mesh, BuildOrFail(mesh, o40), AnalyticSurface::FarinCubic, false);
    std::cout << ToString(c) << " IM error: 0 steps " << e0 << ", 20 steps " << e20
              << ", 40 steps " << e40 << "\n";
    EXPECT_GT(e0, 1e-4) << ToString(c);
    EXPECT_LT(e20, 1e-3 * e0) << ToString(c);
    EXPECT_LT(e40, 1e-9) << ToString(c);
  }
  const SplineOptions kag{ Construction::KaG, SplitPointRule::Bary, BoundaryMode::GradientToSplitPoint, 40 };
  EXPECT_LT(MaxError(mesh, BuildOrFail(mesh, kag), AnalyticSurface::FarinCubic, false), 1e-12);
}

TEST(CubicConstructions, IMStallsAndSpreadsBoundaryErrorWithoutBoundaryGradients)
{
  const SampledMesh mesh = Sample("jittered", JitteredGrid(4, 0.25, 3u), AnalyticSurface::FarinCubic);
  for (BoundaryMode b : { BoundaryMode::Midpoint, BoundaryMode::Perpendicular })
  {
    // CTi stalls: the boundary rule keeps an O(h^3) error that IM cannot remove.
    const SplineOptions cti{ Construction::CTi, SplitPointRule::Bary, b, 40 };
    EXPECT_GT(MaxError(mesh, BuildOrFail(mesh, cti), AnalyticSurface::FarinCubic, false), 1e-5);
    // Ka is exact inside before IM; IM spreads the boundary error into the interior.
    SplineOptions ka{ Construction::Ka, SplitPointRule::Bary, b, 0 };
    EXPECT_LT(MaxError(mesh, BuildOrFail(mesh, ka), AnalyticSurface::FarinCubic, true), 1e-13);
    ka.Iterations = 20;
    const double spread = MaxError(mesh, BuildOrFail(mesh, ka), AnalyticSurface::FarinCubic, true);
    std::cout << "Ka interior error after 20 IM steps, boundary " << ToString(b) << ": " << spread << "\n";
    EXPECT_GT(spread, 1e-6);
  }
}

TEST(CubicConstructions, FOAgreesWithThePrintedClosedForm)
{
  // Eq. (22): with U3 = t0 U2 + t1 U0 + t2 U1, Q = (T30 - t1^2 V0 - 2 t1 t2 T01 - 2 t0 t1 T02
  // - t2^2 T10 - t0^2 T20 + T31 - t1^2 T01 - 2 t1 t2 T10 - 2 t0 t2 T12 - t2^2 V1 - t0^2 T21)
  // / (2 t0 (t1 + t2)).
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> R(-1.0, 1.0);
  auto rnd = [&] { return Vec3(R(rng), R(rng), R(rng)); };
  const Vec2 A[3] = { Vec2(0, 0), Vec2(1, 0.1), Vec2(0.3, 0.9) };
  const Vec2 U3(0.9, -0.7);
  const Vec2 B[3] = { A[1], A[0], U3 };
  const Vec3 V0 = rnd(), V1 = rnd(), V2 = rnd(), T01 = rnd(), T10 = rnd(), T02 = rnd(), T20 = rnd(),
             T12 = rnd(), T21 = rnd(), T30 = rnd(), T31 = rnd(), V3 = rnd();
  const Vec3 macroT[10] = { V0, T01, T02, T10, Vec3::Zero(), T20, V1, T12, T21, V2 };
  // Tbar over (U1, U0, U3): exponents 300=V1 210=T10 201=T13 120=T01 111=Qbar 102=T31 030=V0
  // 021=T03 012=T30 003=V3; only T30 and T31 (row 2 at U3) enter.
  const Vec3 macroTbar[10] = { V1, T10, rnd(), T01, rnd(), T31, V0, rnd(), T30, V3 };
  const Vec3 b = Barycentric(A[2], A[0], A[1], U3);
  const double t0 = b[0], t1 = b[1], t2 = b[2];
  const Vec3 printed = (T30 - t1 * t1 * V0 - 2 * t1 * t2 * T01 - 2 * t0 * t1 * T02 - t2 * t2 * T10 -
                         t0 * t0 * T20 + T31 - t1 * t1 * T01 - 2 * t1 * t2 * T10 -
                         2 * t0 * t2 * T12 - t2 * t2 * V1 - t0 * t0 * T21) /
    (2 * t0 * (t1 + t2));
  SharedCubicEdge edge;
  const Vec3 ours = MacroEdgeQ(MacroEdgeRule::ZeroResidualSum, macroT, A, macroTbar, B, edge);
  EXPECT_LT((ours - printed).norm(), 1e-12 * printed.norm());
}

namespace
{
// Reference for the closed forms: the step solved from its definition, the Rule A residuals of
// row 2 evaluated by blossoming (RuleAResiduals) and SolveAffineResiduals; the tie by the full
// blossom (TiedCubicCentre).
Vec3 RuleAReferenceCentre(const Vec3* PA, const Vec2* A, const Vec3* PB, const Vec2* B,
  bool sumToZero)
{
  Vec3 net[10];
  std::copy(PA, PA + 10, net);
  auto residuals = [&](const Vec3& X, Vec3* out) {
    net[CubicCentre] = X;
    RuleAResiduals(3, net, A, PB, B, 2, out);
  };
  return SolveAffineResiduals(residuals, 2, sumToZero);
}

double RelativeError(const Vec3& a, const Vec3& b)
{
  return (a - b).norm() / std::max(1.0, b.norm());
}
} // namespace

TEST(CubicConstructions, ClosedFormsAgreeWithTheRuleAMinimisation)
{
  // Random triangle pairs sharing an edge (both orientations of the neighbour, every edge of T),
  // random nets: Fa's micro-edge step, FO's and Ka's macro-edge Q and their C1 ties, and the
  // micro-net of a macro-patch, against the generic definitions.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> R(-1.0, 1.0);
  auto pt = [&] { return Vec2(R(rng), R(rng)); };
  double worst = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial)
  {
    Vec3 PA[10], PB[10];
    for (int a = 0; a < 10; ++a)
    {
      PA[a] = Vec3(R(rng), R(rng), R(rng));
      PB[a] = Vec3(R(rng), R(rng), R(rng));
    }
    const Vec2 A[3] = { pt(), pt(), pt() };
    if (std::abs(SignedArea2(A[0], A[1], A[2])) < 0.05)
    {
      continue;
    }
    const int l = trial % 3, flip = (trial / 3) % 2, rot = (trial / 6) % 3;
    // B: T's edge (l, l+1), reversed unless flip, and an off-edge vertex, rotated by rot.
    const Vec2 edge0 = A[flip ? l : (l + 1) % 3], edge1 = A[flip ? (l + 1) % 3 : l];
    const Vec2 off =
      0.5 * (edge0 + edge1) - (0.4 + std::abs(R(rng))) * (A[(l + 2) % 3] - edge0) + 0.3 * pt();
    const Vec2 AM[3] = { A[l], A[(l + 1) % 3], (A[0] + A[1] + A[2]) / 3.0 };
    if (std::abs(Barycentric(A[0], A[1], A[2], off)[(l + 2) % 3]) < 0.1 ||
      std::abs(Barycentric(AM[0], AM[1], AM[2], off)[2]) < 0.1)
    {
      continue; // the off-edge vertex (nearly) on the edge's line: ill-conditioned
    }
    ++checked;
    const Vec2 B0[3] = { edge0, edge1, off };
    const Vec2 B[3] = { B0[rot], B0[(rot + 1) % 3], B0[(rot + 2) % 3] };
    for (const bool sumToZero : { true, false })
    {
      const MacroEdgeRule rule =
        sumToZero ? MacroEdgeRule::ZeroResidualSum : MacroEdgeRule::LeastSquares;
      SharedCubicEdge edge;
      const Vec3 Q = MacroEdgeQ(rule, PA, A, PB, B, edge);
      worst = std::max(worst, RelativeError(Q, RuleAReferenceCentre(PA, A, PB, B, sumToZero)));
      Vec3 net[10];
      std::copy(PA, PA + 10, net);
      net[CubicCentre] = Q;
      worst = std::max(worst,
        RelativeError(CubicRuleARow1(PA, Q, edge.A, edge.B, edge.X), TiedCubicCentre(net, A, B)));
    }
    // Fa's step on micro-triangles: AM = (U_l, U_l+1, Z), AMbar = (edge, Zbar) as the builder
    // passes them (and rotated).
    Vec3 C, Cbar;
    MinimiseMicroEdgeC2Jump(PA, AM, PB, B, C, Cbar);
    const Vec3 refC = RuleAReferenceCentre(PA, AM, PB, B, false);
    Vec3 net[10];
    std::copy(PA, PA + 10, net);
    net[CubicCentre] = refC;
    worst = std::max(worst, RelativeError(C, refC));
    worst = std::max(worst, RelativeError(Cbar, TiedCubicCentre(net, AM, B)));
    // Fa's step straight from the macro-patches (FaMicroEdgeCentres) against the same step on
    // their micro-nets, subdivided at split points inside T and Tbar.
    Vec3 tau(0.2 + 0.5 * std::abs(R(rng)), 0.2, 0.0);
    tau[2] = 1.0 - tau[0] - tau[1];
    const Vec3 tauBar(0.25, 0.15 + 0.4 * std::abs(R(rng)), 0.3);
    const Vec3 tauBarN = tauBar / tauBar.sum();
    const int lBar = (3 - rot) % 3; // B[lBar] = edge0, B[lBar + 1] = edge1
    const Vec2 Z = tau[0] * A[0] + tau[1] * A[1] + tau[2] * A[2];
    const Vec2 Zbar = tauBarN[0] * B[0] + tauBarN[1] * B[1] + tauBarN[2] * B[2];
    const Vec2 AZ[3] = { A[l], A[(l + 1) % 3], Z };
    const Vec2 BZ[3] = { B[lBar], B[(lBar + 1) % 3], Zbar };
    Vec3 PM[10], PMbar[10];
    SubTriangle(3, PA, Vec3::Unit(l), Vec3::Unit((l + 1) % 3), tau, PM);
    SubTriangle(3, PB, Vec3::Unit(lBar), Vec3::Unit((lBar + 1) % 3), tauBarN, PMbar);
    Vec3 subC, subCbar, faC, faCbar;
    MinimiseMicroEdgeC2Jump(PM, AZ, PMbar, BZ, subC, subCbar);
    FaMicroEdgeCentres({ PA, l, tau }, { PB, lBar, tauBarN }, flip == 1,
      Barycentric(AZ[0], AZ[1], AZ[2], Zbar), faC, faCbar);
    worst = std::max(worst, RelativeError(faC, subC));
    worst = std::max(worst, RelativeError(faCbar, subCbar));
    worst = std::max(worst, RelativeError(faC, RuleAReferenceCentre(PM, AZ, PMbar, BZ, false)));
  }
  EXPECT_GT(checked, 100);
  EXPECT_LT(worst, 1e-12);
  // Not a shared edge: a clear NaN, never a silent value.
  const Vec2 A[3] = { Vec2(0, 0), Vec2(1, 0), Vec2(0, 1) };
  const Vec2 B[3] = { Vec2(1, 0), Vec2(0, 1e-3), Vec2(1, -1) };
  Vec3 P[10];
  std::fill(P, P + 10, Vec3::Ones());
  SharedCubicEdge edge;
  EXPECT_TRUE(MacroEdgeQ(MacroEdgeRule::LeastSquares, P, A, P, B, edge).hasNaN());
}
