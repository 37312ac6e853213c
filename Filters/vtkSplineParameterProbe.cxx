// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineParameterProbe.h"

#include "BezierTriangle.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
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
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkSplineParameterProbe);

vtkSplineParameterProbe::vtkSplineParameterProbe()
{
  this->SetNumberOfInputPorts(2);
}

vtkSplineParameterProbe::~vtkSplineParameterProbe() = default;

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
// The source spline flattened into plain arrays, read concurrently by the queries.
struct Spline
{
  ctsplines::BezierCells Cells;
  std::vector<ctk::Vec2> Corners; // parameter triangle of each cell
  std::vector<vtkIdType> MacroIds;
};

// Read access to a valid spline's cells and arrays: the source's own arrays (RawSource) or a
// gathered copy of them (ReadSpline), whichever the build reads.
template <typename OffsetT, typename IdT>
struct SplineArrays
{
  const OffsetT* Offsets; // NCells + 1, Offsets[0] == 0
  const IdT* Ids;
  const double* XYZ;     // 3 per point
  const double* Weights; // 1 per point, or nullptr (polynomial)
  const double* UV;      // 2 per point
  vtkIdType NPoints, NCells;

  vtkIdType Id(vtkIdType c, int a) const { return static_cast<vtkIdType>(this->Ids[this->Offsets[c] + a]); }
};

// Builds the spline the queries read, in ONE pass over the arrays: the cells (with their
// parameter triangles and macro-triangle ids) in the locality order of their parameter
// triangles (ctk::TriangleLocalityOrder; small splines keep their order), the control points
// renumbered by first use in that order (points no cell uses are dropped), and the locator over
// the triangles. The cells and points that neighbouring queries read are then neighbours in
// memory: on 1e6 Delaunay triangles in qhull's order, gathering control points was half of a
// probe's time. The locator breaks ties by source cell id, so every query gets the cell it
// would get in the source's order. macroIds: per source cell, or empty (the source cell id).
template <typename OffsetT, typename IdT>
void BuildSpline(const SplineArrays<OffsetT, IdT>& in, const std::vector<vtkIdType>& macroIds,
  Spline& out, ctk::ParameterLocator& locator)
{
  const vtkIdType nCells = in.NCells;
  std::vector<ctk::Id> order;
  {
    std::vector<ctk::Id> cornerIds;
    ctk::ResizeForOverwrite(cornerIds, static_cast<size_t>(3 * nCells));
    for (vtkIdType c = 0; c < nCells; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        cornerIds[3 * c + a] = in.Id(c, a);
      }
    }
    order = ctk::TriangleLocalityOrder(in.NPoints, nCells, cornerIds.data(), in.UV);
  }
  const bool reordered = !order.empty();
  auto source = [&](vtkIdType k) { return reordered ? order[k] : k; };
  out.Cells = ctsplines::BezierCells();
  ctk::ResizeForOverwrite(out.Cells.Degree, nCells);
  ctk::ResizeForOverwrite(out.Cells.Offsets, nCells + 1);
  std::vector<ctk::Vec2> corners;
  ctk::ResizeForOverwrite(corners, 3 * nCells);
  ctk::ResizeForOverwrite(out.MacroIds, nCells);
  out.Cells.Offsets[0] = 0;
  for (vtkIdType k = 0; k < nCells; ++k)
  {
    const vtkIdType c = source(k);
    const vtkIdType npts = static_cast<vtkIdType>(in.Offsets[c + 1] - in.Offsets[c]);
    int n = 1;
    while (ctk::BezierPointCount(n) < npts)
    {
      ++n; // valid cells only: npts is (n + 1)(n + 2) / 2 for some n <= MaxDegree
    }
    out.Cells.Degree[k] = static_cast<signed char>(n);
    if (out.Cells.Orders[n].empty())
    {
      out.Cells.Orders[n] = ctk::VtkBezierTriangleOrder(n);
    }
    out.Cells.Offsets[k + 1] = out.Cells.Offsets[k] + npts;
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType p = in.Id(c, a);
      corners[3 * k + a] = ctk::Vec2(in.UV[2 * p], in.UV[2 * p + 1]);
    }
    out.MacroIds[k] = macroIds.empty() ? c : macroIds[c];
  }
  // Points by first use.
  std::vector<vtkIdType> newId;
  ctk::AssignLarge(newId, static_cast<size_t>(in.NPoints), vtkIdType(-1));
  ctk::ResizeForOverwrite(out.Cells.Ids, static_cast<size_t>(out.Cells.Offsets[nCells]));
  ctk::ResizeForOverwrite(out.Cells.Points, static_cast<size_t>(in.NPoints));
  ctk::ResizeForOverwrite(out.Cells.Weights, in.Weights ? static_cast<size_t>(in.NPoints) : 0);
  vtkIdType next = 0;
  for (vtkIdType k = 0; k < nCells; ++k)
  {
    const vtkIdType c = source(k);
    vtkIdType* newIds = &out.Cells.Ids[out.Cells.Offsets[k]];
    for (vtkIdType i = 0; i < out.Cells.Offsets[k + 1] - out.Cells.Offsets[k]; ++i)
    {
      const vtkIdType q = in.Id(c, static_cast<int>(i));
      vtkIdType& p = newId[q];
      if (p < 0)
      {
        p = next++;
        out.Cells.Points[p] = ctk::Vec3(in.XYZ[3 * q], in.XYZ[3 * q + 1], in.XYZ[3 * q + 2]);
        if (in.Weights)
        {
          out.Cells.Weights[p] = in.Weights[q];
        }
      }
      newIds[i] = p;
    }
  }
  out.Cells.Points.resize(next);
  out.Cells.Weights.resize(in.Weights ? next : 0);
  out.Corners.clear();
  locator.Build(std::move(corners), std::move(order));
}

