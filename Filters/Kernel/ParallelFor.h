// SPDX-License-Identifier: GPL-3.0-or-later
// How the kernel's loops are split: a ParallelFor given by the caller (the VTK module passes its
// thread pool, CTSplinesSMP.h), and helpers whose results do not depend on the split.
#ifndef CTSplines_Kernel_ParallelFor_h
#define CTSplines_Kernel_ParallelFor_h

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>

namespace ctk
{
using Id = std::int64_t;

/// Runs body(begin, end) over the chunks of [0, n); the caller may run chunks concurrently.
using ParallelFor = std::function<void(Id n, const std::function<void(Id, Id)>& body)>;
void SerialFor(Id n, const std::function<void(Id, Id)>& body);

/// The lowest id reported from concurrent chunks, so that an error names the same element
/// whatever the thread count.
class LowestId
{
public:
  void Report(Id id)
  {
    Id seen = this->Value.load(std::memory_order_relaxed);
    while (id < seen && !this->Value.compare_exchange_weak(seen, id))
    {
    }
  }
  /// The lowest reported id, or -1 when none was reported.
  Id Get() const
  {
    const Id v = this->Value.load();
    return v == std::numeric_limits<Id>::max() ? -1 : v;
  }

private:
  std::atomic<Id> Value{ std::numeric_limits<Id>::max() };
};

/// Runs body(i) for every block i of [0, n) cut every blockSize elements, each block whole in
/// one chunk of parallelFor over the elements (the chunk holding its first element): work kept
/// per block (counts, lists) then does not depend on how the loop is split.
template <typename ParallelForT, typename Body>
void ForBlocks(const ParallelForT& parallelFor, Id n, Id blockSize, Body&& body)
{
  parallelFor(n, [&](Id begin, Id end) {
    for (Id i = (begin + blockSize - 1) / blockSize; i * blockSize < end; ++i)
    {
      body(i);
    }
  });
}

/// The number of blocks of ForBlocks.
inline Id BlockCount(Id n, Id blockSize)
{
  return (n + blockSize - 1) / blockSize;
}
} // namespace ctk

#endif
