// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineContinuityFilter.h"

#include "BezierTriangle.h"
#include "CTSplinesArrayRanges.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "EdgeContinuity.h"
#include "MeshTopology.h"

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

// The input, validated and flattened so that the parallel part reads plain arrays.
struct ContinuityInput
{
  ctsplines::BezierCells Cells;
  std::vector<vtkIdType> MacroIds, FaceIds; // empty: no such array
};

// Rule A compares polynomial nets: rational weights must be constant per cell.
std::string CheckPolynomial(const ctsplines::BezierCells& cells)
{
  for (vtkIdType c = 0; c < cells.NumberOfCells() && !cells.Weights.empty(); ++c)
  {
    const vtkIdType* ids = cells.CellIds(c);
    const double w0 = cells.Weights[ids[0]];
    for (int p = 1; p < ctk::BezierPointCount(cells.Degree[c]); ++p)
    {
      if (std::abs(cells.Weights[ids[p]] - w0) > 1e-14 * std::abs(w0))
      {
        return "cell " + std::to_string(c) +
          " is rational (its weights are not all equal); the continuity filter compares "
          "polynomial Bezier nets";
      }
    }
  }
  return std::string();
}

std::string ReadInput(vtkDataSet* input, const std::string& uvName, const std::string& macroName,
  const std::string& faceName, ContinuityInput& in)
{
  std::string error = ctsplines::GatherBezierCellsWithUV(input, uvName, in.Cells,
    "the domain point (u, v) of each control point, needed by Rule A");
  if (error.empty())
  {
    error = CheckPolynomial(in.Cells);
  }
  auto readIds = [&](const std::string& name, std::vector<vtkIdType>& out) {
    vtkDataArray* a = ctsplines::FindArray(input->GetCellData(), name);
    if (!a || !error.empty())
    {
      return;
    }
    error = ctsplines::CopyIdArray(
      a, "cell data array '" + name + "'", in.Cells.NumberOfCells(), "cell", -1, out);
  };
  readIds(macroName, in.MacroIds);
  readIds(faceName, in.FaceIds);
  return error;
}

// The edges of the cells, by corner keys (point ids, merged by coordinates when asked).
struct EdgeMatching
{
  std::vector<ctk::Id> Corners; // 3 corner keys per cell
  std::vector<vtkIdType> KeyPoint; // a point id of each key
  ctk::MeshTopology Topology;
};

std::string MatchEdges(const ctsplines::BezierCells& cells, bool coincident, double tolerance,
  EdgeMatching& edges)
{
  double radius = -1;
  if (coincident)
  {
    Eigen::AlignedBox3d box;
    for (vtkIdType c = 0; c < cells.NumberOfCells(); ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        box.extend(cells.Points[cells.CellIds(c)[a]]);
      }
    }
    radius = tolerance * box.diagonal().norm();
  }
  vtkIdType nKeys = 0;
  edges.Corners = CornerKeys(cells, radius, nKeys, edges.KeyPoint);
  const ctk::TopologyStatus status = ctk::BuildMeshTopology(
    nKeys, cells.NumberOfCells(), edges.Corners.data(), edges.Topology);
  return status.Ok ? std::string()
                   : "cannot match the cells' edges (corners numbered after merging coincident "
                     "points): " +
      status.Message;
}

int KindOf(const ContinuityInput& in, vtkIdType A, vtkIdType B)
{
  if (B < 0)
  {
    return vtkSplineContinuityFilter::Boundary;
  }
  if (!in.FaceIds.empty() && in.FaceIds[A] != in.FaceIds[B])
  {
    return vtkSplineContinuityFilter::Interface;
  }
  const bool sameMacroTriangle = !in.MacroIds.empty() && in.MacroIds[A] == in.MacroIds[B];
  return sameMacroTriangle ? vtkSplineContinuityFilter::Micro : vtkSplineContinuityFilter::Macro;
}

