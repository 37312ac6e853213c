// SPDX-License-Identifier: GPL-3.0-or-later
// Bad input to the kernel, one case per crash class found by fuzzing (issue 13): duplicate
// triangles, folded parameterisations, values large enough to overflow, a parameter box that
// overflows the locator, distances that overflow CGAL, and non-finite results. Each must give
// a failed status naming the offending element, never a crash or NaN output.
#include "ParameterLocator.h"
#include "PointToMeshDistance.h"
#include "QuarticCloughTocher.h"
#include "SplineDataValidation.h"
#include "LocalityOrder.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <tuple>
#include <utility>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace ctk_test;

namespace
{
// Two triangles on edge (1, 2): (0, 1, 2) and (1, 3, 2), a unit square split by its diagonal.
SampledMesh Square()
{
  ParameterMesh m;
  m.UV = { Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(1, 1) };
  m.Triangles = { 0, 1, 2, 1, 3, 2 };
  SampledMesh s = Sample("square", m, AnalyticSurface::Franke);
  BuildMeshTopology(4, 2, s.Triangles.data(), s.Topology);
  return s;
}

// Every construction, then the quartic scheme; returns the messages of failed builds.
std::vector<std::string> FailuresOfAllConstructions(const SampledMesh& mesh)
{
  std::vector<std::string> messages;
  for (int c = 0; c <= static_cast<int>(Construction::Kashyap); ++c)
  {
    SplineOptions options;
    options.Method = static_cast<Construction>(c);
    CubicSpline spline;
    const BuildStatus s = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, options, spline);
    messages.push_back(s.Ok ? std::string() : s.Message);
  }
  QuarticSpline quartic;
  SplineOptions options;
  options.Iterations = 2;
  const BuildStatus s = BuildQuarticCloughTocher(mesh.Data(), mesh.Topology, options, quartic);
  messages.push_back(s.Ok ? std::string() : s.Message);
  return messages;
}
} // namespace

TEST(InputValidation, ValidSquareBuildsEverywhere)
{
  for (const std::string& m : FailuresOfAllConstructions(Square()))
  {
    EXPECT_EQ(m, "");
  }
}

TEST(InputValidation, DuplicateTrianglesAreRejectedByName)
{
  // A triangle and its copy (reversed or not) share all three edges: each edge has two
  // triangles, so it looked manifold, and the Bézier extraction then read EdgeTriangles[-1].
  // (A duplicate with other neighbours is a non-manifold edge, reported as such.)
  for (const std::vector<Id>& tris : { std::vector<Id>{ 0, 1, 2, 0, 2, 1 },
         std::vector<Id>{ 3, 4, 5, 0, 1, 2, 2, 1, 0 }, std::vector<Id>{ 0, 1, 2, 1, 2, 0 } })
  {
    MeshTopology topo;
    const Id nT = static_cast<Id>(tris.size() / 3);
    const TopologyStatus s = BuildMeshTopology(6, nT, tris.data(), topo);
    EXPECT_FALSE(s.Ok);
    EXPECT_EQ(s.Triangle, nT - 1);
    const std::string pair =
      "duplicate triangles " + std::to_string(nT - 2) + " and " + std::to_string(nT - 1);
    EXPECT_NE(s.Message.find(pair), std::string::npos) << s.Message;
  }
}

TEST(InputValidation, FoldedParameterisationIsRejectedByName)
{
  // Vertex 3 moved across edge (1, 2): both triangles now lie on the same side of it in (u, v).
  SampledMesh mesh = Square();
  mesh.UV[6] = 0.2;
  mesh.UV[7] = 0.3;
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_NE(m.find("folded parameterisation: triangles 0 and 1"), std::string::npos) << m;
    EXPECT_NE(m.find("edge (1, 2)"), std::string::npos) << m;
  }
}

