// SPDX-License-Identifier: GPL-3.0-or-later
// OverwriteAllocator's large blocks: usable, kept across growth, aligned to whole huge pages,
// given back to the system when freed whatever glibc's mmap threshold when nothing is retained,
// else retained within the limit and made into the next blocks before any fresh page.
#include "LargeArrays.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>
#if defined(__linux__)
#include <sys/prctl.h>
#endif

namespace
{
using Id = std::int64_t;

// Resident bytes of this process (Linux), or -1.
long long ResidentBytes()
{
  std::ifstream statm("/proc/self/statm");
  long long size = 0, resident = -1;
  if (!(statm >> size >> resident))
  {
    return -1;
  }
  return resident * static_cast<long long>(sysconf(_SC_PAGESIZE));
}

TEST(LargeArrays, BlocksAcrossTheThresholdKeepTheirContents)
{
  // Growth by push_back crosses LargeBlockBytes: heap to mapped, and mapped to mapped.
  ctk::OverwriteVector<Id> v;
  const Id n = static_cast<Id>(3 * ctk::LargeBlockBytes / sizeof(Id)) + 17;
  for (Id i = 0; i < n; ++i)
  {
    v.push_back(3 * i + 1);
  }
  Id wrong = 0;
  for (Id i = 0; i < n; ++i)
  {
    wrong += v[i] != 3 * i + 1;
  }
  EXPECT_EQ(wrong, 0);
  // A copy and a shrink to below the threshold keep the values too.
  ctk::OverwriteVector<Id> copy = v;
  copy.resize(100);
  copy.shrink_to_fit();
  EXPECT_EQ(copy[99], 3 * 99 + 1);
  EXPECT_EQ(std::accumulate(v.begin(), v.end(), Id(0)), 3 * (n - 1) * n / 2 + n);
}

TEST(LargeArrays, MappedBlocksStartOnHugePages)
{
#if CTSPLINES_MAP_LARGE_ARRAYS
  for (const std::size_t bytes : { ctk::LargeBlockBytes, ctk::LargeBlockBytes + 8,
         std::size_t(5) << 21, (std::size_t(5) << 21) - 8 })
  {
    ctk::OverwriteVector<double> v;
    ctk::ResizeForOverwrite(v, bytes / sizeof(double));
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % (std::uintptr_t(1) << 21), 0u)
      << bytes << " bytes";
    v.back() = 1.0; // the last element is inside the mapping
    v.front() = 2.0;
    EXPECT_EQ(v.back() + v.front(), 3.0);
  }
#else
  GTEST_SKIP() << "large blocks come from the heap in this build (ASan)";
#endif
}

// Whether the mapping that holds p may get transparent huge pages (its THPeligible flag in
// /proc/self/smaps), or -1 when not found.
int HugePageEligible(const void* p)
{
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p);
  std::ifstream smaps("/proc/self/smaps");
  bool inside = false;
  for (std::string line; std::getline(smaps, line);)
  {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> begin >> dash >> end && dash == '-')
    {
      inside = begin <= at && at < end;
    }
    else if (inside && line.rfind("THPeligible:", 0) == 0)
    {
      return std::stoi(line.substr(12));
    }
  }
  return -1;
}

// Mapped blocks ask for huge pages from the smallest (LargeBlockBytes, two huge pages) up: on
// guests where a small page's first touch costs a fault of about 11 us, that is 1,024 faults.
TEST(LargeArrays, MappedBlocksAreAdvisedForHugePages)
{
#if CTSPLINES_MAP_LARGE_ARRAYS && defined(__linux__)
  std::ifstream enabled("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(enabled, modes);
  if (modes.find("[madvise]") == std::string::npos || prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) == 1)
  {
    GTEST_SKIP() << "transparent huge pages: " << modes << " (the advice shows under madvise)";
  }
  for (const std::size_t bytes : { ctk::LargeBlockBytes, std::size_t(5) << 21 })
  {
    ctk::OverwriteVector<char> v;
    ctk::ResizeForOverwrite(v, bytes);
    const int eligible = HugePageEligible(v.data());
    if (eligible < 0)
    {
      GTEST_SKIP() << "no THPeligible field in /proc/self/smaps";
    }
    EXPECT_EQ(eligible, 1) << bytes << " bytes";
  }
#else
  GTEST_SKIP() << "large blocks come from the heap in this build";
#endif
}

// Restores the retained blocks' limit at the end of a test, and starts with none retained.
struct RetainedLimit
{
  std::size_t Saved = ctk::LargeBlockCacheLimit();
  explicit RetainedLimit(std::size_t bytes)
  {
    ctk::ReleaseLargeBlockCache();
    ctk::SetLargeBlockCacheLimit(bytes);
  }
  ~RetainedLimit()
  {
    ctk::ReleaseLargeBlockCache();
    ctk::SetLargeBlockCacheLimit(this->Saved);
  }
};

