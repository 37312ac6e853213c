// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineParameterProbe.h"

#include "BezierTriangle.h"
#include "CTSplinesArrayRanges.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "CTSplinesRecycledArrays.h"
#include "CTSplinesSMP.h"
#include "LargeArrays.h"
#include "LocalityOrder.h"
#include "SplineDataValidation.h"
#include "ParameterLocator.h"

#include <Eigen/Geometry> // for cross

#include "vtkAlgorithmOutput.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkCharArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkCellArray.h"
#include "vtkWeakPointer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <sstream>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

vtkStandardNewMacro(vtkSplineParameterProbe);

vtkSplineParameterProbe::vtkSplineParameterProbe()
  : Recycled(new ctsplines::RecycledArrays)
{
  this->SetNumberOfInputPorts(2);
}

vtkSplineParameterProbe::~vtkSplineParameterProbe() = default;

void vtkSplineParameterProbe::SetReuseOutputArrays(bool reuse)
{
  if (this->Recycled->SetReuse(this->ReuseOutputArrays, reuse))
  {
    this->Modified();
  }
}

vtkTypeUInt64 vtkSplineParameterProbe::GetReusedOutputBytes() const
{
  return this->Recycled->GetReusedBytes();
}

void vtkSplineParameterProbe::ReleaseSpline()
{
  this->Cache.reset();
}

void vtkSplineParameterProbe::SetSourceConnection(vtkAlgorithmOutput* algOutput)
{
  this->SetInputConnection(1, algOutput);
}

void vtkSplineParameterProbe::SetSourceData(vtkDataObject* source)
{
  this->SetInputData(1, source);
}

vtkDataObject* vtkSplineParameterProbe::GetSource()
{
  if (this->GetNumberOfInputConnections(1) < 1)
  {
    return nullptr;
  }
  return this->GetExecutive()->GetInputData(1, 0);
}

int vtkSplineParameterProbe::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  if (port == 1)
  {
    // Optional for the pipeline so that a missing source gets a clear message from RequestData.
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkSplineParameterProbe::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  if (!input)
  {
    return 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataObject* output = vtkDataObject::GetData(outInfo);
  // Point sets keep their type (and structure); anything else becomes a cloud of points.
  const char* type = vtkPointSet::SafeDownCast(input) ? input->GetClassName() : "vtkPolyData";
  if (!output || std::strcmp(output->GetClassName(), type) != 0)
  {
    vtkSmartPointer<vtkDataObject> newOutput;
    if (vtkPointSet::SafeDownCast(input))
    {
      newOutput.TakeReference(input->NewInstance());
    }
    else
    {
      newOutput = vtkSmartPointer<vtkPolyData>::New();
    }
    outInfo->Set(vtkDataObject::DATA_OBJECT(), newOutput);
  }
  return 1;
}

int vtkSplineParameterProbe::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Every query point may fall in any cell: always ask for the whole spline.
  if (vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0))
  {
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
    if (sourceInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
        sourceInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
    }
  }
  // A structured input feeding a point cloud output has no extent request from downstream.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  return 1;
}

namespace
{
// Three doubles, copied element by element: std::copy_n of 3 stayed a call to memmove on the
// probe's per-query path (4 calls per query, about 7 % of a probe's time).
inline void Copy3(const double* from, double* to)
{
  to[0] = from[0];
  to[1] = from[1];
  to[2] = from[2];
}

static_assert(std::is_same<vtkIdType, vtkTypeInt64>::value ||
    std::is_same<vtkIdType, vtkTypeInt32>::value,
  "vtkIdType is one of the cell array storage types");

// VTK's point order of a Bézier triangle of every degree, and the degree of every point count.
struct BezierShapes
{
  std::array<std::vector<int>, ctk::MaxDegree + 1> Orders;
  std::array<signed char, ctk::MaxBezierPoints + 1> DegreeOfCount{};

  BezierShapes()
  {
    for (int n = 1; n <= ctk::MaxDegree; ++n)
    {
      this->Orders[n] = ctk::VtkBezierTriangleOrder(n);
      this->DegreeOfCount[ctk::BezierPointCount(n)] = static_cast<signed char>(n);
    }
  }
  /// The degree (1..MaxDegree) of a Bézier triangle of npts points, or 0 when none has as many.
  int Degree(vtkIdType npts) const
  {
    return npts >= 0 && npts <= ctk::MaxBezierPoints ? this->DegreeOfCount[npts] : 0;
  }
};
const BezierShapes& Shapes()
{
  static const BezierShapes shapes;
  return shapes;
}

// A valid spline's arrays, read where they are (the source's own arrays, or ReadSpline's checked
// copy): nothing is renumbered or gathered per cell beforehand, so a build touches no memory
// the size of the spline. The construction writes its splines in a locality order, which
// queries processed in the same order (LocalityOrder below) then read nearly in memory order.
template <typename OffsetT, typename IdT>
struct SplineArrays
{
  const OffsetT* Offsets; // NCells + 1, Offsets[0] == 0
  const IdT* Ids;
  const double* XYZ;         // 3 per point
  const double* Weights;     // 1 per point, or nullptr (polynomial)
  const double* UV;          // 2 per point
  const vtkIdType* MacroIds; // 1 per cell, or nullptr (the cell id)
  vtkIdType NPoints, NCells;

