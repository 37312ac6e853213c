// SPDX-License-Identifier: GPL-3.0-or-later
// Input checks shared by the module's filters (private header). Each returns an empty string on
// success or a message naming the problem and the offending array, point or cell, for
// vtkErrorMacro.
#ifndef CTSplinesInput_h
#define CTSplinesInput_h

#include "MeshTopology.h" // for ctk::Id

#include "vtkPoints.h"
#include "vtkType.h" // for vtkIdType

#include <string>
#include <vector>

class vtkAbstractArray;
class vtkDataArray;
class vtkDataSetAttributes;
class vtkPoints;
class vtkPolyData;
class vtkUnstructuredGrid;

namespace ctsplines
{
/// Checks that `array` exists and has one tuple per element (`tuples` of them). `what` names the
/// array's role in messages ("point data array 'dFdu'"); `element` is "point" or "cell".
/// Every array a filter reads goes through this (or CopyArray/CopyIdArray, which call it).
std::string CheckTuples(
  vtkAbstractArray* array, const std::string& what, vtkIdType tuples, const char* element);

/// CheckTuples and the component count.
std::string CheckShape(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element);

/// The value checks of CopyArray on an array of the right shape, copying into out.
std::string ReadValues(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element, double* out, int nanGroup);

/// Copies `array` (any numeric type) into row-major doubles after checking that it exists, has
/// `tuples` tuples of `components` components and only finite values of magnitude below
/// ctk::MaxInputMagnitude (far from overflow in the constructions' products). With nanGroup > 0, NaN marks "no value" for whole aligned groups of nanGroup
/// components (a partly NaN group is an error).
/// (The copy is written without zeroing first when `out` is a ctk::OverwriteVector.)
template <typename Allocator>
std::string CopyArray(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element, std::vector<double, Allocator>& out, int nanGroup = 0)
{
  std::string error = CheckShape(array, what, components, tuples, element);
  if (error.empty())
  {
    ctk::ResizeForOverwrite(out, static_cast<size_t>(tuples) * components);
    error = ReadValues(array, what, components, tuples, element, out.data(), nanGroup);
  }
  return error;
}

/// CheckShape, without a copy when `array` stores row-major doubles (vtkDoubleArray): values
/// then points at its storage, which the caller reads in place while the array lives and checks
/// where it reads it (the mid-edge gradients: ctk::UnusableEdgeGradients); otherwise at `copy`,
/// filled and checked as by CopyArray. nullptr with an error.
std::string ShareOrCopyArray(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element, std::vector<double>& copy, const double*& values);

/// Copies a one-component id array (MacroTriangleId, GlobalIds, ...) after checking its size and
/// that every value is an integer in [0, limit) (limit < 0: any non-negative integer).
std::string CopyIdArray(vtkDataArray* array, const std::string& what, vtkIdType tuples,
  const char* element, vtkIdType limit, std::vector<vtkIdType>& out);

/// Finds a point/cell data array by name; empty name or missing array gives nullptr.
vtkDataArray* FindArray(vtkDataSetAttributes* attributes, const std::string& name);

/// Copies the points of a data set (checking finiteness) into row-major doubles.
template <typename Allocator>
std::string CopyPoints(vtkPoints* points, std::vector<double, Allocator>& out)
{
  if (!points)
  {
    return "the input has no points";
  }
  return CopyArray(
    points->GetData(), "the point coordinates", 3, points->GetNumberOfPoints(), "point", out);
}

/// Extracts the triangles of a poly data as #T by 3 point ids. Fails on vertices, lines,
/// strips or polygons that are not triangles, naming the first offending cell id.
std::string ExtractTriangles(vtkPolyData* input, ctk::OverwriteVector<ctk::Id>& triangles);
std::string ExtractTriangles(vtkPolyData* input, std::vector<ctk::Id>& triangles);
/// The same for an unstructured grid of VTK_TRIANGLE cells (as redistribution filters output).
std::string ExtractTriangles(vtkUnstructuredGrid* input, ctk::OverwriteVector<ctk::Id>& triangles);

} // namespace ctsplines

#endif