TEST(InputValidation, MixedTriangleOrientationIsNoFold)
{
  SampledMesh mesh = Square();
  std::swap(mesh.Triangles[4], mesh.Triangles[5]); // (1, 2, 3): clockwise, same domain
  BuildMeshTopology(4, 2, mesh.Triangles.data(), mesh.Topology);
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_EQ(m, "");
  }
}

TEST(InputValidation, ClockwiseTrianglesAreNoFold)
{
  SampledMesh mesh = Square();
  mesh.Triangles = { 0, 2, 1, 1, 2, 3 }; // both clockwise: consistent, negative areas
  BuildMeshTopology(4, 2, mesh.Triangles.data(), mesh.Topology);
  ASSERT_TRUE(mesh.Topology.ConsistentlyOriented);
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_EQ(m, "");
  }
  mesh.UV[6] = 0.2; // and folded as in FoldedParameterisationIsRejectedByName
  mesh.UV[7] = 0.3;
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_NE(m.find("folded parameterisation: triangles 0 and 1"), std::string::npos) << m;
  }
}

TEST(InputValidation, ValuesThatWouldOverflowAreRejected)
{
  for (double big : { 1e150, 1e300, -1e200 })
  {
    SampledMesh mesh = Square();
    mesh.Fu[3 * 2 + 1] = big; // vertex 2
    for (const std::string& m : FailuresOfAllConstructions(mesh))
    {
      EXPECT_NE(m.find("derivatives d/du of vertex 2"), std::string::npos) << m;
      EXPECT_NE(m.find("rescale"), std::string::npos) << m;
    }
  }
  SampledMesh mesh = Square();
  mesh.UV[1] = std::nan("");
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_NE(m.find("(u, v) of vertex 0"), std::string::npos) << m;
  }
}

// The filter checks the values while copying them (CopyArray) and says so: the kernel then skips
// its own pass over them, but still checks the geometry.
TEST(InputValidation, ValuesCheckedByTheCallerAreNotReadAgain)
{
  SampledMesh mesh = Square();
  mesh.Fu[3 * 2 + 1] = 1e150; // vertex 2: rejected unless the caller vouches for the values
  const BuildStatus unchecked = ValidateSplineData(mesh.Data(), mesh.Topology);
  ASSERT_FALSE(unchecked.Ok);
  EXPECT_NE(unchecked.Message.find("derivatives d/du of vertex 2"), std::string::npos)
    << unchecked.Message;
  mesh.ValuesChecked = true;
  EXPECT_TRUE(ValidateSplineData(mesh.Data(), mesh.Topology).Ok);
  mesh.UV[2 * 3] = 0.0; // vertex 3 onto the diagonal: a fold is still found
  mesh.UV[2 * 3 + 1] = 0.0;
  EXPECT_FALSE(ValidateSplineData(mesh.Data(), mesh.Topology).Ok);
}

// The cubic constructions check a macro-element's control points through its split point S
// (every other point enters S with finite weights; one test per triangle). Points whose sum over
// a macro-element would overflow (an earlier test summed all 19) must not fail the build.
TEST(InputValidation, FiniteControlPointsWhoseSumOverflowsAreAccepted)
{
  SampledMesh mesh = Square();
  for (size_t v = 0; v < 4; ++v)
  {
    mesh.F[3 * v] = 1e307; // 19 of them overflow
    mesh.F[3 * v + 1] = mesh.F[3 * v + 2] = 0.0;
  }
  std::fill(mesh.Fu.begin(), mesh.Fu.end(), 0.0);
  std::fill(mesh.Fv.begin(), mesh.Fv.end(), 0.0);
  std::fill(mesh.EdgeGradients.begin(), mesh.EdgeGradients.end(), 0.0);
  mesh.ValuesChecked = true; // beyond what the validation lets through
  // Not Kashyap: its C1 smoothing (MoveLeastOntoTie) takes the tie's slope as a difference of two
  // blossoms of the data, which loses it entirely at this magnitude.
  for (int c = 0; c < static_cast<int>(Construction::Kashyap); ++c)
  {
    SplineOptions options;
    options.Method = static_cast<Construction>(c);
    CubicSpline spline;
    const BuildStatus s = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, options, spline);
    EXPECT_TRUE(s.Ok) << ToString(options.Method) << ": " << s.Message;
    for (const Vec3& p : spline.ControlPoints)
    {
      EXPECT_NEAR(p.x() / 1e307, 1.0, 1e-12) << ToString(options.Method);
    }
  }
}