  vtkIdType Id(vtkIdType c, int a) const { return static_cast<vtkIdType>(this->Ids[this->Offsets[c] + a]); }
  vtkIdType Size(vtkIdType c) const
  {
    return static_cast<vtkIdType>(this->Offsets[c + 1] - this->Offsets[c]);
  }
  /// The parameter triangle of cell c: the (u, v) of its corner control points.
  void Corners(vtkIdType c, ctk::Vec2* A) const
  {
    const IdT* ids = this->Ids + this->Offsets[c];
    for (int a = 0; a < 3; ++a)
    {
      const double* uv = this->UV + 2 * static_cast<vtkIdType>(ids[a]);
      A[a] = ctk::Vec2(uv[0], uv[1]);
    }
  }
  /// Corners as the locator reads them: corners(c, A).
  auto CornersFunction() const
  {
    return [this](ctk::Id c, ctk::Vec2* A) { this->Corners(c, A); };
  }
  /// The net of cell c in canonical order (see ctsplines::GatherNet) and its degree; shapes:
  /// Shapes().
  const double* Net(
    vtkIdType c, const BezierShapes& shapes, int& degree, ctk::Vec3* P, double* w) const
  {
    degree = shapes.Degree(this->Size(c));
    return ctsplines::GatherNet(
      shapes.Orders[degree], this->Ids + this->Offsets[c], this->XYZ, this->Weights, P, w);
  }
  vtkIdType MacroId(vtkIdType c) const { return this->MacroIds ? this->MacroIds[c] : c; }

  // Prefetches of what Corners and Net read, for cells c .. c + n - 1 (see QueryBatch); beyond
  // the last cell, nothing.
  void PrefetchOffsets(vtkIdType c, vtkIdType n) const
  {
    const vtkIdType last = std::min(c + n, this->NCells);
    ctk::PrefetchRead(this->Offsets + c);
    ctk::PrefetchRead(this->Offsets + last);
  }
  void PrefetchIds(vtkIdType c, vtkIdType n) const
  {
    const vtkIdType last = std::min(c + n, this->NCells);
    for (; c < last; ++c)
    {
      ctk::PrefetchRead(this->Ids + this->Offsets[c]);
    }
  }
  void PrefetchCorners(vtkIdType c, vtkIdType n) const
  {
    const vtkIdType last = std::min(c + n, this->NCells);
    for (; c < last; ++c)
    {
      const IdT* ids = this->Ids + this->Offsets[c];
      for (int a = 0; a < 3; ++a)
      {
        ctk::PrefetchRead(this->UV + 2 * static_cast<vtkIdType>(ids[a]));
      }
    }
  }
  void PrefetchNet(vtkIdType c) const
  {
    if (this->MacroIds)
    {
      ctk::PrefetchRead(this->MacroIds + c);
    }
    const IdT* ids = this->Ids + this->Offsets[c];
    const vtkIdType size = this->Size(c);
    for (vtkIdType a = 0; a < size; ++a)
    {
      ctk::PrefetchRead(this->XYZ + 3 * static_cast<vtkIdType>(ids[a]));
      if (this->Weights)
      {
        ctk::PrefetchRead(this->Weights + ids[a]);
      }
    }
  }
};

// Whether the cells come in the spline filter's layout, macro-triangle by macro-triangle: cells
// 3 i, 3 i + 1, 3 i + 2 (and no others) share a macro-triangle id. The locator then lists
// macro-triangles, whose fat boxes cover fewer buckets than their three thin micro-triangles':
// on 3e6 cells 13.9e6 bucket entries instead of 25.7e6 when measured (session 16), a third of
// the ranges to keep (results are the same in any layout; this only decides what is cheaper).
// Vectorised: no early exit.
bool MacroTriples(const vtkIdType* macroIds, vtkIdType nCells)
{
  if (!macroIds || nCells % 3 != 0)
  {
    return false;
  }
  vtkIdType differ = 0;
  for (vtkIdType c = 0; c < nCells; c += 3)
  {
    const vtkIdType m = macroIds[c];
    differ |= (m ^ macroIds[c + 1]) | (m ^ macroIds[c + 2]);
  }
  if (differ != 0)
  {
    return false;
  }
  vtkIdType same = 0;
  for (vtkIdType c = 3; c < nCells; c += 3)
  {
    same |= macroIds[c] == macroIds[c - 3];
  }
  return same == 0;
}

// The spline the queries read and its locator, a grid of cell ids over the parameter
// triangles: the arrays are the source's own (held here) or a copy (Copy*).
struct ProbeSpline
{
  std::variant<SplineArrays<vtkTypeInt64, vtkTypeInt64>, SplineArrays<vtkTypeInt32, vtkTypeInt32>>
    Arrays;
  std::vector<vtkSmartPointer<vtkAbstractArray>> Held;
  ctsplines::BezierCells Copy;
  std::vector<double> CopyUV;
  std::vector<vtkIdType> CopyMacroIds;
  ctk::TriangleBucketGrid Grid;