// The kernel's measures of interior edge e (cells A < B); PA and PB receive the two nets.
ctk::EdgeContinuity MeasureEdge(const ContinuityInput& in, const EdgeMatching& edges, vtkIdType e,
  int kind, int samples, ctk::Vec3* PA, ctk::Vec3* PB)
{
  const ctsplines::BezierCells& cells = in.Cells;
  const ctk::MeshTopology& topology = edges.Topology;
  const vtkIdType A = topology.EdgeTriangles[e][0], B = topology.EdgeTriangles[e][1];
  ctk::EdgePatch sideA, sideB;
  // Corners of the edge in both cells: A's local edge la joins corners la, la + 1.
  const int la = topology.EdgeLocalIndex[e][0];
  sideA.EdgeCorners = { la, (la + 1) % 3 };
  for (int a = 0; a < 3; ++a)
  {
    for (int i = 0; i < 2; ++i)
    {
      if (edges.Corners[3 * B + a] == edges.Corners[3 * A + sideA.EdgeCorners[i]])
      {
        sideB.EdgeCorners[i] = a;
      }
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    const vtkIdType ia = cells.CellIds(A)[a], ib = cells.CellIds(B)[a];
    sideA.Domain[a] = ctk::Vec2(cells.UV[2 * ia], cells.UV[2 * ia + 1]);
    sideB.Domain[a] = ctk::Vec2(cells.UV[2 * ib], cells.UV[2 * ib + 1]);
  }
  // Weights, if any, are constant per cell (checked): the nets are polynomial.
  double w[ctk::MaxBezierPoints];
  cells.Net(A, PA, w);
  cells.Net(B, PB, w);
  sideA.Degree = cells.Degree[A];
  sideB.Degree = cells.Degree[B];
  sideA.Points = PA;
  sideB.Points = PB;
  ctk::EdgeContinuityOptions options;
  options.G1Samples = samples;
  options.Eq7 = kind == vtkSplineContinuityFilter::Macro;
  return ctk::MeasureEdgeContinuity(sideA, sideB, options);
}

// The per-edge output: EdgeKind, Cells and the measures, each edge written by one task.
struct EdgeArrays
{
  explicit EdgeArrays(vtkIdType nEdges)
  {
    for (int m = 0; m < NumberOfMeasures; ++m)
    {
      this->Measures[m] = vtkSmartPointer<vtkDoubleArray>::New();
      this->Measures[m]->SetName(MeasureNames[m]);
      this->Measures[m]->SetNumberOfTuples(nEdges);
    }
    this->Kinds->SetName("EdgeKind");
    this->Kinds->SetNumberOfTuples(nEdges);
    this->Cells->SetName("Cells");
    this->Cells->SetNumberOfComponents(2);
    this->Cells->SetNumberOfTuples(nEdges);
  }
  void Write(vtkIdType e, vtkIdType A, vtkIdType B, int kind, const double* value)
  {
    this->Cells->SetTypedComponent(e, 0, A);
    this->Cells->SetTypedComponent(e, 1, B);
    this->Kinds->SetValue(e, static_cast<unsigned char>(kind));
    for (int m = 0; m < NumberOfMeasures; ++m)
    {
      this->Measures[m]->SetValue(e, value[m]);
    }
  }
  vtkSmartPointer<vtkDoubleArray> Measures[NumberOfMeasures];
  vtkNew<vtkUnsignedCharArray> Kinds;
  vtkNew<vtkIdTypeArray> Cells;
};

// One point per corner key, one line per edge, and the per-edge cell data.
void FillGeometry(const ctsplines::BezierCells& cells, const EdgeMatching& edges,
  const EdgeArrays& arrays, vtkPolyData* output)
{
  const vtkIdType nKeys = static_cast<vtkIdType>(edges.KeyPoint.size());
  const vtkIdType nEdges = static_cast<vtkIdType>(edges.Topology.Edges.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nKeys);
  for (vtkIdType k = 0; k < nKeys; ++k)
  {
    points->SetPoint(k, cells.Points[edges.KeyPoint[k]].data());
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
    connectivity->SetValue(2 * e, edges.Topology.Edges[e][0]);
    connectivity->SetValue(2 * e + 1, edges.Topology.Edges[e][1]);
  }
  vtkNew<vtkCellArray> lines;
  lines->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetLines(lines);
  vtkCellData* cd = output->GetCellData();
  cd->AddArray(arrays.Kinds);
  cd->AddArray(arrays.Cells);
  for (int m = 0; m < NumberOfMeasures; ++m)
  {
    cd->AddArray(arrays.Measures[m]);
  }
}

// Summary per kind, in edge order (deterministic): K_EdgeCount, K_<measure>_Max and _Mean.
void Summarise(const EdgeArrays& arrays, vtkFieldData* fd)
{
  double sum[NumberOfKinds][NumberOfMeasures] = {}, max[NumberOfKinds][NumberOfMeasures] = {};
  vtkIdType count[NumberOfKinds] = {};
  for (vtkIdType e = 0; e < arrays.Kinds->GetNumberOfTuples(); ++e)
  {
    const int kind = arrays.Kinds->GetValue(e);
    ++count[kind];
    for (int m = 0; m < NumberOfMeasures; ++m)
    {
      const double v = arrays.Measures[m]->GetValue(e);
      if (!std::isnan(v))
      {
        sum[kind][m] += v;
        max[kind][m] = std::max(max[kind][m], v);
      }
    }
  }
  auto addValue = [fd](const std::string& name, double v) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->InsertNextValue(v);
    fd->AddArray(a);
  };
  for (int kind = 0; kind < NumberOfKinds; ++kind)
  {
    const std::string prefix =
      std::string(vtkSplineContinuityFilter::GetEdgeKindName(kind)) + "_";
    addValue(prefix + "EdgeCount", static_cast<double>(count[kind]));
    for (int m = 0; m < NumberOfMeasures; ++m)
    {
      if (m == 4 && kind != vtkSplineContinuityFilter::Macro)
      {
        continue;
      }
      addValue(prefix + MeasureNames[m] + "_Max", max[kind][m]);
      addValue(prefix + MeasureNames[m] + "_Mean", count[kind] ? sum[kind][m] / count[kind] : 0);
    }
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
  if (input->GetNumberOfCells() == 0)
  {
    vtkErrorMacro(<< "empty input: no VTK_BEZIER_TRIANGLE cells to measure continuity of");
    return 0;
  }

  // 1. Validate and flatten the input; 2. edges by corner keys.
  ContinuityInput in;
  EdgeMatching edges;
  std::string error = ReadInput(
    input, this->UVArrayName, this->MacroTriangleIdArrayName, this->FaceIdArrayName, in);
  if (error.empty())
  {
    error = MatchEdges(in.Cells, this->MatchCoincidentEdges, this->Tolerance, edges);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  this->UpdateProgress(0.1);

  // 3. Every edge measured by the kernel, in one task.
  const vtkIdType nEdges = static_cast<vtkIdType>(edges.Topology.Edges.size());
  EdgeArrays arrays(nEdges);
  std::vector<unsigned char> failed(nEdges, 0);
  const int samples = this->G1Samples;
  auto measure = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 PA[ctk::MaxBezierPoints], PB[ctk::MaxBezierPoints];
    for (vtkIdType e = begin; e < end; ++e)
    {
      const vtkIdType A = edges.Topology.EdgeTriangles[e][0];
      const vtkIdType B = edges.Topology.EdgeTriangles[e][1];
      const int kind = KindOf(in, A, B);
      // Boundary edges have zero jumps and angle.
      double value[NumberOfMeasures] = { 0, 0, 0, 0, std::numeric_limits<double>::quiet_NaN() };
      if (B >= 0)
      {
        const ctk::EdgeContinuity m = MeasureEdge(in, edges, e, kind, samples, PA, PB);
        failed[e] = !m.Error.empty();
        const double measured[NumberOfMeasures] = { m.C0Gap, m.C1Jump, m.C2Jump, m.G1Angle,
          m.C2JumpEq7 };
        std::copy_n(measured, NumberOfMeasures, value);
      }
      arrays.Write(e, A, B, kind, value);
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nEdges, 20, 0.1, 0.95, measure))
  {
    output->Initialize();
    return 1;
  }
  // The first failed edge, measured again for its message (deterministic).
  const auto first = std::find(failed.begin(), failed.end(), 1);
  if (first != failed.end())
  {
    const vtkIdType e = first - failed.begin();
    const vtkIdType A = edges.Topology.EdgeTriangles[e][0];
    const vtkIdType B = edges.Topology.EdgeTriangles[e][1];
    ctk::Vec3 PA[ctk::MaxBezierPoints], PB[ctk::MaxBezierPoints];
    vtkErrorMacro(<< "cannot measure the edge between cells " << A << " (side A) and " << B
                  << " (side B): "
                  << MeasureEdge(in, edges, e, KindOf(in, A, B), samples, PA, PB).Error);
    output->Initialize();
    return 0;
  }

  // 4. Geometry and cell data; 5. summary per kind.
  FillGeometry(in.Cells, edges, arrays, output);
  Summarise(arrays, output->GetFieldData());
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
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
