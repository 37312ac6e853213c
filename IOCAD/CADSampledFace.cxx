// SPDX-License-Identifier: GPL-3.0-or-later
#include "CADSampledFace.h"

#include "CADArrayNames.h"
#include "CTSplinesInput.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <cmath>
#include <sstream>

namespace ctcad
{
namespace
{
/// The sampler's arrays must all be there (the spline reads some, the stages the others).
std::string CheckArraysPresent(vtkPolyData* block)
{
  for (const char* name : { names::GlobalNodeId, names::UV, names::Du, names::Dv,
         names::StitchDu, names::StitchDv })
  {
    if (!block->GetPointData()->GetArray(name))
    {
      return std::string("has no point data array '") + name +
        "' (the input must come from vtkCADFaceSampler)";
    }
  }
  for (const char* name :
    { names::EdgeCurvePoints, names::StitchEdgeGradients, names::BRepEdgeId })
  {
    if (!block->GetCellData()->GetArray(name))
    {
      return std::string("has no cell data array '") + name +
        "' (the input must come from vtkCADFaceSampler)";
    }
  }
  return std::string();
}

/// The integer ids of an array of `components` per tuple (GlobalNodeId, BRepEdgeId).
std::string CopyIds(vtkDataArray* a, const char* name, int components, vtkIdType tuples,
  const char* element, std::vector<ctk::Id>& out)
{
  const std::string what = std::string(element) + " data array '" + name + "'";
  if (!vtkIdTypeArray::SafeDownCast(a))
  {
    return what + " is not a vtkIdTypeArray";
  }
  if (a->GetNumberOfComponents() != components || a->GetNumberOfTuples() != tuples)
  {
    return what + " has " + std::to_string(a->GetNumberOfTuples()) + " tuples of " +
      std::to_string(a->GetNumberOfComponents()) + " components, not " + std::to_string(tuples) +
      " of " + std::to_string(components);
  }
  const vtkIdType* values = vtkIdTypeArray::SafeDownCast(a)->GetPointer(0);
  out.assign(values, values + components * tuples);
  return std::string();
}

/// The per-point and per-cell arrays, copied and checked.
std::string ReadArrays(vtkPolyData* block, const ctk::SplineOptions& options, SampledFace& face)
{
  using ctsplines::CopyArray;
  vtkPointData* pd = block->GetPointData();
  vtkCellData* cd = block->GetCellData();
  const vtkIdType nV = block->GetNumberOfPoints(), nT = block->GetNumberOfCells();
  ctk::SplineInput& in = face.Input;
  auto point = [&](const char* name) { return std::string("point data array '") + name + "'"; };
  auto cell = [&](const char* name) { return std::string("cell data array '") + name + "'"; };
  std::string error = CopyIds(pd->GetArray(names::GlobalNodeId), names::GlobalNodeId, 1, nV,
    "point", face.GlobalNode);
  auto pointArray = [&](const char* name, int components, auto& values) {
    if (error.empty())
    {
      error = CopyArray(pd->GetArray(name), point(name), components, nV, "point", values);
    }
  };
  pointArray(names::UV, 2, in.UV);
  pointArray(names::StitchDu, 3, in.Fu);
  pointArray(names::StitchDv, 3, in.Fv);
  pointArray(names::Du, 3, face.SurfaceFu);
  pointArray(names::Dv, 3, face.SurfaceFv);
  if (error.empty())
  {
    error = CopyIds(cd->GetArray(names::BRepEdgeId), names::BRepEdgeId, 3, nT, "cell",
      face.BRepEdge);
  }
  if (error.empty())
  {
    error = CopyArray(cd->GetArray(names::EdgeCurvePoints), cell(names::EdgeCurvePoints), 18, nT,
      "cell", in.BoundaryCurvePoints, 6);
  }
  if (error.empty() && ctk::UsesEdgeGradients(options))
  {
    error = CopyArray(cd->GetArray(names::StitchEdgeGradients),
      cell(names::StitchEdgeGradients), 18, nT, "cell", in.EdgeGradients);
  }
  vtkDataArray* tangent = cd->GetArray(names::TangentInterface);
  if (error.empty() && tangent)
  {
    std::vector<double> values;
    error = CopyArray(tangent, cell(names::TangentInterface), 3, nT, "cell", values);
    face.Tangent.assign(values.begin(), values.end());
  }
  return error;
}

/// The block's FallbackConstruction, if any, into face: a construction that can be stitched,
/// or -1 for none.
std::string ReadFallback(vtkPolyData* block, SampledFace& face)
{
  vtkDataArray* a = block->GetFieldData()->GetArray(names::FallbackConstruction);
  if (!a)
  {
    return std::string();
  }
  const bool one = a->GetNumberOfTuples() == 1 && a->GetNumberOfComponents() == 1;
  const double value = one ? a->GetTuple1(0) : std::nan("");
  const int c = value == std::floor(value) && std::abs(value) <= ctk::NumberOfConstructions
    ? static_cast<int>(value)
    : -2;
  if (c != -1 &&
    (!ctk::IsConstruction(c) || !ctk::CanBeStitched(static_cast<ctk::Construction>(c))))
  {
    std::ostringstream message;
    message << "field data '" << names::FallbackConstruction << "' ("
            << (one ? "value " + std::to_string(value) : "not one value")
            << ") names no construction that can be stitched";
    return message.str();
  }
  face.FallbackConstruction = c;
  return std::string();
}
} // namespace

std::string ReadSampledFace(vtkDataObject* object, int f, const ctk::SplineOptions& options,
  bool fallbacks, SampledFace& face)
{
  const std::string where = "block " + std::to_string(f) + " ";
  vtkPolyData* block = vtkPolyData::SafeDownCast(object);
  if (!block)
  {
    return where + "is not a vtkPolyData";
  }
  if (block->GetNumberOfPoints() == 0 || block->GetNumberOfCells() == 0)
  {
    return where + "has " + std::to_string(block->GetNumberOfPoints()) + " points and " +
      std::to_string(block->GetNumberOfCells()) + " cells: no face mesh";
  }
  std::string error = CheckArraysPresent(block);
  if (error.empty())
  {
    error = ctsplines::ExtractTriangles(block, face.Input.Triangles);
  }
  if (error.empty())
  {
    error = ctsplines::CopyPoints(block->GetPoints(), face.Input.F);
  }
  if (error.empty() && fallbacks)
  {
    error = ReadFallback(block, face);
  }
  if (error.empty())
  {
    error = ReadArrays(block, FaceOptions(face, options), face);
  }
  return error.empty() ? error : where + error;
}

} // namespace ctcad
