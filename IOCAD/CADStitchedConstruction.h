// SPDX-License-Identifier: GPL-3.0-or-later
// The Construction setter of the CAD classes (private header): only the constructions that take
// prescribed boundary curves can be stitched (the kernel's construction table says which).
#ifndef CADStitchedConstruction_h
#define CADStitchedConstruction_h

#include "vtkCloughTocherSplineFilter.h"
#include "vtkObject.h"

namespace ctcad
{
/// Sets value to construction and marks self modified; a construction that cannot be stitched
/// is reported on self and leaves value unchanged.
inline void SetStitchedConstruction(vtkObject* self, int& value, int construction)
{
  if (!vtkCloughTocherSplineFilter::GetConstructionCanBeStitched(construction))
  {
    vtkErrorWithObjectMacro(self, << "construction " << construction << " ("
                                  << vtkCloughTocherSplineFilter::GetConstructionName(construction)
                                  << ") cannot be stitched: it takes no prescribed boundary curves");
    return;
  }
  if (value != construction)
  {
    value = construction;
    self->Modified();
  }
}
} // namespace ctcad

#endif
