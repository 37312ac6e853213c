// SPDX-License-Identifier: GPL-3.0-or-later
// Parallel loops of the module (private header): a grain size and a persistent pool, and the
// glue between the kernel's ParallelFor and them.
#ifndef CTSplinesSMP_h
#define CTSplinesSMP_h

#include "CubicCloughTocher.h" // for ctk::ParallelFor
#include "LargeArrays.h"       // for ctk::AdviseHugePages

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkSmartPointer.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__unix__)
#include <unistd.h> // for getpid
#endif

namespace ctsplines
{
/// Smallest number of elements worth a thread, by kind of work per element: waking the pool's
/// threads and waiting for them costs about 10-50 us, much more on a loaded machine.
/// A kernel evaluation per element (a patch, a query, a cell): about 0.3-10 us.
constexpr vtkIdType GrainForEvaluations = 1024;
/// A copy of a few words per element: memory bound, threads pay only on long loops.
constexpr vtkIdType GrainForCopies = vtkIdType(1) << 16;

/// Threads for the module's loops: CTSPLINES_NUM_THREADS when set (the Python package sets it
/// to the number of cores on import and leaves VTK's own backend alone), else VTK's: the
/// thread count of vtkSMPTools under its STDThread backend, 1 under the Sequential one.
inline int LoopThreads()
{
  if (const char* value = std::getenv("CTSPLINES_NUM_THREADS"))
  {
    if (std::atoi(value) > 0)
    {
      return std::atoi(value);
    }
  }
  if (std::strcmp(vtkSMPTools::GetBackend(), "STDThread") == 0)
  {
    return std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads());
  }
  return 1;
}

/// Worker threads started once and reused by every ParallelFor of the module (VTK 9.2's
/// STDThread backend starts and joins new threads on every vtkSMPTools::For it splits). One
/// loop at a time: a loop started while another runs (from another thread, or nested in a
/// chunk) runs on its calling thread.
class LoopPool
{
public:
  using Body = std::function<void(vtkIdType, vtkIdType)>;

  static LoopPool& Instance()
  {
    static LoopPool pool;
    return pool;
  }

  /// Runs body over [begin, end) in chunks of `grain` on `threads` threads, the caller one of
  /// them. Returns false, having run nothing, when the pool is busy.
  bool Run(int threads, vtkIdType begin, vtkIdType end, vtkIdType grain, const Body& body)
  {
    if (InLoop() || !this->SameProcess())
    {
      return false;
    }
    std::unique_lock<std::mutex> loop(this->LoopMutex, std::try_to_lock);
    if (!loop.owns_lock())
    {
      return false;
    }
    this->Resize(threads - 1);
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Loop = { &body, end, grain };
      this->Next.store(begin);
      this->Closed = false;
      ++this->Generation;
    }
    this->Wake.notify_all();
    // Workers that joined use body until they are done: wait for them (even if a chunk throws
    // here); those not awake yet when the caller is done skip this loop, so a loaded machine
    // does not make the caller wait for their wake-up.
    struct Wait
    {
      LoopPool& Pool;
      ~Wait()
      {
        std::unique_lock<std::mutex> lock(this->Pool.Mutex);
        this->Pool.Closed = true;
        this->Pool.Done.wait(lock, [this] { return this->Pool.Running == 0; });
      }
    } wait{ *this };
    this->Work();
    return true;
  }

  ~LoopPool() { this->Resize(0); }

private:
  struct LoopData
  {
    const Body* Function = nullptr;
    vtkIdType End = 0, Grain = 1;
  };

  static bool& InLoop()
  {
    static thread_local bool inLoop = false;
    return inLoop;
  }

  // A forked child has none of the workers (the CAD reader forks): it runs loops serially.
  bool SameProcess() const
  {
#if defined(__unix__)
    return getpid() == this->Owner;
#else
    return true;
#endif
  }

  // Chunks taken in turn from a shared counter: which thread runs a chunk does not matter.
  void Work()
  {
    struct Flag
    {
      Flag() { InLoop() = true; }
      ~Flag() { InLoop() = false; }
    } inLoop;
    const LoopData loop = this->Loop;
    for (vtkIdType b = this->Next.fetch_add(loop.Grain); b < loop.End;
         b = this->Next.fetch_add(loop.Grain))
    {
      (*loop.Function)(b, std::min(loop.End, b + loop.Grain));
    }
  }

  void Worker(unsigned long seen)
  {
    std::unique_lock<std::mutex> lock(this->Mutex);
    for (;;)
    {
      this->Wake.wait(lock, [&] { return this->Stop || this->Generation != seen; });
      if (this->Stop)
      {
        return;
      }
      seen = this->Generation;
      if (this->Closed)
      {
        continue;
      }
      ++this->Running;
      lock.unlock();
      this->Work();
      lock.lock();
      if (--this->Running == 0)
      {
        this->Done.notify_one();
      }
    }
  }

  // Called with LoopMutex held, no loop running.
  void Resize(int workers)
  {
    if (workers == static_cast<int>(this->Workers.size()))
    {
      return;
    }
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Stop = true;
    }
    this->Wake.notify_all();
    for (std::thread& t : this->Workers)
    {
      t.join();
    }
    this->Workers.clear();
    this->Stop = false;
    for (int i = 0; i < workers; ++i)
    {
      this->Workers.emplace_back(&LoopPool::Worker, this, this->Generation);
    }
  }

  std::mutex LoopMutex; // one loop at a time
  std::mutex Mutex;     // guards the fields below and the condition variables
  std::condition_variable Wake, Done;
  std::vector<std::thread> Workers;
  LoopData Loop;
  std::atomic<vtkIdType> Next{ 0 };
  int Running = 0;               // workers inside the current loop
  unsigned long Generation = 0;  // loops started
  bool Closed = true;            // the caller is done: late workers skip the loop
  bool Stop = false;
