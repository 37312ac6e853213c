// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineContinuityFilter.h"

#include "BezierTriangle.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "MeshTopology.h"
#include "RuleA.h"

#include <Eigen/Geometry> // for cross

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStaticPointLocator.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numeric>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkSplineContinuityFilter);

vtkSplineContinuityFilter::vtkSplineContinuityFilter() = default;
vtkSplineContinuityFilter::~vtkSplineContinuityFilter() = default;

int vtkSplineContinuityFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

const char* vtkSplineContinuityFilter::GetEdgeKindName(int kind)
{
  switch (kind)
  {
    case Macro:
      return "Macro";
    case Micro:
      return "Micro";
    case Boundary:
      return "Boundary";
    case Interface:
      return "Interface";
    default:
      return "Unknown";
  }
}

namespace
{
constexpr int NumberOfKinds = 4;
constexpr int NumberOfMeasures = 5;
const char* const MeasureNames[NumberOfMeasures] = { "C0Gap", "C1Jump", "C2Jump", "G1Angle",
  "C2JumpEq7" };

// Numbers the distinct corner points of the cells (first use order). With a radius >= 0, corners
// within that distance are merged (union-find, smallest number as representative).
std::vector<ctk::Id> CornerKeys(const ctsplines::BezierCells& cells, double radius,
  vtkIdType& nKeys, std::vector<vtkIdType>& keyPoint)
{
  const vtkIdType nCells = cells.NumberOfCells();
  std::vector<vtkIdType> cornerOf(cells.Points.size(), -1), cornerPoint;
  std::vector<ctk::Id> corners(3 * nCells);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int a = 0; a < 3; ++a)
    {
      vtkIdType& k = cornerOf[cells.CellIds(c)[a]];
      if (k < 0)
      {
        k = static_cast<vtkIdType>(cornerPoint.size());
        cornerPoint.push_back(cells.CellIds(c)[a]);
      }
      corners[3 * c + a] = k;
    }
  }
  const vtkIdType nCorners = static_cast<vtkIdType>(cornerPoint.size());
  std::vector<vtkIdType> parent(nCorners);
  std::iota(parent.begin(), parent.end(), 0);
  if (radius >= 0)
  {
    auto find = [&parent](vtkIdType i) {
      while (parent[i] != i)
      {
        i = parent[i] = parent[parent[i]];
      }
      return i;
    };
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(nCorners);
    for (vtkIdType k = 0; k < nCorners; ++k)
    {
      points->SetPoint(k, cells.Points[cornerPoint[k]].data());
    }
    vtkNew<vtkPolyData> cloud;
    cloud->SetPoints(points);
    vtkNew<vtkStaticPointLocator> locator;
    locator->SetDataSet(cloud);
    locator->BuildLocator();
    vtkNew<vtkIdList> near;
    for (vtkIdType k = 0; k < nCorners; ++k)
    {
      locator->FindPointsWithinRadius(radius, cells.Points[cornerPoint[k]].data(), near);
      for (vtkIdType i = 0; i < near->GetNumberOfIds(); ++i)
      {
        const vtkIdType a = find(k), b = find(near->GetId(i));
        parent[std::max(a, b)] = std::min(a, b);
      }
    }
    for (vtkIdType k = 0; k < nCorners; ++k)
    {
      parent[k] = find(k);
    }
  }
  // Compact numbering of the representatives.
  std::vector<vtkIdType> keyOf(nCorners, -1);
  keyPoint.clear();
  for (vtkIdType k = 0; k < nCorners; ++k)
  {
    if (keyOf[parent[k]] < 0)
    {
      keyOf[parent[k]] = static_cast<vtkIdType>(keyPoint.size());
      keyPoint.push_back(cornerPoint[parent[k]]);
    }
  }
  nKeys = static_cast<vtkIdType>(keyPoint.size());
  for (ctk::Id& k : corners)
  {
    k = keyOf[parent[k]];
  }
  return corners;
}