// Whether the source's own arrays pass every check of ReadSpline (cell types and sizes, point
// ids, usable coordinates, (u, v) and weights, parameter triangles of nonzero area).
template <typename OffsetT, typename IdT>
bool IsValidInPlace(const unsigned char* types, const SplineArrays<OffsetT, IdT>& in)
{
  if (in.NCells > 0 && in.Offsets[0] != 0)
  {
    return false;
  }
  for (vtkIdType c = 0; c < in.NCells; ++c)
  {
    const vtkIdType npts = static_cast<vtkIdType>(in.Offsets[c + 1] - in.Offsets[c]);
    bool sized = false;
    for (int n = 1; n <= ctk::MaxDegree; ++n)
    {
      sized = sized || ctk::BezierPointCount(n) == npts;
    }
    if (types[c] != VTK_BEZIER_TRIANGLE || !sized)
    {
      return false;
    }
    for (vtkIdType i = in.Offsets[c]; i < static_cast<vtkIdType>(in.Offsets[c + 1]); ++i)
    {
      if (in.Ids[i] < 0 || static_cast<vtkIdType>(in.Ids[i]) >= in.NPoints)
      {
        return false;
      }
    }
  }
  for (vtkIdType p = 0; p < in.NPoints; ++p)
  {
    if (!ctk::IsUsablePoint(ctk::Vec3(in.XYZ[3 * p], in.XYZ[3 * p + 1], in.XYZ[3 * p + 2])) ||
      !ctk::IsUsableValue(in.UV[2 * p]) || !ctk::IsUsableValue(in.UV[2 * p + 1]) ||
      (in.Weights && !(ctk::IsUsableValue(in.Weights[p]) && in.Weights[p] > 0)))
    {
      return false;
    }
  }
  if (in.NCells == 0)
  {
    return true;
  }
  auto corner = [&](vtkIdType c, int a) {
    const vtkIdType p = in.Id(c, a);
    return ctk::Vec2(in.UV[2 * p], in.UV[2 * p + 1]);
  };
  ctk::Vec2 lo = corner(0, 0), hi = lo;
  for (vtkIdType c = 0; c < in.NCells; ++c)
  {
    for (int a = 0; a < 3; ++a)
    {
      lo = lo.cwiseMin(corner(c, a));
      hi = hi.cwiseMax(corner(c, a));
    }
  }
  const double diag2 = (hi - lo).squaredNorm();
  for (vtkIdType c = 0; c < in.NCells; ++c)
  {
    if (!(std::abs(ctk::SignedArea2(corner(c, 0), corner(c, 1), corner(c, 2))) > 1e-13 * diag2))
    {
      return false;
    }
  }
  return true;
}

