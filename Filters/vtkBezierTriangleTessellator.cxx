// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierTriangleTessellator.h"

#include "BezierTriangle.h"
#include "CTSplinesInput.h"

#include <Eigen/Geometry> // for cross

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <sstream>
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
// A point of the per-cell sampling lattice (i, j, k), i + j + k = L, and where its output point
// lives: a corner a, the inner point Step of local edge l (counted from corner l), or interior
// point Step of the cell.
struct LatticePoint
{
  ctk::Vec3 T;
  enum KindType : signed char
  {
    Corner,
    Edge,
    Interior
  } Kind;
  signed char Local; // corner a or edge l
  int Step;
};

struct Lattice
{
  int L = 0;
  std::vector<LatticePoint> Points;
  std::vector<int> Triangles; // 3 lattice indices each, oriented like the cell

  explicit Lattice(int level)
    : L(level)
  {
    auto index = [level](int j, int k) { return k * (level + 1) - k * (k - 1) / 2 + j; };
    int interior = 0;
    for (int k = 0; k <= level; ++k)
    {
      for (int j = 0; j <= level - k; ++j)
      {
        const int i = level - j - k;
        LatticePoint p;
        // Exact zeros on edges: points there depend on the edge's control points only.
        p.T = ctk::Vec3(double(i) / level, double(j) / level, double(k) / level);
        if (j == 0 && k == 0)
        {
          p.Kind = LatticePoint::Corner, p.Local = 0, p.Step = 0;
        }
        else if (j == level)
        {
          p.Kind = LatticePoint::Corner, p.Local = 1, p.Step = 0;
        }
        else if (k == level)
        {
          p.Kind = LatticePoint::Corner, p.Local = 2, p.Step = 0;
        }
        else if (k == 0)
        {
          p.Kind = LatticePoint::Edge, p.Local = 0, p.Step = j;
        }
        else if (i == 0)
        {
          p.Kind = LatticePoint::Edge, p.Local = 1, p.Step = k;
        }
        else if (j == 0)
        {
          p.Kind = LatticePoint::Edge, p.Local = 2, p.Step = i;
        }
        else
        {
          p.Kind = LatticePoint::Interior, p.Local = 0, p.Step = interior++;
        }
        this->Points.push_back(p);
      }
    }
    for (int k = 0; k < level; ++k)
    {
      for (int j = 0; j < level - k; ++j)
      {
        this->Triangles.insert(
          this->Triangles.end(), { index(j, k), index(j + 1, k), index(j, k + 1) });
        if (j + k + 2 <= level)
        {
          this->Triangles.insert(
            this->Triangles.end(), { index(j + 1, k), index(j + 1, k + 1), index(j, k + 1) });
        }
      }
    }
  }
};

// Connectivity of the Bézier cells as flat arrays, read concurrently later.
struct BezierCells
{
  std::vector<vtkIdType> Offsets{ 0 };
  std::vector<vtkIdType> Ids;
  std::vector<signed char> Degree;
};