  /// Reads the valid spline `arrays`, whose parameter triangles span [lo, hi]: builds the grid
  /// over them, over macro-triangles (cells 3 i .. 3 i + 2) when the cells are in the spline
  /// filter's layout (MacroTriples).
  template <typename OffsetT, typename IdT>
  std::string Adopt(const SplineArrays<OffsetT, IdT>& arrays, const ctk::Vec2& lo, const ctk::Vec2& hi)
  {
    this->Arrays = arrays;
    const auto corners = arrays.CornersFunction();
    const ctk::Id group = MacroTriples(arrays.MacroIds, arrays.NCells) ? 3 : 1;
    if (!(arrays.NCells > 0 ? this->Grid.Build(arrays.NCells, corners, lo, hi, group)
                            : this->Grid.Build(0, corners)))
    {
      return "the source spline has too many cells for the probe's locator (at most 2^32 - 1 "
             "cells and bucket entries)";
    }
    return {};
  }
};

// The pass over the cells of AdoptInPlace: cell types and sizes, point ids, macro-triangle ids;
// the box [lo, hi] of the parameter triangles, their smallest area, and the span of every
// group of `group` cells on `grid` (spans[g]). Block by block, so that the ids are checked
// while the block's are in cache, as the corners are read (a pass of its own read all 120 MB
// of ids of 1e6 triangles once more). False at the first bad cell.
template <typename OffsetT, typename IdT>
bool CheckCells(const unsigned char* types, const SplineArrays<OffsetT, IdT>& in, vtkIdType nIds,
  vtkIdType group, const ctk::TriangleBucketGrid& grid,
  ctk::TriangleBucketGrid::Spans& spans, ctk::Vec2& lo, ctk::Vec2& hi,
  double& minArea)
{
  constexpr vtkIdType BlockGroups = 512; // 1536 cubic cells: 60 KB of ids
  const BezierShapes& shapes = Shapes(); // a call per cell was 1 % of a first call
  lo = ctk::Vec2::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  minArea = std::numeric_limits<double>::infinity();
  for (vtkIdType b0 = 0; b0 < in.NCells; b0 += BlockGroups * group)
  {
    const vtkIdType b1 = std::min(b0 + BlockGroups * group, in.NCells);
    for (vtkIdType c = b0; c < b1; ++c)
    {
      if (types[c] != VTK_BEZIER_TRIANGLE || shapes.Degree(in.Size(c)) == 0 ||
        (in.MacroIds && !(in.MacroIds[c] >= 0 && in.MacroIds[c] < vtkIdType(9e15))))
      {
        return false; // 9e15: CopyIdArray's range
      }
    }
    // Offsets[0] is 0 and every size so far a Bezier triangle's: the block's ids start in
    // the array; they end in it when Offsets[b1] <= nIds.
    const vtkIdType first = static_cast<vtkIdType>(in.Offsets[b0]);
    const vtkIdType last = static_cast<vtkIdType>(in.Offsets[b1]);
    if (last > nIds || !ctk::AllIdsInRange(in.Ids + first, last - first, in.NPoints))
    {
      return false;
    }
    ctk::Vec2 A[3];
    for (vtkIdType c0 = b0; c0 < b1; c0 += group)
    {
      ctk::Vec2 groupLo = ctk::Vec2::Constant(std::numeric_limits<double>::infinity());
      ctk::Vec2 groupHi = -groupLo;
      for (vtkIdType c = c0; c < std::min(c0 + group, b1); ++c)
      {
        in.Corners(c, A);
        groupLo = groupLo.cwiseMin(A[0]).cwiseMin(A[1]).cwiseMin(A[2]);
        groupHi = groupHi.cwiseMax(A[0]).cwiseMax(A[1]).cwiseMax(A[2]);
        minArea = std::min(minArea, std::abs(ctk::SignedArea2(A[0], A[1], A[2])));
      }
      spans[c0 / group] = grid.SpanOf(groupLo, groupHi);
      lo = lo.cwiseMin(groupLo);
      hi = hi.cwiseMax(groupHi);
    }
  }
  return true;
}

// Whether every value of the points' coordinates, (u, v) and weights (null: none) is usable, and
// the box [lo, hi] of the (u, v). From the ranges CacheRanges stored for an array unmodified
// since (FiniteRanges: the spline filter's output), which bound all its values; otherwise from a
// pass over them (at 1e6 triangles, 540 MB: 50-55 ms of a first call).
bool UsablePointArrays(vtkDataArray* xyz, vtkDataArray* uv, vtkDataArray* w, vtkIdType nPoints,
  ctk::Vec2& lo, ctk::Vec2& hi)
{
  double ranges[6];
  auto usableRanges = [&](vtkDataArray* a, int nc) {
    if (!ctsplines::FiniteRanges(a, ranges))
    {
      return false;
    }
    for (int k = 0; k < 2 * nc; ++k)
    {
      if (!ctk::IsUsableValue(ranges[k]))
      {
        return false;
      }
    }
    return true;
  };
  auto values = [](vtkDataArray* a) { return vtkDoubleArray::FastDownCast(a)->GetPointer(0); };
  if (!(usableRanges(xyz, 3) || ctk::AllUsableValues(values(xyz), 3 * nPoints)))
  {
    return false;
  }
  if (w && !(usableRanges(w, 1) && ranges[0] > 0.0) &&
    !ctk::AllUsableValues(values(w), nPoints, true))
  {
    return false;
  }
  if (usableRanges(uv, 2))
  {
    lo = ctk::Vec2(ranges[0], ranges[2]);
    hi = ctk::Vec2(ranges[1], ranges[3]);
    return true;
  }
  return ctk::AllUsablePairs(values(uv), nPoints, lo, hi);
}

// Whether the source's own arrays pass every check of ReadSpline (cell types and sizes, point
// ids, macro-triangle ids, parameter triangles of nonzero area; the points' arrays, checked by
// UsablePointArrays, whose (u, v) span [pointsLo, pointsHi]); if so, `out` adopts them. The
// grid is laid over the box of the points' (u, v) before the one pass over the cells, which
// then gives every group's span: the corners are read once, not again by the grid's build (25
// ms of a 0.2 s first call on 1e6 triangles). The box is the cells' for the spline filter's
// output (its control points lie in their triangles); for another, the grid is built again over
// the cells' box (the same results: a grid finds the same triangles over any box). nIds: the
// length of the connectivity array.
template <typename OffsetT, typename IdT>
bool AdoptInPlace(const unsigned char* types, const SplineArrays<OffsetT, IdT>& in,
  vtkIdType nIds, const ctk::Vec2& pointsLo, const ctk::Vec2& pointsHi, ProbeSpline& out)
{
  if (in.NCells > 0 ? in.Offsets[0] != 0 || static_cast<vtkIdType>(in.Offsets[in.NCells]) != nIds
                    : nIds != 0)
  {
    return false;
  }
  ctk::TriangleBucketGrid& grid = out.Grid;
  const ctk::Id group = MacroTriples(in.MacroIds, in.NCells) ? 3 : 1;
  if (!grid.Prepare(in.NCells, pointsLo, pointsHi, group))
  {
    return false; // ReadSpline names the limit
  }
  ctk::TriangleBucketGrid::Spans spans;
  ctk::ResizeForOverwrite(spans, static_cast<size_t>(grid.GetNumberOfGroups()));
  // Every area must exceed the bound relative to the box (the spline filter's test), which is
  // the smallest exceeding it.
  ctk::Vec2 lo, hi;
  double minArea;
  if (!CheckCells(types, in, nIds, group, grid, spans, lo, hi, minArea) ||
    (in.NCells > 0 && !(minArea > 1e-13 * (hi - lo).squaredNorm())))
  {
    return false;
  }
  if (in.NCells > 0 && lo == pointsLo && hi == pointsHi)
  {
    out.Arrays = in;
    return grid.List(spans);
  }
  return out.Adopt(in, lo, hi).empty();
}

// The usual source (an unstructured grid with double points, (u, v) and weights, and vtkIdType
// macro-triangle ids) read in place: the probe reads the source's own arrays (on 1e6 triangles
// a copy touched about 1 GB of fresh memory). False, with nothing built, when the source is of
// another kind or fails a check: ReadSpline then reads it (and names the offender).
bool ReadSplineInPlace(vtkDataSet* source, const std::string& uvName, ProbeSpline& out)
{
  vtkUnstructuredGrid* ug = vtkUnstructuredGrid::SafeDownCast(source);
  vtkCellArray* cells = ug ? ug->GetCells() : nullptr;
  vtkUnsignedCharArray* types = ug ? ug->GetCellTypesArray() : nullptr;
  const vtkIdType nCells = source->GetNumberOfCells(), nPoints = source->GetNumberOfPoints();
  vtkPointData* pd = source->GetPointData();
  vtkDataArray* w = pd->GetRationalWeights();
  w = w ? w : ctsplines::FindArray(pd, "RationalWeights");
  vtkDataArray* xyzArray = ug && ug->GetPoints() ? ug->GetPoints()->GetData() : nullptr;
  vtkDataArray* uvArray = ctsplines::FindArray(pd, uvName);
  vtkDataArray* macroArray = source->GetCellData()->GetArray("MacroTriangleId");
  auto doubles = [](vtkDataArray* a, int components, vtkIdType tuples) {
    vtkDoubleArray* d = vtkDoubleArray::FastDownCast(a);
    return d && d->GetNumberOfComponents() == components && d->GetNumberOfTuples() == tuples
      ? d->GetPointer(0)
      : nullptr;
  };
  const double* xyz = doubles(xyzArray, 3, nPoints);
  const double* uv = doubles(uvArray, 2, nPoints);
  const double* weights = w ? doubles(w, 1, nPoints) : nullptr;
  vtkIdTypeArray* macroIds = vtkIdTypeArray::FastDownCast(macroArray);
  if (!cells || !types || types->GetNumberOfTuples() != nCells ||
    cells->GetNumberOfCells() != nCells || nPoints == 0 || !xyz || !uv || (w && !weights) ||
    (macroArray &&
      (!macroIds || macroIds->GetNumberOfComponents() != 1 ||
        macroIds->GetNumberOfTuples() != nCells)))
  {
    return false;
  }
  ctk::Vec2 pointsLo, pointsHi;
  if (!UsablePointArrays(xyzArray, uvArray, weights ? w : nullptr, nPoints, pointsLo, pointsHi))
  {
    return false;
  }
  auto build = [&](vtkDataArray* offsetArray, vtkDataArray* idArray, const auto* offsets,
                 const auto* ids) {
    using OffsetT = std::remove_cv_t<std::remove_pointer_t<decltype(offsets)>>;
    using IdT = std::remove_cv_t<std::remove_pointer_t<decltype(ids)>>;
    const SplineArrays<OffsetT, IdT> arrays{ offsets, ids, xyz, weights, uv,
      macroIds ? macroIds->GetPointer(0) : nullptr, nPoints, nCells };
    if (!AdoptInPlace(
          types->GetPointer(0), arrays, idArray->GetNumberOfValues(), pointsLo, pointsHi, out))
    {
      return false;
    }
    out.Held = { offsetArray, idArray, xyzArray, uvArray, w, macroArray };
    out.Copy = ctsplines::BezierCells();
    std::vector<double>().swap(out.CopyUV);
    std::vector<vtkIdType>().swap(out.CopyMacroIds);
    return true;
  };
  return cells->IsStorage64Bit()
    ? build(cells->GetOffsetsArray64(), cells->GetConnectivityArray64(),
        cells->GetOffsetsArray64()->GetPointer(0), cells->GetConnectivityArray64()->GetPointer(0))
    : build(cells->GetOffsetsArray32(), cells->GetConnectivityArray32(),
        cells->GetOffsetsArray32()->GetPointer(0), cells->GetConnectivityArray32()->GetPointer(0));
}

// The reference reading: copies and checks the source's arrays (any array types, any data
// set), naming the first offender; the probe then reads the copy.
std::string ReadSpline(vtkDataSet* source, const std::string& uvName, ProbeSpline& out)
{
  ctsplines::BezierCells& cells = out.Copy;
  std::vector<double>& uv = out.CopyUV;
  std::ostringstream os;
  vtkPointData* pd = source->GetPointData();
  vtkDataArray* uvArray = ctsplines::FindArray(pd, uvName);
  if (!uvArray)
  {
    os << "the source spline has no point data array '" << uvName
       << "' (the domain point (u, v) of each control point)";
    return os.str();
  }
  std::string error = ctsplines::CopyArray(uvArray,
    "the source's point data array '" + uvName + "'", 2, source->GetNumberOfPoints(), "point", uv);
  if (error.empty())
  {
    error = ctsplines::GatherBezierCells(source, cells, "source cell", "the source's ");
  }
  if (!error.empty())
  {
    return error;
  }
  const vtkIdType nCells = cells.NumberOfCells();
  vtkDataArray* macro = source->GetCellData()->GetArray("MacroTriangleId");
  out.CopyMacroIds.clear();
  if (macro)
  {
    error = ctsplines::CopyIdArray(macro, "the source's cell data array 'MacroTriangleId'",
      nCells, "cell", -1, out.CopyMacroIds);
    if (!error.empty())
    {
      return error;
    }
  }
  const SplineArrays<vtkIdType, vtkIdType> arrays{ cells.Offsets.data(), cells.Ids.data(),
    reinterpret_cast<const double*>(cells.Points.data()),
    cells.Weights.empty() ? nullptr : cells.Weights.data(), uv.data(),
    macro ? out.CopyMacroIds.data() : nullptr, static_cast<vtkIdType>(cells.Points.size()),
    nCells };

  // Zero-area parameter triangles have no barycentric coordinates (same test as the spline
  // filter: relative to the extent of the parameter domain). In parallel; the lowest
  // offending cell is reported whatever the thread count.
  ctk::Vec2 lo, hi;
  if (nCells > 0)
  {
    ctk::Vec2 A[3];
    arrays.Corners(0, A);
    lo = A[0];
    hi = A[0];
    for (vtkIdType c = 0; c < nCells; ++c)
    {
      arrays.Corners(c, A);
      for (int a = 0; a < 3; ++a)
      {
        lo = lo.cwiseMin(A[a]);
        hi = hi.cwiseMax(A[a]);
      }
    }
    const double diag2 = (hi - lo).squaredNorm();
    ctk::LowestId firstBad;
    ctsplines::ParallelFor(0, nCells, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
      ctk::Vec2 B[3];
      for (vtkIdType c = b; c < e; ++c)
      {
        arrays.Corners(c, B);
        if (!(std::abs(ctk::SignedArea2(B[0], B[1], B[2])) > 1e-13 * diag2))
        {
          firstBad.Report(c);
          break;
        }
      }
    });
    if (firstBad.Get() >= 0)
    {
      const vtkIdType c = firstBad.Get();
      os << "degenerate parameter triangle: source cell " << c << " (corner points "
         << arrays.Id(c, 0) << ", " << arrays.Id(c, 1) << ", " << arrays.Id(c, 2)
         << ") has zero area in (u, v)";
      return os.str();
    }
  }
  out.Held.clear();
  return out.Adopt(arrays, lo, hi);
}
} // namespace

