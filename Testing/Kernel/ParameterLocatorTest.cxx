// SPDX-License-Identifier: GPL-3.0-or-later
#include "AnalyticSurfaces.h"
#include "ParameterLocator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

using namespace ctk;

namespace
{
// The locator's documented rule evaluated over all triangles.
ParameterLocator::Hit BruteForce(const std::vector<Vec2>& corners, const Vec2& X)
{
  ParameterLocator::Hit hit;
  double bestMin = -ParameterLocator::Tolerance;
  for (Id t = 0; t < static_cast<Id>(corners.size() / 3); ++t)
  {
    const Vec2* c = &corners[3 * t];
    if (SignedArea2(c[0], c[1], c[2]) == 0.0)
    {
      continue;
    }
    const Vec3 b = Barycentric(c[0], c[1], c[2], X);
    if (b.minCoeff() > bestMin || (b.minCoeff() == bestMin && hit.Triangle < 0))
    {
      bestMin = b.minCoeff();
      hit.Triangle = t;
      hit.Barycentric = b;
    }
  }
  return hit;
}

std::vector<Vec2> Corners(const ParameterMesh& m)
{
  std::vector<Vec2> c;
  for (Id i : m.Triangles)
  {
    c.push_back(m.UV[i]);
  }
  return c;
}

// Grid with interior vertices jittered by up to 0.15 h (keeps every triangle's orientation),
// then mapped by a random rotation and anisotropic scale.
ParameterMesh RandomMesh(std::mt19937& rng, int n, GridDiagonal diagonal)
{
  ParameterMesh m = RegularGridMesh(n, diagonal);
  std::uniform_real_distribution<double> J(-0.15 / n, 0.15 / n);
  for (Vec2& p : m.UV)
  {
    const bool boundary = p.x() == 0.0 || p.x() == 1.0 || p.y() == 0.0 || p.y() == 1.0;
    if (!boundary)
    {
      p += Vec2(J(rng), J(rng));
    }
  }
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double angle = 6.0 * U(rng);
  Eigen::Matrix2d R;
  R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  const Eigen::Matrix2d A = R * Eigen::Vector2d(0.2 + 5 * U(rng), 0.2 + 5 * U(rng)).asDiagonal();
  const Vec2 shift(10 * U(rng) - 5, 10 * U(rng) - 5);
  for (Vec2& p : m.UV)
  {
    p = A * p + shift;
  }
  return m;
}

// Queries: random points around the domain (many outside), every vertex, points on every edge.
std::vector<Vec2> QueryPoints(const ParameterMesh& m, std::mt19937& rng, int nRandom)
{
  Vec2 lo = m.UV[0], hi = m.UV[0];
  for (const Vec2& p : m.UV)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec2 pad = 0.2 * (hi - lo);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<Vec2> q;
  for (int i = 0; i < nRandom; ++i)
  {
    const Vec2 s(U(rng), U(rng));
    q.push_back(lo - pad + s.cwiseProduct(hi - lo + 2 * pad));
  }
  for (const Vec2& p : m.UV)
  {
    q.push_back(p);
  }
  for (Id t = 0; t < m.NumberOfTriangles(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      const Vec2& A = m.UV[m.Triangles[3 * t + l]];
      const Vec2& B = m.UV[m.Triangles[3 * t + (l + 1) % 3]];
      const double s = U(rng);
      q.push_back((1 - s) * A + s * B);
      q.push_back(0.5 * (A + B));
    }
  }
  return q;
}

void CheckAgainstBruteForce(const ParameterMesh& m, std::mt19937& rng)
{
  const std::vector<Vec2> corners = Corners(m);
  ParameterLocator locator;
  locator.Build(m.UV, m.NumberOfTriangles(), m.Triangles.data());
  ASSERT_EQ(locator.GetNumberOfTriangles(), m.NumberOfTriangles());
  // About one bucket per triangle.
  EXPECT_LE(locator.GetNumberOfBuckets(), 2 * m.NumberOfTriangles() + 2);
  const std::vector<Vec2> queries = QueryPoints(m, rng, 400);
  const size_t firstOnMesh = 400;
  for (size_t i = 0; i < queries.size(); ++i)
  {
    const Vec2& X = queries[i];
    const ParameterLocator::Hit expected = BruteForce(corners, X);
    const ParameterLocator::Hit hit = locator.Locate(X.x(), X.y());
    ASSERT_EQ(hit.Triangle, expected.Triangle) << "query " << i << " at " << X.transpose();
    if (i >= firstOnMesh)
    {
      // Vertices and edge points belong to the closed domain.
      ASSERT_TRUE(hit.Found()) << "vertex/edge query " << i << " at " << X.transpose();
    }
    if (hit.Found())
    {
      EXPECT_GE(hit.Barycentric.minCoeff(), -ParameterLocator::Tolerance);
      EXPECT_NEAR(hit.Barycentric.sum(), 1.0, 1e-14);
      const Vec2* c = &corners[3 * hit.Triangle];
      const Vec2 back =
        hit.Barycentric[0] * c[0] + hit.Barycentric[1] * c[1] + hit.Barycentric[2] * c[2];
      EXPECT_LE((back - X).norm(), 1e-12 * (1 + X.norm()));
    }
  }
}
} // namespace