std::string GatherBezierCells(vtkDataSet* ds, BezierCells& cells)
{
  const vtkIdType nCells = ds->GetNumberOfCells();
  cells.Degree.resize(nCells);
  cells.Offsets.resize(nCells + 1);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    const int type = ds->GetCellType(c);
    if (type != VTK_BEZIER_TRIANGLE)
    {
      std::ostringstream os;
      os << "cell " << c << " is a " << vtkCellTypes::GetClassNameFromTypeId(type)
         << " (VTK cell type " << type << "); only VTK_BEZIER_TRIANGLE cells are accepted";
      return os.str();
    }
    ds->GetCellPoints(c, ids);
    const vtkIdType npts = ids->GetNumberOfIds();
    int degree = 1;
    while (degree < ctk::MaxDegree && ctk::BezierPointCount(degree) < npts)
    {
      ++degree;
    }
    if (ctk::BezierPointCount(degree) != npts)
    {
      std::ostringstream os;
      os << "Bezier triangle cell " << c << " has " << npts
         << " points, which is not (n+1)(n+2)/2 for an order n in 1.." << ctk::MaxDegree;
      return os.str();
    }
    cells.Degree[c] = static_cast<signed char>(degree);
    cells.Ids.insert(cells.Ids.end(), ids->GetPointer(0), ids->GetPointer(0) + npts);
    cells.Offsets[c + 1] = static_cast<vtkIdType>(cells.Ids.size());
  }
  return {};
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
  BezierCells cells;
  std::string error = GatherBezierCells(input, cells);
  std::vector<double> weights, uv;
  vtkPointData* pd = input->GetPointData();
  const vtkIdType nInPoints = input->GetNumberOfPoints();
  // Optional per-point arrays: checked for size and finiteness, then copied.
  auto readOptional = [&](vtkDataArray* array, int components, std::vector<double>& out) {
    if (!array || !error.empty())
    {
      return array;
    }
    const std::string what =
      std::string("point data array '") + (array->GetName() ? array->GetName() : "") + "'";
    error = ctsplines::CopyArray(array, what, components, "point", out);
    if (error.empty() && array->GetNumberOfTuples() != nInPoints)
    {
      error = what + " has " + std::to_string(array->GetNumberOfTuples()) + " tuples for " +
        std::to_string(nInPoints) + " points";
    }
    return array;
  };
  // VTK's Bézier cells read the active rational weights attribute; the spec names the array.
  vtkDataArray* weightArray = pd->GetRationalWeights();
  readOptional(weightArray ? weightArray : ctsplines::FindArray(pd, "RationalWeights"), 1, weights);
  vtkDataArray* uvArray = readOptional(ctsplines::FindArray(pd, this->UVArrayName), 2, uv);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  std::vector<ctk::Vec3> X(nInPoints);
  for (vtkIdType p = 0; p < nInPoints; ++p)
  {
    input->GetPoint(p, X[p].data());
  }
  std::vector<std::vector<int>> orders(ctk::MaxDegree + 1);
  for (signed char n : cells.Degree)
  {
    if (orders[n].empty())
    {
      orders[n] = ctk::VtkBezierTriangleOrder(n);
    }
  }

  // 2. Shared corners (by point id) and edges (by the two corner point ids), each owned by the
  // first cell that uses it. Edges are bucketed by their lower corner: O(n).
  const int L = this->SubdivisionLevel;
  std::vector<vtkIdType> cornerOf(nInPoints, -1);
  std::vector<vtkIdType> cornerOwner;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int a = 0; a < 3; ++a)
    {
      vtkIdType& corner = cornerOf[cells.Ids[cells.Offsets[c] + a]];
      if (corner < 0)
      {
        corner = static_cast<vtkIdType>(cornerOwner.size());
        cornerOwner.push_back(c);
      }
    }
  }
  const vtkIdType nCorners = static_cast<vtkIdType>(cornerOwner.size());
  auto cornerId = [&](vtkIdType c, int a) { return cornerOf[cells.Ids[cells.Offsets[c] + a]]; };
  std::vector<vtkIdType> bucketStart(nCorners + 1, 0);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      ++bucketStart[std::min(cornerId(c, l), cornerId(c, (l + 1) % 3)) + 1];
    }
  }
  for (vtkIdType v = 0; v < nCorners; ++v)
  {
    bucketStart[v + 1] += bucketStart[v];
  }
  std::vector<vtkIdType> bucketItems(3 * nCells), fill(bucketStart.begin(), bucketStart.end() - 1);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      bucketItems[fill[std::min(cornerId(c, l), cornerId(c, (l + 1) % 3))]++] = 3 * c + l;
    }
  }
  std::vector<vtkIdType> cellEdge(3 * nCells), edgeOwner;
  for (vtkIdType v = 0; v < nCorners; ++v)
  {
    for (vtkIdType i = bucketStart[v]; i < bucketStart[v + 1]; ++i)
    {
      const vtkIdType ce = bucketItems[i], c = ce / 3;
      const int l = static_cast<int>(ce % 3);
      const vtkIdType other = std::max(cornerId(c, l), cornerId(c, (l + 1) % 3));
      vtkIdType edge = -1;
      for (vtkIdType k = bucketStart[v]; k < i && edge < 0; ++k)
      {
        const vtkIdType cek = bucketItems[k], ck = cek / 3;
        const int lk = static_cast<int>(cek % 3);
        if (std::max(cornerId(ck, lk), cornerId(ck, (lk + 1) % 3)) == other)
        {
          edge = cellEdge[cek];
        }
      }
      if (edge < 0)
      {
        // Items are in cell order, so the first cell seen owns the edge.
        edge = static_cast<vtkIdType>(edgeOwner.size());
        edgeOwner.push_back(c);
      }
      cellEdge[ce] = edge;
    }
  }
  const vtkIdType nEdges = static_cast<vtkIdType>(edgeOwner.size());
  const vtkIdType nInterior = static_cast<vtkIdType>(L - 1) * (L - 2) / 2;
  const vtkIdType edgeBase = nCorners, interiorBase = nCorners + nEdges * (L - 1);
  const vtkIdType nOutPoints = interiorBase + nCells * nInterior;
  const Lattice lattice(L);
  const vtkIdType trianglesPerCell = static_cast<vtkIdType>(L) * L;
  const vtkIdType nOutCells = nCells * trianglesPerCell;

  // Output id of lattice point p of cell c, and whether c computes it.
  auto outputId = [&](vtkIdType c, const LatticePoint& p, bool& owned) -> vtkIdType {
    switch (p.Kind)
    {
      case LatticePoint::Corner:
      {
        const vtkIdType v = cornerId(c, p.Local);
        owned = cornerOwner[v] == c;
        return v;
      }
      case LatticePoint::Edge:
      {
        const vtkIdType e = cellEdge[3 * c + p.Local];
        owned = edgeOwner[e] == c;
        // Stored from the lower corner id: walk backwards when the cell's edge runs downwards.
        const bool forward = cornerId(c, p.Local) <= cornerId(c, (p.Local + 1) % 3);
        return edgeBase + e * (L - 1) + (forward ? p.Step : L - p.Step) - 1;
      }
      default:
        owned = true;
        return interiorBase + c * nInterior + p.Step;
    }
  };

  // 3. Output arrays, then every cell fills its triangles and the points it owns.
  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(nOutPoints);
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nOutPoints);
  vtkNew<vtkDoubleArray> uvOut;
  uvOut->SetName("UV");
  uvOut->SetNumberOfComponents(2);
  if (uvArray)
  {
    uvOut->SetNumberOfTuples(nOutPoints);
  }
  vtkNew<vtkIdTypeArray> offsets, connectivity, bezierCellId;
  offsets->SetNumberOfTuples(nOutCells + 1);
  connectivity->SetNumberOfTuples(3 * nOutCells);
  bezierCellId->SetName("BezierCellId");
  bezierCellId->SetNumberOfTuples(nOutCells);
  double* xyz = coords->GetPointer(0);
  double* nrm = normals->GetPointer(0);
  double* uvw = uvArray ? uvOut->GetPointer(0) : nullptr;
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  vtkIdType* source = bezierCellId->GetPointer(0);
  const bool rational = !weights.empty();

  auto tessellate = [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints], Q[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    for (vtkIdType c = begin; c < end; ++c)
    {
      const int n = cells.Degree[c];
      const std::vector<int>& order = orders[n];
      const vtkIdType* ids = &cells.Ids[cells.Offsets[c]];
      for (int p = 0; p < ctk::BezierPointCount(n); ++p)
      {
        P[order[p]] = X[ids[p]];
        if (rational)
        {
          w[order[p]] = weights[ids[p]];
        }
        if (uvw)
        {
          Q[order[p]] = ctk::Vec3(uv[2 * ids[p]], uv[2 * ids[p] + 1], 0.0);
        }
      }
      const double* wp = rational ? w : nullptr;
      for (const LatticePoint& lp : lattice.Points)
      {
        bool owned = false;
        const vtkIdType id = outputId(c, lp, owned);
        if (!owned)
        {
          continue;
        }
        ctk::BezierJet jet = ctk::EvaluateBezierTriangle(n, P, wp, lp.T, 1);
        std::copy_n(jet.Value.data(), 3, xyz + 3 * id);
        // Parametric derivatives of the cell's (r, s): t = (1 - r - s, r, s).
        ctk::Vec3 dr = jet.DT[1] - jet.DT[0], ds = jet.DT[2] - jet.DT[0];
        ctk::Vec3 normal = dr.cross(ds);
        if (!(normal.norm() > 1e-12 * (dr.squaredNorm() + ds.squaredNorm())))
        {
          // Singular point (e.g. a collapsed corner): take the limit from inside the cell.
          const ctk::Vec3 inside = (1 - 1e-7) * lp.T + ctk::Vec3::Constant(1e-7 / 3);
          jet = ctk::EvaluateBezierTriangle(n, P, wp, inside, 1);
          dr = jet.DT[1] - jet.DT[0];
          ds = jet.DT[2] - jet.DT[0];
          normal = dr.cross(ds);
        }
        const double length = normal.norm();
        if (length > 0)
        {
          normal /= length;
        }
        std::copy_n(normal.data(), 3, nrm + 3 * id);
        if (uvw)
        {
          const ctk::Vec3 q = ctk::EvaluateBezierTriangle(n, Q, wp, lp.T, 0).Value;
          uvw[2 * id] = q.x();
          uvw[2 * id + 1] = q.y();
        }
      }
      for (vtkIdType m = 0; m < trianglesPerCell; ++m)
      {
        const vtkIdType cell = c * trianglesPerCell + m;
        for (int a = 0; a < 3; ++a)
        {
          bool owned = false;
          conn[3 * cell + a] = outputId(c, lattice.Points[lattice.Triangles[3 * m + a]], owned);
        }
        off[cell] = 3 * cell;
        source[cell] = c;
      }
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
  if (uvArray)
  {
    output->GetPointData()->AddArray(uvOut);
  }
  output->GetCellData()->AddArray(bezierCellId);
  for (const char* name : { "MacroTriangleId", "MicroTriangleId" })
  {
    vtkDataArray* in = input->GetCellData()->GetArray(name);
    if (!in)
    {
      continue;
    }
    vtkSmartPointer<vtkDataArray> out = vtkSmartPointer<vtkDataArray>::Take(in->NewInstance());
    out->SetName(name);
    out->SetNumberOfComponents(in->GetNumberOfComponents());
    out->SetNumberOfTuples(nOutCells);
    vtkSMPTools::For(0, nCells, [&](vtkIdType begin, vtkIdType end) {
      for (vtkIdType c = begin; c < end; ++c)
      {
        for (vtkIdType m = 0; m < trianglesPerCell; ++m)
        {
          out->SetTuple(c * trianglesPerCell + m, c, in);
        }
      }
    });
    output->GetCellData()->AddArray(out);
  }
  this->UpdateProgress(1.0);
  return 1;
}

void vtkBezierTriangleTessellator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
}
