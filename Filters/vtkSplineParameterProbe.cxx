// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineParameterProbe.h"

#include "BezierTriangle.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "CTSplinesSMP.h"
#include "LargeArrays.h"
#include "LocalityOrder.h"
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
#include "vtkWeakPointer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
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
  std::vector<ctk::Id> SourceCell; // the source's id of each cell; empty: the same
};

// Moves the cells (with their corners and macro-triangle ids) into the locality order of their
// parameter triangles (ctk::TriangleLocalityOrder), renumbers the control points by first use in
// that order and rebuilds the locator: the cells and points that neighbouring queries read are
// then neighbours in memory. On 1e6 Delaunay triangles in qhull's order, gathering control points
// was half of a probe's time. Small splines (they fit in cache) keep their order. The locator
// breaks ties by source cell id, so that every query gets the same cell as before.
void ToLocalityOrder(Spline& s, ctk::ParameterLocator& locator)
{
  const ctsplines::BezierCells& in = s.Cells;
  const vtkIdType nCells = in.NumberOfCells();
  // The corners as a mesh of 3 vertices per triangle.
  std::vector<ctk::Id> cornerIds;
  ctk::ResizeForOverwrite(cornerIds, static_cast<size_t>(3 * nCells));
  std::iota(cornerIds.begin(), cornerIds.end(), ctk::Id(0));
  const ctk::Vec2* corners = nCells > 0 ? locator.TriangleCorners(0) : nullptr;
  std::vector<ctk::Id> order = ctk::TriangleLocalityOrder(3 * nCells, nCells, cornerIds.data(),
    corners ? corners->data() : nullptr);
  std::vector<ctk::Id>().swap(cornerIds);
  if (order.empty())
  {
    return;
  }
  Spline out;
  out.Cells.Orders = in.Orders;
  ctk::ResizeForOverwrite(out.Cells.Degree, nCells);
  ctk::ResizeForOverwrite(out.Cells.Offsets, nCells + 1);
  ctk::ResizeForOverwrite(out.Corners, 3 * nCells);
  ctk::ResizeForOverwrite(out.MacroIds, nCells);
  out.Cells.Offsets[0] = 0;
  for (vtkIdType k = 0; k < nCells; ++k)
  {
    const vtkIdType c = order[k];
    out.Cells.Degree[k] = in.Degree[c];
    out.Cells.Offsets[k + 1] = out.Cells.Offsets[k] + in.Offsets[c + 1] - in.Offsets[c];
    std::copy_n(corners + 3 * c, 3, &out.Corners[3 * k]);
    out.MacroIds[k] = s.MacroIds[c];
  }
  // Points by first use; points no cell uses are dropped.
  const vtkIdType nPoints = static_cast<vtkIdType>(in.Points.size());
  const bool rational = !in.Weights.empty();
  std::vector<vtkIdType> newId;
  ctk::AssignLarge(newId, static_cast<size_t>(nPoints), vtkIdType(-1));
  ctk::ResizeForOverwrite(out.Cells.Ids, static_cast<size_t>(out.Cells.Offsets[nCells]));
  ctk::ResizeForOverwrite(out.Cells.Points, static_cast<size_t>(nPoints));
  ctk::ResizeForOverwrite(out.Cells.Weights, rational ? static_cast<size_t>(nPoints) : 0);
  vtkIdType next = 0;
  for (vtkIdType k = 0; k < nCells; ++k)
  {
    const vtkIdType* ids = in.CellIds(order[k]);
    vtkIdType* newIds = &out.Cells.Ids[out.Cells.Offsets[k]];
    for (vtkIdType i = 0; i < out.Cells.Offsets[k + 1] - out.Cells.Offsets[k]; ++i)
    {
      vtkIdType& p = newId[ids[i]];
      if (p < 0)
      {
        p = next++;
        out.Cells.Points[p] = in.Points[ids[i]];
        if (rational)
        {
          out.Cells.Weights[p] = in.Weights[ids[i]];
        }
      }
      newIds[i] = p;
    }
  }
  out.Cells.Points.resize(next);
  out.Cells.Weights.resize(rational ? next : 0);
  out.SourceCell = std::move(order);
  s = std::move(out);
  locator.Build(std::move(s.Corners), s.SourceCell.data());
}

std::string ReadSpline(vtkDataSet* source, const std::string& uvName, Spline& s)
{
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
  s.SourceCell.clear();
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
    ctk::ResizeForOverwrite(s.MacroIds, nCells);
    std::iota(s.MacroIds.begin(), s.MacroIds.end(), vtkIdType(0));
  }
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
  bool Reordered = false; // Data and Locator in the locality order (ToLocalityOrder)

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
    const std::string error = ReadSpline(source, this->UVArrayName, this->Cache->Data);
    if (!error.empty())
    {
      vtkErrorMacro(<< error);
      return 0;
    }
    // The locator takes over the corners; the evaluation reads them from there.
    this->Cache->Locator.Build(std::move(this->Cache->Data.Corners));
    this->Cache->Source = source;
    this->Cache->SourceTime = source->GetMTime();
    this->Cache->UVName = this->UVArrayName;
    this->Cache->Reordered = false;
    ++this->NumberOfSplineBuilds;
  }
  else if (!this->Cache->Reordered)
  {
    // Probed again: the locality order pays for itself from now on (one probe alone would not
    // repay it: it allocates the spline's arrays a second time).
    ToLocalityOrder(this->Cache->Data, this->Cache->Locator);
    this->Cache->Reordered = true;
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
