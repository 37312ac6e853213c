// SPDX-License-Identifier: GPL-3.0-or-later
#include "AnalyticSurfaces.h"
#include "MeshTopology.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

using namespace ctk;
using namespace ctk_test;

TEST(MeshTopology, RegularGridCounts)
{
  for (int n : { 1, 3, 8 })
  {
    for (GridDiagonal d : { GridDiagonal::Forward, GridDiagonal::Backward, GridDiagonal::Alternating })
    {
      const ParameterMesh m = RegularGridMesh(n, d);
      MeshTopology topo;
      ASSERT_TRUE(BuildMeshTopology(static_cast<Id>(m.UV.size()), m.NumberOfTriangles(),
        m.Triangles.data(), topo)
                    .Ok);
      EXPECT_EQ(static_cast<Id>(topo.Edges.size()), 3 * n * n + 2 * n);
      EXPECT_EQ(topo.NumberOfBoundaryEdges(), 4 * n);
      // Every local edge points to an edge that lists the triangle back.
      for (Id t = 0; t < m.NumberOfTriangles(); ++t)
      {
        for (int l = 0; l < 3; ++l)
        {
          const Id e = topo.TriangleEdges[t][l];
          const auto& et = topo.EdgeTriangles[e];
          ASSERT_TRUE(et[0] == t || et[1] == t);
          const int s = et[0] == t ? 0 : 1;
          EXPECT_EQ(topo.EdgeLocalIndex[e][s], l);
          const Id a = m.Triangles[3 * t + l], b = m.Triangles[3 * t + (l + 1) % 3];
          EXPECT_EQ(topo.Edges[e][0], std::min(a, b));
          EXPECT_EQ(topo.Edges[e][1], std::max(a, b));
        }
      }
    }
  }
}

TEST(MeshTopology, MixedOrientationIsAccepted)
{
  // Two triangles sharing edge (1, 2), one of them clockwise.
  const Id tris[] = { 0, 1, 2, 1, 2, 3 };
  MeshTopology topo;
  ASSERT_TRUE(BuildMeshTopology(4, 2, tris, topo).Ok);
  EXPECT_EQ(topo.Edges.size(), 5u);
  EXPECT_EQ(topo.Neighbor(0, 1), 1);
  EXPECT_EQ(topo.Neighbor(1, 0), 0);
}

TEST(MeshTopology, NonManifoldEdgeIsReported)
{
  const Id tris[] = { 0, 1, 2, 1, 0, 3, 0, 1, 4 };
  MeshTopology topo;
  const TopologyStatus s = BuildMeshTopology(5, 3, tris, topo);
  EXPECT_FALSE(s.Ok);
  EXPECT_EQ(s.Triangle, 2);
  EXPECT_NE(s.Message.find("non-manifold edge (0, 1)"), std::string::npos) << s.Message;
}

TEST(MeshTopology, RepeatedVertexAndOutOfRangeAreReported)
{
  MeshTopology topo;
  const Id repeated[] = { 0, 1, 2, 2, 3, 2 };
  TopologyStatus s = BuildMeshTopology(4, 2, repeated, topo);
  EXPECT_FALSE(s.Ok);
  EXPECT_EQ(s.Triangle, 1);
  const Id outside[] = { 0, 1, 7 };
  s = BuildMeshTopology(4, 1, outside, topo);
  EXPECT_FALSE(s.Ok);
  EXPECT_NE(s.Message.find("point 7"), std::string::npos) << s.Message;
}

// A grid numbered at random, large enough for several vertex and triangle blocks of
// BuildMeshTopology's parallel passes.
struct LargeMesh
{
  Id NumberOfVertices, NumberOfTriangles;
  std::vector<Id> Triangles;
};
LargeMesh ShuffledGrid()
{
  const ParameterMesh m = RegularGridMesh(300, GridDiagonal::Alternating);
  const Id nV = static_cast<Id>(m.UV.size());
  return { nV, m.NumberOfTriangles(), ShuffledTriangles(m.Triangles, nV, 3u) };
}

