// SPDX-License-Identifier: GPL-3.0-or-later
// A locality order of a mesh's triangles: the constructions visit triangles (and edges, through
// their first triangle) in this order, whatever the input's numbering, and still write every
// value at its place in the input's numbering. Neighbours in (u, v) are then visited close in
// time and their shared vertex and edge data stay in cache: on a Delaunay mesh numbered as
// qhull or CGAL number it, the construction's time otherwise grows as n^1.3.
#ifndef CTSplines_Kernel_LocalityOrder_h
#define CTSplines_Kernel_LocalityOrder_h

#include "LargeArrays.h"
#include "MeshTopology.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace ctk
{
/// Asks for the cache line of p ahead of a read: gathers (a renumbering's rows, the probe's
/// cells and control points) read at random, and each miss otherwise stalls the loop.
inline void PrefetchRead(const void* p)
{
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  // An asm statement, not __builtin_prefetch: GCC deletes loops whose only effects are
  // __builtin_prefetch calls (C++ loops are assumed to terminate, and a prefetch counts as no
  // effect), which silently dropped whole prefetch stages of the probe.
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#elif defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p, 0, 3);
#else
  (void)p;
#endif
}
/// How many rows ahead the gathers prefetch: enough misses in flight to cover the latency.
constexpr Id PrefetchDistance = 16;

/// How far ahead a loop reading a large array in sequence asks for its cache lines. The
/// hardware prefetchers stop at each 4 KiB page. A core's read of the same memory: 11.6 GB/s
/// plain, 13.2 with this; the ranges scan of a 1e6-triangle spline's points and (u, v): 7.7 ->
/// 12.7 GB/s (with two sets of SSE2 accumulators; now PointRanges.cxx's AVX2 loop).
constexpr std::size_t StreamPrefetchBytes = 4096;
/// The chunks of ForStreamChunks: its prefetches come in bursts of a chunk's lines, and more
/// than 8 at once waited for the core's line fill buffers (1 KiB: 10.0 GB/s, 4 KiB: 8.9, 512
/// bytes: 10.3, for a check of usable values).
constexpr std::size_t StreamChunkBytes = 512;
/// Asks for the cache line `bytes` past p, which may lie beyond the array's end (a prefetch
/// never faults; the address is formed as an integer, not by pointer arithmetic).
inline void PrefetchAhead(const void* p, std::size_t bytes)
{
  PrefetchRead(reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(p) + bytes));
}
/// body(begin, end) over the items [0, n) of `data` (perItem values of T each) in chunks of
/// StreamChunkBytes, the lines StreamPrefetchBytes ahead of each chunk asked for first: for
/// bulk checks of large arrays. The body's inner loop stays vectorisable when it reduces into
/// locals (a reduction into a captured variable stayed scalar: 4.7 GB/s).
template <typename T, typename Body>
void ForStreamChunks(const T* data, Id n, int perItem, Body&& body)
{
  constexpr std::size_t Line = 64;
  const std::size_t per = static_cast<std::size_t>(std::max(perItem, 1));
  const std::size_t itemBytes = sizeof(T) * per;
  const Id chunk = std::max<Id>(1, static_cast<Id>(StreamChunkBytes / itemBytes));
  for (Id b = 0; b < n; b += chunk)
  {
    const T* first = data + per * static_cast<std::size_t>(b);
    for (std::size_t k = 0; k < static_cast<std::size_t>(chunk) * itemBytes; k += Line)
    {
      PrefetchAhead(first, StreamPrefetchBytes + k);
    }
    body(b, std::min(n, b + chunk));
  }
}

/// Meshes with fewer triangles keep their own order: their data fits in cache.
constexpr Id MinTrianglesForLocalityOrder = Id(1) << 15;

/// The triangles sorted by the Morton key of their centroid in (u, v) (16 bits per axis over
/// the vertices' bounding box; ties keep the input's order), or empty (the input's order) below
/// MinTrianglesForLocalityOrder triangles or when a vertex id is out of range (left to the
/// topology's validation). triangles: #T by 3 vertex ids, uv: #V by 2. The keys are computed in
/// chunks of parallelFor.
std::vector<Id> TriangleLocalityOrder(Id numVertices, Id numTriangles, const Id* triangles,
  const double* uv, const ParallelFor& parallelFor = SerialFor);