TEST(ParameterLocator, MatchesBruteForceOnRandomGrids)
{
  std::mt19937 rng(17);
  for (int trial = 0; trial < 12; ++trial)
  {
    const int n = 1 + trial * 2;
    CheckAgainstBruteForce(RandomMesh(rng, n, static_cast<GridDiagonal>(trial % 3)), rng);
  }
}

TEST(ParameterLocator, MatchesBruteForceOnRefinedTriangles)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-3.0, 3.0);
  for (int level = 0; level <= 4; ++level)
  {
    Vec2 A[3];
    do
    {
      for (Vec2& a : A)
      {
        a = Vec2(U(rng), U(rng));
      }
    } while (std::abs(SignedArea2(A[0], A[1], A[2])) < 1.0);
    CheckAgainstBruteForce(RefinedTriangleMesh(A[0], A[1], A[2], level), rng);
  }
}

// Points just outside single triangles, their smallest barycentric coordinate from 0.3 to 3 times
// the tolerance below zero, on triangles of any scale, shape, orientation and offset: the
// locator's rejection without divisions (below -2 tolerances, from signed areas) keeps every
// triangle the rule accepts, with the same coordinates, bit for bit.
TEST(ParameterLocator, PointsAtTheToleranceMatchBruteForce)
{
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double tol = ParameterLocator::Tolerance;
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 400; ++trial)
  {
    const double scale = std::pow(10.0, -6.0 + 9.0 * U(rng));
    const Vec2 offset = std::pow(10.0, -3.0 + 6.0 * U(rng)) * Vec2(U(rng) - 0.5, U(rng) - 0.5);
    std::vector<Vec2> corners(3);
    do
    {
      for (Vec2& c : corners)
      {
        c = offset + scale * Vec2(U(rng), U(rng));
      }
    } while (std::abs(SignedArea2(corners[0], corners[1], corners[2])) < 1e-3 * scale * scale);
    ParameterLocator locator;
    locator.Build(1, corners.data());
    for (int q = 0; q < 20; ++q)
    {
      // Barycentric (a, b, c) with c = -f tol, a point beyond edge (0, 1), or near corner 2.
      const double f = 0.3 + 2.7 * U(rng), a = U(rng);
      Vec3 bary(a * (1 + f * tol), (1 - a) * (1 + f * tol), -f * tol);
      if (q % 4 == 3)
      {
        bary = Vec3(-f * tol, 0.5 * f * tol, 1 + 0.5 * f * tol);
      }
      const int k = q % 3; // which corner the coordinates start from
      const Vec2 X = bary[0] * corners[k] + bary[1] * corners[(k + 1) % 3] +
        bary[2] * corners[(k + 2) % 3];
      const ParameterLocator::Hit expected = BruteForce(corners, X);
      const ParameterLocator::Hit hit = locator.Locate(X.x(), X.y());
      ASSERT_EQ(hit.Triangle, expected.Triangle) << "trial " << trial << " query " << q;
      if (hit.Found())
      {
        ++accepted;
        ASSERT_EQ(hit.Barycentric, expected.Barycentric) << "trial " << trial << " query " << q;
      }
      else
      {
        ++rejected;
      }
    }
  }
  // Both sides of the tolerance were reached.
  EXPECT_GT(accepted, 400);
  EXPECT_GT(rejected, 400);
}

