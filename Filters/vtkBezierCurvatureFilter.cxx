// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierCurvatureFilter.h"

#include "BezierTriangle.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"

#include <Eigen/Eigenvalues> // for GeneralizedSelfAdjointEigenSolver
#include <Eigen/Geometry>    // for cross

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
struct Curvatures
{
  double K, H, Max, Min;
  ctk::Vec3 Normal, MaxDirection, MinDirection;
};

// Curvatures from the fundamental forms of x(r, s); see the class comment for the sign of H.
Curvatures FromJet(const ctk::ParametricJet& jet)
{
  Curvatures k;
  const ctk::Vec3 cross = jet.Du.cross(jet.Dv);
  k.Normal = cross.normalized();
  Eigen::Matrix2d I, II;
  I << jet.Du.dot(jet.Du), jet.Du.dot(jet.Dv), jet.Du.dot(jet.Dv), jet.Dv.dot(jet.Dv);
  II << jet.Duu.dot(k.Normal), jet.Duv.dot(k.Normal), jet.Duv.dot(k.Normal),
    jet.Dvv.dot(k.Normal);
  // det I = |x_r x x_s|^2 exactly, without cancellation.
  const double detI = cross.squaredNorm();
  k.K = II.determinant() / detI;
  k.H = -(I(0, 0) * II(1, 1) - 2 * I(0, 1) * II(0, 1) + I(1, 1) * II(0, 0)) / (2 * detI);
  // Principal curvatures and directions: II v = lambda I v with kappa = -lambda, so the smallest
  // lambda gives the largest curvature. The symmetric eigenproblem stays accurate at umbilics,
  // where H +- sqrt(H^2 - K) would lose half the digits.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> eig(II, I);
  k.Max = -eig.eigenvalues()[0];
  k.Min = -eig.eigenvalues()[1];
  const Eigen::Vector2d vMax = eig.eigenvectors().col(0), vMin = eig.eigenvectors().col(1);
  k.MaxDirection = (vMax.x() * jet.Du + vMax.y() * jet.Dv).normalized();
  k.MinDirection = (vMin.x() * jet.Du + vMin.y() * jet.Dv).normalized();
  return k;
}
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
  auto makeArray = [nOutPoints](const char* name, int components) {
    vtkSmartPointer<vtkDoubleArray> a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(nOutPoints);
    return a;
  };
  auto coords = makeArray(nullptr, 3);
  auto normals = makeArray("Normals", 3);
  auto gauss = makeArray("Gauss_Curvature", 1);
  auto mean = makeArray("Mean_Curvature", 1);
  auto kmax = makeArray("Maximum_Curvature", 1);
  auto kmin = makeArray("Minimum_Curvature", 1);
  auto dmax = makeArray("Maximum_Curvature_Direction", 3);
  auto dmin = makeArray("Minimum_Curvature_Direction", 3);
  vtkNew<vtkIdTypeArray> offsets, connectivity, bezierCellId;
  offsets->SetNumberOfTuples(nOutCells + 1);
  connectivity->SetNumberOfTuples(3 * nOutCells);
  bezierCellId->SetName("BezierCellId");
  bezierCellId->SetNumberOfTuples(nOutCells);
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  vtkIdType* source = bezierCellId->GetPointer(0);

  // The cell's own parametrisation (r, s): domain (0,0), (1,0), (0,1), t = (1 - r - s, r, s).
  const ctk::Vec2 R0(0, 0), R1(1, 0), R2(0, 1);
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
        const ctk::ParametricJet exact = ctk::EvaluateOverDomain(n, R, wp, R0, R1, R2, t, 2);
        coords->SetTypedTuple(id, ctk::EvaluateBezierTriangle(n, P, wp, t, 0).Value.data());
        const Curvatures k = ctk::IsSingularTangentPlane(exact.Du, exact.Dv)
          ? FromJet(ctk::EvaluateOverDomain(n, R, wp, R0, R1, R2, ctk::NudgeInside(t), 2))
          : FromJet(exact);
        normals->SetTypedTuple(id, k.Normal.data());
        gauss->SetValue(id, k.K);
        mean->SetValue(id, k.H);
        kmax->SetValue(id, k.Max);
        kmin->SetValue(id, k.Min);
        dmax->SetTypedTuple(id, k.MaxDirection.data());
        dmin->SetTypedTuple(id, k.MinDirection.data());
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
  vtkPointData* outPD = output->GetPointData();
  outPD->SetNormals(normals);
  for (vtkDoubleArray* a : { gauss.Get(), mean.Get(), kmax.Get(), kmin.Get(), dmax.Get(),
         dmin.Get() })
  {
    outPD->AddArray(a);
  }
  data.AddTo(outPD);
  ctsplines::CopyCellDataBySource(input, output->GetCellData(), source, nOutCells);
  output->GetCellData()->AddArray(bezierCellId);
  for (vtkDoubleArray* a : { gauss.Get(), mean.Get(), kmax.Get(), kmin.Get() })
  {
    output->GetFieldData()->AddArray(RobustRange(a, this->RobustRangePercentile));
  }
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
