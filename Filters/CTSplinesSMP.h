// SPDX-License-Identifier: GPL-3.0-or-later
// Parallel loops of the module (private header): vtkSMPTools with a grain size, and the glue
// between the kernel's ParallelFor and vtkSMPTools.
#ifndef CTSplinesSMP_h
#define CTSplinesSMP_h

#include "CubicCloughTocher.h" // for ctk::ParallelFor
#include "LargeArrays.h"       // for ctk::AdviseHugePages

#include "vtkDataArray.h"
#include "vtkSMPTools.h"

#include <algorithm>

namespace ctsplines
{
/// Smallest number of elements worth a thread, by kind of work per element. VTK 9.2's STDThread
/// backend starts (and joins) a new set of threads on every vtkSMPTools::For call that it splits
/// (about 50-100 us on this machine), and splits any loop longer than its grain.
/// A kernel evaluation per element (a patch, a query, a cell): about 0.3-10 us.
constexpr vtkIdType GrainForEvaluations = 1024;
/// A copy of a few words per element: memory bound, threads pay only on long loops.
constexpr vtkIdType GrainForCopies = vtkIdType(1) << 16;

/// vtkSMPTools::For(begin, end, functor) with a grain of at least minimumPerThread elements: a
/// shorter loop runs on the calling thread and starts no thread; a longer one gets about four
/// chunks per thread (VTK's own default), for balance on a shared machine. Every element must
/// be computed independently of the chunking (no order-dependent reductions), so results do
/// not depend on the thread count.
template <typename Functor>
void ParallelFor(vtkIdType begin, vtkIdType end, vtkIdType minimumPerThread, Functor&& functor)
{
  const vtkIdType n = end - begin;
  if (n <= 0)
  {
    return;
  }
  const vtkIdType threads = std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads());
  const vtkIdType chunksPerThread = 4;
  const vtkIdType chunks = threads * chunksPerThread;
  const vtkIdType grain = std::max<vtkIdType>({ minimumPerThread, 1, (n + chunks - 1) / chunks });
  if (threads == 1 || grain >= n)
  {
    functor(begin, end);
    return;
  }
  vtkSMPTools::For(begin, end, grain, functor);
}

/// Runs the kernel's loops (over triangles, vertices or edges, each a kernel evaluation)
/// through ParallelFor, whatever vtkSMPTools backend is active.
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
