// SPDX-License-Identifier: GPL-3.0-or-later
// Glue between the kernel's ParallelFor and vtkSMPTools (private header of the module).
#ifndef CTSplinesSMP_h
#define CTSplinesSMP_h

#include "CubicCloughTocher.h" // for ctk::ParallelFor
#include "LargeArrays.h"       // for ctk::AdviseHugePages

#include "vtkDataArray.h"
#include "vtkSMPTools.h"

namespace ctsplines
{
/// Runs the kernel's chunked loops through vtkSMPTools (whatever backend is active). Every
/// element is computed independently, so results do not depend on the thread count.
inline void SMPFor(ctk::Id n, const std::function<void(ctk::Id, ctk::Id)>& body)
{
  vtkSMPTools::For(0, n, [&body](vtkIdType begin, vtkIdType end) { body(begin, end); });
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
