// SPDX-License-Identifier: GPL-3.0-or-later
// Large blocks mapped on their own, and the process-wide cache of freed ones (LargeArrays.h).
#include "LargeArrays.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <unistd.h>
#endif

namespace ctk
{
namespace
{
using Clock = std::chrono::steady_clock;

// A retained block: a whole number of huge pages, aligned to one.
struct Block
{
  char* Begin;
  std::size_t Length;
  Clock::time_point Retained;
};

// Gives [p, p + length) back to the system.
void UnmapRange(void* p, std::size_t length) noexcept
{
#if CTSPLINES_MAP_LARGE_ARRAYS
  (void)munmap(p, length);
#else
  (void)p;
  (void)length;
#endif
}

// The retained blocks, oldest first, and the lengths of the blocks VTK arrays hold. Nothing
// allocates once a block is off the list or on it: every change under the lock either cannot
// throw or throws before it changes anything.
struct LargeBlockCache
{
  std::mutex Mutex;
  std::vector<Block> Blocks;
  std::vector<std::pair<void*, std::size_t>> Handed; // MapArrayBlock: freed by pointer alone
  std::size_t Bytes = 0;
  std::size_t Limit = DefaultLimit();
  // As jemalloc's decay of dirty pages: a block unused this long is not part of a series of
  // constructions any more.
  static constexpr std::chrono::seconds RetainFor{ 10 };
  // A block assembled of more pieces would cost more mappings than its fresh pages' faults save.
  static constexpr std::size_t MaxPieces = 64;

  static std::size_t DefaultLimit()
  {
    if (const char* mb = std::getenv("CTSPLINES_LARGE_BLOCK_CACHE_MB"))
    {
      char* end = nullptr;
      const unsigned long long v = std::strtoull(mb, &end, 10);
      if (end != mb && *end == '\0')
      {
        return static_cast<std::size_t>(v) << 20;
      }
    }
#if defined(__linux__) && defined(_SC_PHYS_PAGES)
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0)
    {
      return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) / 4;
    }
#endif
    return std::size_t(1) << 30;
  }

  // Unmaps and removes the n oldest blocks.
  void DropOldest(std::size_t n) noexcept
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      this->Bytes -= this->Blocks[i].Length;
      UnmapRange(this->Blocks[i].Begin, this->Blocks[i].Length);
    }
    this->Blocks.erase(this->Blocks.begin(), this->Blocks.begin() + static_cast<std::ptrdiff_t>(n));
  }

  // Unmaps the blocks retained longer than RetainFor, then the oldest beyond the limit.
  void Drop(Clock::time_point now) noexcept
  {
    std::size_t n = 0, dropped = 0;
    while (n < this->Blocks.size() &&
      (now - this->Blocks[n].Retained > RetainFor || this->Bytes - dropped > this->Limit))
    {
      dropped += this->Blocks[n++].Length;
    }
    this->DropOldest(n);
  }

  // Takes the first `length` bytes of Blocks[i] (all of it when it is no longer).
  Block TakePrefix(std::size_t i, std::size_t length) noexcept
  {
    Block& b = this->Blocks[i];
    const Block piece{ b.Begin, std::min(length, b.Length), b.Retained };
    b.Begin += piece.Length;
    b.Length -= piece.Length;
    this->Bytes -= piece.Length;
    if (b.Length == 0)
    {
      this->Blocks.erase(this->Blocks.begin() + static_cast<std::ptrdiff_t>(i));
    }
    return piece;
  }

  // Retained pages for a block of `length` bytes, appended to `pieces` (capacity MaxPieces
  // reserved) in the order they are to lie in it: the newest block of that length (a
  // construction that follows another on the same mesh asks for the same lengths), else the
  // start of the shortest longer one, else the longest ones while they fall short.
  void TakeFor(std::size_t length, std::vector<Block>& pieces) noexcept
  {
    const std::size_t maxPieces = std::min(MaxPieces, pieces.capacity()); // push_back: no throw
    if (maxPieces == pieces.size())
    {
      return;
    }
    std::size_t best = this->Blocks.size();
    for (std::size_t i = this->Blocks.size(); i-- > 0;)
    {
      const std::size_t l = this->Blocks[i].Length;
      if (l == length)
      {
        pieces.push_back(this->TakePrefix(i, length));
        return;
      }
      if (l > length && (best == this->Blocks.size() || l < this->Blocks[best].Length))
      {
        best = i;
      }
    }
    if (best < this->Blocks.size())
    {
      pieces.push_back(this->TakePrefix(best, length));
      return;
    }
    std::size_t taken = 0;
    while (taken < length && !this->Blocks.empty() && pieces.size() < maxPieces)
    {
      const auto longest = std::max_element(this->Blocks.begin(), this->Blocks.end(),
        [](const Block& a, const Block& b) { return a.Length < b.Length; });
      pieces.push_back(this->TakePrefix(
        static_cast<std::size_t>(longest - this->Blocks.begin()), length - taken));
      taken += pieces.back().Length;
    }
  }

  // Adds [p, p + length) as the newest block, joined with the retained blocks right before and
  // after it (the rest of a block whose start it was, say). False when the list cannot grow.
  bool Add(char* p, std::size_t length, Clock::time_point now) noexcept
  {
    Block joined{ p, length, now };
    for (std::size_t i = this->Blocks.size(); i-- > 0;)
    {
      const Block& b = this->Blocks[i];
      if (b.Begin == joined.Begin + joined.Length || b.Begin + b.Length == joined.Begin)
      {
        joined.Begin = std::min(joined.Begin, b.Begin);
        joined.Length += b.Length;
        this->Bytes -= b.Length;
        this->Blocks.erase(this->Blocks.begin() + static_cast<std::ptrdiff_t>(i));
      }
    }
    try
    {
      this->Blocks.push_back(joined); // never allocates after an erase
    }
    catch (...)
    {
      return false;
    }
    this->Bytes += joined.Length;
    return true;
  }
};