// The usual source (an unstructured grid with double points, (u, v) and weights) read in place:
// the probe's spline is built from the source's own arrays, without first copying them (on
// 1e6 triangles the copy touched about 1 GB of fresh memory). False, with nothing built, when
// the source is of another kind or fails a check: ReadSpline then reads it (and names the
// offender).
bool ReadSplineInPlace(
  vtkDataSet* source, const std::string& uvName, Spline& out, ctk::ParameterLocator& locator)
{
  vtkUnstructuredGrid* ug = vtkUnstructuredGrid::SafeDownCast(source);
  vtkCellArray* cells = ug ? ug->GetCells() : nullptr;
  vtkUnsignedCharArray* types = ug ? ug->GetCellTypesArray() : nullptr;
  const vtkIdType nCells = source->GetNumberOfCells(), nPoints = source->GetNumberOfPoints();
  vtkPointData* pd = source->GetPointData();
  vtkDataArray* w = pd->GetRationalWeights();
  w = w ? w : ctsplines::FindArray(pd, "RationalWeights");
  auto doubles = [](vtkDataArray* a, int components, vtkIdType tuples) {
    vtkDoubleArray* d = vtkDoubleArray::FastDownCast(a);
    return d && d->GetNumberOfComponents() == components && d->GetNumberOfTuples() == tuples
      ? d->GetPointer(0)
      : nullptr;
  };
  const double* xyz = ug && ug->GetPoints() ? doubles(ug->GetPoints()->GetData(), 3, nPoints) : nullptr;
  const double* uv = doubles(ctsplines::FindArray(pd, uvName), 2, nPoints);
  const double* weights = w ? doubles(w, 1, nPoints) : nullptr;
  if (!cells || !types || types->GetNumberOfTuples() != nCells ||
    cells->GetNumberOfCells() != nCells || nPoints == 0 || !xyz || !uv || (w && !weights))
  {
    return false;
  }
  std::vector<vtkIdType> macroIds;
  if (vtkDataArray* macro = source->GetCellData()->GetArray("MacroTriangleId"))
  {
    if (!ctsplines::CopyIdArray(macro, "", nCells, "cell", -1, macroIds).empty())
    {
      return false;
    }
  }
  auto build = [&](const auto* offsets, const auto* ids) {
    using OffsetT = std::remove_cv_t<std::remove_pointer_t<decltype(offsets)>>;
    using IdT = std::remove_cv_t<std::remove_pointer_t<decltype(ids)>>;
    const SplineArrays<OffsetT, IdT> arrays{ offsets, ids, xyz, weights, uv, nPoints, nCells };
    if (!IsValidInPlace(types->GetPointer(0), arrays))
    {
      return false;
    }
    BuildSpline(arrays, macroIds, out, locator);
    return true;
  };
  return cells->IsStorage64Bit()
    ? build(cells->GetOffsetsArray64()->GetPointer(0), cells->GetConnectivityArray64()->GetPointer(0))
    : build(cells->GetOffsetsArray32()->GetPointer(0), cells->GetConnectivityArray32()->GetPointer(0));
}

