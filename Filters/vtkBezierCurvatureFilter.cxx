// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierCurvatureFilter.h"

#include "BezierTriangle.h"
#include "CTSplinesArrayRanges.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "SurfaceCurvatures.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBezierCurvatureFilter);

vtkBezierCurvatureFilter::vtkBezierCurvatureFilter() = default;
vtkBezierCurvatureFilter::~vtkBezierCurvatureFilter() = default;

int vtkBezierCurvatureFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

namespace
{
// The p-th and (100 - p)-th percentiles of a one-component array (nearest rank, O(n)), as a
// 2-component field data array named after it.
vtkSmartPointer<vtkDoubleArray> RobustRange(vtkDoubleArray* a, double p)
{
  std::vector<double> v(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfTuples());
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  auto range = vtkSmartPointer<vtkDoubleArray>::New();
  range->SetName((std::string(a->GetName()) + "_RobustRange").c_str());
  range->SetNumberOfComponents(2);
  double lohi[2] = { 0.0, 0.0 };
  if (!v.empty())
  {
    const size_t last = v.size() - 1;
    const size_t lo = static_cast<size_t>(std::llround(p / 100.0 * last));
    std::nth_element(v.begin(), v.begin() + lo, v.end());
    lohi[0] = v[lo];
    std::nth_element(v.begin(), v.begin() + (last - lo), v.end());
    lohi[1] = v[last - lo];
  }
  range->InsertNextTuple(lohi);
  return range;
}

vtkSmartPointer<vtkDoubleArray> MakeArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

// The curvature point data of the output; each point is written by exactly one cell.
struct CurvatureArrays
{
  explicit CurvatureArrays(vtkIdType nPoints)
    : Normals(MakeArray("Normals", 3, nPoints))
    , Gauss(MakeArray("Gauss_Curvature", 1, nPoints))
    , Mean(MakeArray("Mean_Curvature", 1, nPoints))
    , Max(MakeArray("Maximum_Curvature", 1, nPoints))
    , Min(MakeArray("Minimum_Curvature", 1, nPoints))
    , MaxDirection(MakeArray("Maximum_Curvature_Direction", 3, nPoints))
    , MinDirection(MakeArray("Minimum_Curvature_Direction", 3, nPoints))
  {
  }
  void Write(vtkIdType id, const ctk::SurfaceCurvatures& k)
  {
    Normals->SetTypedTuple(id, k.Normal.data());
    Gauss->SetValue(id, k.Gauss);
    Mean->SetValue(id, k.Mean);
    Max->SetValue(id, k.Max);
    Min->SetValue(id, k.Min);
    MaxDirection->SetTypedTuple(id, k.MaxDirection.data());
    MinDirection->SetTypedTuple(id, k.MinDirection.data());
  }
  // The arrays as point data, the robust ranges of the scalars as field data.
  void AddTo(vtkPointData* pd, vtkFieldData* fd, double percentile) const
  {
    pd->SetNormals(Normals);
    for (vtkDoubleArray* a : { Gauss.Get(), Mean.Get(), Max.Get(), Min.Get(), MaxDirection.Get(),
           MinDirection.Get() })
    {
      pd->AddArray(a);
    }
    for (vtkDoubleArray* a : { Gauss.Get(), Mean.Get(), Max.Get(), Min.Get() })
    {
      fd->AddArray(RobustRange(a, percentile));
    }
  }
  vtkSmartPointer<vtkDoubleArray> Normals, Gauss, Mean, Max, Min, MaxDirection, MinDirection;
};
} // namespace

int vtkBezierCurvatureFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output data object");
    return 0;
  }
  const vtkIdType nCells = input->GetNumberOfCells();
  if (nCells == 0)
  {
    vtkErrorMacro(<< "empty input: no VTK_BEZIER_TRIANGLE cells to compute curvatures of");
    return 0;
  }

  // 1. Validate and flatten the input so that the parallel part reads plain arrays.
  ctsplines::BezierCells cells;
  std::string error = ctsplines::GatherBezierCellsAndCellData(input, cells);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }

  const int L = this->SubdivisionLevel;
  const ctsplines::SamplingLattice lattice(L);
  const ctsplines::LatticeNumbering numbering(cells, lattice, this->MergePoints);
  const vtkIdType nOutPoints = numbering.NumberOfPoints();
  ctsplines::PointDataInterpolator data;
  error = data.Gather(input, this->UVArrayName, nOutPoints);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const vtkIdType trianglesPerCell = static_cast<vtkIdType>(L) * L;
  const vtkIdType nOutCells = nCells * trianglesPerCell;

  // 2. Output arrays; each point is written by exactly one cell.
  auto coords = MakeArray(nullptr, 3, nOutPoints);
  CurvatureArrays curvatures(nOutPoints);
  vtkNew<vtkIdTypeArray> offsets, connectivity, bezierCellId;
  offsets->SetNumberOfTuples(nOutCells + 1);
  connectivity->SetNumberOfTuples(3 * nOutCells);
  bezierCellId->SetName("BezierCellId");
  bezierCellId->SetNumberOfTuples(nOutCells);
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  vtkIdType* source = bezierCellId->GetPointer(0);

  auto evaluate = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints], R[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    std::vector<ctk::Vec3> nets(std::max(1, data.NumberOfNets()) * ctk::MaxBezierPoints);
    for (vtkIdType c = begin; c < end; ++c)
    {
      const int n = cells.Degree[c];
      const double* wp = cells.Net(c, P, w);
      // Derivatives from the net relative to its first point (R): the differences are then
      // formed of small numbers (exact for nearby points), which keeps the second derivatives
      // of small cells accurate. Positions come from the net itself, as the tessellator's.
      ctk::RelativeNet(n, P, R);
      data.LoadNets(cells, c, nets.data());
      for (int li = 0; li < static_cast<int>(lattice.Points.size()); ++li)
      {
        bool owned = false;
        const vtkIdType id = numbering.OutputId(c, li, owned);
        if (!owned)
        {
          continue;
        }
        const ctk::Vec3& t = lattice.Points[li].T;
        coords->SetTypedTuple(id, ctk::EvaluateBezierTriangle(n, P, wp, t, 0).Value.data());
        curvatures.Write(id, ctk::BezierTriangleCurvatures(n, R, wp, t));
        data.Write(n, nets.data(), wp, t, id);
      }
      numbering.WriteTriangles(c, off, conn, source);
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nCells, 20, 0.0, 0.95, evaluate))
  {
    output->Initialize();
    return 1;
  }
  off[nOutCells] = 3 * nOutCells;

  vtkNew<vtkPoints> points;
  points->SetData(coords);
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetPolys(polys);
  curvatures.AddTo(output->GetPointData(), output->GetFieldData(), this->RobustRangePercentile);
  data.AddTo(output->GetPointData());
  ctsplines::CopyCellDataBySource(input, output->GetCellData(), source, nOutCells);
  output->GetCellData()->AddArray(bezierCellId);
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  this->UpdateProgress(1.0);
  return 1;
}

void vtkBezierCurvatureFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "MergePoints: " << (this->MergePoints ? "on" : "off") << "\n";
  os << indent << "RobustRangePercentile: " << this->RobustRangePercentile << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
}
