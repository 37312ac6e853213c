// SPDX-License-Identifier: GPL-3.0-or-later
// Input checks shared by the module's filters (private header). Each returns an empty string on
// success or a message naming the problem and the offending array, point or cell, for
// vtkErrorMacro.
#ifndef CTSplinesInput_h
#define CTSplinesInput_h

#include "MeshTopology.h" // for ctk::Id

#include <string>
#include <vector>

class vtkDataArray;
class vtkDataSetAttributes;
class vtkPoints;
class vtkPolyData;
class vtkUnstructuredGrid;

namespace ctsplines
{
/// Copies `array` (any numeric type) into row-major doubles after checking that it exists, has
/// `components` components and only finite values. `what` names the array's role in messages
/// ("point data array 'dFdu'"); `element` is "point" or "cell". With nanGroup > 0, NaN marks
/// "no value" for whole aligned groups of nanGroup components (a partly NaN group is an error).
std::string CopyArray(vtkDataArray* array, const std::string& what, int components,
  const char* element, std::vector<double>& out, int nanGroup = 0);

/// Finds a point/cell data array by name; empty name or missing array gives nullptr.
vtkDataArray* FindArray(vtkDataSetAttributes* attributes, const std::string& name);

/// Copies the points of a data set (checking finiteness) into row-major doubles.
std::string CopyPoints(vtkPoints* points, std::vector<double>& out);

/// Extracts the triangles of a poly data as #T by 3 point ids. Fails on vertices, lines,
/// strips or polygons that are not triangles, naming the first offending cell id.
std::string ExtractTriangles(vtkPolyData* input, std::vector<ctk::Id>& triangles);
/// The same for an unstructured grid of VTK_TRIANGLE cells (as redistribution filters output).
std::string ExtractTriangles(vtkUnstructuredGrid* input, std::vector<ctk::Id>& triangles);

} // namespace ctsplines

#endif