LargeBlockCache& Cache()
{
  static LargeBlockCache* const cache = new LargeBlockCache; // blocks may be freed at exit
  return *cache;
}

#if CTSPLINES_MAP_LARGE_ARRAYS
// A fresh mapping of `length` bytes (a multiple of HugePageBytes) aligned to a huge page.
void* MapFresh(std::size_t length)
{
  constexpr std::size_t huge = HugePageBytes;
  // Mapped with a huge page of slack, whose unaligned ends are then unmapped.
  void* m = mmap(nullptr, length + huge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
    -1, 0);
  if (m == MAP_FAILED)
  {
    throw std::bad_alloc();
  }
  const std::uintptr_t raw = reinterpret_cast<std::uintptr_t>(m);
  const std::uintptr_t begin = (raw + huge - 1) & ~std::uintptr_t(huge - 1);
  if (begin > raw)
  {
    (void)munmap(m, begin - raw);
  }
  if (raw + huge > begin)
  {
    (void)munmap(reinterpret_cast<void*>(begin + length), raw + huge - begin);
  }
  AdviseHugePages(reinterpret_cast<void*>(begin), length);
  return reinterpret_cast<void*>(begin);
}

// Moves the pages of [from, from + length) over [to, to + length), a range of a mapping of
// ours, with their page tables (no copy, no zeroing), one huge page at a time: a retained block
// may span several mappings, which one mremap call cannot move before Linux 6.17, and a failed
// MREMAP_FIXED may unmap its target first. Returns the bytes moved; on a failure the huge page
// at `to` + the result is not ours any more and the source's rest is still mapped.
std::size_t MovePages(char* from, char* to, std::size_t length) noexcept
{
  std::size_t at = 0;
  while (at < length && mremap(from + at, HugePageBytes, HugePageBytes,
                          MREMAP_MAYMOVE | MREMAP_FIXED, to + at) != MAP_FAILED)
  {
    at += HugePageBytes;
  }
  return at;
}

// Unmaps pieces[first..].
void UnmapPieces(const std::vector<Block>& pieces, std::size_t first) noexcept
{
  for (std::size_t i = first; i < pieces.size(); ++i)
  {
    UnmapRange(pieces[i].Begin, pieces[i].Length);
  }
}

