// SPDX-License-Identifier: GPL-3.0-or-later
// The continuity measures across a shared edge: zero for one polynomial over both sides, the
// known C2 jump of a C1 join built by construction, jumps that follow a moved ordinate
// linearly, invariance under the parametrisation of the neighbour, and errors on bad input.
#include "EdgeContinuity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace ctk;

namespace
{
// The edge U0 U1; A over (U0, U1, U2) above it, B over (U1, U0, U3) below, as in eq. (7).
const Vec2 U0(0, 0), U1(1, 0), U2(0.4, 0.9), U3(0.6, -0.7);
// A cubic map F of the plane, given by its net over a reference triangle.
const Vec2 T0(-1, -2), T1(3, -1), T2(0, 3);

std::vector<Vec3> RandomCubic(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-0.3, 0.3);
  std::vector<Vec3> P;
  for (const auto& e : BezierExponents(3))
  {
    const Vec2 d = (e[0] * T0 + e[1] * T1 + e[2] * T2) / 3.0;
    P.emplace_back(d.x() + U(rng), d.y() + U(rng), 2 * U(rng)); // a graph-like, regular patch
  }
  return P;
}

// F's net of degree n >= 3 over the triangle (W0, W1, W2).
std::vector<Vec3> Over(
  const std::vector<Vec3>& F, int n, const Vec2& W0, const Vec2& W1, const Vec2& W2)
{
  std::vector<Vec3> P(BezierPointCount(n));
  SubTriangle(3, F.data(), Barycentric(T0, T1, T2, W0), Barycentric(T0, T1, T2, W1),
    Barycentric(T0, T1, T2, W2), P.data());
  for (int k = 3; k < n; ++k)
  {
    std::vector<Vec3> up(BezierPointCount(k + 1));
    ElevateDegree(k, P.data(), up.data());
    P = up;
  }
  return P;
}

EdgePatch Side(const std::vector<Vec3>& P, int n, const Vec2& W0, const Vec2& W1, const Vec2& W2,
  int p, int q)
{
  EdgePatch side;
  side.Degree = n;
  side.Points = P.data();
  side.Domain = { W0, W1, W2 };
  side.EdgeCorners = { p, q };
  return side;
}

// The standard pair: A = F over (U0, U1, U2), B = F over (U1, U0, U3) plus `extra` (by index).
struct Pair
{
  Pair(int nA, int nB, unsigned seed = 1)
    : F(RandomCubic(seed))
    , PA(Over(F, nA, U0, U1, U2))
    , PB(Over(F, nB, U1, U0, U3))
    , A(Side(PA, nA, U0, U1, U2, 0, 1))
    , B(Side(PB, nB, U1, U0, U3, 1, 0))
  {
  }
  EdgeContinuity Measure(const EdgeContinuityOptions& options = {})
  {
    A.Points = PA.data();
    B.Points = PB.data();
    const EdgeContinuity m = MeasureEdgeContinuity(A, B, options);
    EXPECT_TRUE(m.Error.empty()) << m.Error;
    return m;
  }
  std::vector<Vec3> F, PA, PB;
  EdgePatch A, B;
};
// B's apex is its corner 2: B's ordinate with exponents (i, j, k) lies in row k.
} // namespace

// One polynomial over both sides (degrees 3 to 5, elevated to the higher one): C-infinity, so
// every measure vanishes to round-off; eq. (7) is defined for two cubics only.
TEST(EdgeContinuity, OnePolynomialIsSmooth)
{
  for (int nA = 3; nA <= 5; ++nA)
  {
    for (int nB = 3; nB <= 5; ++nB)
    {
      Pair pair(nA, nB);
      const EdgeContinuity m = pair.Measure();
      EXPECT_LT(m.C0Gap, 1e-14) << nA << " " << nB;
      EXPECT_LT(m.C1Jump, 1e-14) << nA << " " << nB;
      EXPECT_LT(m.C2Jump, 1e-14) << nA << " " << nB;
      EXPECT_LT(m.G1Angle, 1e-5) << nA << " " << nB;
      if (nA == 3 && nB == 3)
      {
        EXPECT_LT(m.C2JumpEq7, 1e-14);
      }
      else
      {
        EXPECT_TRUE(std::isnan(m.C2JumpEq7));
      }
    }
  }
}

