// SPDX-License-Identifier: GPL-3.0-or-later
// Large blocks mapped on their own, and the process-wide cache of freed ones (LargeArrays.h).
#include "LargeArrays.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <mutex>
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

// The retained blocks, oldest first, and the lengths of the blocks VTK arrays hold.
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

  // Takes out the blocks retained longer than RetainFor; the caller unmaps them outside the
  // lock.
  std::vector<Block> TakeExpired(Clock::time_point now)
  {
    std::size_t n = 0;
    while (n < this->Blocks.size() && now - this->Blocks[n].Retained > RetainFor)
    {
      ++n;
    }
    return this->TakeFirst(n);
  }

  // Takes out the oldest blocks until at least `bytes` are taken or none is left.
  std::vector<Block> TakeOldest(std::size_t bytes)
  {
    std::size_t taken = 0, n = 0;
    while (n < this->Blocks.size() && taken < bytes)
    {
      taken += this->Blocks[n++].Length;
    }
    return this->TakeFirst(n);
  }

  std::vector<Block> TakeFirst(std::size_t n)
  {
    std::vector<Block> out(this->Blocks.begin(), this->Blocks.begin() + n);
    this->Blocks.erase(this->Blocks.begin(), this->Blocks.begin() + n);
    for (const Block& b : out)
    {
      this->Bytes -= b.Length;
    }
    return out;
  }

  // Takes the first `length` bytes of Blocks[i] (all of it when it is no longer).
  Block TakePrefix(std::size_t i, std::size_t length)
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

  // Retained pages for a block of `length` bytes, in the order they are to lie in it: the
  // newest block of that length (a construction that follows another on the same mesh asks
  // for the same lengths), else the start of the shortest longer one, else the longest ones
  // while they fall short. Empty when nothing is retained.
  std::vector<Block> TakeFor(std::size_t length)
  {
    std::size_t best = this->Blocks.size();
    for (std::size_t i = this->Blocks.size(); i-- > 0;)
    {
      const std::size_t l = this->Blocks[i].Length;
      if (l == length)
      {
        return { this->TakePrefix(i, length) };
      }
      if (l > length && (best == this->Blocks.size() || l < this->Blocks[best].Length))
      {
        best = i;
      }
    }
    if (best < this->Blocks.size())
    {
      return { this->TakePrefix(best, length) };
    }
    std::vector<Block> pieces;
    std::size_t taken = 0;
    while (taken < length && !this->Blocks.empty() && pieces.size() < MaxPieces)
    {
      const auto longest = std::max_element(this->Blocks.begin(), this->Blocks.end(),
        [](const Block& a, const Block& b) { return a.Length < b.Length; });
      pieces.push_back(this->TakePrefix(
        static_cast<std::size_t>(longest - this->Blocks.begin()), length - taken));
      taken += pieces.back().Length;
    }
    return pieces;
  }
};

LargeBlockCache& Cache()
{
  static LargeBlockCache* const cache = new LargeBlockCache; // blocks may be freed at exit
  return *cache;
}

#if CTSPLINES_MAP_LARGE_ARRAYS
void Unmap(const std::vector<Block>& blocks)
{
  for (const Block& b : blocks)
  {
    (void)munmap(b.Begin, b.Length);
  }
}

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

// Moves the pages of [from, from + length) to [to, to + length), a range of this module's
// mapping, with the page tables (no copy, no zeroing); a huge page that cannot move leaves fresh
// memory at `to` and is given back. False when not even fresh memory could be mapped there.
bool MovePages(char* from, char* to, std::size_t length) noexcept
{
  if (mremap(from, length, length, MREMAP_MAYMOVE | MREMAP_FIXED, to) != MAP_FAILED)
  {
    return true;
  }
  if (length > HugePageBytes) // a block assembled earlier spans several mappings
  {
    for (std::size_t at = 0; at < length; at += HugePageBytes)
    {
      if (!MovePages(from + at, to + at, HugePageBytes))
      {
        (void)munmap(from + at + HugePageBytes, length - at - HugePageBytes);
        return false;
      }
    }
    return true;
  }
  (void)munmap(from, length);
  // mremap may have unmapped the target before it failed.
  return mmap(to, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1,
           0) != MAP_FAILED;
}

// A block of `length` bytes from these retained pieces (in that order) and fresh pages after
// them.
void* Assemble(const std::vector<Block>& pieces, std::size_t length)
{
  void* block = nullptr;
  try
  {
    block = MapFresh(length);
  }
  catch (...)
  {
    Unmap(pieces);
    throw;
  }
  char* to = static_cast<char*>(block);
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    if (!MovePages(pieces[i].Begin, to, pieces[i].Length))
    {
      Unmap(std::vector<Block>(pieces.begin() + static_cast<std::ptrdiff_t>(i) + 1, pieces.end()));
      (void)munmap(block, length);
      throw std::bad_alloc();
    }
    to += pieces[i].Length;
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
  std::vector<Block> evicted;
  try
  {
    const auto now = Clock::now();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    cache.Blocks.push_back({ static_cast<char*>(p), length, now });
    cache.Bytes += length;
    evicted = cache.TakeExpired(now);
    if (cache.Bytes > cache.Limit)
    {
      std::vector<Block> oldest = cache.TakeOldest(cache.Bytes - cache.Limit);
      evicted.insert(evicted.end(), oldest.begin(), oldest.end());
    }
  }
  catch (...) // no memory for the list: the block goes back to the system
  {
    (void)munmap(p, length);
    return;
  }
  Unmap(evicted);
}

// Retains a freed block of `length` bytes, or unmaps it when it exceeds the limit (which would
// only evict it again, after the madvise).
void Release(void* p, std::size_t length) noexcept
{
  bool keep = false;
  {
    LargeBlockCache& cache = Cache();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    keep = length <= cache.Limit;
  }
  if (keep)
  {
    Retain(p, length);
  }
  else
  {
    (void)munmap(p, length);
  }
}
#endif
} // namespace

#if CTSPLINES_MAP_LARGE_ARRAYS
void* MapLargeBlock(std::size_t bytes)
{
  const std::size_t length = LargeBlockLength(bytes);
  LargeBlockCache& cache = Cache();
  std::vector<Block> pieces, expired;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    pieces = cache.TakeFor(length);
    expired = cache.TakeExpired(Clock::now());
  }
  Unmap(expired);
  if (pieces.size() == 1 && pieces[0].Length == length)
  {
    return pieces[0].Begin;
  }
  return Assemble(pieces, length);
}

void UnmapLargeBlock(void* p, std::size_t bytes) noexcept
{
  Release(p, LargeBlockLength(bytes));
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
  Release(p, length);
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
  std::vector<Block> evicted;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    cache.Limit = bytes;
    if (cache.Bytes > cache.Limit)
    {
      evicted = cache.TakeOldest(cache.Bytes - cache.Limit);
    }
  }
#if CTSPLINES_MAP_LARGE_ARRAYS
  Unmap(evicted);
#endif
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
  std::vector<Block> all;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    all.swap(cache.Blocks);
    cache.Bytes = 0;
  }
#if CTSPLINES_MAP_LARGE_ARRAYS
  Unmap(all);
#endif
}

} // namespace ctk