namespace
{
// The query points' (u, v): raw coordinates for the usual point sets (GetPoint is a virtual call
// per point), GetPoint otherwise.
struct QueryPoints
{
  vtkDataSet* Input;
  const double* XYZ = nullptr;

  explicit QueryPoints(vtkDataSet* input)
    : Input(input)
  {
    if (input->GetNumberOfPoints() > 0)
    {
      // vtkDataSet::GetPoint is thread safe once it has been called from one thread.
      double x[3];
      input->GetPoint(0, x);
    }
    vtkPointSet* pointSet = vtkPointSet::SafeDownCast(input);
    vtkDataArray* coords = pointSet && pointSet->GetPoints() ? pointSet->GetPoints()->GetData() : nullptr;
    vtkDoubleArray* doubles = vtkDoubleArray::FastDownCast(coords);
    this->XYZ = doubles ? doubles->GetPointer(0) : nullptr;
  }
  void Get(vtkIdType i, double x[3]) const
  {
    if (this->XYZ)
    {
      Copy3(this->XYZ + 3 * i, x);
    }
    else
    {
      this->Input->GetPoint(i, x);
    }
  }
};

// Whether the queries come in a coherent order: at least half of the sampled consecutive pairs
// (every 16th query and the next) lie in the same or neighbouring buckets. A sample is enough
// for the decision, which changes no result (only the order of the work), and it is the same
// on any thread count; coherent queries then skip the key pass over all of them.
bool IsCoherentOrder(const QueryPoints& queries, vtkIdType nPoints, const ctk::TriangleBucketGrid& grid)
{
  constexpr vtkIdType Stride = 16;
  vtkIdType pairs = 0, near = 0;
  for (vtkIdType i = 0; i + 1 < nPoints; i += Stride)
  {
    double x[3], y[3];
    queries.Get(i, x);
    queries.Get(i + 1, y);
    ctk::Id ix, iy, jx, jy;
    const bool found = grid.BucketCell(x[0], x[1], ix, iy) && grid.BucketCell(y[0], y[1], jx, jy);
    near += found && std::abs(ix - jx) <= 1 && std::abs(iy - jy) <= 1;
    ++pairs;
  }
  return 2 * near >= pairs;
}

// The queries in the Morton order of their buckets, as (key << 32 | query) values (empty: the
// input's order, for queries mostly in neighbouring buckets already, or beyond 2^32 of them).
// Neighbouring queries then read neighbouring cells, and a spline written in a locality order
// nearly in memory order, whatever the order of the queries (random queries on 1e6 triangles
// were ~10x slower per query than on 1e4 without this); the results are scattered back. Each
// query is computed independently, so the order changes no result.
ctk::OverwriteVector<std::uint64_t> LocalityOrder(
  const QueryPoints& queries, vtkIdType nPoints, const ctk::TriangleBucketGrid& grid)
{
  ctk::OverwriteVector<std::uint64_t> keyed;
  if (nPoints > vtkIdType(UINT32_MAX))
  {
    return keyed;
  }
  if (IsCoherentOrder(queries, nPoints, grid))
  {
    // Already in a coherent order (grid rows, a polyline, sorted points): processed as they
    // come, their results are written in memory order; the sort's scattered writes cost more
    // than it saved (1e6 queries in grid rows: on 1e5 triangles 0.33 -> 0.21 s, on 1e4
    // 0.31 -> 0.19 s, on 1e6 the same).
    return keyed;
  }
  // Columns and rows beyond 2^16 share keys (the order is only coarser).
  int shift = 0;
  while (((std::max(grid.GetNumberOfColumns(), grid.GetNumberOfRows()) - 1) >> shift) >= 65536)
  {
    ++shift;
  }
  ctk::ResizeForOverwrite(keyed, static_cast<size_t>(nPoints));
  ctsplines::ParallelFor(0, nPoints, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    double x[3];
    ctk::Id ix, iy;
    for (vtkIdType i = b; i < e; ++i)
    {
      queries.Get(i, x);
      const std::uint32_t key = grid.BucketCell(x[0], x[1], ix, iy)
        ? ctk::MortonKey16(static_cast<std::uint32_t>(ix >> shift), static_cast<std::uint32_t>(iy >> shift))
        : 0;
      keyed[i] = (std::uint64_t(key) << 32) | std::uint64_t(i);
    }
  });
  ctk::SortByUpperHalf(keyed, ctsplines::SMPCopyFor);
  return keyed;
}

