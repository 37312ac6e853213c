// SPDX-License-Identifier: GPL-3.0-or-later
// Parallel loops of the module (private header): a grain size and a persistent pool, and the
// glue between the kernel's ParallelFor and them.
#ifndef CTSplinesSMP_h
#define CTSplinesSMP_h

#include "CubicCloughTocher.h" // for ctk::ParallelFor
#include "LargeArrays.h"       // for ctk::AdviseHugePages

#include "vtkDataArray.h"

#include <algorithm>
#include <functional>

namespace ctsplines
{
/// Smallest number of elements worth a thread, by kind of work per element: waking the pool's
/// threads and waiting for them costs about 10-50 us, much more on a loaded machine.
/// A kernel evaluation per element (a patch, a query, a cell): about 0.3-10 us.
constexpr vtkIdType GrainForEvaluations = 1024;
/// A copy of a few words per element: memory bound, threads pay only on long loops.
constexpr vtkIdType GrainForCopies = vtkIdType(1) << 16;

/// Threads for the module's loops (vtkCTSplinesThreads::GetNumberOfThreads).
int LoopThreads();

/// Runs body over [begin, end) in chunks of `grain` on the module's pool of `threads` threads
/// (started once, reused), the caller one of them. Returns false, having run nothing, when the
/// pool is busy (a loop started from another thread, or nested in a chunk): the caller then
/// runs the loop itself.
bool RunOnPool(int threads, vtkIdType begin, vtkIdType end, vtkIdType grain,
  const std::function<void(vtkIdType, vtkIdType)>& body);

/// Runs functor(b, e) over chunks of [begin, end) with at least minimumPerThread elements per
/// thread: a shorter loop runs on the calling thread and wakes no thread; a longer one gets about
/// four chunks per thread, for balance on a shared machine, on the module's pool (RunOnPool). Every
/// element must be computed independently of the chunking (no order-dependent reductions), so
/// results do not depend on the thread count.
template <typename Functor>
void ParallelFor(vtkIdType begin, vtkIdType end, vtkIdType minimumPerThread, Functor&& functor)
{
  const vtkIdType n = end - begin;
  if (n <= 0)
  {
    return;
  }
  const int threads = LoopThreads();
  const vtkIdType chunks = vtkIdType(threads) * 4;
  const vtkIdType grain = std::max<vtkIdType>({ minimumPerThread, 1, (n + chunks - 1) / chunks });
  if (threads == 1 || grain >= n ||
    !RunOnPool(threads, begin, end, grain, [&functor](vtkIdType b, vtkIdType e) { functor(b, e); }))
  {
    functor(begin, end);
  }
}

/// Runs the kernel's loops (over triangles, vertices or edges, each a kernel evaluation)
/// through ParallelFor.
inline void SMPFor(ctk::Id n, const std::function<void(ctk::Id, ctk::Id)>& body)
{
  ParallelFor(
    0, n, GrainForEvaluations, [&body](vtkIdType begin, vtkIdType end) { body(begin, end); });
}

/// SetNumberOfTuples for an output array (contiguous storage) that is then written in parallel
/// loops: its storage is advised for huge pages before the first touch (see LargeArrays.h).
inline void AllocateTuples(vtkDataArray* array, vtkIdType tuples)
{
  array->SetNumberOfTuples(tuples);
  if (tuples > 0)
  {
    ctk::AdviseHugePages(array->GetVoidPointer(0),
      static_cast<size_t>(tuples) * array->GetNumberOfComponents() * array->GetDataTypeSize());
  }
}

} // namespace ctsplines

#endif
