// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierTriangleTessellator.h"

#include "BezierTriangle.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "CTSplinesSMP.h" // for AllocateTuples

#include <Eigen/Geometry> // for cross

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <vector>

vtkStandardNewMacro(vtkBezierTriangleTessellator);

vtkBezierTriangleTessellator::vtkBezierTriangleTessellator() = default;
vtkBezierTriangleTessellator::~vtkBezierTriangleTessellator() = default;

int vtkBezierTriangleTessellator::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

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
  std::string error = ctsplines::GatherBezierCellsWithUV(input, this->UVArrayName, cells);
  const bool withUV = !cells.UV.empty();
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
  const vtkIdType trianglesPerCell = static_cast<vtkIdType>(L) * L;
  const vtkIdType nOutCells = nCells * trianglesPerCell;

  // 3. Output arrays, then every cell fills its triangles and the points it owns.
  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  ctsplines::AllocateTuples(coords, nOutPoints);
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  ctsplines::AllocateTuples(normals, nOutPoints);
  vtkNew<vtkDoubleArray> uvOut;
  uvOut->SetName("UV");
  uvOut->SetNumberOfComponents(2);
  if (withUV)
  {
    ctsplines::AllocateTuples(uvOut, nOutPoints);
  }
  vtkNew<vtkIdTypeArray> offsets, connectivity, bezierCellId;
  ctsplines::AllocateTuples(offsets, nOutCells + 1);
  ctsplines::AllocateTuples(connectivity, 3 * nOutCells);
  bezierCellId->SetName("BezierCellId");
  ctsplines::AllocateTuples(bezierCellId, nOutCells);
  double* xyz = coords->GetPointer(0);
  double* nrm = normals->GetPointer(0);
  double* uvw = withUV ? uvOut->GetPointer(0) : nullptr;
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  vtkIdType* source = bezierCellId->GetPointer(0);

  auto tessellate = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints], Q[ctk::MaxBezierPoints], R[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    for (vtkIdType c = begin; c < end; ++c)
    {
      const int n = cells.Degree[c];
      const double* wp = cells.Net(c, P, w);
      ctk::RelativeNet(n, P, R); // for the normals' accuracy
      if (uvw)
      {
        cells.UVNet(c, Q);
      }
      for (int li = 0; li < static_cast<int>(lattice.Points.size()); ++li)
      {
        const ctsplines::SamplingLattice::Point& lp = lattice.Points[li];
        bool owned = false;
        const vtkIdType id = numbering.OutputId(c, li, owned);
        if (!owned)
        {
          continue;
        }
        const ctk::Vec3 x = ctk::EvaluateBezierTriangle(n, P, wp, lp.T, 0).Value;
        std::copy_n(x.data(), 3, xyz + 3 * id);
        const ctk::Vec3 normal = ctk::PatchNormal(n, R, wp, lp.T);
        std::copy_n(normal.data(), 3, nrm + 3 * id);
        if (uvw)
        {
          const ctk::Vec3 q = ctk::EvaluateBezierTriangle(n, Q, wp, lp.T, 0).Value;
          uvw[2 * id] = q.x();
          uvw[2 * id + 1] = q.y();
        }
      }
      numbering.WriteTriangles(c, off, conn, source);
    }
  };
  // Blocks of cells in sequence, each in parallel, so progress and abort are handled on the
  // calling thread.
  const vtkIdType nBlocks = std::min<vtkIdType>(nCells, 20);
  for (vtkIdType b = 0; b < nBlocks; ++b)
  {
    vtkSMPTools::For(b * nCells / nBlocks, (b + 1) * nCells / nBlocks, tessellate);
    this->UpdateProgress(0.95 * double(b + 1) / double(nBlocks));
    if (this->GetAbortExecute())
    {
      output->Initialize();
      return 1;
    }
  }
  off[nOutCells] = 3 * nOutCells;

  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  outPoints->SetData(coords);
  output->SetPolys(polys);
  output->GetPointData()->SetNormals(normals);
  if (withUV)
  {
    output->GetPointData()->AddArray(uvOut);
  }
  output->GetCellData()->AddArray(bezierCellId);
  ctsplines::RepeatCellIdArrays(input, output->GetCellData(), trianglesPerCell);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkBezierTriangleTessellator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
}