TEST(ParameterLocator, BoundaryOfTheUnitSquare)
{
  const ParameterMesh m = RegularGridMesh(7, GridDiagonal::Alternating);
  ParameterLocator locator;
  locator.Build(m.UV, m.NumberOfTriangles(), m.Triangles.data());
  for (double s : { 0.0, 0.1, 1.0 / 3.0, 0.5, 0.77, 1.0 })
  {
    EXPECT_TRUE(locator.Locate(s, 0.0).Found()) << s;
    EXPECT_TRUE(locator.Locate(0.0, s).Found()) << s;
    EXPECT_TRUE(locator.Locate(s, 1.0).Found()) << s;
    EXPECT_TRUE(locator.Locate(1.0, s).Found()) << s;
    EXPECT_FALSE(locator.Locate(s, -1e-9).Found()) << s;
    EXPECT_FALSE(locator.Locate(-1e-9, s).Found()) << s;
    EXPECT_FALSE(locator.Locate(s, 1 + 1e-9).Found()) << s;
    EXPECT_FALSE(locator.Locate(1 + 1e-9, s).Found()) << s;
  }
  EXPECT_FALSE(locator.Locate(1e300, -1e300).Found());
  EXPECT_FALSE(locator.Locate(std::nan(""), 0.5).Found());
  EXPECT_FALSE(locator.Locate(0.5, std::numeric_limits<double>::infinity()).Found());
}

TEST(ParameterLocator, EmptyAndDegenerateTriangles)
{
  ParameterLocator empty;
  EXPECT_FALSE(empty.Locate(0.0, 0.0).Found());
  empty.Build(0, nullptr);
  EXPECT_FALSE(empty.Locate(0.0, 0.0).Found());

  // A zero-area triangle is never reported; the good one still is.
  const std::vector<Vec2> corners = { Vec2(0, 0), Vec2(1, 1), Vec2(2, 2), Vec2(0, 0), Vec2(1, 0),
    Vec2(0, 1) };
  ParameterLocator locator;
  locator.Build(2, corners.data());
  EXPECT_EQ(locator.Locate(0.5, 0.5).Triangle, 1);
  EXPECT_EQ(locator.Locate(0.2, 0.1).Triangle, 1);
  EXPECT_FALSE(locator.Locate(1.5, 1.5).Found());

  ParameterLocator onlyDegenerate;
  onlyDegenerate.Build(1, corners.data());
  EXPECT_FALSE(onlyDegenerate.Locate(1.0, 1.0).Found());
}

TEST(ParameterLocator, ClockwiseTrianglesAndSharedVertex)
{
  // A fan of clockwise triangles around (0, 0): the centre is found, with a unit coordinate.
  std::vector<Vec2> corners;
  const int k = 7;
  for (int i = 0; i < k; ++i)
  {
    const double a0 = 2 * M_PI * i / k, a1 = 2 * M_PI * (i + 1) / k;
    corners.insert(corners.end(),
      { Vec2(0, 0), Vec2(std::cos(a1), std::sin(a1)), Vec2(std::cos(a0), std::sin(a0)) });
  }
  ParameterLocator locator;
  locator.Build(k, corners.data());
  const ParameterLocator::Hit hit = locator.Locate(0.0, 0.0);
  ASSERT_TRUE(hit.Found());
  EXPECT_EQ(hit.Triangle, BruteForce(corners, Vec2(0, 0)).Triangle);
  EXPECT_NEAR(hit.Barycentric[0], 1.0, 1e-15);
  EXPECT_EQ(locator.Locate(0.3, 0.01).Triangle, 0);
}

