// SPDX-License-Identifier: GPL-3.0-or-later
// Glue between the kernel's ParallelFor and vtkSMPTools (private header of the module).
#ifndef CTSplinesSMP_h
#define CTSplinesSMP_h

#include "CubicCloughTocher.h" // for ctk::ParallelFor

#include "vtkSMPTools.h"

namespace ctsplines
{
/// Runs the kernel's chunked loops through vtkSMPTools (whatever backend is active). Every
/// element is computed independently, so results do not depend on the thread count.
inline void SMPFor(ctk::Id n, const std::function<void(ctk::Id, ctk::Id)>& body)
{
  vtkSMPTools::For(0, n, [&body](vtkIdType begin, vtkIdType end) { body(begin, end); });
}
} // namespace ctsplines

#endif
