// SPDX-License-Identifier: GPL-3.0-or-later
#include "AnalyticSurfaces.h"
#include "MeshTopology.h"

#include <gtest/gtest.h>

using namespace ctk;

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