TEST(ParameterLocator, ConcurrentQueriesAgree)
{
  std::mt19937 rng(3);
  const ParameterMesh m = RandomMesh(rng, 20, GridDiagonal::Forward);
  ParameterLocator locator;
  locator.Build(m.UV, m.NumberOfTriangles(), m.Triangles.data());
  const std::vector<Vec2> queries = QueryPoints(m, rng, 5000);
  std::vector<Id> serial(queries.size()), a(queries.size()), b(queries.size());
  for (size_t i = 0; i < queries.size(); ++i)
  {
    serial[i] = locator.Locate(queries[i].x(), queries[i].y()).Triangle;
  }
  auto run = [&](std::vector<Id>& out) {
    for (size_t i = 0; i < queries.size(); ++i)
    {
      out[i] = locator.Locate(queries[i].x(), queries[i].y()).Triangle;
    }
  };
  std::thread t1(run, std::ref(a)), t2(run, std::ref(b));
  t1.join();
  t2.join();
  EXPECT_EQ(a, serial);
  EXPECT_EQ(b, serial);
}

// The grid over corners read in place (through the mesh's indices, as the probe reads a spline's
// arrays) locates exactly as the copying locator and the brute-force rule; ties go to the lowest
// id.
TEST(TriangleBucketGrid, CornersReadInPlace)
{
  std::mt19937 rng(11);
  const ParameterMesh m = RandomMesh(rng, 15, GridDiagonal::Alternating);
  auto corners = [&m](Id t, Vec2* c) {
    for (int a = 0; a < 3; ++a)
    {
      c[a] = m.UV[m.Triangles[3 * t + a]];
    }
  };
  TriangleBucketGrid grid;
  ASSERT_TRUE(grid.Build(m.NumberOfTriangles(), corners));
  ParameterLocator locator;
  locator.Build(m.UV, m.NumberOfTriangles(), m.Triangles.data());
  EXPECT_EQ(grid.GetNumberOfBuckets(), locator.GetNumberOfBuckets());
  const std::vector<Vec2> all = Corners(m);
  for (const Vec2& X : QueryPoints(m, rng, 300))
  {
    const LocatorHit hit = grid.Locate(X.x(), X.y(), corners);
    EXPECT_EQ(hit.Triangle, BruteForce(all, X).Triangle);
    EXPECT_EQ(hit.Triangle, locator.Locate(X.x(), X.y()).Triangle);
    EXPECT_EQ(grid.Bucket(X.x(), X.y()), locator.Bucket(X.x(), X.y()));
  }

  const std::vector<Vec2> square = { Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 0), Vec2(1, 1),
    Vec2(0, 1) };
  auto squareCorners = [&square](Id t, Vec2* c) { std::copy_n(&square[3 * t], 3, c); };
  ASSERT_TRUE(grid.Build(2, squareCorners));
  EXPECT_EQ(grid.Locate(0.5, 0.5, squareCorners).Triangle, 0);
  EXPECT_EQ(grid.Locate(0.2, 0.8, squareCorners).Triangle, 1);
  EXPECT_FALSE(grid.Locate(1.5, 0.5, squareCorners).Found());
}