TEST(LargeArrays, FreedBlocksLeaveTheProcess)
{
#if CTSPLINES_MAP_LARGE_ARRAYS && defined(__GLIBC__) && defined(M_MMAP_THRESHOLD)
  const RetainedLimit limit(0); // nothing retained
  // As after NumPy frees a 32 MiB array: glibc then serves blocks up to 32 MiB from its heap.
  ASSERT_EQ(mallopt(M_MMAP_THRESHOLD, 32 << 20), 1);
  ASSERT_EQ(mallopt(M_TRIM_THRESHOLD, 64 << 20), 1);
  const std::size_t bytes = std::size_t(24) << 20;
  ctk::OverwriteVector<char> v;
  ctk::ResizeForOverwrite(v, bytes);
  for (std::size_t i = 0; i < bytes; i += 4096)
  {
    v[i] = 1; // resident
  }
  const long long touched = ResidentBytes();
  ASSERT_GT(touched, 0);
  ctk::OverwriteVector<char>().swap(v);
  const long long freed = ResidentBytes();
  EXPECT_LT(freed, touched - static_cast<long long>(bytes) + (4ll << 20))
    << "resident " << touched << " -> " << freed << " bytes after freeing " << bytes;
  mallopt(M_MMAP_THRESHOLD, 128 << 10); // fixed at glibc's initial value from here on
#else
  GTEST_SKIP() << "large blocks come from the heap in this build";
#endif
}

#if CTSPLINES_MAP_LARGE_ARRAYS
// A live block to map between blocks mapped one after the other: once freed, they are then not
// neighbours, which the cache would join into one.
ctk::OverwriteVector<char> Spacer()
{
  ctk::OverwriteVector<char> s;
  ctk::ResizeForOverwrite(s, ctk::LargeBlockBytes);
  return s;
}

// A block freed and asked for again with its length comes back at the same address, without a
// new mapping; a shorter one takes the start of the shortest longer block, whose rest stays.
TEST(LargeArrays, RetainedBlocksServeTheirLengthOrShorter)
{
  const RetainedLimit limit(std::size_t(64) << 20);
  const std::size_t n = (std::size_t(8) << 20) / sizeof(double);
  const double* first = nullptr;
  const double* longer = nullptr;
  ctk::OverwriteVector<char> spacer;
  {
    ctk::OverwriteVector<double> v, w;
    ctk::ResizeForOverwrite(v, n);
    spacer = Spacer();
    ctk::ResizeForOverwrite(w, 2 * n);
    v.back() = 1.0;
    first = v.data();
    longer = w.data();
  }
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(24) << 20);
  {
    ctk::OverwriteVector<double> again;
    ctk::ResizeForOverwrite(again, n - 5); // the same number of huge pages
    EXPECT_EQ(again.data(), first);
    EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(16) << 20);
    again.back() = 2.0; // usable to its end
    EXPECT_EQ(again.back(), 2.0);
    ctk::OverwriteVector<double> shorter;
    ctk::ResizeForOverwrite(shorter, n / 2); // 4 MiB: the start of the 16 MiB block
    EXPECT_EQ(shorter.data(), longer);
    EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(12) << 20);
    shorter.back() = 3.0;
    EXPECT_EQ(shorter.back(), 3.0);
  }
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(24) << 20);
  {
    // The start taken from the 16 MiB block was joined again with its rest.
    ctk::OverwriteVector<double> whole;
    ctk::ResizeForOverwrite(whole, 2 * n);
    EXPECT_EQ(whole.data(), longer);
    EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(8) << 20);
  }
  ctk::ReleaseLargeBlockCache();
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 0u);
}

// A block longer than every retained one is made of them, longest first, moved with their page
// tables, and fresh pages after them: the process's resident size grows by the fresh part only.
TEST(LargeArrays, LongerBlocksAreMadeOfRetainedOnes)
{
  const RetainedLimit limit(std::size_t(64) << 20);
  ASSERT_EQ(setenv("CTSPLINES_POISON_RETAINED_BLOCKS", "1", 1), 0); // resident, full of 0xff
  constexpr std::size_t MiB = std::size_t(1) << 20;
  {
    ctk::OverwriteVector<char> a, b, c;
    ctk::ResizeForOverwrite(a, 4 * MiB);
    ctk::ResizeForOverwrite(b, 8 * MiB);
    ctk::ResizeForOverwrite(c, 6 * MiB);
  }
  unsetenv("CTSPLINES_POISON_RETAINED_BLOCKS");
  ASSERT_EQ(ctk::LargeBlockCacheBytes(), 18 * MiB);
  const long long before = ResidentBytes();
  ASSERT_GT(before, 0);
  ctk::OverwriteVector<unsigned char> v;
  ctk::ResizeForOverwrite(v, 22 * MiB);
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % (std::uintptr_t(1) << 21), 0u);
  const auto ones = std::count(v.begin(), v.begin() + 18 * MiB, (unsigned char)0xff);
  const auto zeros = std::count(v.begin() + 18 * MiB, v.end(), (unsigned char)0);
  EXPECT_EQ(ones, static_cast<std::ptrdiff_t>(18 * MiB)); // the retained pages, moved
  EXPECT_EQ(zeros, static_cast<std::ptrdiff_t>(4 * MiB)); // fresh ones
  std::fill(v.begin(), v.end(), (unsigned char)7);
  const long long after = ResidentBytes();
  EXPECT_LT(after, before + static_cast<long long>(6 * MiB))
    << "resident " << before << " -> " << after << " bytes for 4 MiB of fresh pages";
  EXPECT_EQ(std::count(v.begin(), v.end(), (unsigned char)7), static_cast<std::ptrdiff_t>(22 * MiB));