// Values that pass the caller's checks yet overflow inside a construction: a build either fails,
// naming the macro-element, or every control point it returns is finite (never silent inf or
// NaN). Random vertices of a grid get values, derivatives and mid-edge gradients near the
// largest double, so that the overflow happens in different control points (T, I1, C, I2, S).
TEST(InputValidation, NoBuildReturnsANonFiniteControlPoint)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> magnitude(0.3, 1.79);
  std::uniform_int_distribution<int> coin(0, 3);
  int failed = 0, built = 0, rejectedGradients = 0;
  for (int trial = 0; trial < 24; ++trial)
  {
    SampledMesh mesh = Sample("grid", RegularGridMesh(3, GridDiagonal::Alternating),
      AnalyticSurface::Franke);
    mesh.ValuesChecked = true; // beyond what the validation lets through
    const int v = trial % 16;
    for (auto* a : { &mesh.F, &mesh.Fu, &mesh.Fv })
    {
      for (int c = 0; c < 3; ++c)
      {
        const int pick = coin(rng);
        if (pick > 0)
        {
          (*a)[3 * v + c] = (pick == 1 ? -1.0 : 1.0) * magnitude(rng) * 1e308;
        }
      }
    }
    for (double& g : mesh.EdgeGradients)
    {
      g = coin(rng) == 0 ? magnitude(rng) * 1e308 : g;
    }
    for (int c = 0; c <= static_cast<int>(Construction::Kashyap); ++c)
    {
      for (int iterations : { 0, 2 })
      {
        SplineOptions options;
        options.Method = static_cast<Construction>(c);
        options.Iterations = iterations;
        CubicSpline spline;
        const BuildStatus s = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, options, spline);
        if (!s.Ok)
        {
          // The mid-edge gradients are checked where they are read, whatever ValuesChecked says.
          const bool overflow = s.Message.find("non-finite control point") != std::string::npos;
          EXPECT_TRUE(overflow ||
            s.Message.find("the mid-edge gradients of triangle") != std::string::npos)
            << s.Message;
          failed += overflow ? 1 : 0;
          rejectedGradients += overflow ? 0 : 1;
          continue;
        }
        ++built;
        for (const Vec3& p : spline.ControlPoints)
        {
          ASSERT_TRUE(p.allFinite()) << ToString(options.Method) << " trial " << trial;
        }
      }
    }
  }
  EXPECT_GT(failed, 20);
  EXPECT_GT(built, 20);
  EXPECT_GT(rejectedGradients, 20); // MGo and MGi read every one, KaG the boundary edges'
}

TEST(InputValidation, SplitPointsOutsideTheirTriangleAreRejected)
{
  const SampledMesh mesh = Square();
  for (const Vec3& bad : { Vec3(std::nan(""), 0.5, 0.5), Vec3(-0.1, 0.6, 0.5), Vec3(0.5, 0.5, 0.5) })
  {
    const std::vector<Vec3> tau = { Vec3::Constant(1.0 / 3), bad };
    SplineData data = mesh.Data();
    data.SplitTau = tau.data();
    CubicSpline spline;
    const BuildStatus s = BuildCubicCloughTocher(data, mesh.Topology, SplineOptions(), spline);
    EXPECT_NE(s.Message.find("split point of triangle 1"), std::string::npos) << s.Message;
  }
}

