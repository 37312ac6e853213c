// SPDX-License-Identifier: GPL-3.0-or-later
// A filter's previous output arrays, written again by its next execution (private header).
//
// A new output array's first touch costs the kernel's zeroing of every page it writes, and on a
// virtual machine the host's provisioning of them: a quarter of a spline construction's time at
// 1e6 triangles, and the wall that keeps a tessellation from scaling on two threads
// (docs/performance_history.md, sessions 21-25). When a filter runs again with outputs of the same
// sizes (time steps of one mesh, a property changed, an IM sweep), its previous output's arrays
// are resident already. The pipeline releases that output just before RequestData; the filter
// keeps its own reference to the large arrays, and writes again only those that nothing else
// references by then, neither the array object nor its storage (vtkAOSDataArrayTemplate's
// ShallowCopy shares the storage between array objects, as vtkArrayRename does). An array a
// downstream filter or the caller still holds is never written: its reference is dropped here
// and the new output gets a new array.
#ifndef CTSplinesRecycledArrays_h
#define CTSplinesRecycledArrays_h

#include "CTSplinesSMP.h" // for AllocateTuples

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>
#include <vector>

class vtkAlgorithm;
class vtkDataSet;

namespace ctsplines
{
class RecycledArrays
{
public:
  /// Arrays below this size (1 MiB unless set) are not kept: their pages are not worth it.
  static std::size_t MinimumBytes() { return MinimumBytesValue().load(std::memory_order_relaxed); }
  /// For tests and fuzzing only: with a smaller size, small outputs take the recycling paths too
  /// (the filters fuzzer sets 0, then checks that filters writing into their previous outputs'
  /// arrays give a new filter's bits).
  static void SetMinimumBytes(std::size_t bytes)
  {
    MinimumBytesValue().store(bytes, std::memory_order_relaxed);
  }

  /// At the start of an execution (RecycledArraysScope), with the sizes that decide the
  /// output's (shape): keeps the previous output's arrays only when enabled and the shape is the
  /// previous execution's, and only those that nothing else references now. Everything else is
  /// released before the execution allocates anything.
  void Begin(bool enabled, const std::vector<vtkIdType>& shape);

  /// A kept array that only this object references and that accept() takes, or null. It is no
  /// longer kept; its values are the old ones, its name, information and lookup table are as
  /// it had them.
  vtkSmartPointer<vtkDataArray> Take(const std::function<bool(vtkDataArray*)>& accept);

  /// An array of prototype's exact class with `components` x `tuples` values, not initialised:
  /// a kept one of that class and size (name, information, lookup table and lookup cleared,
  /// marked modified), or a new one (AllocateTuples). prototype is only read for its class.
  vtkSmartPointer<vtkDataArray> NewLike(vtkDataArray* prototype, int components, vtkIdType tuples);

  /// NewLike for class T.
  template <class T>
  vtkSmartPointer<T> New(int components, vtkIdType tuples)
  {
    vtkNew<T> prototype;
    return vtkSmartPointer<T>(T::SafeDownCast(this->NewLike(prototype, components, tuples)));
  }

  /// Releases the kept arrays that release() picks: those the rest of an execution cannot take
  /// (peak memory).
  void ReleaseIf(const std::function<bool(vtkDataArray*)>& release);

  /// Releases the kept arrays that were not taken.
  void ReleaseUnused();

  /// At the end of a successful execution: keeps output's arrays of MinimumBytes or more (points,
  /// point and cell data, cells, cell types) when enabled, for the next execution.
  void End(vtkDataSet* output, bool enabled);
  /// The same for the given arrays only (of MinimumBytes or more; nulls are skipped): a filter
  /// whose output also holds arrays it passes from its input keeps just its own.
  void End(const std::vector<vtkDataArray*>& arrays, bool enabled);

  /// Whether an algorithm's output 0 may be kept for its next execution: reuse (its property)
  /// unless the pipeline releases the output's data once it is consumed (ReleaseDataFlag, its own
  /// or the global one), which a kept reference would defeat.
  static bool MayKeepOutput(vtkAlgorithm* algorithm, bool reuse);

