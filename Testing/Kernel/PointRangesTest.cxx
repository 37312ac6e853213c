// SPDX-License-Identifier: GPL-3.0-or-later
#include "CubicCloughTocher.h"
#include "LocalityOrder.h"
#include "PointRanges.h"
#include "SplineMeasures.h"
#include "TestMeshes.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace ctk;
using namespace ctk_test;

namespace
{
// The ranges by their definition, one point after the other. The products go through volatile
// doubles, so that no compiler fuses them with the sums (VTK's sums are of rounded squares).
PointRanges Reference(const double* p, int nc, Id n)
{
  PointRanges r(nc);
  for (Id i = 0; i < n; ++i)
  {
    double s = 0.0;
    for (int c = 0; c < nc; ++c)
    {
      const double x = p[nc * i + c];
      r.Lo[c] = std::min(r.Lo[c], x);
      r.Hi[c] = std::max(r.Hi[c], x);
      volatile double square = x * x;
      s += square;
    }
    r.SquaredNormLo = std::min(r.SquaredNormLo, s);
    r.SquaredNormHi = std::max(r.SquaredNormHi, s);
  }
  return r;
}

// Values of every magnitude and sign, zeros of both signs among them.
std::vector<double> RandomValues(size_t n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40), kind(0, 19);
  std::vector<double> v(n);
  for (double& x : v)
  {
    const int k = kind(rng);
    x = k == 0 ? 0.0 : k == 1 ? -0.0 : std::ldexp(mantissa(rng), exponent(rng));
  }
  return v;
}

// Runs body(name) with the scans on each instruction set this CPU has (AVX2, SSE2, none), then
// restores the best.
template <typename Body>
void ForEachISA(Body&& body)
{
  const PointRangeISA best = SetPointRangeISA(PointRangeISA::AVX2);
#if defined(__x86_64__) && defined(__GNUC__)
  // The build gives x86-64 its AVX2 loop (PointRangesAVX2.cxx), and SSE2 is always there.
  ASSERT_EQ(best, __builtin_cpu_supports("avx2") ? PointRangeISA::AVX2 : PointRangeISA::SSE2);
#endif
  for (PointRangeISA isa : { PointRangeISA::AVX2, PointRangeISA::SSE2, PointRangeISA::Scalar })
  {
    if (static_cast<int>(isa) <= static_cast<int>(best))
    {
      SetPointRangeISA(isa);
      body(isa == PointRangeISA::AVX2 ? "AVX2, " : isa == PointRangeISA::SSE2 ? "SSE2, " : "scalar, ");
    }
  }
  SetPointRangeISA(best);
}

void ExpectSame(const PointRanges& a, const PointRanges& b, const std::string& what)
{
  ASSERT_EQ(a.Components, b.Components) << what;
  for (int c = 0; c < a.Components; ++c)
  {
    EXPECT_EQ(a.Lo[c], b.Lo[c]) << what << " component " << c; // -0 == +0: the sign may differ
    EXPECT_EQ(a.Hi[c], b.Hi[c]) << what << " component " << c;
  }
  EXPECT_EQ(a.SquaredNormLo, b.SquaredNormLo) << what;
  EXPECT_EQ(a.SquaredNormHi, b.SquaredNormHi) << what;
  EXPECT_EQ(a.NaN, b.NaN) << what;
}
} // namespace

// Every count (the vector loops take four or two points at a time, the rest goes one by one)
// and every position of the extremes, on every instruction set: the bits of the definition.
TEST(PointRanges, ScanGivesTheDefinitionsBits)
{
  ForEachISA([](const std::string& isa) {
    for (int nc : { 2, 3 })
    {
      for (Id n = 0; n <= 41; ++n)
      {
        for (unsigned seed = 0; seed < 8; ++seed)
        {
          const std::vector<double> v = RandomValues(static_cast<size_t>(nc * n), 97 * seed + n);
          ExpectSame(ScanPointRanges(v.data(), nc, n), Reference(v.data(), nc, n),
            isa + std::to_string(nc) + " components, " + std::to_string(n) + " points");
        }
      }
    }
  });
}

