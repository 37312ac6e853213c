// SPDX-License-Identifier: GPL-3.0-or-later
// DelaunayTriangulation against the definition: counter-clockwise triangles that cover the
// convex hull (Euler's count), no point strictly inside a triangle's circumcircle (a scan of all
// points), duplicates unused, degenerate input empty.
#include "DelaunayTriangulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace
{
using ctk::Id;

double Orient(const double* a, const double* b, const double* c)
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// > 0 when d is strictly inside the circumcircle of the counter-clockwise (a, b, c).
double InCircle(const double* a, const double* b, const double* c, const double* d)
{
  const double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1];
  const double cx = c[0] - d[0], cy = c[1] - d[1];
  return (ax * ax + ay * ay) * (bx * cy - by * cx) - (bx * bx + by * by) * (ax * cy - ay * cx) +
    (cx * cx + cy * cy) * (ax * by - ay * bx);
}
} // namespace

TEST(DelaunayTriangulation, RandomPointsMeetTheDefinition)
{
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int n = 600;
  std::vector<double> xy(2 * n);
  // The unit square's corners (the hull, 4 points) and random points inside.
  const double corners[8] = { 0, 0, 1, 0, 1, 1, 0, 1 };
  std::copy_n(corners, 8, xy.begin());
  for (int i = 8; i < 2 * n; ++i)
  {
    xy[i] = 0.01 + 0.98 * U(rng);
  }
  const std::vector<Id> t = ctk::DelaunayTriangulation(xy);
  ASSERT_EQ(t.size() % 3, 0u);
  EXPECT_EQ(static_cast<Id>(t.size() / 3), 2 * n - 2 - 4); // 2n - 2 - h triangles
  EXPECT_EQ(t, ctk::DelaunayTriangulation(xy)); // the same order for the same points
  std::set<Id> used(t.begin(), t.end());
  EXPECT_EQ(static_cast<int>(used.size()), n);
  int violations = 0;
  for (size_t k = 0; k < t.size(); k += 3)
  {
    const double *a = &xy[2 * t[k]], *b = &xy[2 * t[k + 1]], *c = &xy[2 * t[k + 2]];
    ASSERT_GT(Orient(a, b, c), 0.0) << "triangle " << k / 3;
    for (int p = 0; p < n; ++p)
    {
      violations += p != t[k] && p != t[k + 1] && p != t[k + 2] &&
        InCircle(a, b, c, &xy[2 * p]) > 1e-12;
    }
  }
  EXPECT_EQ(violations, 0);
}

TEST(DelaunayTriangulation, DuplicatesAndDegenerateInput)
{
  // Point 3 repeats point 1 exactly: one vertex, used once.
  const std::vector<double> square = { 0, 0, 1, 0, 0, 1, 1, 0, 0.9, 0.8 };
  const std::vector<Id> t = ctk::DelaunayTriangulation(square);
  EXPECT_EQ(t.size(), 6u);
  EXPECT_GE(std::count(t.begin(), t.end(), Id(1)) + std::count(t.begin(), t.end(), Id(3)), 1);
  EXPECT_EQ(std::count(t.begin(), t.end(), Id(1)) * std::count(t.begin(), t.end(), Id(3)), 0);
  EXPECT_TRUE(ctk::DelaunayTriangulation({ 0, 0, 1, 1, 2, 2, 3, 3 }).empty()); // collinear
  EXPECT_TRUE(ctk::DelaunayTriangulation({ 0, 0, 1, 1 }).empty());
  EXPECT_TRUE(ctk::DelaunayTriangulation({}).empty());
}