  /// Bytes of the arrays reused since Begin.
  std::size_t GetReusedBytes() const { return this->Reused; }

  /// Releases everything kept.
  void Clear();

  /// A filter's ReuseOutputArrays setter: sets `property` to `reuse`, and when turned off
  /// releases everything kept (the arrays go with the output, as without the property). True
  /// when the property changed: the filter then calls Modified().
  bool SetReuse(bool& property, bool reuse);

private:
  static std::atomic<std::size_t>& MinimumBytesValue(); // one for the process: in the .cxx
  friend class RecycledArraysScope;
  std::mutex Executing; // held by the RecycledArraysScope of an execution
  std::vector<vtkSmartPointer<vtkDataArray>> Kept;
  std::vector<vtkIdType> Shape;
  std::atomic<std::size_t> Reused{ 0 };
};

/// One execution's use of a filter's RecycledArrays: Begin on construction, Clear on destruction
/// unless End was called (an execution that fails or is aborted keeps nothing of the output it
/// did not finish, nor of the one before). Get() is null when another execution of the same
/// filter holds the arrays (vtkThreadedCompositeDataPipeline runs blocks concurrently): this one
/// then neither reuses nor keeps anything.
class RecycledArraysScope
{
public:
  RecycledArraysScope(RecycledArrays& recycled, bool enabled, const std::vector<vtkIdType>& shape)
    : Recycled(recycled)
    , Lock(recycled.Executing, std::try_to_lock)
  {
    if (this->Lock.owns_lock())
    {
      this->Recycled.Begin(enabled, shape);
    }
  }
  ~RecycledArraysScope()
  {
    if (this->Lock.owns_lock() && !this->Ended)
    {
      this->Recycled.Clear();
    }
  }
  RecycledArraysScope(const RecycledArraysScope&) = delete;
  RecycledArraysScope& operator=(const RecycledArraysScope&) = delete;

  /// The arrays for this execution, or null.
  RecycledArrays* Get() const { return this->Lock.owns_lock() ? &this->Recycled : nullptr; }

  /// RecycledArrays::End of an output.
  void End(vtkDataSet* output, bool enabled)
  {
    if (this->Lock.owns_lock())
    {
      this->Recycled.End(output, enabled);
      this->Ended = true;
    }
  }
  /// RecycledArrays::End of the given arrays.
  void End(const std::vector<vtkDataArray*>& arrays, bool enabled)
  {
    if (this->Lock.owns_lock())
    {
      this->Recycled.End(arrays, enabled);
      this->Ended = true;
    }
  }

private:
  RecycledArrays& Recycled;
  std::unique_lock<std::mutex> Lock;
  bool Ended = false;
};

/// recycled->New<T>, or a new T allocated (AllocateTuples) when recycled is null.
template <class T>
vtkSmartPointer<T> NewOutputArray(RecycledArrays* recycled, int components, vtkIdType tuples)
{
  if (recycled)
  {
    return recycled->New<T>(components, tuples);
  }
  auto array = vtkSmartPointer<T>::New();
  array->SetNumberOfComponents(components);
  AllocateTuples(array, tuples);
  return array;
}

/// recycled->NewLike, or a new array of prototype's class allocated (AllocateTuples) when
/// recycled is null.
vtkSmartPointer<vtkDataArray> NewOutputArrayLike(
  RecycledArrays* recycled, vtkDataArray* prototype, int components, vtkIdType tuples);

/// A cell array of nCells cells and connectivitySize ids below maxId, its offsets and
/// connectivity allocated (not initialised; from recycled when it has them): 32-bit storage
/// whenever every offset and id fits. VTK reads both; they are a large part of an output's
/// bytes.
vtkSmartPointer<vtkCellArray> NewCellArray(vtkIdType nCells, vtkIdType connectivitySize,
  vtkIdType maxId, RecycledArrays* recycled = nullptr);
} // namespace ctsplines

#endif