/// The bounding box lo, hi of the n points uv (#n by 2, n > 0), the same whatever the split of
/// parallelFor's chunks (min and max are exact; NaN coordinates may or may not be skipped).
void BoundingBoxUV(Id n, const double* uv, double lo[2], double hi[2],
  const ParallelFor& parallelFor = SerialFor);

/// The Morton key of cell (x, y) of a 2^16 by 2^16 grid: the bits of x at the even positions,
/// those of y at the odd ones.
std::uint32_t MortonKey16(std::uint32_t x, std::uint32_t y);

/// Sorts values by their upper 32 bits (a key; the lower 32 typically hold an index), stable:
/// LSD radix sort, 11 + 11 + 10 bits per pass (digits that all values share are skipped), each
/// pass in blocks on parallelFor; the same result on any thread count. Fewer than 2^32 values.
/// The scatter's buffer is an OverwriteVector, first written by the parallel passes.
void SortByUpperHalf(
  OverwriteVector<std::uint64_t>& values, const ParallelFor& parallelFor = SerialFor);

/// A renumbering of a mesh into its locality order (issue #12), for building and writing a spline
/// in that order: renumbered triangle k is input triangle Triangles[k] (TriangleLocalityOrder),
/// renumbered vertex j is input vertex Vertices[j], by first use in that triangle order
/// (vertices no triangle uses follow, in the input's order). Both empty: the input's order.
struct LocalityRenumbering
{
  std::vector<Id> Triangles;
  OverwriteVector<Id> Vertices; // VerticesByFirstUse's
  bool IsIdentity() const { return this->Triangles.empty(); }
};

/// The vertices 0 .. numVertices - 1 by first use in orderedTriangles (#T by 3 vertex ids, all
/// in that range, read in sequence), then those no triangle uses, by id.
OverwriteVector<Id> VerticesByFirstUse(
  Id numVertices, Id numTriangles, const Id* orderedTriangles);

/// The locality renumbering of a mesh (empty below MinTrianglesForLocalityOrder triangles or
/// when an id is out of range, as TriangleLocalityOrder).
/// SplineInput::RenumberToLocalityOrder does this and the renumbering with one gather of the
/// triangles instead of two.
LocalityRenumbering MakeLocalityRenumbering(Id numVertices, Id numTriangles, const Id* triangles,
  const double* uv, const ParallelFor& parallelFor = SerialFor);

namespace detail
{
template <std::size_t... I, typename F>
void ForEachIndex(std::index_sequence<I...>, F&& f)
{
  (f(std::integral_constant<std::size_t, I>()), ...);
}
template <std::size_t I, std::size_t... W>
constexpr std::size_t NthWidth()
{
  constexpr std::size_t widths[] = { W... };
  return widths[I];
}
} // namespace detail