// B's parameter triangle expressed in A's parameters: unchanged when the shared corners have the
// same (u, v) on both sides, else moved by the similarity (with a reflection if needed) that maps
// B's copy of the edge onto A's and puts B's apex on the other side.
void CommonDomain(const ctk::Vec2* DA, int pa, int qa, ctk::Vec2* DB, int pb, int qb)
{
  const ctk::Vec2 Ap = DA[pa], Aq = DA[qa], Bp = DB[pb], Bq = DB[qb];
  const double scale = (Aq - Ap).norm();
  if ((Bp - Ap).norm() <= 1e-9 * scale && (Bq - Aq).norm() <= 1e-9 * scale)
  {
    return;
  }
  using C = std::complex<double>;
  auto z = [](const ctk::Vec2& v) { return C(v.x(), v.y()); };
  const C ap = z(Ap), bp = z(Bp);
  const C direct = (z(Aq) - ap) / (z(Bq) - bp), mirror = (z(Aq) - ap) / std::conj(z(Bq) - bp);
  const int apexA = 3 - pa - qa, apexB = 3 - pb - qb;
  const C apex = ap + direct * (z(DB[apexB]) - bp);
  // B's apex must end up on the side of the edge opposite A's apex.
  const bool reflect = ctk::Cross2(Aq - Ap, DA[apexA] - Ap) *
      ctk::Cross2(Aq - Ap, ctk::Vec2(apex.real(), apex.imag()) - Ap) > 0;
  for (int i = 0; i < 3; ++i)
  {
    const C d = reflect ? ap + mirror * std::conj(z(DB[i]) - bp) : ap + direct * (z(DB[i]) - bp);
    DB[i] = ctk::Vec2(d.real(), d.imag());
  }
}

void Elevate(int from, int to, ctk::Vec3* P)
{
  ctk::Vec3 tmp[ctk::MaxBezierPoints];
  for (int n = from; n < to; ++n)
  {
    ctk::ElevateDegree(n, P, tmp);
    std::copy_n(tmp, ctk::BezierPointCount(n + 1), P);
  }
}

} // namespace