#if defined(__unix__)
  const pid_t Owner = getpid();
#endif
};

/// Chunks per thread of a long loop. Threads take chunks from a shared counter, so a loop's
/// tail is at most one chunk on one thread. With 4 per thread the caller ran 57 % of CTi's main
/// pass on 2 threads (perf, a 2-vCPU guest); 16 gave 1e6 triangles on 2 threads 3-19 % less wall
/// time (median 5 %) in 7 of 9 alternated pairs, 3 and 9 % more in the other two.
constexpr vtkIdType ChunksPerThread = 16;
/// Runs functor(b, e) over chunks of [begin, end) with at least minimumPerThread elements per
/// thread: a shorter loop runs on the calling thread and wakes no thread; a longer one gets about
/// ChunksPerThread chunks per thread, for balance on a shared machine, on the module's LoopPool.
/// Every element must be computed independently of the chunking (no order-dependent
/// reductions), so results do not depend on the thread count.
template <typename Functor>
void ParallelFor(vtkIdType begin, vtkIdType end, vtkIdType minimumPerThread, Functor&& functor)
{
  const vtkIdType n = end - begin;
  if (n <= 0)
  {
    return;
  }
  const int threads = LoopThreads();
  const vtkIdType chunks = vtkIdType(threads) * ChunksPerThread;
  const vtkIdType grain = std::max<vtkIdType>({ minimumPerThread, 1, (n + chunks - 1) / chunks });
  if (threads == 1 || grain >= n ||
    !LoopPool::Instance().Run(
      threads, begin, end, grain, [&functor](vtkIdType b, vtkIdType e) { functor(b, e); }))
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

/// Runs the kernel's loops of a few words per element (renumbering, topology, locality order)
/// through ParallelFor.
inline void SMPCopyFor(ctk::Id n, const std::function<void(ctk::Id, ctk::Id)>& body)
{
  ParallelFor(0, n, GrainForCopies, [&body](vtkIdType begin, vtkIdType end) { body(begin, end); });
}

/// SetNumberOfTuples for an output array (contiguous storage) that is then written in parallel
/// loops: its storage is advised for huge pages before the first touch (see LargeArrays.h).
/// Storage of ctk::LargeBlockBytes or more is a block of the module's own (ctk::MapArrayBlock):
/// retained when VTK frees it, its pages serve the next large arrays without fresh pages.
inline void AllocateTuples(vtkDataArray* array, vtkIdType tuples)
{
#if CTSPLINES_MAP_LARGE_ARRAYS
  // The kernel's threshold, as for its working arrays: glibc's heap pages that an output array
  // took fresh while the module's retained pages waited raised a construction's peak (1.05x
  // the output at 1e6 triangles from 32 MiB, 1.03x from 4 MiB).
  const vtkIdType values = tuples * array->GetNumberOfComponents();
  const std::size_t bytes = static_cast<std::size_t>(values) * array->GetDataTypeSize();
  if (tuples > 0 && bytes >= ctk::LargeBlockBytes && array->HasStandardMemoryLayout())
  {
    array->SetVoidArray(ctk::MapArrayBlock(bytes), values, 0,
      vtkAbstractArray::VTK_DATA_ARRAY_USER_DEFINED);
    array->SetArrayFreeFunction(&ctk::FreeArrayBlock);
    return;
  }
#endif
  array->SetNumberOfTuples(tuples);
  if (tuples > 0)
  {
    ctk::AdviseHugePages(array->GetVoidPointer(0),
      static_cast<size_t>(tuples) * array->GetNumberOfComponents() * array->GetDataTypeSize());
  }
}

} // namespace ctsplines

#endif
