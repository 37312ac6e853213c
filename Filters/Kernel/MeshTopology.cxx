// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshTopology.h"

#include "LargeArrays.h"
#include "LocalityOrder.h" // for PrefetchRead

#include <algorithm>

namespace ctk
{
Id MeshTopology::NumberOfBoundaryEdges() const
{
  return static_cast<Id>(std::count_if(EdgeTriangles.begin(), EdgeTriangles.end(),
    [](const std::array<Id, 2>& et) { return et[1] < 0; }));
}

namespace
{
// Half-edge h = 3t + l joins triangles[h] and triangles[NextCorner(h)].
Id NextCorner(Id h)
{
  return h % 3 == 2 ? h - 2 : h + 1;
}

// Edges are numbered by their smaller vertex, then by their first half-edge: the work is cut in
// blocks of vertices (each block's half-edges bucketed and matched on its own, in cache) and of
// triangles (the pass that sends each half-edge to its vertex block), at most MaxBlocks each.
// Vertex blocks are powers of two (no division per half-edge); a half-edge is carried with its
// smaller vertex's offset in its block, in the bits above HalfEdgeBits (3.6e11 half-edges).
constexpr int MinVertexBlockBits = 12, MaxVertexBlockBits = 23, HalfEdgeBits = 40;
constexpr Id HalfEdgeMask = (Id(1) << HalfEdgeBits) - 1;
constexpr Id MinTriangleBlock = Id(1) << 15;
constexpr Id MaxBlocks = 256;

Id BlockSize(Id n, Id minimum)
{
  return std::max(minimum, (n + MaxBlocks - 1) / MaxBlocks);
}

int VertexBlockBits(Id numPoints)
{
  int bits = MinVertexBlockBits;
  while (bits < MaxVertexBlockBits && (Id(1) << bits) * MaxBlocks < numPoints)
  {
    ++bits;
  }
  return bits;
}

// What is wrong with triangle p: a vertex id outside [0, numPoints) (*outside set to it), a
// repeated vertex, or nothing. The counting pass tests every triangle with it; the failure's
// message is written from the same answer.
enum class TriangleFault
{
  None,
  Outside,
  Repeat
};
TriangleFault CheckTriangle(Id numPoints, const Id* p, Id* outside = nullptr)
{
  for (int l = 0; l < 3; ++l)
  {
    if (p[l] < 0 || p[l] >= numPoints)
    {
      if (outside)
      {
        *outside = p[l];
      }
      return TriangleFault::Outside;
    }
  }
  return p[0] == p[1] || p[1] == p[2] || p[2] == p[0] ? TriangleFault::Repeat
                                                      : TriangleFault::None;
}

// The failure of the lowest offending triangle's check (t fails it).
TopologyStatus TriangleFailure(Id numPoints, const Id* triangles, Id t)
{
  const Id* p = triangles + 3 * t;
  MessageBuilder os;
  Id outside = 0;
  if (CheckTriangle(numPoints, p, &outside) == TriangleFault::Outside)
  {
    os << "triangle " << TriangleId{ t } << " references point " << outside << " outside [0, "
       << numPoints << ")";
  }
  else
  {
    os << "triangle " << TriangleId{ t } << " repeats a vertex (" << VertexId{ p[0] } << ", "
       << VertexId{ p[1] } << ", " << VertexId{ p[2] } << ")";
  }
  TopologyStatus status = os.Failure<TopologyStatus>();
  status.Triangle = t;
  return status;
}

// A vertex block's half-edges bucketed by their smaller vertex v, in half-edge order: bucket
// v - v0 is Half[Start[v - v0] ..), with each half-edge's other vertex at the same place in Far
// (read while bucketing, when its triangle row is asked for anyway: the pairing's search then
// reads the bucket alone, the triangles only for a pair's checks; a matched half-edge's Far is
// set to -1).
struct Buckets
{
  std::vector<Id> Start;
  Id* Half = nullptr;
  OverwriteVector<Id> Far;
};

void FillBuckets(const Id* triangles, Id v0, Id v1, const Id* in, Id n, Buckets& b)
{
  b.Start.assign(static_cast<size_t>(v1 - v0 + 1), 0);
  for (Id i = 0; i < n; ++i)
  {
    ++b.Start[(in[i] >> HalfEdgeBits) + 1];
  }
  for (Id v = v0; v < v1; ++v)
  {
    b.Start[v - v0 + 1] += b.Start[v - v0];
  }
  ResizeForOverwrite(b.Far, static_cast<size_t>(n));
  std::vector<Id> fill(b.Start.begin(), b.Start.end() - 1);
  Id *half = b.Half, *far = b.Far.data(), *next = fill.data();
  for (Id i = 0; i < n; ++i)
  {
    // The triangles of later half-edges asked for ahead: reading each half-edge's triangle,
    // the matching waited on a miss for a third of its time.
    if (i + PrefetchDistance < n)
    {
      PrefetchRead(triangles + (in[i + PrefetchDistance] & HalfEdgeMask));
    }
    const Id h = in[i] & HalfEdgeMask, at = next[in[i] >> HalfEdgeBits]++;
    half[at] = h;
    far[at] = std::max(triangles[h], triangles[NextCorner(h)]);
  }
}

// The failures of PairBucket, out of its loop (which is then small enough to be inlined).
[[gnu::noinline]] TopologyStatus DuplicateTriangles(Id v, Id other, Id opposite, Id t, Id t2)
{
  MessageBuilder os;
  os << "duplicate triangles " << TriangleId{ std::min(t, t2) } << " and "
     << TriangleId{ std::max(t, t2) } << " have the same vertices (" << VertexId{ v } << ", "
     << VertexId{ other } << ", " << VertexId{ opposite } << ")";
  TopologyStatus failure = os.Failure<TopologyStatus>();
  failure.Triangle = std::max(t, t2);
  return failure;
}
[[gnu::noinline]] TopologyStatus NonManifoldEdge(Id v, Id other, Id t, Id t2, Id t3)
{
  MessageBuilder os;
  os << "non-manifold edge (" << VertexId{ v } << ", " << VertexId{ other }
     << ") shared by triangles " << TriangleId{ t } << ", " << TriangleId{ t2 } << " and "
     << TriangleId{ t3 };
  TopologyStatus failure = os.Failure<TopologyStatus>();
  failure.Triangle = t3;
  return failure;
}

// The edges of the bucket of vertex v (count half-edges h, their other vertices far), in the
// order of their first half-edge: an interior edge as its two half-edges, a boundary edge as ~h,
// written at `written` (advanced past them). Returns the number of edges, or -1 with `failure`
// set at the bucket's first non-manifold edge or duplicate triangles.
Id PairBucket(const Id* triangles, Id v, const Id* h, Id* far, Id count, Id*& written,
  TopologyStatus& failure, bool& consistent)
{
  Id edges = 0, *write = written;
  bool opposed = true;
  for (Id i = 0; i < count; ++i)
  {
    const Id other = far[i];
    if (other < 0)
    {
      continue; // matched to an earlier half-edge
    }
    Id j = i + 1;
    while (j < count && far[j] != other)
    {
      ++j;
    }
    ++edges;
    if (j == count)
    {
      *write++ = ~h[i];
      continue;
    }
    const Id t = h[i] / 3, t2 = h[j] / 3, opposite = triangles[3 * t + (h[i] % 3 + 2) % 3];
    if (triangles[3 * t2 + (h[j] % 3 + 2) % 3] == opposite)
    {
      failure = DuplicateTriangles(v, other, opposite, t, t2);
      return -1;
    }
    Id k = j + 1;
    while (k < count && far[k] != other)
    {
      ++k;
    }
    if (k < count)
    {
      failure = NonManifoldEdge(v, other, t, t2, h[k] / 3);
      return -1;
    }
    far[j] = -1;
    // Half-edge h runs from triangles[h]: from v for one of a consistent pair only.
    opposed &= (triangles[h[i]] == v) != (triangles[h[j]] == v);
    *write++ = h[i];
    *write++ = h[j];
  }
  written = write;
  consistent &= opposed;
  return edges;
}

// The n half-edges of one vertex block (with their vertex offsets) are rewritten as the block's
// edges in order: an interior edge as its two half-edges, a boundary edge as ~h (the buckets'
// half-edges in `scratch`). Returns the number of edges, or -1 with `failure` set;
// `consistent`: whether every interior edge's half-edges run along it in opposite directions.
Id MatchBlock(const Id* triangles, Id v0, Id v1, Id* halfEdges, Id n, Id* scratch,
  TopologyStatus& failure, bool& consistent)
{
  consistent = true;
  Buckets b;
  b.Half = scratch;
  FillBuckets(triangles, v0, v1, halfEdges, n, b);
  Id edges = 0;
  Id* write = halfEdges; // free: the buckets hold every half-edge
  const Id* start = b.Start.data();
  for (Id v = v0; v < v1; ++v)
  {
    const Id begin = start[v - v0];
    const Id made = PairBucket(triangles, v, b.Half + begin, b.Far.data() + begin,
      start[v - v0 + 1] - begin, write, failure, consistent);
    if (made < 0)
    {
      return -1;
    }
    edges += made;
  }
  return edges;
}
} // namespace

TopologyStatus BuildMeshTopology(Id numPoints, Id numTriangles, const Id* triangles,
  MeshTopology& topology, const ParallelFor& parallelFor, const Id* rank)
{
  // Each half-edge to its vertex block, in half-edge order within the block: counted per
  // triangle block (the triangles checked in the same pass), then written at the offsets of its
  // triangle block.
  topology.ConsistentlyOriented = false; // until every block is matched
  const Id nH = 3 * numTriangles;
  const int vertexBits = VertexBlockBits(numPoints);
  const Id vertexBlock = Id(1) << vertexBits;
  const Id triangleBlock = BlockSize(numTriangles, MinTriangleBlock);
  const Id nVB = BlockCount(numPoints, vertexBlock), nTB = BlockCount(numTriangles, triangleBlock);
  std::vector<Id> offset(static_cast<size_t>(nTB * nVB), 0); // [triangle block][vertex block]
  LowestId bad;
  ForBlocks(parallelFor, numTriangles, triangleBlock, [&](Id b) {
    Id* count = offset.data() + b * nVB;
    for (Id t = b * triangleBlock; t < std::min(numTriangles, (b + 1) * triangleBlock); ++t)
    {
      const Id* p = triangles + 3 * t;
      if (CheckTriangle(numPoints, p) != TriangleFault::None)
      {
        bad.Report(t);
        return; // later triangles of the block cannot be lower
      }
      ++count[std::min(p[0], p[1]) >> vertexBits];
      ++count[std::min(p[1], p[2]) >> vertexBits];
      ++count[std::min(p[2], p[0]) >> vertexBits];
    }
  });
  if (bad.Get() >= 0)
  {
    return TriangleFailure(numPoints, triangles, bad.Get());
  }
  std::vector<Id> blockStart(static_cast<size_t>(nVB + 1), 0);
  for (Id vb = 0, sum = 0; vb < nVB; ++vb)
  {
    blockStart[vb] = sum;
    for (Id b = 0; b < nTB; ++b)
    {
      const Id count = offset[b * nVB + vb];
      offset[b * nVB + vb] = sum;
      sum += count;
    }
    blockStart[vb + 1] = sum;
  }
  // Uninitialised: written in the parallel loops (first touch spread over the threads). The
  // blocks' buckets are kept in TriangleEdges' storage (3T ids, written only after the matching):
  // fresh pages cost more than the matching on a guest that returns freed memory to its host.
  OverwriteVector<Id> byBlock;
  ResizeForOverwrite(byBlock, static_cast<size_t>(nH));
  static_assert(sizeof(topology.TriangleEdges[0]) == 3 * sizeof(Id), "packed rows");
  ResizeForOverwrite(topology.TriangleEdges, static_cast<size_t>(numTriangles));
  Id* scratch = numTriangles > 0 ? topology.TriangleEdges.front().data() : nullptr;
  ForBlocks(parallelFor, numTriangles, triangleBlock, [&](Id b) {
    Id* next = offset.data() + b * nVB;
    for (Id t = b * triangleBlock; t < std::min(numTriangles, (b + 1) * triangleBlock); ++t)
    {
      const Id* p = triangles + 3 * t;
      for (int l = 0; l < 3; ++l)
      {
        const Id v = std::min(p[l], p[l == 2 ? 0 : l + 1]);
        byBlock[next[v >> vertexBits]++] = ((v & (vertexBlock - 1)) << HalfEdgeBits) | (3 * t + l);
      }
    }
  });

  // Each vertex block's edges; the lowest failing block names the failure (its first one).
  std::vector<Id> edgeStart(static_cast<size_t>(nVB + 1), 0);
  std::vector<TopologyStatus> failures(static_cast<size_t>(nVB));
  std::vector<char> consistent(static_cast<size_t>(nVB), 0);
  ForBlocks(parallelFor, numPoints, vertexBlock, [&](Id vb) {
    const Id b = blockStart[vb];
    bool blockConsistent = false;
    edgeStart[vb + 1] = MatchBlock(triangles, vb * vertexBlock,
      std::min(numPoints, (vb + 1) * vertexBlock), byBlock.data() + b, blockStart[vb + 1] - b,
      scratch + b, failures[vb], blockConsistent);
    consistent[vb] = blockConsistent;
  });
  for (Id vb = 0; vb < nVB; ++vb)
  {
    if (!failures[vb].Ok)
    {
      return failures[vb];
    }
    edgeStart[vb + 1] += edgeStart[vb];
  }
  topology.ConsistentlyOriented =
    std::all_of(consistent.begin(), consistent.end(), [](char c) { return c != 0; });

  const size_t nE = static_cast<size_t>(edgeStart[nVB]);
  ResizeForOverwrite(topology.Edges, nE);
  ResizeForOverwrite(topology.EdgeTriangles, nE);
  ResizeForOverwrite(topology.EdgeLocalIndex, nE);
  ForBlocks(parallelFor, numPoints, vertexBlock, [&](Id vb) {
    const Id* h = byBlock.data() + blockStart[vb];
    const Id* end = byBlock.data() + blockStart[vb + 1];
    for (Id e = edgeStart[vb]; h < end; ++e)
    {
      if (h + PrefetchDistance < end) // the triangle row read below, for a later edge
      {
        const Id ahead = h[PrefetchDistance];
        PrefetchRead(triangles + (ahead < 0 ? ~ahead : ahead));
      }
      const bool boundary = *h < 0;
      Id h0 = boundary ? ~*h : *h, h1 = boundary ? -1 : h[1];
      h += boundary ? 1 : 2;
      if (rank && !boundary)
      {
        // Picked without a branch: which side ranks first is a coin toss.
        const Id sides[2] = { h0, h1 };
        const int second = rank[h1 / 3] < rank[h0 / 3];
        h0 = sides[second];
        h1 = sides[1 - second];
      }
      const Id a = triangles[h0], b = triangles[NextCorner(h0)];
      std::array<Id, 2>& edge = topology.Edges[e];
      edge[0] = std::min(a, b);
      edge[1] = std::max(a, b);
      std::array<Id, 2>& sides = topology.EdgeTriangles[e];
      sides[0] = h0 / 3;
      sides[1] = boundary ? -1 : h1 / 3;
      std::array<signed char, 2>& local = topology.EdgeLocalIndex[e];
      local[0] = static_cast<signed char>(h0 % 3);
      local[1] = static_cast<signed char>(boundary ? -1 : h1 % 3);
      topology.TriangleEdges[h0 / 3][h0 % 3] = e;
      if (!boundary)
      {
        topology.TriangleEdges[h1 / 3][h1 % 3] = e;
      }
    }
  });
  return {};
}

} // namespace ctk
