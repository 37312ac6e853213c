// SPDX-License-Identifier: GPL-3.0-or-later
// Large arrays that are written once, right after allocation (control points, connectivity,
// output arrays). Their cost is dominated by first-touch page faults: one per 4 KiB page, which
// measured several seconds per GB on a loaded 2-core VM, against ~0.2 s per GB with 2 MiB
// transparent huge pages. Linux's common THP mode is "madvise", so such arrays are advised
// explicitly before they are touched. Header-only; a no-op where MADV_HUGEPAGE is unavailable.
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
/// Asks for transparent huge pages on the whole 2 MiB pages inside [p, p + bytes). Contents are
/// unchanged; ranges below a few MiB are left alone.
inline void AdviseHugePages(const void* p, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t huge = std::uintptr_t(1) << 21;
  if (!p || bytes < 4 * huge)
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

/// std::allocator, except that construct() without arguments default-initialises: resize() of
/// trivial elements leaves them unwritten. For arrays filled in parallel loops after resize():
/// value-initialisation would write every page first, serially, on the calling thread.
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
template <typename T>
void AssignLarge(std::vector<T>& v, std::size_t n, const T& value)
{
  if (v.capacity() < n)
  {
    std::vector<T>().swap(v);
    v.reserve(n);
    AdviseHugePages(v.data(), n * sizeof(T));
  }
  v.assign(n, value);
}
} // namespace ctk

#endif