TEST(InputValidation, Inc3WithCoincidentCornersUsesTheBarycentre)
{
  // Vertices 1 and 2 at one 3D point: their incentre would lie on an edge of the triangle.
  SampledMesh mesh = Square();
  std::copy_n(&mesh.F[3], 3, &mesh.F[6]);
  SplineOptions options;
  options.SplitPoint = SplitPointRule::Inc3;
  for (Construction c : { Construction::CTo, Construction::Ka, Construction::KaG })
  {
    options.Method = c;
    CubicSpline spline;
    const BuildStatus s = BuildCubicCloughTocher(mesh.Data(), mesh.Topology, options, spline);
    ASSERT_TRUE(s.Ok) << s.Message;
    EXPECT_TRUE(spline.SplitTau[0].isApprox(Vec3::Constant(1.0 / 3.0)));
    EXPECT_GT(spline.SplitTau[1].minCoeff(), 0.1);
  }
}

TEST(InputValidation, UnderflowingDomainIsRejected)
{
  SampledMesh mesh = Square();
  for (double& x : mesh.UV)
  {
    x *= 1e-200;
  }
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_NE(m.find("parameter domain is too small"), std::string::npos) << m;
  }
}

TEST(InputValidation, SmallButRepresentableDomainWorks)
{
  // 1e-50 is far from underflow: the spline is the same up to the scale of (u, v).
  SampledMesh mesh = Square();
  for (double& x : mesh.UV)
  {
    x *= 1e-50;
  }
  for (const std::string& m : FailuresOfAllConstructions(mesh))
  {
    EXPECT_EQ(m, "");
  }
}

TEST(InputValidation, NonFiniteControlPointNamesItsTriangle)
{
  const SampledMesh mesh = Square();
  CubicSpline spline;
  ASSERT_TRUE(BuildCubicCloughTocher(mesh.Data(), mesh.Topology, SplineOptions(), spline).Ok);
  const auto check = [&](Id point) {
    OverwriteVector<Vec3> points = spline.ControlPoints;
    points[point].y() = std::nan("");
    return CheckFiniteControlPoints(points, mesh.Topology, mesh.Triangles.data(), 4, 2,
      CubicSplineLayout::PointsPerTriangle);
  };
  EXPECT_TRUE(CheckFiniteControlPoints(spline.ControlPoints, mesh.Topology,
    mesh.Triangles.data(), 4, 2, CubicSplineLayout::PointsPerTriangle)
                .Ok);
  // Vertex 3 is only in triangle 1; the last triangle-owned point is triangle 1's.
  EXPECT_NE(check(3).Message.find("triangle 1"), std::string::npos) << check(3).Message;
  const Id last = static_cast<Id>(spline.ControlPoints.size()) - 1;
  EXPECT_NE(check(last).Message.find("triangle 1"), std::string::npos);
  EXPECT_NE(check(0).Message.find("triangle 0"), std::string::npos);
}

TEST(InputValidation, LocatorSurvivesAnOverflowingParameterBox)
{
  // The box of these corners is 2e308 wide: its extent is inf, and the bucket count was a NaN
  // cast to an integer.
  const std::vector<Vec2> corners = { Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(-1e308, -1e308),
    Vec2(1e308, -1e308), Vec2(0, 1e308) };
  ParameterLocator locator;
  locator.Build(2, corners.data());
  const ParameterLocator::Hit hit = locator.Locate(0.2, 0.3);
  ASSERT_GE(hit.Triangle, 0);
  EXPECT_EQ(hit.Triangle, 0);
  EXPECT_NEAR(hit.Barycentric.x(), 0.5, 1e-15);
  EXPECT_LT(locator.Locate(std::nan(""), 0.0).Triangle, 0);
  // Tiny and huge extents together: finite spacings, every query in range.
  const std::vector<Vec2> thin = { Vec2(0, 0), Vec2(1e300, 0), Vec2(0, 1e-300) };
  locator.Build(1, thin.data());
  EXPECT_EQ(locator.Locate(1.0, 1e-302).Triangle, 0);
  EXPECT_LT(locator.Locate(-1e308, 1e308).Triangle, 0);
}