// Groups of micro-triangles (each macro-triangle of a jittered grid split at a point, outside it
// for every fifth one, as a Clough-Tocher spline's cells come): the grid over groups locates
// exactly as the grid over single triangles and the brute-force rule, barycentric coordinates
// included, ties (shared vertices, edges and split points) to the lowest id; with fewer
// entries. A last, incomplete group and groups that are not macro-triangles (k = 4) are still
// right, and so is the build in steps (Prepare, SpanOf, List).
TEST(TriangleBucketGrid, GroupsLocateAsSingleTriangles)
{
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(0.1, 1.0);
  const ParameterMesh m = RandomMesh(rng, 12, GridDiagonal::Alternating);
  std::vector<Vec2> micro, splits;
  for (Id t = 0; t < m.NumberOfTriangles(); ++t)
  {
    const Vec2* A[3] = { &m.UV[m.Triangles[3 * t]], &m.UV[m.Triangles[3 * t + 1]],
      &m.UV[m.Triangles[3 * t + 2]] };
    Vec3 w(U(rng), U(rng), U(rng));
    w /= w.sum();
    if (t % 5 == 0)
    {
      w = Vec3(1.4, -0.15, -0.25); // outside, beyond corner 0
    }
    const Vec2 S = w[0] * *A[0] + w[1] * *A[1] + w[2] * *A[2];
    splits.push_back(S);
    for (int l = 0; l < 3; ++l)
    {
      micro.insert(micro.end(), { *A[l], *A[(l + 1) % 3], S });
    }
  }
  Vec2 lo = micro[0], hi = micro[0];
  for (const Vec2& p : micro)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  std::vector<Vec2> queries = QueryPoints(m, rng, 400);
  for (size_t i = 0; i < micro.size(); i += 3)
  {
    queries.push_back(micro[i + 2]);                     // split point: 3 micro-triangles
    queries.push_back(0.5 * (micro[i] + micro[i + 2]));  // micro edge: 2
  }
  for (const Id n : { Id(micro.size() / 3), Id(micro.size() / 3 - 1) })
  {
    auto corners = [&micro](Id t, Vec2* c) { std::copy_n(&micro[3 * t], 3, c); };
    const std::vector<Vec2> used(micro.begin(), micro.begin() + 3 * n);
    TriangleBucketGrid single, grouped, fours;
    ASSERT_TRUE(single.Build(n, corners, lo, hi));
    ASSERT_TRUE(grouped.Build(n, corners, lo, hi, 3));
    ASSERT_TRUE(fours.Build(n, corners, lo, hi, 4));
    EXPECT_EQ(grouped.GetGroupSize(), 3);
    EXPECT_LT(grouped.GetNumberOfEntries(), single.GetNumberOfEntries() / 2);
    // The build in steps, from the groups' boxes: over [lo, hi] the same rows and boxes as
    // the box build; over a larger box another grid, which locates the same.
    TriangleBucketGrid steps, wider;
    for (TriangleBucketGrid* grid : { &steps, &wider })
    {
      const Vec2 margin = grid == &steps ? Vec2(0, 0) : Vec2(0.3, 0.2);
      ASSERT_TRUE(grid->Prepare(n, lo - margin, hi + margin, 3));
      ASSERT_EQ(grid->GetNumberOfGroups(), (n + 2) / 3);
      TriangleBucketGrid::Spans spans;
      for (Id t = 0; t < n; t += 3)
      {
        Vec2 groupLo = micro[3 * t], groupHi = groupLo;
        for (Id c = 3 * t; c < 3 * std::min(t + 3, n); ++c)
        {
          groupLo = groupLo.cwiseMin(micro[c]);
          groupHi = groupHi.cwiseMax(micro[c]);
        }
        spans.push_back(grid->SpanOf(groupLo, groupHi));
      }
      ASSERT_TRUE(grid->List(spans));
    }
    ASSERT_EQ(steps.GetNumberOfBuckets(), grouped.GetNumberOfBuckets());
    ASSERT_EQ(steps.GetNumberOfEntries(), grouped.GetNumberOfEntries());
    for (Id b = 0; b < steps.GetNumberOfBuckets(); ++b)
    {
      ASSERT_TRUE(std::equal(steps.RowBegin(b), steps.RowEnd(b), grouped.RowBegin(b),
        grouped.RowEnd(b))) << "bucket " << b;
      ASSERT_TRUE(std::equal(steps.RowBoxes(b), steps.RowBoxes(b) + (steps.RowEnd(b) - steps.RowBegin(b)),
        grouped.RowBoxes(b))) << "bucket " << b;
    }
    for (size_t i = 0; i < queries.size(); ++i)
    {
      const Vec2& X = queries[i];
      const LocatorHit expected = BruteForce(used, X);
      for (const TriangleBucketGrid* grid : { &single, &grouped, &fours, &wider })
      {
        const LocatorHit hit = grid->Locate(X.x(), X.y(), corners);
        ASSERT_EQ(hit.Triangle, expected.Triangle)
          << "group size " << grid->GetGroupSize() << ", " << n << " triangles, query " << i;
        ASSERT_EQ(hit.Barycentric, expected.Barycentric) << "query " << i;
      }
    }
  }
}