int vtkSplineContinuityFilter::RequestData(
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
    vtkErrorMacro(<< "empty input: no VTK_BEZIER_TRIANGLE cells to measure continuity of");
    return 0;
  }

  // 1. Validate and flatten the input.
  ctsplines::BezierCells cells;
  std::string error = ctsplines::GatherBezierCellsWithUV(input, this->UVArrayName, cells,
    "the domain point (u, v) of each control point, needed by Rule A");
  const std::vector<double>& uv = cells.UV;
  for (vtkIdType c = 0; c < nCells && error.empty() && !cells.Weights.empty(); ++c)
  {
    const vtkIdType* ids = cells.CellIds(c);
    const double w0 = cells.Weights[ids[0]];
    for (int p = 1; p < ctk::BezierPointCount(cells.Degree[c]); ++p)
    {
      if (std::abs(cells.Weights[ids[p]] - w0) > 1e-14 * std::abs(w0))
      {
        error = "cell " + std::to_string(c) +
          " is rational (its weights are not all equal); the continuity filter compares "
          "polynomial Bezier nets";
        break;
      }
    }
  }
  auto readIds = [&](const std::string& name, std::vector<vtkIdType>& out) {
    vtkDataArray* a = ctsplines::FindArray(input->GetCellData(), name);
    if (!a || !error.empty())
    {
      return;
    }
    error = ctsplines::CopyIdArray(a, "cell data array '" + name + "'", nCells, "cell", -1, out);
  };
  std::vector<vtkIdType> macroIds, faceIds;
  readIds(this->MacroTriangleIdArrayName, macroIds);
  readIds(this->FaceIdArrayName, faceIds);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }

  // 2. Edges by corner keys (point ids, merged by coordinates when asked).
  double radius = -1;
  if (this->MatchCoincidentEdges)
  {
    Eigen::AlignedBox3d box;
    for (vtkIdType c = 0; c < nCells; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        box.extend(cells.Points[cells.CellIds(c)[a]]);
      }
    }
    radius = this->Tolerance * box.diagonal().norm();
  }
  vtkIdType nKeys = 0;
  std::vector<vtkIdType> keyPoint;
  const std::vector<ctk::Id> corners = CornerKeys(cells, radius, nKeys, keyPoint);
  ctk::MeshTopology topology;
  const ctk::TopologyStatus status = ctk::BuildMeshTopology(nKeys, nCells, corners.data(), topology);
  if (!status.Ok)
  {
    vtkErrorMacro(<< "cannot match the cells' edges (corners numbered after merging coincident "
                     "points): "
                  << status.Message);
    return 0;
  }
  this->UpdateProgress(0.1);

  // 3. Every edge measured by one task.
  const vtkIdType nEdges = static_cast<vtkIdType>(topology.Edges.size());
  auto makeArray = [nEdges](const char* name, int components) {
    vtkSmartPointer<vtkDoubleArray> a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(nEdges);
    return a;
  };
  vtkSmartPointer<vtkDoubleArray> measures[NumberOfMeasures];
  for (int m = 0; m < NumberOfMeasures; ++m)
  {
    measures[m] = makeArray(MeasureNames[m], 1);
  }
  vtkNew<vtkUnsignedCharArray> kinds;
  kinds->SetName("EdgeKind");
  kinds->SetNumberOfTuples(nEdges);
  vtkNew<vtkIdTypeArray> edgeCells;
  edgeCells->SetName("Cells");
  edgeCells->SetNumberOfComponents(2);
  edgeCells->SetNumberOfTuples(nEdges);
  const int samples = this->G1Samples;
  const double nan = std::numeric_limits<double>::quiet_NaN();

  auto measure = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 PA[ctk::MaxBezierPoints], PB[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    for (vtkIdType e = begin; e < end; ++e)
    {
      const vtkIdType A = topology.EdgeTriangles[e][0], B = topology.EdgeTriangles[e][1];
      edgeCells->SetTypedComponent(e, 0, A);
      edgeCells->SetTypedComponent(e, 1, B);
      double value[NumberOfMeasures] = { 0, 0, 0, 0, nan };
      int kind = Boundary;
      if (B >= 0)
      {
        if (!faceIds.empty() && faceIds[A] != faceIds[B])
        {
          kind = Interface;
        }
        else
        {
          kind = !macroIds.empty() && macroIds[A] == macroIds[B] ? Micro : Macro;
        }
        // Corners of the edge in both cells: A's local edge la joins corners la, la + 1.
        const int la = topology.EdgeLocalIndex[e][0];
        const int pa = la, qa = (la + 1) % 3, apexA = (la + 2) % 3;
        int pb = 0, qb = 0;
        for (int a = 0; a < 3; ++a)
        {
          pb = corners[3 * B + a] == corners[3 * A + pa] ? a : pb;
          qb = corners[3 * B + a] == corners[3 * A + qa] ? a : qb;
        }
        ctk::Vec2 DA[3], DB[3];
        for (int a = 0; a < 3; ++a)
        {
          const vtkIdType ia = cells.CellIds(A)[a], ib = cells.CellIds(B)[a];
          DA[a] = ctk::Vec2(uv[2 * ia], uv[2 * ia + 1]);
          DB[a] = ctk::Vec2(uv[2 * ib], uv[2 * ib + 1]);
        }
        CommonDomain(DA, pa, qa, DB, pb, qb);
        const int nA = cells.Degree[A], nB = cells.Degree[B], n = std::max(nA, nB);
        // Weights, if any, are constant per cell (checked above): the nets are polynomial.
        cells.Net(A, PA, w);
        cells.Net(B, PB, w);
        Elevate(nA, n, PA);
        Elevate(nB, n, PB);
        double jumps[3] = { 0, 0, 0 };
        ctk::RuleAJumps(n, PA, DA, PB, DB, std::min(n, 2), jumps);
        std::copy_n(jumps, 3, value);
        double angle = 0;
        ctk::Vec3 RA[ctk::MaxBezierPoints], RB[ctk::MaxBezierPoints];
        ctk::RelativeNet(n, PA, RA);
        ctk::RelativeNet(n, PB, RB);
        for (int k = 1; k <= samples; ++k)
        {
          const double s = double(k) / (samples + 1);
          ctk::Vec3 tA = ctk::Vec3::Zero(), tB = ctk::Vec3::Zero();
          tA[pa] = 1 - s, tA[qa] = s;
          tB[pb] = 1 - s, tB[qb] = s;
          const double cosine =
            ctk::PatchNormal(n, RA, nullptr, tA).dot(ctk::PatchNormal(n, RB, nullptr, tB));
          angle = std::max(angle, std::acos(std::max(-1.0, std::min(1.0, cosine))));
        }
        value[3] = angle * 180.0 / M_PI;
        if (kind == Macro && n == 3)
        {
          // Eq. (7): both sides' blossoms at (Ui, U2, U3), U2 and U3 the two apexes.
          const int apexB = 3 - pb - qb;
          double eq7 = 0;
          for (int i : { pa, qa })
          {
            const ctk::Vec2 U[3] = { DA[i], DA[apexA], DB[apexB] };
            ctk::Vec3 argsA[3], argsB[3];
            for (int a = 0; a < 3; ++a)
            {
              argsA[a] = ctk::Barycentric(DA[0], DA[1], DA[2], U[a]);
              argsB[a] = ctk::Barycentric(DB[0], DB[1], DB[2], U[a]);
            }
            eq7 = std::max(eq7, (ctk::Blossom(3, PA, argsA) - ctk::Blossom(3, PB, argsB)).norm());
          }
          value[4] = eq7;
        }
      }
      kinds->SetValue(e, static_cast<unsigned char>(kind));
      for (int m = 0; m < NumberOfMeasures; ++m)
      {
        measures[m]->SetValue(e, value[m]);
      }
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nEdges, 20, 0.1, 0.95, measure))
  {
    output->Initialize();
    return 1;
  }

  // 4. Geometry: one point per corner key, one line per edge.
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nKeys);
  for (vtkIdType k = 0; k < nKeys; ++k)
  {
    points->SetPoint(k, cells.Points[keyPoint[k]].data());
  }
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nEdges + 1);
  connectivity->SetNumberOfTuples(2 * nEdges);
  for (vtkIdType e = 0; e <= nEdges; ++e)
  {
    offsets->SetValue(e, 2 * e);
  }
  for (vtkIdType e = 0; e < nEdges; ++e)
  {
    connectivity->SetValue(2 * e, topology.Edges[e][0]);
    connectivity->SetValue(2 * e + 1, topology.Edges[e][1]);
  }
  vtkNew<vtkCellArray> lines;
  lines->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetLines(lines);
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(kinds);
  cd->AddArray(edgeCells);
  for (int m = 0; m < NumberOfMeasures; ++m)
  {
    cd->AddArray(measures[m]);
  }

  // 5. Summary per kind, in edge order (deterministic).
  double sum[NumberOfKinds][NumberOfMeasures] = {}, max[NumberOfKinds][NumberOfMeasures] = {};
  vtkIdType count[NumberOfKinds] = {};
  for (vtkIdType e = 0; e < nEdges; ++e)
  {
    const int kind = kinds->GetValue(e);
    ++count[kind];
    for (int m = 0; m < NumberOfMeasures; ++m)
    {
      const double v = measures[m]->GetValue(e);
      if (!std::isnan(v))
      {
        sum[kind][m] += v;
        max[kind][m] = std::max(max[kind][m], v);
      }
    }
  }
  vtkFieldData* fd = output->GetFieldData();
  auto addValue = [fd](const std::string& name, double v) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->InsertNextValue(v);
    fd->AddArray(a);
  };
  for (int kind = 0; kind < NumberOfKinds; ++kind)
  {
    const std::string prefix = std::string(GetEdgeKindName(kind)) + "_";
    addValue(prefix + "EdgeCount", static_cast<double>(count[kind]));
    for (int m = 0; m < NumberOfMeasures; ++m)
    {
      if (m == 4 && kind != Macro)
      {
        continue;
      }
      addValue(prefix + MeasureNames[m] + "_Max", max[kind][m]);
      addValue(prefix + MeasureNames[m] + "_Mean", count[kind] ? sum[kind][m] / count[kind] : 0);
    }
  }
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSplineContinuityFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MatchCoincidentEdges: " << (this->MatchCoincidentEdges ? "on" : "off") << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "G1Samples: " << this->G1Samples << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
  os << indent << "MacroTriangleIdArrayName: " << this->MacroTriangleIdArrayName << "\n";
  os << indent << "FaceIdArrayName: " << this->FaceIdArrayName << "\n";
}