TEST(MeshTopology, SameEdgesOnAnyNumberOfThreads)
{
  const LargeMesh m = ShuffledGrid();
  MeshTopology serial;
  ASSERT_TRUE(BuildMeshTopology(m.NumberOfVertices, m.NumberOfTriangles, m.Triangles.data(), serial).Ok);
  // Edges numbered by their smaller vertex, then by their first local edge 3 t + l, which is
  // the edge's first side.
  auto key = [&serial](size_t e, int side) {
    return 3 * serial.EdgeTriangles[e][side] + serial.EdgeLocalIndex[e][side];
  };
  for (size_t e = 0; e < serial.Edges.size(); ++e)
  {
    if (e > 0)
    {
      ASSERT_LT(std::make_pair(serial.Edges[e - 1][0], key(e - 1, 0)),
        std::make_pair(serial.Edges[e][0], key(e, 0))) << "edge " << e;
    }
    if (!serial.IsBoundaryEdge(static_cast<Id>(e)))
    {
      ASSERT_LT(key(e, 0), key(e, 1)) << "edge " << e;
    }
  }
  for (const auto& [threads, chunk] : { std::pair<int, Id>{ 2, 4999 }, { 3, 7777 }, { 3, 1 << 16 } })
  {
    MeshTopology parallel;
    ASSERT_TRUE(BuildMeshTopology(m.NumberOfVertices, m.NumberOfTriangles, m.Triangles.data(),
      parallel, ThreadedFor(threads, chunk)).Ok);
    EXPECT_EQ(serial.Edges, parallel.Edges) << threads << " threads";
    EXPECT_EQ(serial.TriangleEdges, parallel.TriangleEdges) << threads << " threads";
    EXPECT_EQ(serial.EdgeTriangles, parallel.EdgeTriangles) << threads << " threads";
    EXPECT_EQ(serial.EdgeLocalIndex, parallel.EdgeLocalIndex) << threads << " threads";
    // By rank: the same edges, each interior edge's sides swapped when rank says so.
    std::vector<Id> rank(static_cast<size_t>(m.NumberOfTriangles));
    for (Id t = 0; t < m.NumberOfTriangles; ++t)
    {
      rank[t] = (t * 7919) % m.NumberOfTriangles; // a permutation: 7919 is prime
    }
    MeshTopology ranked;
    ASSERT_TRUE(BuildMeshTopology(m.NumberOfVertices, m.NumberOfTriangles, m.Triangles.data(),
      ranked, ThreadedFor(threads, chunk), rank.data()).Ok);
    EXPECT_EQ(serial.Edges, ranked.Edges) << threads << " threads";
    EXPECT_EQ(serial.TriangleEdges, ranked.TriangleEdges) << threads << " threads";
    size_t swapped = 0, wrong = 0;
    for (size_t e = 0; e < serial.Edges.size(); ++e)
    {
      const auto& et = serial.EdgeTriangles[e];
      const bool swap = et[1] >= 0 && rank[et[1]] < rank[et[0]];
      swapped += swap;
      const auto& el = serial.EdgeLocalIndex[e];
      wrong += ranked.EdgeTriangles[e] != (swap ? std::array<Id, 2>{ et[1], et[0] } : et);
      wrong += ranked.EdgeLocalIndex[e] != (swap ? std::array<signed char, 2>{ el[1], el[0] } : el);
    }
    EXPECT_EQ(wrong, 0u) << threads << " threads";
    EXPECT_GT(swapped, serial.Edges.size() / 4) << "the ranks reorder many edges";
  }
}