// The groups a bucket lists that MayHold keeps are the only candidates: locating among them gives
// Locate's triangle and coordinates, bit for bit, for queries anywhere (vertices, edges, outside
// the mesh), and the box test keeps well under the bucket's groups on a random mesh.
TEST(TriangleBucketGrid, BoxFilterKeepsEveryCandidate)
{
  std::mt19937 rng(31);
  const ParameterMesh m = RandomMesh(rng, 30, GridDiagonal::Alternating);
  const std::vector<Vec2> all = Corners(m);
  auto corners = [&all](Id t, Vec2* c) { std::copy_n(&all[3 * t], 3, c); };
  TriangleBucketGrid grid;
  ASSERT_TRUE(grid.Build(m.NumberOfTriangles(), corners));
  std::vector<Vec2> queries = QueryPoints(m, rng, 2000);
  std::uniform_real_distribution<double> wide(-0.2, 1.2);
  for (int i = 0; i < 500; ++i)
  {
    queries.emplace_back(wide(rng), wide(rng));
  }
  size_t listed = 0, kept = 0;
  std::vector<std::uint32_t> groups;
  for (size_t i = 0; i < queries.size(); ++i)
  {
    const Vec2& X = queries[i];
    Id ix, iy;
    ASSERT_TRUE(grid.BucketCell(X.x(), X.y(), ix, iy));
    const Id b = iy * grid.GetNumberOfColumns() + ix;
    ASSERT_EQ(b, grid.Bucket(X.x(), X.y()));
    const TriangleBucketGrid::Place place = grid.PlaceOf(X.x(), X.y());
    ASSERT_EQ(place.Bucket, b);
    groups.clear();
    grid.ForEachCandidate(place, [&groups](std::uint32_t g) { groups.push_back(g); });
    // The vectorised filter keeps what MayHold keeps, entry by entry, in the bucket's order.
    std::vector<std::uint32_t> scalar;
    for (const std::uint32_t* g = grid.RowBegin(b); g != grid.RowEnd(b); ++g)
    {
      if (TriangleBucketGrid::MayHold(grid.RowBoxes(b)[g - grid.RowBegin(b)], place))
      {
        scalar.push_back(*g);
      }
    }
    ASSERT_EQ(groups, scalar) << "query " << i;
    listed += grid.RowEnd(b) - grid.RowBegin(b);
    kept += groups.size();
    const LocatorHit among =
      grid.LocateAmong(groups.data(), groups.data() + groups.size(), X.x(), X.y(), corners);
    const LocatorHit expected = BruteForce(all, X);
    ASSERT_EQ(among.Triangle, expected.Triangle) << "query " << i << " at " << X.transpose();
    ASSERT_EQ(among.Barycentric, expected.Barycentric) << "query " << i;
    ASSERT_EQ(grid.Locate(X.x(), X.y(), corners).Triangle, expected.Triangle) << "query " << i;
  }
  EXPECT_LT(double(kept), 0.7 * double(listed)) << kept << " of " << listed;
}
