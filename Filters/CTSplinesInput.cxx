// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesInput.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <cmath>
#include <sstream>

namespace ctsplines
{
std::string CopyArray(vtkDataArray* array, const std::string& what, int components,
  const char* element, std::vector<double>& out)
{
  std::ostringstream os;
  if (!array)
  {
    os << what << " is missing";
    return os.str();
  }
  if (array->GetNumberOfComponents() != components)
  {
    os << what << " has " << array->GetNumberOfComponents() << " components, expected "
       << components;
    return os.str();
  }
  const vtkIdType n = array->GetNumberOfTuples();
  out.resize(static_cast<size_t>(n) * components);
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int c = 0; c < components; ++c)
    {
      const double x = array->GetComponent(i, c);
      if (!std::isfinite(x))
      {
        os << what << " has a non-finite value (" << x << ") at " << element << " " << i;
        return os.str();
      }
      out[static_cast<size_t>(i) * components + c] = x;
    }
  }
  return {};
}

vtkDataArray* FindArray(vtkDataSetAttributes* attributes, const std::string& name)
{
  return name.empty() ? nullptr : attributes->GetArray(name.c_str());
}

std::string CopyPoints(vtkPoints* points, std::vector<double>& out)
{
  if (!points)
  {
    return "the input has no points";
  }
  return CopyArray(points->GetData(), "the point coordinates", 3, "point", out);
}

std::string ExtractTriangles(vtkPolyData* input, std::vector<ctk::Id>& triangles)
{
  std::ostringstream os;
  const vtkIdType nVerts = input->GetNumberOfVerts(), nLines = input->GetNumberOfLines();
  const vtkIdType nPolys = input->GetNumberOfPolys(), nStrips = input->GetNumberOfStrips();
  // vtkPolyData numbers cells as vertices, lines, polygons, strips.
  if (nVerts > 0)
  {
    os << "cell 0 is a vertex cell; only triangles are accepted";
    return os.str();
  }
  if (nLines > 0)
  {
    os << "cell 0 is a line cell; only triangles are accepted";
    return os.str();
  }
  if (nStrips > 0)
  {
    os << "cell " << nPolys << " is a triangle strip; only triangles are accepted (apply "
       << "vtkTriangleFilter first)";
    return os.str();
  }
  triangles.resize(static_cast<size_t>(nPolys) * 3);
  auto it = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  vtkIdType cellId = 0;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
  {
    vtkIdType npts;
    const vtkIdType* pts;
    it->GetCurrentCell(npts, pts);
    if (npts != 3)
    {
      os << "cell " << cellId << " is a polygon with " << npts
         << " points; only triangles are accepted (apply vtkTriangleFilter first)";
      return os.str();
    }
    for (int l = 0; l < 3; ++l)
    {
      triangles[3 * cellId + l] = pts[l];
    }
  }
  return {};
}

} // namespace ctsplines