TEST(InputValidation, DistanceQueriesCannotOverflow)
{
  PointToMeshDistance d;
  const std::vector<double> huge = { 0, 0, 0, 1e200, 0, 0, 0, 1e200, 0 };
  const std::vector<Id> tri = { 0, 1, 2 };
  const std::string message = d.Build(3, huge.data(), 1, tri.data());
  EXPECT_NE(message.find("point 1"), std::string::npos) << message;
  EXPECT_NE(message.find("too large"), std::string::npos) << message;
  const std::vector<double> unit = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
  ASSERT_EQ(d.Build(3, unit.data(), 1, tri.data()), "");
  // Far queries (squares beyond double range) still get their distance.
  for (const Vec3& p : { Vec3(1e200, 1e200, 0), Vec3(-1e308, 1e308, 0.5), Vec3(0.25, 0.25, 1e190) })
  {
    const PointToMeshDistance::Result far = d.Query(p);
    ASSERT_TRUE(std::isfinite(far.Distance));
    EXPECT_EQ(far.Triangle, 0);
    const double m = p.cwiseAbs().maxCoeff();
    EXPECT_NEAR(far.Distance / m, (p / m).norm(), 1e-15);
  }
  const PointToMeshDistance::Result nan = d.Query(Vec3(std::nan(""), 0, 0));
  EXPECT_TRUE(std::isnan(nan.Distance));
  EXPECT_EQ(nan.Triangle, -1);
  EXPECT_NEAR(d.Query(Vec3(0.25, 0.25, 2)).Distance, 2.0, 1e-15);
}

TEST(InputValidation, DistanceQueriesSurviveDenormalCoordinates)
{
  // A denormal coordinate beside ordinary ones (found by fuzzing): CGAL's query constructed a
  // sphere with a NaN squared radius and aborted on its precondition.
  const std::vector<double> points = { 0, 3.21256e-319, -128, 0, 0, 0, -128, 0, 0, 0, 0, 28,
    -54, -127.99609375, 0 };
  const std::vector<Id> tris = { 0, 1, 2, 1, 2, 3, 1, 3, 4, 0, 2, 4 };
  PointToMeshDistance d;
  ASSERT_EQ(d.Build(5, points.data(), 4, tris.data()), "");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-200, 200);
  for (int q = 0; q < 200; ++q)
  {
    const Vec3 p = q < 5 ? Vec3(points[3 * q], points[3 * q + 1], points[3 * q + 2])
                         : Vec3(coordinate(rng), coordinate(rng), 1e-320 * q);
    const PointToMeshDistance::Result r = d.Query(p);
    ASSERT_TRUE(std::isfinite(r.Distance)) << q;
    ASSERT_GE(r.Triangle, 0);
    // The closest point is no farther than any mesh vertex.
    for (int v = 0; v < 5; ++v)
    {
      EXPECT_LE(r.Distance, (p - Vec3(points[3 * v], points[3 * v + 1], points[3 * v + 2])).norm() + 1e-12);
    }
    if (q < 5)
    {
      EXPECT_LT(r.Distance, 1e-12);
    }
  }
  // A sliver beside an ordinary triangle: left out (CGAL divided by its area), queries stay
  // finite and find the ordinary triangle or the sliver's longest edge within 1e-12.
  const std::vector<double> sliver = { 0, 0, 0, 1, 0, 0, 0.5, 1e-15, 1e-15, 0, -1, 0 };
  const std::vector<Id> sliverTris = { 0, 1, 2, 0, 3, 1 };
  ASSERT_EQ(d.Build(4, sliver.data(), 2, sliverTris.data()), "");
  EXPECT_EQ(d.GetNumberOfTriangles(), 1);
  for (const Vec3& p : { Vec3(0.5, 0.3, 0.2), Vec3(0.5, 1e-15, 1e-15), Vec3(0.2, -0.5, 3) })
  {
    const PointToMeshDistance::Result r = d.Query(p);
    ASSERT_TRUE(std::isfinite(r.Distance));
    EXPECT_EQ(r.Triangle, 1);
  }
  const std::vector<double> tiny = { 0, 0, 0, 1e-60, 0, 0, 0, 1e-60, 0 };
  EXPECT_NE(d.Build(3, tiny.data(), 1, tris.data()).find("too small"), std::string::npos);
}