TEST(MeshTopology, FailuresNameTheSameTriangleOnAnyNumberOfThreads)
{
  const LargeMesh m = ShuffledGrid();
  // The triangles at the lowest and highest vertex ids.
  Id low = 0, high = 0;
  for (Id t = 0; t < m.NumberOfTriangles; ++t)
  {
    const Id* p = &m.Triangles[3 * t];
    low = std::min({ p[0], p[1], p[2] }) == 0 ? t : low;
    high = std::max({ p[0], p[1], p[2] }) == m.NumberOfVertices - 1 ? t : high;
  }
  auto copyOf = [&](Id t) { return std::vector<Id>(&m.Triangles[3 * t], &m.Triangles[3 * t + 3]); };
  // Copies of both, the one at the high vertex first: the edges are matched in vertex order, so
  // the copy at vertex 0 (the last triangle) is named (as a duplicate, or a third triangle at
  // an interior edge), as on one thread.
  std::vector<Id> duplicated = m.Triangles;
  for (Id t : { high, low })
  {
    const std::vector<Id> copy = copyOf(t);
    duplicated.insert(duplicated.end(), copy.begin(), copy.end());
  }
  std::vector<Id> badIds = m.Triangles;
  badIds[3 * 150000 + 1] = -1;
  badIds[3 * 90000 + 2] = badIds[3 * 90000];
  badIds[3 * 100000] = m.NumberOfVertices;
  const std::string copyNamed = " and " + std::to_string(m.NumberOfTriangles + 1);
  const struct
  {
    const std::vector<Id>& Triangles;
    Id Named;
    std::string Text;
  } cases[] = { { duplicated, m.NumberOfTriangles + 1, copyNamed },
    { badIds, 90000, "triangle 90000 repeats a vertex" } };
  for (const auto& c : cases)
  {
    const Id nT = static_cast<Id>(c.Triangles.size() / 3);
    for (int threads : { 1, 2, 3 })
    {
      MeshTopology topo;
      const TopologyStatus s = BuildMeshTopology(
        m.NumberOfVertices, nT, c.Triangles.data(), topo, ThreadedFor(threads, 5001));
      EXPECT_FALSE(s.Ok);
      EXPECT_EQ(s.Triangle, c.Named) << threads << " threads: " << s.Message;
      EXPECT_NE(s.Message.find(c.Text), std::string::npos) << s.Message;
    }
  }
}

// ConsistentlyOriented: true for a grid (all its triangles counter-clockwise) in any numbering,
// all reversed too, and false once any one triangle is reversed, whichever vertex block its
// edges fall in, on any number of threads.
TEST(MeshTopology, ConsistentOrientationIsFoundInEveryBlock)
{
  const LargeMesh m = ShuffledGrid(); // vertex and triangle ids shuffled: orientation kept
  auto consistent = [&m](const std::vector<Id>& tris, const ParallelFor& parallelFor) {
    MeshTopology topo;
    EXPECT_TRUE(
      BuildMeshTopology(m.NumberOfVertices, m.NumberOfTriangles, tris.data(), topo, parallelFor).Ok);
    return topo.ConsistentlyOriented;
  };
  EXPECT_TRUE(consistent(m.Triangles, SerialFor));
  std::vector<Id> reversed = m.Triangles;
  for (Id t = 0; t < m.NumberOfTriangles; ++t)
  {
    std::swap(reversed[3 * t + 1], reversed[3 * t + 2]);
  }
  EXPECT_TRUE(consistent(reversed, ThreadedFor(2, 4999)));
  for (const Id t : { Id(0), m.NumberOfTriangles / 3, m.NumberOfTriangles - 1 })
  {
    std::vector<Id> one = m.Triangles;
    std::swap(one[3 * t + 1], one[3 * t + 2]);
    EXPECT_FALSE(consistent(one, SerialFor)) << "triangle " << t;
    EXPECT_FALSE(consistent(one, ThreadedFor(3, 7777))) << "triangle " << t;
  }
  // A failed build leaves it false.
  MeshTopology topo;
  ASSERT_TRUE(BuildMeshTopology(m.NumberOfVertices, m.NumberOfTriangles, m.Triangles.data(), topo).Ok);
  const Id bad[] = { 0, 1, 1 };
  EXPECT_FALSE(BuildMeshTopology(m.NumberOfVertices, 1, bad, topo).Ok);
  EXPECT_FALSE(topo.ConsistentlyOriented);
}