// B = F + c lambda^2 with lambda the barycentric coordinate of B's apex (zero on the edge): a C1
// join that is not C2. B's net gains c k (k - 1) / (n (n - 1)) in row k, so the C2 jump is
// 2 |c| / (n (n - 1)); eq. (7) differs by c times the cubic blossom of lambda^2 at
// (Ui, U2, U3), i.e. |c| |lambda(U2)| / 3. Both scale linearly with c.
TEST(EdgeContinuity, C1JoinByConstructionHasTheKnownC2Jump)
{
  const double lambdaU2 = Barycentric(U1, U0, U3, U2)[2];
  for (int n : { 3, 4, 6 })
  {
    for (double scale : { 1.0, 2.0, 1e-3 })
    {
      Pair pair(3, n);
      const Vec3 c = scale * Vec3(0.3, -0.2, 0.6);
      for (const auto& e : BezierExponents(n))
      {
        pair.PB[BezierIndex(n, e[0], e[1])] += c * double(e[2] * (e[2] - 1)) / (n * (n - 1));
      }
      const EdgeContinuity m = pair.Measure();
      EXPECT_LT(m.C0Gap, 1e-14) << n;
      EXPECT_LT(m.C1Jump, 1e-14) << n;
      EXPECT_LT(m.G1Angle, 1e-5) << n;
      EXPECT_NEAR(m.C2Jump, 2 * c.norm() / (n * (n - 1)), 1e-14) << n;
      if (n == 3)
      {
        EXPECT_NEAR(m.C2JumpEq7, c.norm() * std::abs(lambdaU2) / 3, 1e-14);
      }
    }
  }
}

// A moved ordinate of B: in row 0 the C0 gap, in row 1 the C1 jump is exactly the displacement;
// the G1 angle follows it linearly for small displacements.
TEST(EdgeContinuity, MovedOrdinateGivesLinearJumps)
{
  const Vec3 direction(0.1, -0.2, 1.0);
  double angle[2] = { 0, 0 };
  for (int k = 0; k < 2; ++k)
  {
    const double delta = 1e-5 * (k + 1);
    Pair pair(3, 3);
    pair.PB[BezierIndex(3, 1, 1)] += delta * direction; // the centre (1, 1, 1): row 1
    const EdgeContinuity m = pair.Measure();
    EXPECT_LT(m.C0Gap, 1e-14);
    EXPECT_NEAR(m.C1Jump, delta * direction.norm(), 1e-15);
    angle[k] = m.G1Angle;

    Pair gap(3, 4);
    gap.PB[BezierIndex(4, 2, 2)] += delta * direction; // an edge ordinate: row 0
    const EdgeContinuity g = gap.Measure();
    EXPECT_NEAR(g.C0Gap, delta * direction.norm(), 1e-15);
  }
  EXPECT_GT(angle[0], 1e-5);
  EXPECT_NEAR(angle[1] / angle[0], 2.0, 1e-3);
}

// B's parameters may be those of another face: any similarity of its true parameter triangle,
// direct or reflected, is mapped back onto A's edge and gives the same measures.
TEST(EdgeContinuity, NeighbourParametrisationDoesNotMatter)
{
  Pair pair(3, 3);
  pair.PB[BezierIndex(3, 1, 1)] += Vec3(1e-3, 2e-3, -3e-3);
  pair.PB[BezierIndex(3, 0, 1)] += Vec3(0, 0, 5e-3);
  const EdgeContinuity reference = pair.Measure();
  ASSERT_GT(reference.C1Jump, 1e-3);
  const double c = 1.7 * std::cos(0.4), s = 1.7 * std::sin(0.4);
  for (bool reflect : { false, true })
  {
    Pair moved = pair;
    for (Vec2& d : moved.B.Domain)
    {
      const Vec2 e = reflect ? Vec2(d.x(), -d.y()) : d;
      d = Vec2(c * e.x() - s * e.y() + 2.0, s * e.x() + c * e.y() - 1.0);
    }
    const EdgeContinuity m = moved.Measure();
    EXPECT_NEAR(m.C0Gap, reference.C0Gap, 1e-13) << reflect;
    EXPECT_NEAR(m.C1Jump, reference.C1Jump, 1e-13) << reflect;
    EXPECT_NEAR(m.C2Jump, reference.C2Jump, 1e-13) << reflect;
    EXPECT_NEAR(m.C2JumpEq7, reference.C2JumpEq7, 1e-13) << reflect;
    EXPECT_EQ(m.G1Angle, reference.G1Angle) << reflect; // from the nets alone

    Vec2 DA[3] = { U0, U1, U2 };
    Vec2 DB[3] = { moved.B.Domain[0], moved.B.Domain[1], moved.B.Domain[2] };
    MapDomainOntoEdge(DA, 0, 1, DB, 1, 0);
    for (int a = 0; a < 3; ++a)
    {
      const Vec2 expected = a == 0 ? U1 : a == 1 ? U0 : U3;
      EXPECT_NEAR((DB[a] - expected).norm(), 0, 1e-14) << reflect << " corner " << a;
    }
  }
}