// A batch of queries, located stage by stage with prefetches: each stage asks for the cache
// lines the next one reads (the buckets' row offsets, then their rows of group ids and boxes;
// for the groups whose box holds the query, their cells' offsets, connectivity and corner
// (u, v), which the barycentric tests read; once located, the cells' control points, which the
// evaluation reads). On a spline larger than the cache a query's reads are a chain of dependent
// misses; over a batch the misses of its queries overlap (1e6 queries in grid rows on 1e6
// Delaunay triangles, one thread: 0.42 -> 0.32 s).
struct QueryBatch
{
  static constexpr int Size = 32;
  int Count = 0;
  vtkIdType Index[Size]; // query ids
  double X[Size][3];
  ctk::TriangleBucketGrid::Place Places[Size];
  ctk::LocatorHit Hits[Size];
  // The groups query j's bucket lists that may hold it: Kept[KeptBegin[j] .. KeptBegin[j + 1]).
  std::vector<std::uint32_t> Kept;
  std::size_t KeptBegin[Size + 1];

  /// Locates queries k0 .. k1 - 1 of the processing order (queryOrder, or k itself when empty),
  /// k1 - k0 <= Size.
  template <typename Arrays>
  void Locate(const QueryPoints& queries, const ctk::OverwriteVector<std::uint64_t>& queryOrder,
    vtkIdType k0, vtkIdType k1, const ctk::TriangleBucketGrid& grid, const Arrays& arrays)
  {
    this->Count = static_cast<int>(k1 - k0);
    for (int j = 0; j < this->Count; ++j)
    {
      const vtkIdType k = k0 + j;
      this->Index[j] =
        queryOrder.empty() ? k : static_cast<vtkIdType>(queryOrder[k] & 0xFFFFFFFFu);
      queries.Get(this->Index[j], this->X[j]);
      this->Places[j] = grid.PlaceOf(this->X[j][0], this->X[j][1]);
      if (this->Places[j].Bucket >= 0)
      {
        ctk::PrefetchRead(&grid.RowOffset(this->Places[j].Bucket));
      }
    }
    for (int j = 0; j < this->Count; ++j)
    {
      if (this->Places[j].Bucket >= 0)
      {
        ctk::PrefetchRead(grid.RowBegin(this->Places[j].Bucket));
        ctk::PrefetchRead(grid.RowBoxes(this->Places[j].Bucket));
      }
    }
    this->Keep(grid);
    const ctk::Id groupSize = grid.GetGroupSize();
    auto forKeptCells = [&](auto&& visit) {
      for (std::uint32_t g : this->Kept)
      {
        visit(static_cast<vtkIdType>(g) * groupSize, groupSize);
      }
    };
    forKeptCells([&](vtkIdType c, ctk::Id n) { arrays.PrefetchOffsets(c, n); });
    forKeptCells([&](vtkIdType c, ctk::Id n) { arrays.PrefetchIds(c, n); });
    forKeptCells([&](vtkIdType c, ctk::Id n) { arrays.PrefetchCorners(c, n); });
    const auto corners = arrays.CornersFunction();
    for (int j = 0; j < this->Count; ++j)
    {
      const std::uint32_t* kept = this->Kept.data();
      this->Hits[j] = grid.LocateAmong(kept + this->KeptBegin[j], kept + this->KeptBegin[j + 1],
        this->X[j][0], this->X[j][1], corners);
      if (this->Hits[j].Found())
      {
        arrays.PrefetchNet(this->Hits[j].Triangle);
      }
    }
  }

private:
  // Kept: the groups of each query's bucket that may hold it (outside the spline: none).
  void Keep(const ctk::TriangleBucketGrid& grid)
  {
    this->Kept.clear(); // keeps its storage: no allocation after the first batches
    for (int j = 0; j < this->Count; ++j)
    {
      this->KeptBegin[j] = this->Kept.size();
      if (this->Places[j].Bucket >= 0)
      {
        grid.ForEachCandidate(
          this->Places[j], [this](std::uint32_t g) { this->Kept.push_back(g); });
      }
    }
    this->KeptBegin[this->Count] = this->Kept.size();
  }
};

} // namespace