// ForStreamChunks hands every item over once, in order, in chunks of StreamChunkBytes (the last
// one shorter), for items of one value, of several, and of more bytes than a chunk; none for
// n = 0.
TEST(InputValidation, StreamChunksCoverEveryItemOnceInOrder)
{
  auto chunks = [](const auto* data, Id n, int perItem) {
    std::vector<std::pair<Id, Id>> seen;
    ForStreamChunks(data, n, perItem, [&](Id begin, Id end) { seen.emplace_back(begin, end); });
    return seen;
  };
  const std::vector<double> values(3 * 1000);
  const std::vector<std::int32_t> ids(1000);
  for (const auto& [n, perItem, bytes] : { std::tuple<Id, int, std::size_t>{ 1000, 1, 8 },
         { 1000, 3, 8 }, { 30, 100, 8 }, { 1000, 1, 4 }, { 0, 1, 8 }, { 1, 2, 8 } })
  {
    const auto seen = bytes == 4 ? chunks(ids.data(), n, perItem) : chunks(values.data(), n, perItem);
    const Id chunk = std::max<Id>(1, Id(StreamChunkBytes / (bytes * perItem)));
    ASSERT_EQ(seen.size(), static_cast<size_t>((n + chunk - 1) / chunk)) << n << " " << perItem;
    Id next = 0;
    for (const auto& [begin, end] : seen)
    {
      EXPECT_EQ(begin, next) << n << " " << perItem;
      EXPECT_EQ(end, std::min(n, begin + chunk)) << n << " " << perItem;
      next = end;
    }
    EXPECT_EQ(next, n) << perItem;
  }
}

// The bulk checks read their arrays in prefetched chunks (ForStreamChunks: 64 doubles, 32
// pairs, 128 32-bit or 64 64-bit ids): a bad value, an extreme of the box or an id out of range
// is caught in the first, a middle and the last chunk, and a good chunk after a bad one does not
// clear it.
TEST(InputValidation, BulkArrayChecksCatchEveryChunk)
{
  constexpr size_t n = 1001; // 15 chunks of 64 values and a part
  const std::vector<double> values(n, 0.5);
  for (const size_t k : { size_t(0), size_t(63), size_t(64), size_t(500), n - 2, n - 1 })
  {
    std::vector<double> v = values;
    v[k] = std::nan("");
    EXPECT_FALSE(AllUsableValues(v.data(), n)) << k;
    Vec2 lo, hi;
    EXPECT_EQ(AllUsablePairs(v.data(), n / 2, lo, hi), k >= n - 1) << k;
    v = values;
    v[k] = 0.0;
    EXPECT_FALSE(AllUsableValues(v.data(), n, true)) << k;
    if (k < n - 3) // both values within the n / 2 pairs
    {
      v[k] = -3.0 - double(k);
      v[n - 3 - k] = 4.0 + double(k); // the same component: n - 3 is even
      ASSERT_TRUE(AllUsablePairs(v.data(), n / 2, lo, hi)) << k;
      EXPECT_EQ(lo[k % 2], -3.0 - double(k)) << k;
      EXPECT_EQ(hi[k % 2], 4.0 + double(k)) << k;
    }
  }
  const Id nPoints = 100;
  const std::vector<int> narrow(n, 99);
  const std::vector<long long> wide(n, 0);
  for (const size_t k : { size_t(0), size_t(127), size_t(128), size_t(700), n - 1 })
  {
    std::vector<int> a = narrow;
    a[k] = 100;
    EXPECT_FALSE(AllIdsInRange(a.data(), n, nPoints)) << k;
    std::vector<long long> b = wide;
    b[k] = -1;
    EXPECT_FALSE(AllIdsInRange(b.data(), n, nPoints)) << k;
  }
  EXPECT_TRUE(AllIdsInRange(narrow.data(), n, nPoints));
  EXPECT_TRUE(AllIdsInRange(wide.data(), n, nPoints));
}

