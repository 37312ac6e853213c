// SPDX-License-Identifier: GPL-3.0-or-later
// Edge adjacency of a triangle mesh: unique edges, the (at most two) triangles at each edge and
// boundary edges. No orientation is assumed. Built in O(n) (bucketed by the smaller vertex id).
#ifndef CTSplines_Kernel_MeshTopology_h
#define CTSplines_Kernel_MeshTopology_h

#include "MessageIds.h" // for Id
#include "LargeArrays.h"
#include "ParallelFor.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ctk
{
/// Local edge l of a triangle joins its vertices l and (l + 1) % 3; it is opposite vertex
/// (l + 2) % 3.
struct MeshTopology
{
  /// Unique edges, each as (a, b) with a < b. #E by 2.
  OverwriteVector<std::array<Id, 2>> Edges;
  /// Edge id of each local edge of each triangle. #T by 3.
  OverwriteVector<std::array<Id, 3>> TriangleEdges;
  /// The triangles at each edge (second is -1 on a boundary edge). #E by 2.
  OverwriteVector<std::array<Id, 2>> EdgeTriangles;
  /// Local edge index of the edge in each of EdgeTriangles. #E by 2.
  OverwriteVector<std::array<signed char, 2>> EdgeLocalIndex;
  /// Whether the two triangles of every interior edge run along it in opposite directions (set
  /// by BuildMeshTopology; false when unknown). Then triangles whose signed areas in (u, v) all
  /// have one sign cannot fold at any edge.
  bool ConsistentlyOriented = false;

  bool IsBoundaryEdge(Id e) const { return EdgeTriangles[e][1] < 0; }
  Id NumberOfBoundaryEdges() const;

  /// The triangle across local edge l of triangle t, or -1 on the boundary.
  Id Neighbor(Id t, int l) const
  {
    const auto& et = EdgeTriangles[TriangleEdges[t][l]];
    return et[0] == t ? et[1] : et[0];
  }
};

/// Result of BuildMeshTopology: Ok, or a message naming the offending triangle/edge.
struct TopologyStatus
{
  bool Ok = true;
  std::string Message;
  std::vector<MessageId> Ids; // the triangles and vertices Message names
  Id Triangle = -1;
};

/// Builds the edge adjacency of numTriangles triangles given as triangles[3 t + l] point ids in
/// [0, numPoints). Fails (with a message) on out-of-range ids, a triangle repeating a vertex,
/// a non-manifold edge (three or more triangles) or two triangles with the same three vertices,
/// naming the same triangle whatever the split of parallelFor's chunks. Edges are numbered by
/// their smaller vertex, then by their first local edge (3 t + l). Sets ConsistentlyOriented.
/// An interior edge's two triangles are in id order, or, given rank, in rank[t] order (for a
/// renumbered mesh: the input's triangle ids, so that the constructions, which read an edge's
/// triangles in that order, give the renumbered mesh the input's bits).
TopologyStatus BuildMeshTopology(Id numPoints, Id numTriangles, const Id* triangles,
  MeshTopology& topology, const ParallelFor& parallelFor = SerialFor, const Id* rank = nullptr);

} // namespace ctk

#endif
