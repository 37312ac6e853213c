// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkCTSplinesThreads.h"

#include "CTSplinesSMP.h"

#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__unix__)
#include <unistd.h> // for getpid
#endif

vtkStandardNewMacro(vtkCTSplinesThreads);

namespace
{
std::atomic<int> ThreadsSetting{ 0 };

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

  std::atomic<vtkIdType> LoopsRun{ 0 };

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
    this->LoopsRun.fetch_add(1);
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

} // namespace

namespace ctsplines
{
int LoopThreads()
{
  const int setting = ThreadsSetting.load(std::memory_order_relaxed);
  if (setting > 0)
  {
    return setting;
  }
  if (std::strcmp(vtkSMPTools::GetBackend(), "STDThread") == 0)
  {
    return std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads());
  }
  return 1;
}

bool RunOnPool(int threads, vtkIdType begin, vtkIdType end, vtkIdType grain,
  const std::function<void(vtkIdType, vtkIdType)>& body)
{
  return LoopPool::Instance().Run(threads, begin, end, grain, body);
}
} // namespace ctsplines

void vtkCTSplinesThreads::SetNumberOfThreads(int threads)
{
  ThreadsSetting.store(std::max(0, threads));
}

int vtkCTSplinesThreads::GetNumberOfThreadsSetting()
{
  return ThreadsSetting.load();
}

int vtkCTSplinesThreads::GetNumberOfThreads()
{
  return ctsplines::LoopThreads();
}

vtkIdType vtkCTSplinesThreads::GetNumberOfParallelLoops()
{
  return LoopPool::Instance().LoopsRun.load();
}

void vtkCTSplinesThreads::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfThreadsSetting: " << GetNumberOfThreadsSetting() << "\n";
  os << indent << "NumberOfThreads: " << GetNumberOfThreads() << "\n";
  os << indent << "NumberOfParallelLoops: " << GetNumberOfParallelLoops() << "\n";
}