// The bulk checks of raw arrays (the probe's source read in place) against the one-value rule,
// value by value: every position of a bad value is caught whatever the vector lane it falls in,
// ids at the ends of the range pass and those just outside fail (32-bit ids also beyond 2^31
// points), and the box of the pairs is exact.
TEST(InputValidation, BulkArrayChecksCatchEveryPosition)
{
  std::vector<double> values(37, 0.5);
  Vec2 lo, hi;
  ASSERT_TRUE(AllUsableValues(values.data(), 37));
  ASSERT_TRUE(AllUsableValues(values.data(), 37, true));
  ASSERT_TRUE(AllUsablePairs(values.data(), 18, lo, hi));
  for (size_t k = 0; k < values.size(); ++k)
  {
    for (const double bad : { std::nan(""), HUGE_VAL, -HUGE_VAL, 1e100, -1e100 })
    {
      std::vector<double> v = values;
      v[k] = bad;
      EXPECT_FALSE(AllUsableValues(v.data(), 37)) << k << " " << bad;
      EXPECT_EQ(AllUsablePairs(v.data(), 18, lo, hi), k >= 36) << k << " " << bad;
    }
    std::vector<double> v = values;
    v[k] = 0.0; // usable, but not positive (weights)
    EXPECT_TRUE(AllUsableValues(v.data(), 37));
    EXPECT_FALSE(AllUsableValues(v.data(), 37, true)) << k;
  }
  std::vector<double> uv = { 0.5, 2.0, -1.0, 0.25, 3.0, -7.0, 0.0, 1e99 };
  ASSERT_TRUE(AllUsablePairs(uv.data(), 4, lo, hi));
  EXPECT_EQ(lo, Vec2(-1.0, -7.0));
  EXPECT_EQ(hi, Vec2(3.0, 1e99));

  for (const Id nPoints : { Id(1), Id(5), Id(1) << 31, (Id(1) << 32) + 7 })
  {
    const Id last = nPoints - 1;
    std::vector<long long> wide(21, 0);
    std::vector<int> narrow(21, 0);
    for (size_t k = 0; k < wide.size(); ++k)
    {
      wide[k] = static_cast<long long>(k % 2 ? last : 0);
      narrow[k] = static_cast<int>(std::min<Id>(wide[k], INT32_MAX));
    }
    ASSERT_TRUE(AllIdsInRange(wide.data(), 21, nPoints)) << nPoints;
    ASSERT_TRUE(AllIdsInRange(narrow.data(), 21, nPoints)) << nPoints;
    for (size_t k = 0; k < wide.size(); ++k)
    {
      for (const long long bad : { -1LL, static_cast<long long>(nPoints), -(1LL << 40) })
      {
        std::vector<long long> w = wide;
        w[k] = bad;
        EXPECT_FALSE(AllIdsInRange(w.data(), 21, nPoints)) << nPoints << " " << k << " " << bad;
        if (bad >= INT32_MIN && bad <= INT32_MAX)
        {
          std::vector<int> n = narrow;
          n[k] = static_cast<int>(bad);
          EXPECT_FALSE(AllIdsInRange(n.data(), 21, nPoints)) << nPoints << " " << k << " " << bad;
        }
      }
      std::vector<int> n = narrow;
      n[k] = INT32_MIN;
      EXPECT_FALSE(AllIdsInRange(n.data(), 21, nPoints)) << nPoints << " " << k;
    }
  }
}

