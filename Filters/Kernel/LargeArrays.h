// SPDX-License-Identifier: GPL-3.0-or-later
// Large arrays that are written once, right after allocation (control points, connectivity,
// output arrays). Their cost is dominated by first-touch page faults: one per 4 KiB page, which
// measured several seconds per GB on a loaded 2-core VM, against ~0.2 s per GB with 2 MiB
// transparent huge pages. Linux's common THP mode is "madvise", so such arrays are advised
// explicitly before they are touched (a no-op where MADV_HUGEPAGE is unavailable). The blocks
// and the retained ones are in LargeArrays.cxx.
#ifndef CTSplines_Kernel_LargeArrays_h
#define CTSplines_Kernel_LargeArrays_h

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ctk
{
/// The size of a transparent huge page on x86-64 and of the blocks MapLargeBlock rounds to.
constexpr std::size_t HugePageBytes = std::size_t(1) << 21;

/// Asks for transparent huge pages on the whole 2 MiB pages inside [p, p + bytes); a range
/// without one is left alone. Contents are unchanged. Each small page costs a fault on its
/// first touch: about 11 us per 4 KiB on this project's KVM guest, against 14-24 GB/s for huge
/// pages (docs/performance_history.md, session 26).
inline void AdviseHugePages(const void* p, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t huge = HugePageBytes;
  if (!p || bytes < huge)
  {
    return;
  }
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + huge - 1) & ~(huge - 1);
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(huge - 1);
  if (end > begin)
  {
    // Advisory only: failure (e.g. THP disabled) just keeps small pages.
    (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  }
#else
  (void)p;
  (void)bytes;
#endif
}

#if defined(__SANITIZE_ADDRESS__)
#define CTSPLINES_MAP_LARGE_ARRAYS 0 // the heap, where ASan's redzones catch overflows
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CTSPLINES_MAP_LARGE_ARRAYS 0
#endif
#endif
#if !defined(CTSPLINES_MAP_LARGE_ARRAYS)
#if defined(__linux__)
#define CTSPLINES_MAP_LARGE_ARRAYS 1
#else
#define CTSPLINES_MAP_LARGE_ARRAYS 0
#endif
#endif

/// Blocks of at least this many bytes are mapped on their own (MapLargeBlock). Smaller ones stay
/// with glibc, whose heap serves them resident once its threshold has risen: 1 MiB was slower
/// and raised the peak at 1e6 triangles (performance_history.md, session 26).
constexpr std::size_t LargeBlockBytes = std::size_t(4) << 20;

#if CTSPLINES_MAP_LARGE_ARRAYS
/// The bytes a mapped block of `bytes` takes: whole huge pages.
inline std::size_t LargeBlockLength(std::size_t bytes)
{
  return (bytes + HugePageBytes - 1) & ~(HugePageBytes - 1);
}
/// A block of `bytes` (>= LargeBlockBytes) mapped on its own, in whole 2 MiB pages advised for
/// huge pages. glibc's malloc serves blocks below its mmap threshold (which rises to 32 MiB once
/// a process frees such a block, as NumPy's users do) from its heap and keeps them resident once
/// freed: a construction's 4-32 MiB working arrays then add to the resident peak on top of the
/// output. The block is made of retained pages (freed blocks, see UnmapLargeBlock) as far as
/// there are any: a retained block of the same length, else the start of a longer one, else up
/// to 64 retained blocks moved together with their page tables (mremap) before fresh pages (a
/// fresh block if a page cannot move). A construction that follows another on the same mesh,
/// which asks for the same lengths, then writes into resident memory instead of faulting in
/// fresh pages, which the kernel zeroes first; and as retained pages are used before any fresh
/// one, retaining them does not raise the process's resident peak beyond the largest size its
/// live blocks reached (unless more than 64 retained blocks wait, or arrays from glibc take
/// fresh pages meanwhile).
void* MapLargeBlock(std::size_t bytes);
/// Gives back a block of MapLargeBlock(bytes): retained for the next MapLargeBlock (within
/// LargeBlockCacheLimit), else unmapped.
void UnmapLargeBlock(void* p, std::size_t bytes) noexcept;
/// MapLargeBlock(bytes) for the storage of a VTK array, which frees it by its pointer alone
/// (SetVoidArray with a user-defined free function: FreeArrayBlock).
void* MapArrayBlock(std::size_t bytes);
/// UnmapLargeBlock of a block of MapArrayBlock (its length recorded there); anything else is left
/// alone.
void FreeArrayBlock(void* p);
#endif

/// The retained blocks' bytes in all stay within this limit, the oldest given back first. As with
/// jemalloc's decay of dirty pages, a block retained for more than 10 s goes back to the system
/// at the next MapLargeBlock or retained block (unless that call takes it), and a retained block
/// is joined with retained neighbours (the rest of a block whose start it was) and advised
/// MADV_FREE, so the kernel may take its pages back under memory pressure; until then they count
/// in the process's resident size. The default is a quarter of the physical memory, or
/// CTSPLINES_LARGE_BLOCK_CACHE_MB from the environment when set; 0 retains nothing. Without
/// mapped blocks (ASan builds) nothing is retained. For tests, CTSPLINES_POISON_RETAINED_BLOCKS=1
/// in the environment fills blocks with 0xff bytes (NaN as doubles, -1 as integers) as they are
/// retained, and keeps them resident: code that reads a large array before writing it then
/// reads garbage, not a fresh mapping's zeros.
std::size_t LargeBlockCacheLimit();
/// Sets LargeBlockCacheLimit; retained blocks beyond the new limit are unmapped at once.
void SetLargeBlockCacheLimit(std::size_t bytes);
/// The bytes retained now.
std::size_t LargeBlockCacheBytes();
/// Unmaps every retained block.
void ReleaseLargeBlockCache();

/// std::allocator, except that construct() without arguments default-initialises: resize() of
/// trivial elements leaves them unwritten. For arrays filled in parallel loops after resize():
/// value-initialisation would write every page first, serially, on the calling thread. Blocks of
/// LargeBlockBytes or more are mapped on their own (MapLargeBlock; the heap under ASan).
template <typename T>
struct OverwriteAllocator : std::allocator<T>
{
  using value_type = T;
  template <typename U>
  struct rebind
  {
    using other = OverwriteAllocator<U>;
  };
  OverwriteAllocator() = default;
  template <typename U>
  OverwriteAllocator(const OverwriteAllocator<U>&) noexcept
  {
  }
  T* allocate(std::size_t n)
  {
#if CTSPLINES_MAP_LARGE_ARRAYS
    static_assert(alignof(T) <= 4096, "page-aligned blocks");
    if (n >= LargeBlockBytes / sizeof(T))
    {
      if (n > std::size_t(-1) / sizeof(T))
      {
        throw std::bad_array_new_length();
      }
      return static_cast<T*>(MapLargeBlock(n * sizeof(T)));
    }
#endif
    return std::allocator<T>::allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept
  {
#if CTSPLINES_MAP_LARGE_ARRAYS
    if (n >= LargeBlockBytes / sizeof(T))
    {
      UnmapLargeBlock(p, n * sizeof(T));
      return;
    }
#endif
    std::allocator<T>::deallocate(p, n);
  }
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value)
  {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args)
  {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <typename T, typename U>
bool operator==(const OverwriteAllocator<T>&, const OverwriteAllocator<U>&)
{
  return true;
}
template <typename T, typename U>
bool operator!=(const OverwriteAllocator<T>&, const OverwriteAllocator<U>&)
{
  return false;
}

/// A vector whose resize(n) leaves trivial elements unwritten (see OverwriteAllocator).
template <typename T>
using OverwriteVector = std::vector<T, OverwriteAllocator<T>>;

/// Resizes v to n elements that the caller then overwrites: when v must grow, its old contents
/// are dropped and the new storage is advised for huge pages before resize() touches it (which
/// writes it, unless v is an OverwriteVector).
template <typename T, typename A>
void ResizeForOverwrite(std::vector<T, A>& v, std::size_t n)
{
  if (v.capacity() < n)
  {
    std::vector<T, A>().swap(v);
    v.reserve(n);
    AdviseHugePages(v.data(), n * sizeof(T));
  }
  v.resize(n);
}

/// assign() with the same treatment.
template <typename T, typename A>
void AssignLarge(std::vector<T, A>& v, std::size_t n, const T& value)
{
  if (v.capacity() < n)
  {
    std::vector<T, A>().swap(v);
    v.reserve(n);
    AdviseHugePages(v.data(), n * sizeof(T));
  }
  v.assign(n, value);
}
} // namespace ctk

#endif
