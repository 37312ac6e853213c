// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierTriangleTessellator.h"

#include "BezierTriangle.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "CTSplinesSMP.h" // for AllocateTuples

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkBezierTriangleTessellator);

vtkBezierTriangleTessellator::vtkBezierTriangleTessellator() = default;
vtkBezierTriangleTessellator::~vtkBezierTriangleTessellator() = default;

int vtkBezierTriangleTessellator::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

namespace
{
// The output being filled: conforming points (LatticeNumbering), exact normals, carried point
// data and the triangles of every cell.
struct Tessellation
{
  const ctsplines::BezierCells& Cells;
  const ctsplines::SamplingLattice& Lattice;
  const ctsplines::LatticeNumbering& Numbering;
  ctsplines::PointDataInterpolator& Data;
  vtkDoubleArray* Coordinates;
  vtkDoubleArray* Normals;
  vtkIdType* Offsets;
  vtkIdType* Connectivity;
  vtkIdType* Source;

  // Points owned by cell c (positions, normals, data) and its triangles.
  void Cell(vtkIdType c, ctk::Vec3* P, ctk::Vec3* R, double* w, ctk::Vec3* nets) const;
  // Splits the points where a cell's own normal differs from the owner's by more than the
  // feature angle (the copies keep the coordinates); returns the number of copies.
  vtkIdType SplitSharpPoints(double featureAngle);
};

void Tessellation::Cell(vtkIdType c, ctk::Vec3* P, ctk::Vec3* R, double* w, ctk::Vec3* nets) const
{
  const int n = this->Cells.Degree[c];
  const double* wp = this->Cells.Net(c, P, w);
  ctk::RelativeNet(n, P, R); // for the normals' accuracy
  this->Data.LoadNets(this->Cells, c, nets);
  double* xyz = this->Coordinates->GetPointer(0);
  double* nrm = this->Normals->GetPointer(0);
  for (int li = 0; li < static_cast<int>(this->Lattice.Points.size()); ++li)
  {
    const ctk::Vec3& t = this->Lattice.Points[li].T;
    bool owned = false;
    const vtkIdType id = this->Numbering.OutputId(c, li, owned);
    if (!owned)
    {
      continue; // each point is written by its owner only
    }
    const ctk::Vec3 x = ctk::EvaluateBezierTriangle(n, P, wp, t, 0).Value;
    std::copy_n(x.data(), 3, xyz + 3 * id);
    const ctk::Vec3 normal = ctk::PatchNormal(n, R, wp, t);
    std::copy_n(normal.data(), 3, nrm + 3 * id);
    this->Data.Write(n, nets, wp, t, id);
  }
  this->Numbering.WriteTriangles(c, this->Offsets, this->Connectivity, this->Source);
}

vtkIdType Tessellation::SplitSharpPoints(double featureAngle)
{
  struct Use
  {
    vtkIdType Id, Cell, NewId;
    int Lattice;
    ctk::Vec3 Normal;
  };
  const double cosine = std::cos(vtkMath::RadiansFromDegrees(featureAngle));
  const vtkIdType nCells = this->Cells.NumberOfCells();
  // Chunks of cells in parallel, each collecting its uses in cell order (deterministic).
  const vtkIdType nChunks = std::min<vtkIdType>(nCells, 256);
  std::vector<std::vector<Use>> chunks(nChunks);
  const double* nrm = this->Normals->GetPointer(0);
  vtkSMPTools::For(0, nChunks, [&](vtkIdType b, vtkIdType e) {
    ctk::Vec3 P[ctk::MaxBezierPoints], R[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    for (vtkIdType chunk = b; chunk < e; ++chunk)
    {
      for (vtkIdType c = chunk * nCells / nChunks; c < (chunk + 1) * nCells / nChunks; ++c)
      {
        const int n = this->Cells.Degree[c];
        const double* wp = this->Cells.Net(c, P, w);
        ctk::RelativeNet(n, P, R);
        for (int li = 0; li < static_cast<int>(this->Lattice.Points.size()); ++li)
        {
          bool owned = true;
          const vtkIdType id = this->Numbering.OutputId(c, li, owned);
          if (owned)
          {
            continue;
          }
          const ctk::Vec3 normal = ctk::PatchNormal(n, R, wp, this->Lattice.Points[li].T);
          if (!(normal.dot(ctk::Vec3(nrm + 3 * id)) >= cosine))
          {
            chunks[chunk].push_back({ id, c, -1, li, normal });
          }
        }
      }
    }
  });
  std::vector<Use> uses;
  for (const std::vector<Use>& chunk : chunks)
  {
    uses.insert(uses.end(), chunk.begin(), chunk.end());
  }
  // Per point, in cell order: a use joins the first copy of the point whose normal is within
  // the angle of its own, or makes a new copy with its normal.
  std::stable_sort(
    uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.Id < b.Id; });
  std::vector<vtkIdType> copiedFrom;
  std::vector<ctk::Vec3> copyNormals;
  for (size_t begin = 0, u = 0; u < uses.size(); begin = u)
  {
    const size_t groupBase = copiedFrom.size();
    for (; u < uses.size() && uses[u].Id == uses[begin].Id; ++u)
    {
      size_t g = groupBase;
      while (g < copiedFrom.size() && !(uses[u].Normal.dot(copyNormals[g]) >= cosine))
      {
        ++g;
      }
      if (g == copiedFrom.size())
      {
        copiedFrom.push_back(uses[u].Id);
        copyNormals.push_back(uses[u].Normal);
      }
      uses[u].NewId = this->Coordinates->GetNumberOfTuples() + static_cast<vtkIdType>(g);
    }
  }
  const vtkIdType first = this->Coordinates->GetNumberOfTuples();
  const vtkIdType copies = static_cast<vtkIdType>(copiedFrom.size());
  for (vtkDoubleArray* a : { this->Coordinates, this->Normals })
  {
    a->Resize(first + copies); // keeps the values (SetNumberOfTuples alone may not)
    a->SetNumberOfTuples(first + copies);
  }
  for (vtkIdType k = 0; k < copies; ++k)
  {
    this->Coordinates->SetTuple(first + k, copiedFrom[k], this->Coordinates);
    this->Normals->SetTuple(first + k, copyNormals[k].data());
  }
  this->Data.Append(first, copiedFrom);
  // Renumber the triangles of the cells concerned; their entries follow the lattice.
  std::stable_sort(
    uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.Cell < b.Cell; });
  const vtkIdType perCell = 3 * static_cast<vtkIdType>(this->Lattice.L) * this->Lattice.L;
  std::vector<vtkIdType> byLattice(this->Lattice.Points.size(), -1);
  for (size_t begin = 0, u = 0; u < uses.size(); begin = u)
  {
    const vtkIdType c = uses[begin].Cell;
    for (; u < uses.size() && uses[u].Cell == c; ++u)
    {
      byLattice[uses[u].Lattice] = uses[u].NewId;
    }
    vtkIdType* connectivity = this->Connectivity + c * perCell;
    for (vtkIdType k = 0; k < perCell; ++k)
    {
      const vtkIdType id = byLattice[this->Lattice.Triangles[k]];
      connectivity[k] = id >= 0 ? id : connectivity[k];
    }
    for (size_t v = begin; v < u; ++v)
    {
      byLattice[uses[v].Lattice] = -1;
    }
  }
  return copies;
}
} // namespace

