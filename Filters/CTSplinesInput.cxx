// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesInput.h"

#include "LargeArrays.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ctsplines
{
std::string CopyArray(vtkDataArray* array, const std::string& what, int components,
  const char* element, std::vector<double>& out, int nanGroup)
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
  ctk::ResizeForOverwrite(out, static_cast<size_t>(n) * components);
  // Values in (tuple, component) order, so the first non-finite one is reported.
  auto copy = [&](auto get) {
    const size_t count = static_cast<size_t>(n) * components;
    for (size_t k = 0; k < count; ++k)
    {
      const double x = get(k);
      if (!std::isfinite(x) && !(nanGroup > 0 && std::isnan(x)))
      {
        os << what << " has a non-finite value (" << x << ") at " << element << " "
           << static_cast<vtkIdType>(k / components);
        return false;
      }
      out[k] = x;
    }
    return true;
  };
  bool ok;
  // Raw pointers for the usual storage; GetComponent (virtual, per value) otherwise.
  if (auto* d = vtkDoubleArray::FastDownCast(array))
  {
    const double* src = d->GetPointer(0);
    ok = copy([src](size_t k) { return src[k]; });
  }
  else if (auto* f = vtkFloatArray::FastDownCast(array))
  {
    const float* src = f->GetPointer(0);
    ok = copy([src](size_t k) { return static_cast<double>(src[k]); });
  }
  else
  {
    ok = copy([array, components](size_t k) {
      return array->GetComponent(
        static_cast<vtkIdType>(k / components), static_cast<int>(k % components));
    });
  }
  if (ok && nanGroup > 0)
  {
    for (size_t g = 0; g < out.size(); g += nanGroup)
    {
      const auto nans = std::count_if(
        out.begin() + g, out.begin() + g + nanGroup, [](double x) { return std::isnan(x); });
      if (nans != 0 && nans != nanGroup)
      {
        os << what << " has a partly NaN group (components " << g % components << " to "
           << g % components + nanGroup - 1 << ") at " << element << " "
           << static_cast<vtkIdType>(g / components) << ": give all or none";
        return os.str();
      }
    }
  }
  return ok ? std::string() : os.str();
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

namespace
{
// Triangles straight from a cell array's offsets and connectivity (32- or 64-bit storage).
std::string TrianglesOfCellArray(
  vtkCellArray* cells, const char* what, std::vector<ctk::Id>& triangles)
{
  std::ostringstream os;
  const vtkIdType n = cells->GetNumberOfCells();
  ctk::ResizeForOverwrite(triangles, static_cast<size_t>(n) * 3);
  auto extract = [&](const auto* offsets, const auto* connectivity) {
    for (vtkIdType cellId = 0; cellId < n; ++cellId)
    {
      const vtkIdType begin = static_cast<vtkIdType>(offsets[cellId]);
      const vtkIdType npts = static_cast<vtkIdType>(offsets[cellId + 1]) - begin;
      if (npts != 3)
      {
        os << "cell " << cellId << " is " << what << " with " << npts
           << " points; only triangles are accepted (apply vtkTriangleFilter first)";
        return false;
      }
      for (int l = 0; l < 3; ++l)
      {
        triangles[3 * cellId + l] = static_cast<ctk::Id>(connectivity[begin + l]);
      }
    }
    return true;
  };
  const bool ok = cells->IsStorage64Bit()
    ? extract(cells->GetOffsetsArray64()->GetPointer(0), cells->GetConnectivityArray64()->GetPointer(0))
    : extract(cells->GetOffsetsArray32()->GetPointer(0), cells->GetConnectivityArray32()->GetPointer(0));
  return ok ? std::string() : os.str();
}
} // namespace

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
  return TrianglesOfCellArray(input->GetPolys(), "a polygon", triangles);
}

std::string ExtractTriangles(vtkUnstructuredGrid* input, std::vector<ctk::Id>& triangles)
{
  const vtkIdType n = input->GetNumberOfCells();
  const unsigned char* types = input->GetCellTypesArray()->GetPointer(0);
  for (vtkIdType c = 0; c < n; ++c)
  {
    if (types[c] != VTK_TRIANGLE)
    {
      std::ostringstream os;
      os << "cell " << c << " is a " << vtkCellTypes::GetClassNameFromTypeId(types[c])
         << "; only triangles are accepted";
      return os.str();
    }
  }
  return TrianglesOfCellArray(input->GetCells(), "a cell", triangles);
}

} // namespace ctsplines