// Blocks added to one scan, or scanned apart and merged in another order, give one scan's ranges.
TEST(PointRanges, BlocksAndMergesGiveOneScansRanges)
{
  ForEachISA([](const std::string& isa) {
    std::mt19937 rng(7u);
    for (int nc : { 2, 3 })
    {
      const Id n = 5000;
      const std::vector<double> v = RandomValues(static_cast<size_t>(nc * n), 11u + nc);
      PointRangeScan blocks(nc);
      PointRanges merged(nc);
      std::uniform_int_distribution<Id> length(0, 70);
      std::vector<std::pair<Id, Id>> pieces;
      for (Id b = 0; b < n;)
      {
        const Id e = std::min(n, b + length(rng));
        blocks.Add(v.data() + nc * b, e - b);
        pieces.emplace_back(b, e);
        b = e;
      }
      std::shuffle(pieces.begin(), pieces.end(), rng);
      for (const auto& piece : pieces)
      {
        merged.Merge(ScanPointRanges(v.data() + nc * piece.first, nc, piece.second - piece.first));
      }
      const PointRanges whole = Reference(v.data(), nc, n);
      ExpectSame(blocks.Result(), whole, isa + "blocks of " + std::to_string(nc));
      ExpectSame(merged, whole, isa + "merged pieces of " + std::to_string(nc));
    }
  });
}

// A NaN anywhere is reported; inf shows in the extremes and the norms.
TEST(PointRanges, NaNIsReportedAndInfShows)
{
  ForEachISA([](const std::string& isa) {
    for (int nc : { 2, 3 })
    {
      const Id n = 23;
      for (Id at = 0; at < nc * n; ++at)
      {
        std::vector<double> v = RandomValues(static_cast<size_t>(nc * n), 3u);
        v[at] = std::numeric_limits<double>::quiet_NaN();
        EXPECT_TRUE(ScanPointRanges(v.data(), nc, n).NaN) << isa << nc << " components, value " << at;
        v[at] = -std::numeric_limits<double>::infinity();
        const PointRanges r = ScanPointRanges(v.data(), nc, n);
        EXPECT_FALSE(r.NaN) << isa << at;
        EXPECT_EQ(r.Lo[at % nc], -std::numeric_limits<double>::infinity()) << isa << at;
        EXPECT_EQ(r.SquaredNormHi, std::numeric_limits<double>::infinity()) << isa << at;
      }
    }
  });
}

namespace
{
// Each block of CubicSpline::BlockRanges has the ranges of its points, and the blocks cover
// every point once.
void ExpectBlocksCoverPoints(const CubicSpline& spline, const std::string& what)
{
  const Id n = static_cast<Id>(spline.ControlPoints.size());
  std::vector<int> seen(static_cast<size_t>(n), 0);
  for (const PointBlockRanges& b : spline.BlockRanges)
  {
    ASSERT_TRUE(b.First >= 0 && b.Count > 0 && b.First + b.Count <= n) << what;
    for (Id p = b.First; p < b.First + b.Count; ++p)
    {
      ++seen[static_cast<size_t>(p)];
    }
    const std::string block = what + ", block at " + std::to_string(b.First);
    ExpectSame(b.Points, Reference(spline.ControlPoints[b.First].data(), 3, b.Count), block);
    ExpectSame(b.Domain, Reference(spline.DomainPoints[b.First].data(), 2, b.Count), block);
  }
  if (!spline.BlockRanges.empty())
  {
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), n) << what << ": each point in one block";
  }
}
} // namespace

