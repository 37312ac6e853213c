// SPDX-License-Identifier: GPL-3.0-or-later
#include "LocalityOrder.h"

#include "LargeArrays.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <array>
#include <cstdint>
#include <limits>

namespace ctk
{
namespace
{
// Bits of x spread to the even positions of the result.
std::uint64_t Spread16(std::uint64_t x)
{
  x = (x | (x << 8)) & 0x00FF00FFu;
  x = (x | (x << 4)) & 0x0F0F0F0Fu;
  x = (x | (x << 2)) & 0x33333333u;
  return (x | (x << 1)) & 0x55555555u;
}
} // namespace

std::uint32_t MortonKey16(std::uint32_t x, std::uint32_t y)
{
  return static_cast<std::uint32_t>(Spread16(x & 0xFFFFu) | (Spread16(y & 0xFFFFu) << 1));
}

// Sorts values by their upper 32 bits (the key; the lower 32 hold the triangle), stable: LSD
// radix sort, 11 + 11 + 10 bits. Each pass counts and scatters in blocks of a size set by n
// alone (digit-major, block-minor positions), so the blocks run in parallel and the result is
// the same on any thread count. Positions are 32-bit (fewer than 2^32 values), which also
// tells the compiler that the scatter's stores do not alias them.
void SortByUpperHalf(OverwriteVector<std::uint64_t>& values, const ParallelFor& parallelFor)
{
  constexpr int shifts[3] = { 32, 43, 54 };
  constexpr std::uint64_t mask = 0x7FF;
  constexpr Id radix = 2048;
  const Id n = static_cast<Id>(values.size());
  const Id block = std::max(Id(1) << 16, BlockCount(n, 64));
  const Id nB = BlockCount(n, block);
  std::vector<std::uint32_t> position(static_cast<std::size_t>(nB * radix)); // [block][digit]
  // Not value-initialised: a serial zeroing (with the page faults of a fresh 8 MB block at 1e6
  // triangles) took the calling thread 5 % of CTi's time on two threads.
  OverwriteVector<std::uint64_t> other;
  for (const int shift : shifts)
  {
    ForBlocks(parallelFor, n, block, [&](Id b) {
      std::uint32_t* count = position.data() + b * radix;
      std::fill_n(count, radix, 0);
      const std::uint64_t* v = values.data() + b * block;
      for (Id i = 0, end = std::min(block, n - b * block); i < end; ++i)
      {
        ++count[(v[i] >> shift) & mask];
      }
    });
    std::uint32_t sum = 0;
    bool oneDigit = false;
    for (Id d = 0; d < radix; ++d)
    {
      const std::uint32_t first = sum;
      for (Id b = 0; b < nB; ++b)
      {
        const std::uint32_t count = position[b * radix + d];
        position[b * radix + d] = sum;
        sum += count;
      }
      oneDigit = oneDigit || Id(sum - first) == n;
    }
    if (oneDigit)
    {
      continue; // the pass would not move anything
    }
    ResizeForOverwrite(other, values.size());
    ForBlocks(parallelFor, n, block, [&](Id b) {
      std::uint32_t* next = position.data() + b * radix;
      const std::uint64_t* v = values.data() + b * block;
      std::uint64_t* out = other.data();
      for (Id i = 0, end = std::min(block, n - b * block); i < end; ++i)
      {
        out[next[(v[i] >> shift) & mask]++] = v[i];
      }
    });
    values.swap(other);
  }
}

void BoundingBoxUV(Id n, const double* uv, double lo[2], double hi[2], const ParallelFor& parallelFor)
{
  std::mutex merge;
  lo[0] = hi[0] = uv[0];
  lo[1] = hi[1] = uv[1];
  parallelFor(n, [&](Id begin, Id end) {
    double chunkLo[2] = { uv[2 * begin], uv[2 * begin + 1] };
    double chunkHi[2] = { chunkLo[0], chunkLo[1] };
    for (Id v = begin + 1; v < end; ++v)
    {
      for (int c = 0; c < 2; ++c)
      {
        chunkLo[c] = std::min(chunkLo[c], uv[2 * v + c]);
        chunkHi[c] = std::max(chunkHi[c], uv[2 * v + c]);
      }
    }
    std::lock_guard<std::mutex> lock(merge);
    for (int c = 0; c < 2; ++c)
    {
      lo[c] = std::min(lo[c], chunkLo[c]);
      hi[c] = std::max(hi[c], chunkHi[c]);
    }
  });
}

std::vector<Id> TriangleLocalityOrder(Id numVertices, Id numTriangles, const Id* triangles,
  const double* uv, const ParallelFor& parallelFor)
{
  std::vector<Id> order;
  if (numTriangles < MinTrianglesForLocalityOrder ||
    numTriangles > Id(std::numeric_limits<std::uint32_t>::max()) || numVertices <= 0)
  {
    return order;
  }
  // Ids out of range are left to the topology's validation, in the input's order.
  std::atomic<bool> outside{ false };
  parallelFor(3 * numTriangles, [&](Id begin, Id end) {
    if (!std::all_of(triangles + begin, triangles + end,
          [&](Id v) { return v >= 0 && v < numVertices; }))
    {
      outside.store(true, std::memory_order_relaxed);
    }
  });
  if (outside.load())
  {
    return order;
  }
  double lo[2], hi[2];
  BoundingBoxUV(numVertices, uv, lo, hi, parallelFor);
  const double scale[2] = { hi[0] > lo[0] ? 65535.0 / (hi[0] - lo[0]) : 0.0,
    hi[1] > lo[1] ? 65535.0 / (hi[1] - lo[1]) : 0.0 };
  OverwriteVector<std::uint64_t> keyed;
  ResizeForOverwrite(keyed, static_cast<std::size_t>(numTriangles));
  std::uint64_t* keys = keyed.data();
  parallelFor(numTriangles, [&](Id begin, Id end) {
    for (Id t = begin; t < end; ++t)
    {
      if (t + PrefetchDistance < end)
      {
        for (int l = 0; l < 3; ++l)
        {
          PrefetchRead(uv + 2 * triangles[3 * (t + PrefetchDistance) + l]);
        }
      }
      std::uint64_t cell[2];
      for (int c = 0; c < 2; ++c)
      {
        const double x = (uv[2 * triangles[3 * t] + c] + uv[2 * triangles[3 * t + 1] + c] +
                           uv[2 * triangles[3 * t + 2] + c]) / 3;
        // Non-finite values (rejected later by the validation) land in cell 0.
        const double s = (x - lo[c]) * scale[c];
        cell[c] = s > 0 ? static_cast<std::uint64_t>(std::min(s, 65535.0)) : 0;
      }
      keys[t] = (std::uint64_t(MortonKey16(static_cast<std::uint32_t>(cell[0]),
                    static_cast<std::uint32_t>(cell[1]))) << 32) | std::uint64_t(t);
    }
  });
  SortByUpperHalf(keyed, parallelFor);
  ResizeForOverwrite(order, keyed.size());
  parallelFor(numTriangles, [&](Id begin, Id end) {
    std::transform(keyed.begin() + begin, keyed.begin() + end, order.begin() + begin,
      [](std::uint64_t v) { return static_cast<Id>(v & 0xFFFFFFFFu); });
  });
  return order;
}

OverwriteVector<Id> VerticesByFirstUse(
  Id numVertices, Id numTriangles, const Id* orderedTriangles)
{
  // Branch-free (a new vertex is about one corner in six, a branch on it mispredicts): every id
  // is written at the end, which advances when the id is new; one spare slot for the last write.
  OverwriteVector<Id> vertices;
  ResizeForOverwrite(vertices, static_cast<std::size_t>(numVertices) + 1);
  std::vector<unsigned char> used(static_cast<std::size_t>(numVertices), 0);
  Id* out = vertices.data();
  Id n = 0;
  for (const Id* p = orderedTriangles; p < orderedTriangles + 3 * numTriangles; ++p)
  {
    const Id v = *p;
    out[n] = v;
    n += 1 - used[v];
    used[v] = 1;
  }
  for (Id v = 0; v < numVertices; ++v)
  {
    if (!used[v])
    {
      out[n++] = v;
    }
  }
  vertices.resize(static_cast<std::size_t>(numVertices));
  return vertices;
}

LocalityRenumbering MakeLocalityRenumbering(Id numVertices, Id numTriangles, const Id* triangles,
  const double* uv, const ParallelFor& parallelFor)
{
  LocalityRenumbering r;
  r.Triangles = TriangleLocalityOrder(numVertices, numTriangles, triangles, uv, parallelFor);
  if (r.Triangles.empty())
  {
    return r;
  }
  OverwriteVector<Id> ordered;
  ResizeForOverwrite(ordered, static_cast<std::size_t>(3 * numTriangles));
  parallelFor(numTriangles, [&](Id begin, Id end) {
    for (Id k = begin; k < end; ++k)
    {
      std::copy_n(triangles + 3 * r.Triangles[k], 3, ordered.data() + 3 * k);
    }
  });
  r.Vertices = VerticesByFirstUse(numVertices, numTriangles, ordered.data());
  return r;
}
} // namespace ctk