int vtkBezierTriangleTessellator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output data object");
    return 0;
  }
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  output->SetPoints(outPoints);
  const vtkIdType nCells = input->GetNumberOfCells();
  if (nCells == 0)
  {
    return 1;
  }

  // 1. Validate and flatten the input so that the parallel part reads plain arrays.
  ctsplines::BezierCells cells;
  std::string error = ctsplines::GatherBezierCells(input, cells);
  if (error.empty())
  {
    error = ctsplines::CheckCellDataArrays(input, "");
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  // 2. Conforming numbering: shared corners and edges are evaluated once, by their owner cell.
  const int L = this->SubdivisionLevel;
  const ctsplines::SamplingLattice lattice(L);
  const ctsplines::LatticeNumbering numbering(cells, lattice, true);
  const vtkIdType nOutPoints = numbering.NumberOfPoints();
  ctsplines::PointDataInterpolator data;
  error = data.Gather(input, this->UVArrayName, nOutPoints);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }

  // 3. Output arrays, then every cell fills its triangles and the points it owns.
  const vtkIdType nOutCells = nCells * L * L;
  vtkNew<vtkDoubleArray> coords, normals;
  normals->SetName("Normals");
  for (vtkDoubleArray* a : { coords.Get(), normals.Get() })
  {
    a->SetNumberOfComponents(3);
    ctsplines::AllocateTuples(a, nOutPoints);
  }
  vtkNew<vtkIdTypeArray> offsets, connectivity, bezierCellId;
  ctsplines::AllocateTuples(offsets, nOutCells + 1);
  ctsplines::AllocateTuples(connectivity, 3 * nOutCells);
  bezierCellId->SetName("BezierCellId");
  ctsplines::AllocateTuples(bezierCellId, nOutCells);
  Tessellation tessellation{ cells, lattice, numbering, data, coords, normals,
    offsets->GetPointer(0), connectivity->GetPointer(0), bezierCellId->GetPointer(0) };
  const auto tessellate = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints], R[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    std::vector<ctk::Vec3> nets(std::max(1, data.NumberOfNets()) * ctk::MaxBezierPoints);
    for (vtkIdType c = begin; c < end; ++c)
    {
      tessellation.Cell(c, P, R, w, nets.data());
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nCells, 20, 0.0, 0.9, tessellate))
  {
    output->Initialize();
    return 1;
  }
  offsets->SetValue(nOutCells, 3 * nOutCells);
  if (this->SplitSharpEdges)
  {
    tessellation.SplitSharpPoints(this->FeatureAngle);
  }

  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  outPoints->SetData(coords);
  output->SetPolys(polys);
  output->GetPointData()->SetNormals(normals);
  data.AddTo(output->GetPointData());
  ctsplines::CopyCellDataBySource(
    input, output->GetCellData(), bezierCellId->GetPointer(0), nOutCells);
  output->GetCellData()->AddArray(bezierCellId);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkBezierTriangleTessellator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "SplitSharpEdges: " << (this->SplitSharpEdges ? "on" : "off") << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
}