// The spline of the last source and its locator, reused while the source and UVArrayName are
// unchanged (the source's MTime covers its points, cells and arrays).
struct vtkSplineParameterProbe::SplineCache
{
  vtkWeakPointer<vtkDataSet> Source;
  vtkMTimeType SourceTime = 0;
  std::string UVName;
  ProbeSpline Data;

  bool Holds(vtkDataSet* source, const std::string& uvName) const
  {
    return this->Source == source && this->SourceTime == source->GetMTime() &&
      this->UVName == uvName;
  }
};

namespace
{
// The output arrays, one tuple per query, written through raw pointers taken once (GetPointer
// is an out-of-line call into VTK: four per query were about 4 % of a probe's instructions).
struct ProbeArrays
{
  vtkSmartPointer<vtkDoubleArray> Coords, Du, Dv, Normals; // Du, Dv, Normals: Derivatives only
  bool Derivatives;
  vtkSmartPointer<vtkIdTypeArray> MacroIds;
  vtkSmartPointer<vtkCharArray> Mask;
  double *CoordsData, *DuData = nullptr, *DvData = nullptr, *NormalsData = nullptr;
  vtkIdType* MacroIdsData;
  char* MaskData;

  /// New arrays, or the previous output's from recycled (see ReuseOutputArrays).
  ProbeArrays(vtkIdType nPoints, bool derivatives, ctsplines::RecycledArrays* recycled)
    : Derivatives(derivatives)
  {
    using ctsplines::NewOutputArray;
    this->Coords = NewOutputArray<vtkDoubleArray>(recycled, 3, nPoints);
    const vtkIdType nDerivatives = derivatives ? nPoints : 0;
    this->Du = NewOutputArray<vtkDoubleArray>(recycled, 3, nDerivatives);
    this->Dv = NewOutputArray<vtkDoubleArray>(recycled, 3, nDerivatives);
    this->Normals = NewOutputArray<vtkDoubleArray>(recycled, 3, nDerivatives);
    this->MacroIds = NewOutputArray<vtkIdTypeArray>(recycled, 1, nPoints);
    this->Mask = NewOutputArray<vtkCharArray>(recycled, 1, nPoints);
    this->Du->SetName("dFdu");
    this->Dv->SetName("dFdv");
    this->Normals->SetName("Normals");
    this->MacroIds->SetName("MacroTriangleId");
    this->Mask->SetName("vtkValidPointMask");
    this->CoordsData = this->Coords->GetPointer(0);
    if (derivatives)
    {
      this->DuData = this->Du->GetPointer(0);
      this->DvData = this->Dv->GetPointer(0);
      this->NormalsData = this->Normals->GetPointer(0);
    }
    this->MacroIdsData = this->MacroIds->GetPointer(0);
    this->MaskData = this->Mask->GetPointer(0);
  }
  /// Query i outside the spline's domain: the query point, zero derivatives, invalid.
  void SetOutside(vtkIdType i, const double x[3])
  {
    double* xyz = this->CoordsData + 3 * i;
    xyz[0] = x[0];
    xyz[1] = x[1];
    xyz[2] = 0.0;
    if (this->Derivatives)
    {
      std::fill_n(this->DuData + 3 * i, 3, 0.0);
      std::fill_n(this->DvData + 3 * i, 3, 0.0);
    }
    this->MacroIdsData[i] = -1;
  }
  void Set(vtkIdType i, const ctk::ParametricJet& jet, vtkIdType macro)
  {
    Copy3(jet.Value.data(), this->CoordsData + 3 * i);
    if (this->Derivatives)
    {
      Copy3(jet.Du.data(), this->DuData + 3 * i);
      Copy3(jet.Dv.data(), this->DvData + 3 * i);
    }
    this->MacroIdsData[i] = macro;
  }
  /// The normals and the mask, from the derivatives and the macro-triangle ids, in the queries'
  /// order: written per query in a locality order, as arrays of their own they cost more
  /// scattered stores than this pass (zero derivatives give a zero normal).
  void Finish(vtkIdType nPoints)
  {
    ctsplines::ParallelFor(0, nPoints, ctsplines::GrainForCopies, [this](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
      {
        this->MaskData[i] = this->MacroIdsData[i] >= 0 ? 1 : 0;
        if (this->Derivatives)
        {
          const ctk::Vec3 du(this->DuData + 3 * i), dv(this->DvData + 3 * i);
          Copy3(du.cross(dv).normalized().data(), this->NormalsData + 3 * i);
        }
      }
    });
  }
};
} // namespace