// The construction's ranges are those of the points it returns, for the rules scanned in their
// main pass and in a second one (edge-based), with and without boundary curve points, split into
// chunks in any order, and with ScanBlockRanges each block's; none without ScanRanges, after IM
// steps, Kashyap's fairing or with the kernel's own locality order, which write or visit the
// points otherwise.
TEST(PointRanges, ConstructionsGiveTheRangesOfTheirPoints)
{
  const SampledMesh mesh =
    Sample("jittered", JitteredGrid(128, 0.3, 5u), AnalyticSurface::Franke);
  const bool reordered = !TriangleLocalityOrder(mesh.NumberOfVertices(), mesh.NumberOfTriangles(),
    mesh.Triangles.data(), mesh.UV.data()).empty();
  ASSERT_TRUE(reordered) << "the locality order's route needs a mesh it renumbers";
  // Boundary curve points beyond the surface's box on every boundary edge: the control points'
  // extremes, which a route that scanned the edge points before they were written would miss.
  SampledMesh curved = mesh;
  const Id nT = mesh.NumberOfTriangles();
  curved.BoundaryCurvePoints.assign(
    static_cast<size_t>(18 * nT), std::numeric_limits<double>::quiet_NaN());
  Id boundaryEdges = 0;
  for (Id e = 0; e < static_cast<Id>(mesh.Topology.Edges.size()); ++e)
  {
    if (mesh.Topology.IsBoundaryEdge(e))
    {
      const Id t = mesh.Topology.EdgeTriangles[e][0];
      double* c = curved.BoundaryCurvePoints.data() + 18 * t + 6 * mesh.Topology.EdgeLocalIndex[e][0];
      for (int k = 0; k < 6; ++k)
      {
        c[k] = (k % 2 ? -20.0 : 20.0) + 1e-3 * double(e);
      }
      ++boundaryEdges;
    }
  }
  ASSERT_GT(boundaryEdges, 0);
  for (const SampledMesh* input : { &mesh, static_cast<const SampledMesh*>(&curved) })
  {
    for (const Construction c : { Construction::CTo, Construction::CTi, Construction::MGo,
           Construction::MGi, Construction::Fa, Construction::FO, Construction::Ka,
           Construction::KaG, Construction::Kashyap })
    {
      for (int iterations : { 0, 1 })
      {
        for (int route = 0; route < 4; ++route) // scanned, not asked, locality order, blocks
        {
          SplineOptions o{ c, SplitPointRule::Inc3, BoundaryMode::Midpoint, iterations };
          o.ScanRanges = route != 1;
          o.LocalityOrder = route == 2;
          o.ScanBlockRanges = route >= 2;
          CubicSpline spline;
          ASSERT_TRUE(
            BuildCubicCloughTocher(input->Data(), input->Topology, o, spline, ThreadedFor(2, 37))
              .Ok);
          const std::string what = std::string(ToString(c)) + ", " +
            std::to_string(iterations) + " iterations, route " + std::to_string(route) +
            (input == &curved ? ", boundary curve points" : "");
          const Id n = static_cast<Id>(spline.ControlPoints.size());
          if (iterations > 0 || c == Construction::Kashyap || route == 1 || route == 2)
          {
            EXPECT_EQ(spline.ControlPointRanges.Components, 0) << what;
            EXPECT_EQ(spline.DomainPointRanges.Components, 0) << what;
            EXPECT_TRUE(spline.BlockRanges.empty()) << what;
            continue;
          }
          EXPECT_EQ(spline.BlockRanges.empty(), route == 0) << what;
          ExpectBlocksCoverPoints(spline, what);
          const PointRanges points = Reference(spline.ControlPoints.data()->data(), 3, n);
          if (input == &curved)
          {
            ASSERT_GE(points.Hi[0], 20.0) << what << ": the curve points are the extremes";
          }
          ExpectSame(spline.ControlPointRanges, points, what + ", control points");
          ExpectSame(spline.DomainPointRanges,
            Reference(spline.DomainPoints.data()->data(), 2, n), what + ", domain points");
        }
      }
    }
  }
}
