// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesInput.h"

#include "CTSplinesSMP.h"
#include "LargeArrays.h"
#include "SplineDataValidation.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

namespace ctsplines
{
std::string CheckTuples(
  vtkAbstractArray* array, const std::string& what, vtkIdType tuples, const char* element)
{
  std::ostringstream os;
  if (!array)
  {
    os << what << " is missing";
  }
  else if (array->GetNumberOfTuples() != tuples)
  {
    os << what << " has " << array->GetNumberOfTuples() << " tuples for " << tuples << " "
       << element << "s";
  }
  return os.str();
}

std::string CheckShape(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element)
{
  std::string error = CheckTuples(array, what, tuples, element);
  if (error.empty() && array->GetNumberOfComponents() != components)
  {
    error = what + " has " + std::to_string(array->GetNumberOfComponents()) +
      " components, expected " + std::to_string(components);
  }
  return error;
}

std::string ReadValues(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element, double* out, int nanGroup)
{
  std::ostringstream os;
  const size_t count = static_cast<size_t>(tuples) * components;
  // One pass without an early exit, flagging a bad value by a select (which compilers
  // vectorize, unlike a branch or an integer reduction), in chunks on the module's pool when
  // values are read through a pointer (GetComponent is not safe to call concurrently on every
  // array); only a bad value or a NaN calls for the second pass, which reports the first bad
  // value in (tuple, component) order.
  auto anyBad = [out](auto get, size_t begin, size_t end) {
    double bad = 0;
    for (size_t k = begin; k < end; ++k)
    {
      out[k] = get(k);
      bad = ctk::IsUsableValue(out[k]) ? bad : 1.0;
    }
    return bad != 0;
  };
  auto read = [&](auto get, bool concurrent) {
    std::atomic<bool> badChunk{ false };
    if (concurrent)
    {
      ParallelFor(0, static_cast<vtkIdType>(count), GrainForCopies, [&](vtkIdType b, vtkIdType e) {
        if (anyBad(get, static_cast<size_t>(b), static_cast<size_t>(e)))
        {
          badChunk.store(true, std::memory_order_relaxed);
        }
      });
    }
    if (concurrent ? !badChunk.load() : !anyBad(get, 0, count))
    {
      return true;
    }
    for (size_t k = 0; k < count; ++k)
    {
      const double x = get(k);
      if (!ctk::IsUsableValue(x) && !(nanGroup > 0 && std::isnan(x)))
      {
        os << what << " has a " << (std::isfinite(x) ? "value too large" : "non-finite value")
           << " (" << x << ") at " << element << " " << static_cast<vtkIdType>(k / components);
        if (std::isfinite(x))
        {
          os << "; magnitudes must stay below " << ctk::MaxInputMagnitude << " (rescale the data)";
        }
        return false;
      }
    }
    // Only NaNs, which nanGroup allows for whole groups (so nanGroup > 0 here: without groups
    // the loop above returned at the first bad value).
    for (size_t g = 0; nanGroup > 0 && g < count; g += nanGroup)
    {
      int nans = 0;
      for (int i = 0; i < nanGroup; ++i)
      {
        nans += std::isnan(get(g + i)) ? 1 : 0;
      }
      if (nans != 0 && nans != nanGroup)
      {
        os << what << " has a partly NaN group (components " << g % components << " to "
           << g % components + nanGroup - 1 << ") at " << element << " "
           << static_cast<vtkIdType>(g / components) << ": give all or none";
        return false;
      }
    }
    return true;
  };
  bool ok;
  // Raw pointers for the usual storage; GetComponent (virtual, per value) otherwise.
  if (auto* d = vtkDoubleArray::FastDownCast(array))
  {
    const double* src = d->GetPointer(0);
    ok = read([src](size_t k) { return src[k]; }, true);
  }
  else if (auto* f = vtkFloatArray::FastDownCast(array))
  {
    const float* src = f->GetPointer(0);
    ok = read([src](size_t k) { return static_cast<double>(src[k]); }, true);
  }
  else
  {
    ok = read(
      [array, components](size_t k) {
        return array->GetComponent(
          static_cast<vtkIdType>(k / components), static_cast<int>(k % components));
      },
      false);
  }
  return ok ? std::string() : os.str();
}

std::string ShareOrCopyArray(vtkDataArray* array, const std::string& what, int components,
  vtkIdType tuples, const char* element, std::vector<double>& copy, const double*& values)
{
  values = nullptr;
  auto* d = vtkDoubleArray::FastDownCast(array);
  if (!d)
  {
    std::string error = CopyArray(array, what, components, tuples, element, copy);
    values = error.empty() ? copy.data() : nullptr;
    return error;
  }
  // No pass over the values: on a large mesh it would take a sixth of MGo's time.
  const std::string error = CheckShape(array, what, components, tuples, element);
  values = error.empty() ? d->GetPointer(0) : nullptr;
  return error;
}

std::string CopyIdArray(vtkDataArray* array, const std::string& what, vtkIdType tuples,
  const char* element, vtkIdType limit, std::vector<vtkIdType>& out)
{
  std::string error = CheckTuples(array, what, tuples, element);
  if (error.empty() && array->GetNumberOfComponents() != 1)
  {
    error = what + " has " + std::to_string(array->GetNumberOfComponents()) +
      " components, expected 1";
  }
  if (!error.empty())
  {
    return error;
  }
  ctk::ResizeForOverwrite(out, static_cast<size_t>(tuples));
  const double top = limit < 0 ? 9e15 : static_cast<double>(limit); // exact in a double
  vtkIdTypeArray* ids = vtkIdTypeArray::FastDownCast(array);
  for (vtkIdType k = 0; k < tuples; ++k)
  {
    const double x = ids ? static_cast<double>(ids->GetValue(k)) : array->GetComponent(k, 0);
    if (!(x >= 0 && x < top) || x != std::floor(x))
    {
      std::ostringstream os;
      os << what << " has the value " << x << " at " << element << " " << k
         << ", expected an integer in [0, " << (limit < 0 ? top : static_cast<double>(limit)) << ")";
      return os.str();
    }
    out[k] = static_cast<vtkIdType>(x);
  }
  return {};
}

vtkDataArray* FindArray(vtkDataSetAttributes* attributes, const std::string& name)
{
  return name.empty() ? nullptr : attributes->GetArray(name.c_str());
}

namespace
{
// Triangles straight from a cell array's offsets and connectivity (32- or 64-bit storage), in
// chunks on the module's pool; the error names the lowest bad cell on any thread count.
template <typename IdVector>
std::string TrianglesOfCellArray(vtkCellArray* cells, const char* what, IdVector& triangles)
{
  const vtkIdType n = cells->GetNumberOfCells();
  ctk::ResizeForOverwrite(triangles, static_cast<size_t>(n) * 3);
  const vtkIdType connectivitySize = cells->GetNumberOfConnectivityIds();
  std::ostringstream os;
  auto extract = [&](const auto* offsets, const auto* connectivity) {
    auto size = [offsets](vtkIdType c) {
      return static_cast<vtkIdType>(offsets[c + 1]) - static_cast<vtkIdType>(offsets[c]);
    };
    auto outside = [&](vtkIdType c) {
      return offsets[c] < 0 || static_cast<vtkIdType>(offsets[c + 1]) > connectivitySize;
    };
    ctk::LowestId bad;
    ParallelFor(0, n, GrainForCopies, [&](vtkIdType begin, vtkIdType end) {
      // Usually every cell is a triangle: one vectorised check of the chunk, one copy.
      bool triangles3 = true;
      for (vtkIdType c = begin; c < end; ++c)
      {
        triangles3 &= size(c) == 3;
      }
      if (triangles3 && offsets[begin] >= 0 &&
        static_cast<vtkIdType>(offsets[end]) <= connectivitySize)
      {
        std::copy(connectivity + offsets[begin], connectivity + offsets[end], &triangles[3 * begin]);
        return;
      }
      for (vtkIdType c = begin; c < end; ++c)
      {
        if (outside(c) || size(c) != 3)
        {
          bad.Report(c);
          return; // later cells of the chunk cannot be lower
        }
        const vtkIdType first = static_cast<vtkIdType>(offsets[c]);
        for (int l = 0; l < 3; ++l)
        {
          triangles[3 * c + l] = static_cast<ctk::Id>(connectivity[first + l]);
        }
      }
    });
    const vtkIdType c = bad.Get();
    if (c >= 0 && outside(c))
    {
      os << "cell " << c << " has offsets outside the connectivity array (corrupt cell array)";
    }
    else if (c >= 0)
    {
      os << "cell " << c << " is " << what << " with " << size(c)
         << " points; only triangles are accepted (apply vtkTriangleFilter first)";
    }
    return c < 0;
  };
  const bool ok = cells->IsStorage64Bit()
    ? extract(cells->GetOffsetsArray64()->GetPointer(0), cells->GetConnectivityArray64()->GetPointer(0))
    : extract(cells->GetOffsetsArray32()->GetPointer(0), cells->GetConnectivityArray32()->GetPointer(0));
  return ok ? std::string() : os.str();
}
template <typename IdVector>
std::string TrianglesOfPolyData(vtkPolyData* input, IdVector& triangles)
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

} // namespace

std::string ExtractTriangles(vtkPolyData* input, std::vector<ctk::Id>& triangles)
{
  return TrianglesOfPolyData(input, triangles);
}

std::string ExtractTriangles(vtkPolyData* input, ctk::OverwriteVector<ctk::Id>& triangles)
{
  return TrianglesOfPolyData(input, triangles);
}

std::string ExtractTriangles(vtkUnstructuredGrid* input, ctk::OverwriteVector<ctk::Id>& triangles)
{
  const vtkIdType n = input->GetNumberOfCells();
  vtkUnsignedCharArray* typeArray = input->GetCellTypesArray();
  if (!typeArray || !input->GetCells() || typeArray->GetNumberOfTuples() != n ||
    input->GetCells()->GetNumberOfCells() != n)
  {
    return "the unstructured grid's cell types and cells disagree in number (corrupt grid)";
  }
  const unsigned char* types = typeArray->GetPointer(0);
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