// The cubic builder runs the triangle and edge checks in its own first passes: on a shuffled
// mesh large enough for the locality order, with several bad triangles or folded edges, it must
// name the same lowest one as ValidateSplineData, threaded or not, degenerate before folded.
TEST(InputValidation, BuilderPassesNameTheLowestBadTriangleOrEdge)
{
  const ParameterMesh grid = JitteredGrid(130, 0.2, 7); // 33,800 triangles, > 2^15
  ParameterMesh shuffled = grid; // the triangles in a random order (the locality order differs)
  std::vector<std::array<Id, 3>> rows(grid.Triangles.size() / 3);
  std::copy_n(grid.Triangles.data(), grid.Triangles.size(), rows.front().data());
  std::shuffle(rows.begin(), rows.end(), std::mt19937(3));
  std::copy_n(rows.front().data(), grid.Triangles.size(), shuffled.Triangles.data());
  const SampledMesh base = Sample("shuffled grid", shuffled, AnalyticSurface::Franke);
  const Id nV = static_cast<Id>(base.UV.size() / 2);
  std::mt19937 rng(11);
  std::uniform_int_distribution<Id> vertex(0, nV - 1);
  for (int trial = 0; trial < 6; ++trial)
  {
    SampledMesh mesh = base;
    // Even trials: three vertices each moved onto a neighbour (zero-area triangles, with folds
    // around them); odd trials: three vertices pushed across the far side of a triangle (folds
    // only, or nearly so).
    for (int site = 0; site < 3; ++site)
    {
      const Id t = mesh.Topology.EdgeTriangles[vertex(rng) % mesh.Topology.Edges.size()][0];
      const Id* p = mesh.Triangles.data() + 3 * t;
      const Vec2 A(mesh.UV[2 * p[0]], mesh.UV[2 * p[0] + 1]);
      const Vec2 B(mesh.UV[2 * p[1]], mesh.UV[2 * p[1] + 1]);
      const Vec2 C(mesh.UV[2 * p[2]], mesh.UV[2 * p[2] + 1]);
      const Vec2 to = trial % 2 == 0 ? B : A + 1.7 * (0.5 * (B + C) - A);
      mesh.UV[2 * p[0]] = to.x();
      mesh.UV[2 * p[0] + 1] = to.y();
    }
    const BuildStatus expected = ValidateSplineData(mesh.Data(), mesh.Topology);
    ASSERT_FALSE(expected.Ok) << "trial " << trial;
    const bool degenerate = expected.Message.find("degenerate parameter triangle") != std::string::npos;
    EXPECT_EQ(degenerate, trial % 2 == 0) << expected.Message;
    if (degenerate)
    {
      // The named cell is the lowest zero-area one.
      double lo[2], hi[2];
      BoundingBoxUV(nV, mesh.UV.data(), lo, hi, SerialFor);
      const double diag2 = (Vec2(hi[0], hi[1]) - Vec2(lo[0], lo[1])).squaredNorm();
      Id first = 0;
      while (!IsDegenerateTriangle(mesh.Data(), first, diag2))
      {
        ++first;
      }
      EXPECT_NE(expected.Message.find("cell " + std::to_string(first) + " "), std::string::npos)
        << expected.Message;
    }
    for (const bool locality : { false, true })
    {
      for (const int threads : { 1, 2 })
      {
        SplineOptions options;
        options.LocalityOrder = locality;
        CubicSpline spline;
        const BuildStatus s = BuildCubicCloughTocher(
          mesh.Data(), mesh.Topology, options, spline, ThreadedFor(threads, 997));
        EXPECT_FALSE(s.Ok);
        EXPECT_EQ(s.Message, expected.Message) << "locality " << locality << ", threads " << threads;
      }
    }
  }
}