// The reference reading: copies and checks the source's arrays (any array types, any data
// set), naming the first offender, then builds the probe's spline from the copy.
std::string ReadSpline(
  vtkDataSet* source, const std::string& uvName, Spline& out, ctk::ParameterLocator& locator)
{
  Spline s;
  std::ostringstream os;
  vtkPointData* pd = source->GetPointData();
  vtkDataArray* uvArray = ctsplines::FindArray(pd, uvName);
  if (!uvArray)
  {
    os << "the source spline has no point data array '" << uvName
       << "' (the domain point (u, v) of each control point)";
    return os.str();
  }
  std::vector<double> uv;
  std::string error = ctsplines::CopyArray(uvArray,
    "the source's point data array '" + uvName + "'", 2, source->GetNumberOfPoints(), "point", uv);
  if (error.empty())
  {
    error = ctsplines::GatherBezierCells(source, s.Cells, "source cell", "the source's ");
  }
  if (!error.empty())
  {
    return error;
  }
  const vtkIdType nCells = s.Cells.NumberOfCells();
  ctk::ResizeForOverwrite(s.Corners, static_cast<size_t>(3 * nCells));
  ctsplines::ParallelFor(0, nCells, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        const vtkIdType p = s.Cells.CellIds(c)[a];
        s.Corners[3 * c + a] = ctk::Vec2(uv[2 * p], uv[2 * p + 1]);
      }
    }
  });

  // Zero-area parameter triangles have no barycentric coordinates (same test as the spline
  // filter: relative to the extent of the parameter domain). In parallel; the lowest
  // offending cell is reported whatever the thread count.
  if (nCells > 0)
  {
    ctk::Vec2 lo = s.Corners[0], hi = s.Corners[0];
    for (const ctk::Vec2& p : s.Corners)
    {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double diag2 = (hi - lo).squaredNorm();
    ctk::LowestId firstBad;
    ctsplines::ParallelFor(0, nCells, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType c = b; c < e; ++c)
      {
        const ctk::Vec2* A = &s.Corners[3 * c];
        if (!(std::abs(ctk::SignedArea2(A[0], A[1], A[2])) > 1e-13 * diag2))
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
         << s.Cells.CellIds(c)[0] << ", " << s.Cells.CellIds(c)[1] << ", "
         << s.Cells.CellIds(c)[2] << ") has zero area in (u, v)";
      return os.str();
    }
  }

  if (vtkDataArray* macro = source->GetCellData()->GetArray("MacroTriangleId"))
  {
    error = ctsplines::CopyIdArray(
      macro, "the source's cell data array 'MacroTriangleId'", nCells, "cell", -1, s.MacroIds);
    if (!error.empty())
    {
      return error;
    }
  }
  else
  {
    s.MacroIds.clear();
  }
  std::vector<ctk::Vec2>().swap(s.Corners);
  const SplineArrays<vtkIdType, vtkIdType> arrays{ s.Cells.Offsets.data(), s.Cells.Ids.data(),
    s.Cells.Points.empty() ? nullptr : s.Cells.Points.data()->data(),
    s.Cells.Weights.empty() ? nullptr : s.Cells.Weights.data(), uv.data(),
    static_cast<vtkIdType>(s.Cells.Points.size()), nCells };
  BuildSpline(arrays, s.MacroIds, out, locator);
  return {};
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
      std::copy_n(this->XYZ + 3 * i, 3, x);
    }
    else
    {
      this->Input->GetPoint(i, x);
    }
  }
};

// Queries in bucket order within windows of consecutive queries: neighbouring queries then
// read the same triangles and control points, which matters once the spline outgrows the cache
// (random queries on 1e6 triangles were ~10x slower per query than on 1e4), while the output
// writes stay within a window. Each query is computed independently, so the order does not
// change any result.
std::vector<vtkIdType> LocalityOrder(const QueryPoints& queries, vtkIdType nPoints,
  const ctk::ParameterLocator& locator)
{
  constexpr vtkIdType window = vtkIdType(1) << 15;
  std::vector<vtkIdType> order;
  ctk::ResizeForOverwrite(order, nPoints);
  ctsplines::ParallelFor(0, (nPoints + window - 1) / window, 1, [&](vtkIdType wb, vtkIdType we) {
    std::vector<std::pair<ctk::Id, vtkIdType>> keyed;
    for (vtkIdType w = wb; w < we; ++w)
    {
      const vtkIdType begin = w * window, end = std::min(nPoints, begin + window);
      keyed.clear();
      for (vtkIdType i = begin; i < end; ++i)
      {
        double x[3];
        queries.Get(i, x);
        keyed.emplace_back(locator.Bucket(x[0], x[1]), i);
      }
      std::sort(keyed.begin(), keyed.end());
      for (vtkIdType i = begin; i < end; ++i)
      {
        order[i] = keyed[i - begin].second;
      }
    }
  });
  return order;
}

} // namespace

// The spline of the last source and its locator, reused while the source and UVArrayName are
// unchanged (the source's MTime covers its points, cells and arrays).
struct vtkSplineParameterProbe::SplineCache
{
  vtkWeakPointer<vtkDataSet> Source;
  vtkMTimeType SourceTime = 0;
  std::string UVName;
  Spline Data;
  ctk::ParameterLocator Locator;

  bool Holds(vtkDataSet* source, const std::string& uvName) const
  {
    return this->Source == source && this->SourceTime == source->GetMTime() &&
      this->UVName == uvName;
  }
};

namespace
{
// The output arrays, one tuple per query.
struct ProbeArrays
{
  vtkNew<vtkDoubleArray> Coords, Du, Dv, Normals; // Du, Dv, Normals with Derivatives only
  bool Derivatives;
  vtkNew<vtkIdTypeArray> MacroIds;
  vtkNew<vtkCharArray> Mask;

