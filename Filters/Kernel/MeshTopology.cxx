// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshTopology.h"

#include "LargeArrays.h"

#include <algorithm>

namespace ctk
{
Id MeshTopology::NumberOfBoundaryEdges() const
{
  return static_cast<Id>(std::count_if(EdgeTriangles.begin(), EdgeTriangles.end(),
    [](const std::array<Id, 2>& et) { return et[1] < 0; }));
}

TopologyStatus BuildMeshTopology(
  Id numPoints, Id numTriangles, const Id* triangles, MeshTopology& topology)
{
  TopologyStatus status;
  auto fail = [&](Id t, const MessageBuilder& msg) {
    status = msg.Failure<TopologyStatus>();
    status.Triangle = t;
    return status;
  };
  for (Id t = 0; t < numTriangles; ++t)
  {
    const Id* p = triangles + 3 * t;
    for (int l = 0; l < 3; ++l)
    {
      if (p[l] < 0 || p[l] >= numPoints)
      {
        // p[l] names no vertex (it is out of range): plain text, never renamed.
        MessageBuilder os;
        os << "triangle " << TriangleId{ t } << " references point " << p[l] << " outside [0, "
           << numPoints << ")";
        return fail(t, os);
      }
    }
    if (p[0] == p[1] || p[1] == p[2] || p[2] == p[0])
    {
      MessageBuilder os;
      os << "triangle " << TriangleId{ t } << " repeats a vertex (" << VertexId{ p[0] } << ", "
         << VertexId{ p[1] } << ", " << VertexId{ p[2] } << ")";
      return fail(t, os);
    }
  }

  // Bucket the 3T half-edges by their smaller vertex (counting sort), then match within buckets.
  std::vector<Id> start(numPoints + 1, 0);
  for (Id h = 0; h < 3 * numTriangles; ++h)
  {
    const Id a = triangles[h], b = triangles[h % 3 == 2 ? h - 2 : h + 1];
    ++start[std::min(a, b) + 1];
  }
  for (Id v = 0; v < numPoints; ++v)
  {
    start[v + 1] += start[v];
  }
  std::vector<Id> bucket;
  ResizeForOverwrite(bucket, 3 * numTriangles);
  {
    std::vector<Id> fill(start.begin(), start.end() - 1);
    for (Id h = 0; h < 3 * numTriangles; ++h)
    {
      const Id a = triangles[h], b = triangles[h % 3 == 2 ? h - 2 : h + 1];
      bucket[fill[std::min(a, b)]++] = h;
    }
  }

  topology.Edges.clear();
  topology.EdgeTriangles.clear();
  topology.EdgeLocalIndex.clear();
  AssignLarge(topology.TriangleEdges, numTriangles, std::array<Id, 3>{ -1, -1, -1 });
  // E = (3T + boundary edges)/2 <= 2T + 1; reserved pages that stay unused cost no memory.
  const size_t edgeGuess = 2 * numTriangles + 1;
  topology.Edges.reserve(edgeGuess);
  topology.EdgeTriangles.reserve(edgeGuess);
  topology.EdgeLocalIndex.reserve(edgeGuess);
  AdviseHugePages(topology.Edges.data(), edgeGuess * sizeof(topology.Edges[0]));
  AdviseHugePages(topology.EdgeTriangles.data(), edgeGuess * sizeof(topology.EdgeTriangles[0]));
  for (Id v = 0; v < numPoints; ++v)
  {
    const Id begin = start[v], end = start[v + 1];
    for (Id s = begin; s < end; ++s)
    {
      const Id h = bucket[s];
      const Id t = h / 3;
      const int l = static_cast<int>(h % 3);
      if (topology.TriangleEdges[t][l] >= 0)
      {
        continue;
      }
      const Id other = std::max(triangles[h], triangles[h % 3 == 2 ? h - 2 : h + 1]);
      const Id e = static_cast<Id>(topology.Edges.size());
      // Element by element: push_back of a braced pair goes through a stack temporary whose
      // reload stalls on store forwarding (a third of the topology's time).
      std::array<Id, 2>& edge = topology.Edges.emplace_back();
      edge[0] = v;
      edge[1] = other;
      std::array<Id, 2>& sides = topology.EdgeTriangles.emplace_back();
      sides[0] = t;
      sides[1] = -1;
      std::array<signed char, 2>& local = topology.EdgeLocalIndex.emplace_back();
      local[0] = static_cast<signed char>(l);
      local[1] = -1;
      topology.TriangleEdges[t][l] = e;
      for (Id s2 = s + 1; s2 < end; ++s2)
      {
        const Id h2 = bucket[s2];
        if (std::max(triangles[h2], triangles[h2 % 3 == 2 ? h2 - 2 : h2 + 1]) != other)
        {
          continue;
        }
        const Id t2 = h2 / 3;
        if (topology.EdgeTriangles[e][1] >= 0)
        {
          MessageBuilder os;
          os << "non-manifold edge (" << VertexId{ v } << ", " << VertexId{ other }
             << ") shared by triangles " << TriangleId{ topology.EdgeTriangles[e][0] } << ", "
             << TriangleId{ topology.EdgeTriangles[e][1] } << " and " << TriangleId{ t2 };
          return fail(t2, os);
        }
        const Id opposite = triangles[3 * t + (l + 2) % 3];
        if (triangles[3 * t2 + (h2 % 3 + 2) % 3] == opposite)
        {
          MessageBuilder os;
          os << "duplicate triangles " << TriangleId{ std::min(t, t2) } << " and "
             << TriangleId{ std::max(t, t2) } << " have the same vertices (" << VertexId{ v }
             << ", " << VertexId{ other } << ", " << VertexId{ opposite } << ")";
          return fail(std::max(t, t2), os);
        }
        topology.EdgeTriangles[e][1] = t2;
        topology.EdgeLocalIndex[e][1] = static_cast<signed char>(h2 % 3);
        topology.TriangleEdges[t2][h2 % 3] = e;
      }
    }
  }
  return status;
}

void OrderEdgeTrianglesByRank(const Id* rank, MeshTopology& topology)
{
  for (size_t e = 0; e < topology.EdgeTriangles.size(); ++e)
  {
    std::array<Id, 2>& t = topology.EdgeTriangles[e];
    if (t[1] >= 0 && rank[t[1]] < rank[t[0]])
    {
      std::swap(t[0], t[1]);
      std::swap(topology.EdgeLocalIndex[e][0], topology.EdgeLocalIndex[e][1]);
    }
  }
}
} // namespace ctk