/// The rows of several arrays (arrays[a]: rows of W_a values, W_a = 0 for `width` values)
/// put in the renumbered order (renumbered row k = input row from[k]), or back in the input's
/// order (back = true), in one pass chunked by parallelFor over the rows: the map is read once
/// and each row's reads are in flight together (the locality renumbering's (u, v), F, f_u and
/// f_v: CTi 0.6 %, CTo 2.6 % faster at 1e6 triangles than a pass each). An empty array is left
/// as is; every other holds from.size() rows.
template <std::size_t... W, typename B, typename... V>
void PermuteRowsTogether(const std::vector<Id, B>& from, bool back, const ParallelFor& parallelFor,
  std::size_t width, V&... arrays)
{
  static_assert(sizeof...(W) == sizeof...(V), "a width per array");
  const std::tuple<V&...> in(arrays...);
  std::tuple<V...> out;
  const std::array<bool, sizeof...(V)> used{ !arrays.empty()... };
  if (from.empty() || std::none_of(used.begin(), used.end(), [](bool u) { return u; }))
  {
    return;
  }
  const auto each = std::index_sequence_for<V...>();
  detail::ForEachIndex(each, [&](auto a) {
    if (used[a])
    {
      ResizeForOverwrite(std::get<a>(out), std::get<a>(in).size()); // huge pages, unwritten
    }
  });
  parallelFor(static_cast<Id>(from.size()), [&](Id begin, Id end) {
    // Locals: rows of ids could alias the captured sizes and pointers, reloaded per row.
    const std::tuple<const typename V::value_type*...> source(arrays.data()...);
    std::tuple<typename V::value_type*...> target;
    detail::ForEachIndex(each, [&](auto a) { std::get<a>(target) = std::get<a>(out).data(); });
    const std::array<bool, sizeof...(V)> on = used;
    const Id* row = from.data();
    const bool gather = !back;
    for (Id k = begin; k < end; ++k)
    {
      const std::size_t i = static_cast<std::size_t>(row[k]), j = static_cast<std::size_t>(k);
      const std::size_t read = gather ? i : j, write = gather ? j : i;
      const std::size_t ahead = gather && k + PrefetchDistance < end
        ? static_cast<std::size_t>(row[k + PrefetchDistance]) + 1
        : 0;
      detail::ForEachIndex(each, [&](auto a) {
        // The usual widths are compile-time constants: std::copy_n of a run-time width is a
        // call to memmove per row (on 1e6 triangles 21 ms of the construction's 35 ms of
        // permutations).
        constexpr std::size_t Wa = detail::NthWidth<a, W...>();
        const std::size_t n = Wa != 0 ? Wa : width;
        if (!on[a])
        {
          return;
        }
        if (ahead != 0)
        {
          PrefetchRead(std::get<a>(source) + n * (ahead - 1));
        }
        const auto* s = std::get<a>(source) + n * read;
        auto* t = std::get<a>(target) + n * write;
        if constexpr (Wa != 0)
        {
          for (std::size_t c = 0; c < Wa; ++c)
          {
            t[c] = s[c];
          }
        }
        else
        {
          std::copy_n(s, n, t);
        }
      });
    }
  });
  detail::ForEachIndex(each, [&](auto a) {
    if (used[a])
    {
      std::get<a>(in).swap(std::get<a>(out));
    }
  });
}

/// Rows of `width` values of v (renumbered row k = input row from[k]) put in the renumbered
/// order, or back in the input's order (back = true), chunked by parallelFor over the rows.
template <typename T, typename A, typename B>
void PermuteRows(std::vector<T, A>& v, std::size_t width, const std::vector<Id, B>& from, bool back,
  const ParallelFor& parallelFor = SerialFor)
{
  switch (width)
  {
    case 1:
      PermuteRowsTogether<1>(from, back, parallelFor, width, v);
      break;
    case 2:
      PermuteRowsTogether<2>(from, back, parallelFor, width, v);
      break;
    case 3:
      PermuteRowsTogether<3>(from, back, parallelFor, width, v);
      break;
    default:
      PermuteRowsTogether<0>(from, back, parallelFor, width, v);
  }
}

/// Runs body(t) for every triangle t, in the given order (empty: 0 .. n-1), chunked by
/// parallelFor over the order's positions.
template <typename ParallelForT, typename Body>
void ForTrianglesInOrder(
  const ParallelForT& parallelFor, Id numTriangles, const std::vector<Id>& order, Body&& body)
{
  parallelFor(numTriangles, [&](Id begin, Id end) {
    for (Id i = begin; i < end; ++i)
    {
      body(order.empty() ? i : order[i]);
    }
  });
}

/// Runs body(e) for every edge e of topology once, from its first triangle
/// (EdgeTriangles[e][0]) in the given triangle order; with no order, in the edges' own order
/// (by their smaller vertex): the same locality on a mesh numbered by first use, without
/// the indirection through the triangles, and an edge's points written in sequence.
template <typename ParallelForT, typename Body>
void ForEdgesInOrder(const ParallelForT& parallelFor, const MeshTopology& topology,
  const std::vector<Id>& order, Body&& body)
{
  if (order.empty())
  {
    parallelFor(static_cast<Id>(topology.Edges.size()), [&](Id begin, Id end) {
      for (Id e = begin; e < end; ++e)
      {
        body(e);
      }
    });
    return;
  }
  const Id nT = static_cast<Id>(topology.TriangleEdges.size());
  ForTrianglesInOrder(parallelFor, nT, order, [&](Id t) {
    for (int l = 0; l < 3; ++l)
    {
      const Id e = topology.TriangleEdges[t][l];
      if (topology.EdgeTriangles[e][0] == t && topology.EdgeLocalIndex[e][0] == l)
      {
        body(e);
      }
    }
  });
}
} // namespace ctk

#endif