int vtkSplineParameterProbe::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkDataSet* output = vtkDataSet::GetData(outputVector);
  vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0);
  vtkDataSet* source = sourceInfo ? vtkDataSet::GetData(sourceInfo) : nullptr;
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output data object");
    return 0;
  }
  // The previous output's arrays for as many queries (see ReuseOutputArrays); otherwise, or when
  // this execution fails, they are released.
  ctsplines::RecycledArraysScope recycling(*this->Recycled, this->ReuseOutputArrays,
    { input->GetNumberOfPoints(), this->ComputeDerivatives ? 1 : 0 });
  if (!source)
  {
    vtkErrorMacro(<< "no spline source: set the spline (VTK_BEZIER_TRIANGLE cells with point "
                     "data '"
                  << this->UVArrayName << "') with SetSourceConnection() or SetSourceData()");
    return 0;
  }
  if (!this->Cache)
  {
    this->Cache = std::make_unique<SplineCache>();
  }
  if (!this->Cache->Holds(source, this->UVArrayName))
  {
    this->Cache->Source = nullptr; // invalid until rebuilt
    if (!ReadSplineInPlace(source, this->UVArrayName, this->Cache->Data))
    {
      const std::string error = ReadSpline(source, this->UVArrayName, this->Cache->Data);
      if (!error.empty())
      {
        vtkErrorMacro(<< error);
        return 0;
      }
    }
    this->Cache->Source = source;
    this->Cache->SourceTime = source->GetMTime();
    this->Cache->UVName = this->UVArrayName;
    ++this->NumberOfSplineBuilds;
  }
  const ProbeSpline& spline = this->Cache->Data;
  this->UpdateProgress(0.1);

  const vtkIdType nPoints = input->GetNumberOfPoints();
  ProbeArrays out(nPoints, this->ComputeDerivatives, recycling.Get());
  const int order = this->ComputeDerivatives ? 1 : 0;
  const QueryPoints queries(input);
  const ctk::OverwriteVector<std::uint64_t> queryOrder = LocalityOrder(queries, nPoints, spline.Grid);
  auto probe = [&](const auto& arrays, vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    const BezierShapes& shapes = Shapes();
    QueryBatch batch;
    for (vtkIdType k0 = begin; k0 < end; k0 += QueryBatch::Size)
    {
      batch.Locate(
        queries, queryOrder, k0, std::min(end, k0 + QueryBatch::Size), spline.Grid, arrays);
      for (int j = 0; j < batch.Count; ++j)
      {
        const vtkIdType i = batch.Index[j];
        const ctk::LocatorHit& hit = batch.Hits[j];
        if (!hit.Found())
        {
          out.SetOutside(i, batch.X[j]);
          continue;
        }
        const vtkIdType c = hit.Triangle;
        int degree;
        const double* wp = arrays.Net(c, shapes, degree, P, w);
        ctk::Vec2 A[3];
        arrays.Corners(c, A);
        out.Set(i,
          ctk::EvaluateOverDomain(degree, P, wp, A[0], A[1], A[2], hit.Barycentric, order),
          arrays.MacroId(c));
      }
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  const bool completed = std::visit(
    [&](const auto& arrays) {
      return ctsplines::ForInBlocks(this, nPoints, 20, 0.1, 0.95,
        [&](vtkIdType begin, vtkIdType end) { probe(arrays, begin, end); });
    },
    spline.Arrays);
  if (!completed)
  {
    output->Initialize();
    return 1;
  }
  out.Finish(nPoints);

  vtkNew<vtkPoints> points;
  points->SetData(out.Coords);
  if (vtkPointSet* pointSet = vtkPointSet::SafeDownCast(output))
  {
    if (vtkPointSet::SafeDownCast(input))
    {
      pointSet->CopyStructure(input);
      pointSet->GetCellData()->PassData(input->GetCellData());
    }
    pointSet->SetPoints(points);
  }
  vtkPointData* outPD = output->GetPointData();
  outPD->PassData(input->GetPointData());
  if (this->ComputeDerivatives)
  {
    outPD->AddArray(out.Du);
    outPD->AddArray(out.Dv);
    outPD->SetNormals(out.Normals);
  }
  outPD->AddArray(out.MacroIds);
  outPD->AddArray(out.Mask);
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  // Only the arrays made here: the input's passed arrays and structure are the input's.
  recycling.End(std::vector<vtkDataArray*>{ out.Coords, out.Du, out.Dv, out.Normals,
                  out.MacroIds, out.Mask },
    ctsplines::RecycledArrays::MayKeepOutput(this, this->ReuseOutputArrays));
  this->UpdateProgress(1.0);
  return 1;
}

int vtkSplineParameterProbe::GetNumberOfCellsPerLocatorEntry() const
{
  return this->Cache && this->Cache->Source
    ? static_cast<int>(this->Cache->Data.Grid.GetGroupSize())
    : 0;
}

void vtkSplineParameterProbe::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Source: " << this->GetSource() << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
  os << indent << "ComputeDerivatives: " << this->ComputeDerivatives << "\n";
  os << indent << "ReuseOutputArrays: " << this->ReuseOutputArrays << "\n";
  os << indent << "NumberOfSplineBuilds: " << this->NumberOfSplineBuilds << "\n";
  os << indent << "NumberOfCellsPerLocatorEntry: " << this->GetNumberOfCellsPerLocatorEntry()
     << "\n";
}