  ProbeArrays(vtkIdType nPoints, bool derivatives)
    : Derivatives(derivatives)
  {
    for (vtkDoubleArray* a : { this->Coords.Get(), this->Du.Get(), this->Dv.Get(), this->Normals.Get() })
    {
      a->SetNumberOfComponents(3);
      ctsplines::AllocateTuples(a, a == this->Coords.Get() || derivatives ? nPoints : 0);
    }
    this->Du->SetName("dFdu");
    this->Dv->SetName("dFdv");
    this->Normals->SetName("Normals");
    this->MacroIds->SetName("MacroTriangleId");
    ctsplines::AllocateTuples(this->MacroIds, nPoints);
    this->Mask->SetName("vtkValidPointMask");
    ctsplines::AllocateTuples(this->Mask, nPoints);
  }
  /// Query i outside the spline's domain: the query point, zero derivatives, invalid.
  void SetOutside(vtkIdType i, const double x[3])
  {
    double* xyz = this->Coords->GetPointer(3 * i);
    xyz[0] = x[0];
    xyz[1] = x[1];
    xyz[2] = 0.0;
    if (this->Derivatives)
    {
      std::fill_n(this->Du->GetPointer(3 * i), 3, 0.0);
      std::fill_n(this->Dv->GetPointer(3 * i), 3, 0.0);
      std::fill_n(this->Normals->GetPointer(3 * i), 3, 0.0);
    }
    this->MacroIds->SetValue(i, -1);
    this->Mask->SetValue(i, 0);
  }
  void Set(vtkIdType i, const ctk::ParametricJet& jet, vtkIdType macro)
  {
    std::copy_n(jet.Value.data(), 3, this->Coords->GetPointer(3 * i));
    if (this->Derivatives)
    {
      ctk::Vec3 normal = jet.Du.cross(jet.Dv);
      const double length = normal.norm();
      if (length > 0)
      {
        normal /= length;
      }
      std::copy_n(jet.Du.data(), 3, this->Du->GetPointer(3 * i));
      std::copy_n(jet.Dv.data(), 3, this->Dv->GetPointer(3 * i));
      std::copy_n(normal.data(), 3, this->Normals->GetPointer(3 * i));
    }
    this->MacroIds->SetValue(i, macro);
    this->Mask->SetValue(i, 1);
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
    if (!ReadSplineInPlace(source, this->UVArrayName, this->Cache->Data, this->Cache->Locator))
    {
      const std::string error =
        ReadSpline(source, this->UVArrayName, this->Cache->Data, this->Cache->Locator);
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
  const Spline& spline = this->Cache->Data;
  const ctk::ParameterLocator& locator = this->Cache->Locator;
  this->UpdateProgress(0.1);

  const vtkIdType nPoints = input->GetNumberOfPoints();
  ProbeArrays out(nPoints, this->ComputeDerivatives);
  const int order = this->ComputeDerivatives ? 1 : 0;
  const QueryPoints queries(input);
  const std::vector<vtkIdType> queryOrder = LocalityOrder(queries, nPoints, locator);
  auto probe = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    for (vtkIdType k = begin; k < end; ++k)
    {
      const vtkIdType i = queryOrder[k];
      double x[3];
      queries.Get(i, x);
      const ctk::ParameterLocator::Hit hit = locator.Locate(x[0], x[1]);
      if (!hit.Found())
      {
        out.SetOutside(i, x);
        continue;
      }
      const vtkIdType c = hit.Triangle;
      const double* wp = spline.Cells.Net(c, P, w);
      const ctk::Vec2* A = locator.TriangleCorners(c);
      out.Set(i,
        ctk::EvaluateOverDomain(spline.Cells.Degree[c], P, wp, A[0], A[1], A[2], hit.Barycentric, order),
        spline.MacroIds[c]);
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nPoints, 20, 0.1, 0.95, probe))
  {
    output->Initialize();
    return 1;
  }

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
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSplineParameterProbe::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Source: " << this->GetSource() << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
  os << indent << "ComputeDerivatives: " << this->ComputeDerivatives << "\n";
  os << indent << "NumberOfSplineBuilds: " << this->NumberOfSplineBuilds << "\n";
}