// The same B with its corners listed in another order: Rule A is unchanged (same domain
// points), the normals of an odd permutation point the other way (G1 angle 180).
TEST(EdgeContinuity, CornerOrderOfTheNeighbour)
{
  Pair pair(3, 3);
  pair.PB[BezierIndex(3, 1, 1)] += Vec3(0, 0, 1e-3);
  const EdgeContinuity reference = pair.Measure();
  // B over (U0, U1, U3) (corners 0 and 1 swapped): the edge is (0, 1) on both sides now.
  Pair swapped = pair;
  swapped.PB = Over(swapped.F, 3, U0, U1, U3);
  swapped.PB[BezierIndex(3, 1, 1)] += Vec3(0, 0, 1e-3);
  swapped.B = Side(swapped.PB, 3, U0, U1, U3, 0, 1);
  const EdgeContinuity m = swapped.Measure();
  EXPECT_NEAR(m.C0Gap, reference.C0Gap, 1e-14);
  EXPECT_NEAR(m.C1Jump, reference.C1Jump, 1e-14);
  EXPECT_NEAR(m.C2Jump, reference.C2Jump, 1e-14);
  EXPECT_NEAR(m.C2JumpEq7, reference.C2JumpEq7, 1e-14);
  EXPECT_NEAR(m.G1Angle, 180.0, 0.5);
  EXPECT_LT(reference.G1Angle, 1.0);
  // The edge's corners listed the other way round on both sides: nothing changes.
  Pair reversed = pair;
  reversed.A.EdgeCorners = { 1, 0 };
  reversed.B.EdgeCorners = { 0, 1 };
  const EdgeContinuity r = reversed.Measure();
  EXPECT_EQ(r.C1Jump, reference.C1Jump);
  EXPECT_NEAR(r.G1Angle, reference.G1Angle, 1e-9);
}

TEST(EdgeContinuity, ReportsBadInput)
{
  Pair pair(3, 3);
  auto error = [&](EdgePatch A, EdgePatch B, EdgeContinuityOptions options = {}) {
    A.Points = pair.PA.data();
    return MeasureEdgeContinuity(A, B, options).Error;
  };
  EdgePatch flat = pair.B;
  flat.Domain[2] = 0.5 * (flat.Domain[0] + flat.Domain[1]); // collinear corners
  EXPECT_EQ(error(pair.A, flat), "side B: the parameter triangle has zero area in (u, v)");
  EdgePatch nan = pair.A;
  nan.Domain[0].x() = std::nan("");
  EXPECT_EQ(error(nan, pair.B), "side A: the parameter triangle has zero area in (u, v)");
  EdgePatch degree = pair.B;
  degree.Degree = MaxDegree + 1;
  EXPECT_EQ(error(pair.A, degree), "side B: degree 11 is not in 1..10");
  EdgePatch corners = pair.A;
  corners.EdgeCorners = { 2, 2 };
  EXPECT_EQ(
    error(corners, pair.B), "side A: edge corners (2, 2) are not two distinct corners 0..2");
  EdgePatch none = pair.B;
  none.Points = nullptr;
  EXPECT_EQ(error(pair.A, none), "side B: no control points");
  EdgeContinuityOptions options;
  options.G1Samples = 0;
  EXPECT_EQ(error(pair.A, pair.B, options), "G1Samples is 0; at least 1 is needed");
}
