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
// The retained blocks, oldest first: each a whole number of huge pages, aligned to one.
struct LargeBlockCache
{
  struct Block
  {
    void* Begin;
    std::size_t Length;
    std::chrono::steady_clock::time_point Retained;
  };
  std::mutex Mutex;
  std::vector<Block> Blocks;
  std::vector<Block> Marked; // RetainWhenFreed: blocks in use, retained once freed
  std::size_t Bytes = 0;
  std::size_t Limit = DefaultLimit();
  // As jemalloc's decay of dirty pages: a block unused this long is not part of a series of
  // constructions any more.
  static constexpr std::chrono::seconds RetainFor{ 10 };

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
  std::vector<Block> TakeExpired(std::chrono::steady_clock::time_point now)
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
};

LargeBlockCache& Cache()
{
  static LargeBlockCache* const cache = new LargeBlockCache; // blocks may be freed at exit
  return *cache;
}

#if CTSPLINES_MAP_LARGE_ARRAYS
void Unmap(const std::vector<LargeBlockCache::Block>& blocks)
{
  for (const LargeBlockCache::Block& b : blocks)
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
  std::vector<LargeBlockCache::Block> evicted;
  try
  {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    cache.Blocks.push_back({ p, length, now });
    cache.Bytes += length;
    evicted = cache.TakeExpired(now);
    if (cache.Bytes > cache.Limit)
    {
      std::vector<LargeBlockCache::Block> oldest = cache.TakeOldest(cache.Bytes - cache.Limit);
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
#endif
} // namespace

#if CTSPLINES_MAP_LARGE_ARRAYS
void* MapLargeBlock(std::size_t bytes)
{
  const std::size_t length = LargeBlockLength(bytes);
  LargeBlockCache& cache = Cache();
  std::vector<LargeBlockCache::Block> dropped;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    // The newest retained block of exactly `length`: a construction that follows another on
    // the same mesh asks for the same lengths. A larger block is not cut down: a smaller array
    // would take the block that the next construction's larger one needs.
    for (auto it = cache.Blocks.rbegin(); it != cache.Blocks.rend(); ++it)
    {
      if (it->Length == length)
      {
        void* p = it->Begin;
        cache.Blocks.erase(std::next(it).base());
        cache.Bytes -= length;
        return p;
      }
    }
    dropped = cache.TakeExpired(std::chrono::steady_clock::now());
  }
  Unmap(dropped);
  return MapFresh(length);
}

void UnmapLargeBlock(void* p, std::size_t bytes) noexcept
{
  const std::size_t length = LargeBlockLength(bytes);
  LargeBlockCache& cache = Cache();
  bool keep = false;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    const auto marked = std::find_if(cache.Marked.begin(), cache.Marked.end(),
      [p](const LargeBlockCache::Block& b) { return b.Begin == p; });
    if (marked != cache.Marked.end())
    {
      cache.Marked.erase(marked);
      keep = length <= cache.Limit;
    }
  }
  if (!keep)
  {
    (void)munmap(p, length);
    return;
  }
  Retain(p, length);
}

void* MapRetainedBlock(std::size_t bytes)
{
  void* p = MapLargeBlock(bytes);
  try
  {
    RetainWhenFreed(p, bytes);
  }
  catch (...)
  {
    UnmapLargeBlock(p, bytes);
    throw;
  }
  return p;
}

void FreeRetainedBlock(void* p)
{
  std::size_t length = 0;
  {
    LargeBlockCache& cache = Cache();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    const auto marked = std::find_if(cache.Marked.begin(), cache.Marked.end(),
      [p](const LargeBlockCache::Block& b) { return b.Begin == p; });
    if (marked == cache.Marked.end())
    {
      return; // not a block of MapRetainedBlock: its length is unknown
    }
    length = marked->Length;
  }
  UnmapLargeBlock(p, length);
}
#endif

void RetainWhenFreed(const void* p, std::size_t bytes)
{
#if CTSPLINES_MAP_LARGE_ARRAYS
  if (p && bytes >= LargeBlockBytes)
  {
    LargeBlockCache& cache = Cache();
    std::lock_guard<std::mutex> lock(cache.Mutex);
    const std::size_t length = LargeBlockLength(bytes);
    if (std::none_of(cache.Marked.begin(), cache.Marked.end(),
          [p](const LargeBlockCache::Block& b) { return b.Begin == p; }))
    {
      cache.Marked.push_back({ const_cast<void*>(p), length, {} });
    }
  }
#else
  (void)p;
  (void)bytes;
#endif
}

std::size_t LargeBlockCacheLimit()
{
  LargeBlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  return cache.Limit;
}

void SetLargeBlockCacheLimit(std::size_t bytes)
{
  LargeBlockCache& cache = Cache();
  std::vector<LargeBlockCache::Block> evicted;
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
  std::vector<LargeBlockCache::Block> all;
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