// A block of `length` bytes from these retained pieces (in that order) and fresh pages after
// them; a fresh block when a piece could not move (every range of ours given back).
void* Assemble(const std::vector<Block>& pieces, std::size_t length)
{
  char* block = nullptr;
  try
  {
    block = static_cast<char*>(MapFresh(length));
  }
  catch (...)
  {
    UnmapPieces(pieces, 0);
    throw;
  }
  char* to = block;
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    const std::size_t moved = MovePages(pieces[i].Begin, to, pieces[i].Length);
    if (moved < pieces[i].Length)
    {
      UnmapRange(block, static_cast<std::size_t>(to - block) + moved);
      UnmapRange(to + moved + HugePageBytes, length - static_cast<std::size_t>(to - block) -
          moved - HugePageBytes);
      UnmapRange(pieces[i].Begin + moved, pieces[i].Length - moved);
      UnmapPieces(pieces, i + 1);
      return MapFresh(length);
    }
    to += moved;
  }
  return block;
}

// Retains the block [p, p + length), giving back the oldest or expired ones beyond the limit.
void Retain(void* p, std::size_t length) noexcept
{
  LargeBlockCache& cache = Cache();
  const char* poison = std::getenv("CTSPLINES_POISON_RETAINED_BLOCKS"); // read each time: tests
  if (poison && std::strcmp(poison, "1") == 0)
  {
    std::memset(p, 0xff, length);
  }
#if defined(MADV_FREE)
  else
  {
    // The kernel may reclaim the pages under pressure (they then read as zeros), else they stay.
    (void)madvise(p, length, MADV_FREE);
  }
#endif
  const auto now = Clock::now();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  if (length > cache.Limit || !cache.Add(static_cast<char*>(p), length, now))
  {
    (void)munmap(p, length); // beyond the limit alone, or no memory for the list
  }
  cache.Drop(now);
}
#endif
} // namespace

#if CTSPLINES_MAP_LARGE_ARRAYS
void* MapLargeBlock(std::size_t bytes)
{
  const std::size_t length = LargeBlockLength(bytes);
  LargeBlockCache& cache = Cache();
  std::vector<Block> pieces;
  pieces.reserve(LargeBlockCache::MaxPieces); // before the cache changes: the only allocation
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    cache.TakeFor(length, pieces);
    cache.Drop(Clock::now());
  }
  if (pieces.size() == 1 && pieces[0].Length == length)
  {
    return pieces[0].Begin;
  }
  return Assemble(pieces, length);
}

void UnmapLargeBlock(void* p, std::size_t bytes) noexcept
{
  Retain(p, LargeBlockLength(bytes));
}

void* MapArrayBlock(std::size_t bytes)
{
  void* p = MapLargeBlock(bytes);
  try
  {
    LargeBlockCache& cache = Cache();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    cache.Handed.emplace_back(p, LargeBlockLength(bytes));
  }
  catch (...)
  {
    UnmapLargeBlock(p, bytes);
    throw;
  }
  return p;
}

void FreeArrayBlock(void* p)
{
  std::size_t length = 0;
  {
    LargeBlockCache& cache = Cache();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    const auto handed = std::find_if(cache.Handed.begin(), cache.Handed.end(),
      [p](const std::pair<void*, std::size_t>& h) { return h.first == p; });
    if (handed == cache.Handed.end())
    {
      return; // not a block of MapArrayBlock: its length is unknown
    }
    length = handed->second;
    cache.Handed.erase(handed);
  }
  Retain(p, length);
}
#endif

std::size_t LargeBlockCacheLimit()
{
  LargeBlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  return cache.Limit;
}

void SetLargeBlockCacheLimit(std::size_t bytes)
{
  LargeBlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  cache.Limit = bytes;
  cache.Drop(Clock::now());
}

std::size_t LargeBlockCacheBytes()
{
  LargeBlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  return cache.Bytes;
}

void ReleaseLargeBlockCache()
{
  LargeBlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  cache.DropOldest(cache.Blocks.size());
}

} // namespace ctk
