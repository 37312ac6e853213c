// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshTopology.h"
#include "MessageIds.h"

#include <gtest/gtest.h>

using namespace ctk;

namespace
{
// Triangles t -> 100 + t, vertices v -> 10 v: another numbering of the same elements.
Id Renamed(IdKind kind, Id id)
{
  return kind == IdKind::Triangle ? 100 + id : 10 * id;
}
} // namespace

TEST(MessageIds, RecordsAndRenamesTaggedIdsOnly)
{
  MessageBuilder os;
  os << "triangle " << TriangleId{ 7 } << " has 3 points (" << VertexId{ 2 } << ", "
     << VertexId{ 12 } << ") of 40";
  ASSERT_EQ(os.Text(), "triangle 7 has 3 points (2, 12) of 40");
  ASSERT_EQ(os.Ids().size(), 3u);
  EXPECT_EQ(os.Ids()[0].Offset, 9u);
  EXPECT_EQ(os.Ids()[0].Kind, IdKind::Triangle);
  EXPECT_EQ(os.Ids()[2].Offset, 28u);
  EXPECT_EQ(os.Ids()[2].Length, 2u);
  EXPECT_EQ(RenameIds(os.Text(), os.Ids(), &Renamed), "triangle 107 has 3 points (20, 120) of 40");
  // Text put before the ids since: they no longer match, the message is kept as it is.
  EXPECT_EQ(RenameIds("mesh: " + os.Text(), os.Ids(), &Renamed), "mesh: " + os.Text());
}

TEST(MessageIds, TopologyErrorsTagTheirTrianglesAndVertices)
{
  const Id tris[] = { 0, 1, 2, 1, 0, 3, 0, 1, 4 };
  MeshTopology topo;
  const TopologyStatus s = BuildMeshTopology(5, 3, tris, topo);
  ASSERT_FALSE(s.Ok);
  EXPECT_EQ(RenameIds(s.Message, s.Ids, &Renamed),
    "non-manifold edge (0, 10) shared by triangles 100, 101 and 102");
  // An id out of range is no vertex: it stays as written.
  const Id outside[] = { 0, 1, 7 };
  const TopologyStatus o = BuildMeshTopology(4, 1, outside, topo);
  EXPECT_EQ(RenameIds(o.Message, o.Ids, &Renamed), "triangle 100 references point 7 outside [0, 4)");
}
