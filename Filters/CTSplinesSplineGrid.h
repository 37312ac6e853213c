// SPDX-License-Identifier: GPL-3.0-or-later
// A kernel spline as VTK cells (private header): vtkCloughTocherSplineFilter's output grid, also
// the per-face output of the CAD stitcher, which builds its faces' splines with the kernel.
#ifndef CTSplinesSplineGrid_h
#define CTSplinesSplineGrid_h

#include "CloughTocherSpline.h"
#include "SplineInput.h"

#include <functional>

class vtkUnstructuredGrid;

namespace ctsplines
{
/// Fills output with the spline built on in's triangles: its control points (moved out of
/// spline, which is left without points), their domain points as point data uvName, three
/// VTK_BEZIER_TRIANGLE cells per triangle (3 t + k: micro-triangle k of triangle t) with cell
/// data MacroTriangleId and MicroTriangleId. With keptTriangles (a distributed piece without its
/// ghost triangles), only those triangles' cells (3 i + k for the i-th) and the control points
/// they use, in their order, are written; MacroTriangleId keeps in's triangle ids. With
/// inputTriangles (in renumbered, ctk::LocalityRenumbering::Triangles), MacroTriangleId is
/// inputTriangles[t] for in's triangle t: the caller's input numbering. connectivityWritten,
/// when given, is called once the cells' connectivity is written, before the cell data is
/// allocated: the caller may free in's triangles and the topology there (peak memory).
void FillSplineGrid(ctk::CloughTocherSpline& spline, const ctk::MeshTopology& topology,
  const ctk::SplineInput& in, const char* uvName, vtkUnstructuredGrid* output,
  const std::vector<ctk::Id>* keptTriangles = nullptr,
  const std::vector<ctk::Id>* inputTriangles = nullptr,
  const std::function<void()>& connectivityWritten = {});
} // namespace ctsplines

#endif
