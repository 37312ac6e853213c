// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK side of the stitcher's stages (private header): a vtkCADFaceSampler block read into
// the stages' SampledFace, every array checked.
#ifndef CADSampledFace_h
#define CADSampledFace_h

#include "CADFaceSplines.h"

#include <string>

class vtkDataObject;

namespace ctcad
{
/// Reads block f of vtkCADFaceSampler's output (the arrays of CADArrayNames.h) for a spline of
/// `options` (the stitch mid-edge gradients only when it uses them); with `fallbacks` (the faces
/// were refined for `options`), the block's FallbackConstruction too, for which the arrays are
/// then read. Returns an empty string, or a message naming the block and the missing or
/// malformed array.
std::string ReadSampledFace(vtkDataObject* block, int f, const ctk::SplineOptions& options,
  bool fallbacks, SampledFace& face);
} // namespace ctcad

#endif
