// SPDX-License-Identifier: GPL-3.0-or-later
// PointToMeshDistance (CGAL AABB tree) against a brute-force scan of all triangles.
#include "PointToMeshDistance.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using ctk::Id;
using ctk::Vec3;

// Closest point of triangle (a, b, c) to p, by minimising over the triangle's interior (when the
// projection falls inside) and its three edges: independent of the Voronoi-region code CGAL uses.
Vec3 ClosestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return a + s * d;
}

double BruteTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  double best = std::numeric_limits<double>::infinity();
  const Vec3 n = (b - a).cross(c - a);
  if (n.squaredNorm() > 0.0)
  {
    const Vec3 q = p - n * ((p - a).dot(n) / n.squaredNorm());
    // Inside when q is on the inner side of all three edges.
    const bool inside = (b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 &&
      (a - c).cross(q - c).dot(n) >= 0.0;
    if (inside)
    {
      best = (p - q).norm();
    }
  }
  best = std::min(best, (p - ClosestOnSegment(p, a, b)).norm());
  best = std::min(best, (p - ClosestOnSegment(p, b, c)).norm());
  best = std::min(best, (p - ClosestOnSegment(p, c, a)).norm());
  return best;
}

struct Mesh
{
  std::vector<double> Points;
  std::vector<Id> Triangles;
  Vec3 P(Id v) const { return Vec3(Points[3 * v], Points[3 * v + 1], Points[3 * v + 2]); }
};

// A bumpy height field over an n x n grid (a connected surface with all orientations).
Mesh BumpyGrid(int n)
{
  Mesh m;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      const double x = double(i) / n, y = double(j) / n;
      m.Points.insert(m.Points.end(), { x, y, 0.3 * std::sin(5 * x) * std::cos(4 * y) });
    }
  }
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const Id a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.Triangles.insert(m.Triangles.end(), { a, b, d, a, d, c });
    }
  }
  return m;
}

// Disconnected random triangles of mixed sizes.
Mesh RandomSoup(int count, unsigned seed)
{
  Mesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0), S(0.01, 0.5);
  for (int t = 0; t < count; ++t)
  {
    const Vec3 c(U(rng), U(rng), U(rng));
    const double s = S(rng);
    for (int a = 0; a < 3; ++a)
    {
      const Vec3 x = c + s * Vec3(U(rng), U(rng), U(rng));
      m.Points.insert(m.Points.end(), { x.x(), x.y(), x.z() });
      m.Triangles.push_back(3 * t + a);
    }
  }
  return m;
}

void CompareWithBruteForce(const Mesh& m, unsigned seed)
{
  ctk::PointToMeshDistance d;
  const Id nt = static_cast<Id>(m.Triangles.size() / 3);
  ASSERT_EQ(d.Build(static_cast<Id>(m.Points.size() / 3), m.Points.data(), nt, m.Triangles.data()), "");
  EXPECT_EQ(d.GetNumberOfTriangles(), nt);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.5, 1.5);
  for (int q = 0; q < 300; ++q)
  {
    const Vec3 p(U(rng), U(rng), U(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (Id t = 0; t < nt; ++t)
    {
      brute = std::min(brute,
        BruteTriangleDistance(p, m.P(m.Triangles[3 * t]), m.P(m.Triangles[3 * t + 1]),
          m.P(m.Triangles[3 * t + 2])));
    }
    const ctk::PointToMeshDistance::Result r = d.Query(p);
    EXPECT_NEAR(r.Distance, brute, 1e-12) << "query " << q;
    EXPECT_NEAR((r.Closest - p).norm(), r.Distance, 1e-14);
    // The reported closest point lies on the reported triangle.
    ASSERT_GE(r.Triangle, 0);
    ASSERT_LT(r.Triangle, nt);
    const Id* tri = &m.Triangles[3 * r.Triangle];
    EXPECT_NEAR(BruteTriangleDistance(r.Closest, m.P(tri[0]), m.P(tri[1]), m.P(tri[2])), 0.0, 1e-12);
  }
}
} // namespace

TEST(PointToMeshDistance, MatchesBruteForceOnBumpyGrid)
{
  CompareWithBruteForce(BumpyGrid(9), 3u);
}

TEST(PointToMeshDistance, MatchesBruteForceOnRandomSoup)
{
  CompareWithBruteForce(RandomSoup(60, 11u), 5u);
}

TEST(PointToMeshDistance, PointsOnTheMeshHaveZeroDistance)
{
  const Mesh m = BumpyGrid(6);
  ctk::PointToMeshDistance d;
  ASSERT_EQ(d.Build(static_cast<Id>(m.Points.size() / 3), m.Points.data(),
              static_cast<Id>(m.Triangles.size() / 3), m.Triangles.data()),
    "");
  for (Id t = 0; t < static_cast<Id>(m.Triangles.size() / 3); t += 7)
  {
    const Vec3 c = (m.P(m.Triangles[3 * t]) + m.P(m.Triangles[3 * t + 1]) + 2 * m.P(m.Triangles[3 * t + 2])) / 4;
    EXPECT_LT(d.Query(c).Distance, 1e-14);
  }
}

TEST(PointToMeshDistance, DegenerateTrianglesAreSkipped)
{
  // One real triangle in the plane z = 0 and a collinear one far away.
  const std::vector<double> pts = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5, 6, 6, 6, 7, 7, 7 };
  const std::vector<Id> tris = { 0, 1, 2, 3, 4, 5 };
  ctk::PointToMeshDistance d;
  ASSERT_EQ(d.Build(6, pts.data(), 2, tris.data()), "");
  EXPECT_EQ(d.GetNumberOfTriangles(), 1);
  const auto r = d.Query(Vec3(0.25, 0.25, 2.0));
  EXPECT_NEAR(r.Distance, 2.0, 1e-15);
  EXPECT_EQ(r.Triangle, 0);
}

TEST(PointToMeshDistance, BadInputIsReported)
{
  const std::vector<double> pts = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
  ctk::PointToMeshDistance d;
  const std::vector<Id> outOfRange = { 0, 1, 3 };
  EXPECT_NE(d.Build(3, pts.data(), 1, outOfRange.data()).find("point 3"), std::string::npos);
  std::vector<double> nan = pts;
  nan[4] = std::nan("");
  const std::vector<Id> tri = { 0, 1, 2 };
  EXPECT_NE(d.Build(3, nan.data(), 1, tri.data()).find("non-finite"), std::string::npos);
  const std::vector<double> line = { 0, 0, 0, 1, 1, 1, 2, 2, 2 };
  EXPECT_NE(d.Build(3, line.data(), 1, tri.data()).find("positive area"), std::string::npos);
  EXPECT_NE(d.Build(3, pts.data(), 0, tri.data()).find("positive area"), std::string::npos);
}
