// SPDX-License-Identifier: GPL-3.0-or-later
// Bit-for-bit comparison of filter outputs, shared by the unit tests and the filters fuzzer:
// ReuseOutputArrays must give the bits a new filter gives.
#ifndef CTSplines_OutputBits_h
#define CTSplines_OutputBits_h

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <cstring>
#include <string>

namespace ctsplines_test
{
/// How two arrays differ (type, shape or values compared as bytes: NaN payloads and the sign of
/// zero too), or empty when they hold the same bits; two null arrays are the same.
inline std::string ArrayDifference(vtkDataArray* a, vtkDataArray* b)
{
  if (!a || !b)
  {
    return a == b ? "" : "one array is missing";
  }
  if (a->GetDataType() != b->GetDataType())
  {
    return "types differ";
  }
  if (a->GetNumberOfComponents() != b->GetNumberOfComponents() ||
    a->GetNumberOfTuples() != b->GetNumberOfTuples())
  {
    return "shapes differ";
  }
  const std::size_t bytes =
    static_cast<std::size_t>(a->GetNumberOfValues()) * static_cast<std::size_t>(a->GetDataTypeSize());
  if (bytes > 0 && std::memcmp(a->GetVoidPointer(0), b->GetVoidPointer(0), bytes) != 0)
  {
    return "values differ";
  }
  return "";
}

/// The same for a cell array's offsets and connectivity.
inline std::string CellsDifference(vtkCellArray* a, vtkCellArray* b)
{
  if (!a || !b)
  {
    return (a ? a->GetNumberOfCells() : 0) == (b ? b->GetNumberOfCells() : 0)
      ? ""
      : "one cell array is missing";
  }
  const std::string offsets = ArrayDifference(a->GetOffsetsArray(), b->GetOffsetsArray());
  return offsets.empty() ? ArrayDifference(a->GetConnectivityArray(), b->GetConnectivityArray())
                         : "offsets: " + offsets;
}

/// The same for every array of point or cell data, matched by name.
inline std::string DataDifference(vtkDataSetAttributes* a, vtkDataSetAttributes* b)
{
  if (a->GetNumberOfArrays() != b->GetNumberOfArrays())
  {
    return "numbers of arrays differ";
  }
  for (int i = 0; i < a->GetNumberOfArrays(); ++i)
  {
    const char* name = a->GetArrayName(i);
    const std::string d = ArrayDifference(a->GetArray(i), name ? b->GetArray(name) : nullptr);
    if (!d.empty())
    {
      return std::string(name ? name : "(unnamed)") + ": " + d;
    }
  }
  return "";
}

/// The same for two point sets: points, cells (of an unstructured grid or polydata), point data
/// and cell data. Other data objects are not compared (empty).
inline std::string OutputDifference(vtkDataObject* a, vtkDataObject* b)
{
  auto* pa = vtkPointSet::SafeDownCast(a);
  auto* pb = vtkPointSet::SafeDownCast(b);
  if (!pa || !pb)
  {
    return "";
  }
  if (std::strcmp(pa->GetClassName(), pb->GetClassName()) != 0)
  {
    return "classes differ";
  }
  auto points = [](vtkPointSet* s) { return s->GetPoints() ? s->GetPoints()->GetData() : nullptr; };
  std::string d = ArrayDifference(points(pa), points(pb));
  if (!d.empty())
  {
    return "points: " + d;
  }
  if (auto* ua = vtkUnstructuredGrid::SafeDownCast(a))
  {
    auto* ub = vtkUnstructuredGrid::SafeDownCast(b);
    d = CellsDifference(ua->GetCells(), ub->GetCells());
    d = d.empty() ? ArrayDifference(ua->GetCellTypesArray(), ub->GetCellTypesArray()) : d;
  }
  else if (auto* qa = vtkPolyData::SafeDownCast(a))
  {
    auto* qb = vtkPolyData::SafeDownCast(b);
    for (auto cells : { &vtkPolyData::GetVerts, &vtkPolyData::GetLines, &vtkPolyData::GetPolys,
           &vtkPolyData::GetStrips })
    {
      d = d.empty() ? CellsDifference((qa->*cells)(), (qb->*cells)()) : d;
    }
  }
  if (!d.empty())
  {
    return "cells: " + d;
  }
  d = DataDifference(pa->GetPointData(), pb->GetPointData());
  if (!d.empty())
  {
    return "point data " + d;
  }
  d = DataDifference(pa->GetCellData(), pb->GetCellData());
  return d.empty() ? "" : "cell data " + d;
}
} // namespace ctsplines_test

#endif