#if defined(MADV_NOHUGEPAGE)
  // Other flags on a huge page inside: two more mappings (the moved pieces are not joined).
  ASSERT_EQ(madvise(v.data() + 10 * MiB, 2 * MiB, MADV_NOHUGEPAGE), 0);
#endif
  ctk::OverwriteVector<unsigned char>().swap(v);
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 22 * MiB); // retained whole
  ctk::OverwriteVector<char> w; // the block of several mappings moves again, its values with it
  ctk::ResizeForOverwrite(w, 30 * MiB);
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 0u);
  EXPECT_EQ(std::count(w.begin(), w.begin() + 22 * MiB, char(7)),
    static_cast<std::ptrdiff_t>(22 * MiB));
  EXPECT_EQ(std::count(w.begin() + 22 * MiB, w.end(), char(0)), static_cast<std::ptrdiff_t>(8 * MiB));
  std::fill(w.begin(), w.end(), 'x');
  EXPECT_EQ(std::count(w.begin(), w.end(), 'x'), static_cast<std::ptrdiff_t>(30 * MiB));
}

// The limit holds: the oldest blocks go first, and a lower limit gives back at once.
TEST(LargeArrays, RetainedBlocksStayWithinTheLimit)
{
  const RetainedLimit limit(std::size_t(20) << 20);
  const std::size_t n = (std::size_t(8) << 20) / sizeof(double);
  const double* oldest = nullptr;
  std::vector<ctk::OverwriteVector<char>> spacers;
  {
    ctk::OverwriteVector<double> a, b, c;
    for (ctk::OverwriteVector<double>* v : { &a, &b, &c })
    {
      ctk::ResizeForOverwrite(*v, n);
      spacers.push_back(Spacer());
    }
    oldest = a.data();
    ctk::OverwriteVector<double>().swap(a);
    ctk::OverwriteVector<double>().swap(b);
    ctk::OverwriteVector<double>().swap(c);
    EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(16) << 20); // a went back
  }
  ctk::OverwriteVector<double> v1, v2; // b and c
  ctk::ResizeForOverwrite(v1, n);
  ctk::ResizeForOverwrite(v2, n);
  EXPECT_NE(v1.data(), oldest);
  EXPECT_NE(v2.data(), oldest);
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 0u);
  ctk::OverwriteVector<double>().swap(v1);
  ctk::OverwriteVector<double>().swap(v2);
  ctk::SetLargeBlockCacheLimit(std::size_t(10) << 20);
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), std::size_t(8) << 20);
  ctk::SetLargeBlockCacheLimit(std::size_t(4) << 20); // below one block: nothing kept
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 0u);
  {
    ctk::OverwriteVector<double> v;
    ctk::ResizeForOverwrite(v, n);
  }
  EXPECT_EQ(ctk::LargeBlockCacheBytes(), 0u);
}

// Released blocks leave the process's resident memory.
TEST(LargeArrays, ReleasedBlocksLeaveTheProcess)
{
  const RetainedLimit limit(std::size_t(256) << 20);
  const std::size_t bytes = std::size_t(64) << 20;
  {
    ctk::OverwriteVector<char> v;
    ctk::ResizeForOverwrite(v, bytes);
    std::memset(v.data(), 1, bytes);
  }
  const long long retained = ResidentBytes();
  ASSERT_GT(retained, 0);
  ctk::ReleaseLargeBlockCache();
  const long long released = ResidentBytes();
  EXPECT_LT(released, retained - static_cast<long long>(bytes) + (4ll << 20))
    << "resident " << retained << " -> " << released << " bytes";
}

// CTSPLINES_POISON_RETAINED_BLOCKS=1: a retained block comes back filled with 0xff bytes.
TEST(LargeArrays, PoisonedBlocksComeBackAsOnes)
{
  const RetainedLimit limit(std::size_t(64) << 20);
  ASSERT_EQ(setenv("CTSPLINES_POISON_RETAINED_BLOCKS", "1", 1), 0);
  const std::size_t n = (std::size_t(6) << 20) / sizeof(std::int64_t);
  {
    ctk::OverwriteVector<std::int64_t> v;
    ctk::ResizeForOverwrite(v, n);
    std::fill(v.begin(), v.end(), 0);
  }
  unsetenv("CTSPLINES_POISON_RETAINED_BLOCKS");
  ctk::OverwriteVector<std::int64_t> v;
  ctk::ResizeForOverwrite(v, n);
  EXPECT_EQ(std::count(v.begin(), v.end(), std::int64_t(-1)), static_cast<std::ptrdiff_t>(n));
}
#endif
} // namespace
