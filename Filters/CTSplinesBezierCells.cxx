// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesBezierCells.h"

#include "CTSplinesInput.h"
#include "CTSplinesRecycledArrays.h"
#include "LargeArrays.h"
#include "SplineDataValidation.h"

#include "vtkAbstractArray.h"
#include "vtkBitArray.h"
#include "vtkCellArray.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <sstream>

namespace ctsplines
{
const double* BezierCells::Net(vtkIdType c, ctk::Vec3* P, double* w) const
{
  return GatherNet(this->Orders[this->Degree[c]], this->CellIds(c),
    reinterpret_cast<const double*>(this->Points.data()),
    this->Weights.empty() ? nullptr : this->Weights.data(), P, w);
}

void BezierCells::UVNet(vtkIdType c, ctk::Vec3* Q) const
{
  this->ValueNet(c, this->UV.data(), 2, 0, Q);
}

void BezierCells::ValueNet(
  vtkIdType c, const double* values, int components, int first, ctk::Vec3* Q) const
{
  const int n = this->Degree[c];
  const std::vector<int>& order = this->Orders[n];
  const vtkIdType* ids = this->CellIds(c);
  for (int p = 0; p < ctk::BezierPointCount(n); ++p)
  {
    const double* v = values + ids[p] * components;
    for (int k = 0; k < 3; ++k)
    {
      Q[order[p]][k] = first + k < components ? v[first + k] : 0.0;
    }
  }
}

std::string PointDataInterpolator::Gather(
  vtkDataSet* ds, const std::string& uvName, vtkIdType outputPoints, RecycledArrays* recycled)
{
  this->Arrays.clear();
  this->Nets = 0;
  this->Components = 0;
  vtkPointData* pd = ds->GetPointData();
  vtkDataArray* weights = pd->GetRationalWeights();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* in = pd->GetArray(a);
    if (!in || !in->GetName() || in == weights || in == pd->GetNormals() ||
      !(in->GetDataType() == VTK_DOUBLE || in->GetDataType() == VTK_FLOAT))
    {
      continue;
    }
    const std::string name = in->GetName();
    if (name == "RationalWeights" || name == "Normals" || (name == "UV" && uvName != "UV"))
    {
      continue;
    }
    Array array;
    array.Name = name == uvName ? "UV" : name;
    array.Components = in->GetNumberOfComponents();
    std::string error = CopyArray(in, "point data array '" + name + "'", array.Components,
      ds->GetNumberOfPoints(), "point", array.Values);
    if (!error.empty())
    {
      return error;
    }
    array.Out = NewOutputArray<vtkDoubleArray>(recycled, array.Components, outputPoints);
    array.Out->SetName(array.Name.c_str());
    this->Nets += (array.Components + 2) / 3;
    this->Components += array.Components;
    this->Arrays.push_back(std::move(array));
  }
  return {};
}

void PointDataInterpolator::LoadNets(const BezierCells& cells, vtkIdType c, ctk::Vec3* nets) const
{
  for (const Array& a : this->Arrays)
  {
    for (int first = 0; first < a.Components; first += 3, nets += ctk::MaxBezierPoints)
    {
      cells.ValueNet(c, a.Values.data(), a.Components, first, nets);
    }
  }
}

void PointDataInterpolator::LoadOrdinates(
  const BezierCells& cells, vtkIdType c, const double* weights, double* f) const
{
  const int n = cells.Degree[c];
  const std::vector<int>& order = cells.Orders[n];
  const vtkIdType* ids = cells.CellIds(c);
  for (const Array& a : this->Arrays)
  {
    for (int k = 0; k < a.Components; ++k, f += ctk::MaxBezierPoints)
    {
      for (int p = 0; p < ctk::BezierPointCount(n); ++p)
      {
        const double value = a.Values[ids[p] * a.Components + k];
        f[order[p]] = weights ? weights[order[p]] * value : value;
      }
    }
  }
}

void PointDataInterpolator::Write(const ctk::BezierBasisTable& basis, const double* f,
  int begin, int end, const double* W, const vtkIdType* ids) const
{
  constexpr int batch = 4; // components per Combine
  ctk::BezierBasisTable::BlockArray v[batch];
  for (const Array& a : this->Arrays)
  {
    double* out = a.Out->GetPointer(0);
    for (int first = 0; first < a.Components; first += batch)
    {
      const int count = std::min(batch, a.Components - first);
      basis.Combine(f, count, begin, end, v);
      f += count * ctk::MaxBezierPoints;
      for (int q = 0; q < end - begin; ++q)
      {
        double* o = out + ids[q] * a.Components + first;
        for (int k = 0; k < count; ++k)
        {
          o[k] = v[k][q] / W[q];
        }
      }
    }
  }
}

void PointDataInterpolator::Write(
  int n, const ctk::Vec3* nets, const double* weights, const ctk::Vec3& t, vtkIdType id) const
{
  for (const Array& a : this->Arrays)
  {
    double* out = a.Out->GetPointer(id * a.Components);
    for (int first = 0; first < a.Components; first += 3, nets += ctk::MaxBezierPoints)
    {
      const ctk::Vec3 v = ctk::EvaluateBezierTriangle(n, nets, weights, t, 0).Value;
      std::copy_n(v.data(), std::min(3, a.Components - first), out + first);
    }
  }
}

void PointDataInterpolator::Append(vtkIdType first, const std::vector<vtkIdType>& from)
{
  for (Array& a : this->Arrays)
  {
    a.Out->Resize(first + static_cast<vtkIdType>(from.size())); // keeps the values
    a.Out->SetNumberOfTuples(first + static_cast<vtkIdType>(from.size()));
    for (size_t k = 0; k < from.size(); ++k)
    {
      a.Out->SetTuple(first + static_cast<vtkIdType>(k), from[k], a.Out);
    }
  }
}

void PointDataInterpolator::AddTo(vtkDataSetAttributes* out) const
{
  for (const Array& a : this->Arrays)
  {
    out->AddArray(a.Out);
  }
}

std::string ReadUV(
  vtkDataSet* ds, const std::string& name, BezierCells& cells, const char* requiredFor)
{
  cells.UV.clear();
  vtkDataArray* array = FindArray(ds->GetPointData(), name);
  if (!array)
  {
    return requiredFor ? "the input has no point data array '" + name + "' (" + requiredFor + ")"
                       : std::string();
  }
  return CopyArray(
    array, "point data array '" + name + "'", 2, ds->GetNumberOfPoints(), "point", cells.UV);
}

namespace
{
std::string NotBezier(const std::string& cellLabel, vtkIdType c, int type)
{
  std::ostringstream os;
  os << cellLabel << " " << c << " is a " << vtkCellTypes::GetClassNameFromTypeId(type)
     << " (VTK cell type " << type << "); only VTK_BEZIER_TRIANGLE cells are accepted";
  return os.str();
}

// Degree of a Bézier triangle with npts points, or 0 when npts is not (n+1)(n+2)/2.
int DegreeOf(vtkIdType npts)
{
  int degree = 1;
  while (degree < ctk::MaxDegree && ctk::BezierPointCount(degree) < npts)
  {
    ++degree;
  }
  return ctk::BezierPointCount(degree) == npts ? degree : 0;
}

std::string BadPointCount(const std::string& cellLabel, vtkIdType c, vtkIdType npts)
{
  std::ostringstream os;
  os << cellLabel << " " << c << " has " << npts
     << " points, which is not (n+1)(n+2)/2 for an order n in 1.." << ctk::MaxDegree;
  return os.str();
}

// Checks cell c (its type and point count) and records its degree; an error message otherwise.
std::string AddCell(
  BezierCells& cells, vtkIdType c, int type, vtkIdType npts, const std::string& cellLabel)
{
  if (type != VTK_BEZIER_TRIANGLE)
  {
    return NotBezier(cellLabel, c, type);
  }
  const int degree = DegreeOf(npts);
  if (degree == 0)
  {
    return BadPointCount(cellLabel, c, npts);
  }
  cells.Degree[c] = static_cast<signed char>(degree);
  if (cells.Orders[degree].empty())
  {
    cells.Orders[degree] = ctk::VtkBezierTriangleOrder(degree);
  }
  return {};
}

// Unstructured grids: straight from the types, offsets and connectivity arrays (no vtkIdList
// per cell), ids copied in parallel. Same checks and messages as the generic path.
template <typename OffsetT, typename IdT>
std::string GatherUnstructured(const unsigned char* types, const OffsetT* offsets,
  const IdT* connectivity, vtkIdType nCells, BezierCells& cells, const std::string& cellLabel)
{
  ctk::ResizeForOverwrite(cells.Degree, nCells);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    std::string error = AddCell(
      cells, c, types[c], static_cast<vtkIdType>(offsets[c + 1] - offsets[c]), cellLabel);
    if (!error.empty())
    {
      return error;
    }
  }
  const vtkIdType base = nCells > 0 ? static_cast<vtkIdType>(offsets[0]) : 0;
  const vtkIdType nIds = nCells > 0 ? static_cast<vtkIdType>(offsets[nCells]) - base : 0;
  ctk::ResizeForOverwrite(cells.Offsets, nCells + 1);
  ctk::ResizeForOverwrite(cells.Ids, nIds);
  ctsplines::ParallelFor(0, nCells + 1, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      cells.Offsets[c] = static_cast<vtkIdType>(offsets[c]) - base;
    }
  });
  ctsplines::ParallelFor(0, nIds, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      cells.Ids[i] = static_cast<vtkIdType>(connectivity[base + i]);
    }
  });
  return {};
}

// What the evaluation needs of gathered cells: point ids in range, usable coordinates (finite,
// far from overflow) and positive rational weights; the first offender is named.
std::string CheckCellValues(
  const BezierCells& cells, const std::string& cellLabel, const std::string& arrayPrefix)
{
  std::ostringstream os;
  const vtkIdType nPoints = static_cast<vtkIdType>(cells.Points.size());
  const vtkIdType nCells = static_cast<vtkIdType>(cells.Degree.size());
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (vtkIdType i = cells.Offsets[c]; i < cells.Offsets[c + 1]; ++i)
    {
      if (cells.Ids[i] < 0 || cells.Ids[i] >= nPoints)
      {
        os << cellLabel << " " << c << " refers to point " << cells.Ids[i] << ", not in [0, "
           << nPoints << ")";
        return os.str();
      }
    }
  }
  for (vtkIdType p = 0; p < nPoints; ++p)
  {
    if (!ctk::IsUsablePoint(cells.Points[p]))
    {
      os << arrayPrefix << "point " << p << " has the coordinates (" << cells.Points[p].transpose()
         << "): they must be finite and below " << ctk::MaxInputMagnitude << " in magnitude";
      return os.str();
    }
  }
  for (size_t p = 0; p < cells.Weights.size(); ++p)
  {
    if (!(cells.Weights[p] > 0))
    {
      os << arrayPrefix << "rational weight of point " << p << " is " << cells.Weights[p]
         << "; rational Bezier weights must be positive";
      return os.str();
    }
  }
  return {};
}

// Point coordinates: raw pointers (in parallel) for float/double storage, GetPoint otherwise.
void CopyPoints(vtkDataSet* ds, ctk::OverwriteVector<ctk::Vec3>& points)
{
  const vtkIdType nPoints = ds->GetNumberOfPoints();
  ctk::ResizeForOverwrite(points, nPoints);
  vtkPointSet* ps = vtkPointSet::SafeDownCast(ds);
  vtkDataArray* data = ps && ps->GetPoints() ? ps->GetPoints()->GetData() : nullptr;
  auto copy = [&](const auto* src) {
    ctsplines::ParallelFor(0, nPoints, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType p = b; p < e; ++p)
      {
        points[p] = ctk::Vec3(src[3 * p], src[3 * p + 1], src[3 * p + 2]);
      }
    });
  };
  if (auto* d = vtkDoubleArray::FastDownCast(data))
  {
    copy(d->GetPointer(0));
  }
  else if (auto* f = vtkFloatArray::FastDownCast(data))
  {
    copy(f->GetPointer(0));
  }
  else
  {
    for (vtkIdType p = 0; p < nPoints; ++p)
    {
      ds->GetPoint(p, points[p].data());
    }
  }
}
} // namespace

std::string GatherBezierCells(vtkDataSet* ds, BezierCells& cells, const std::string& cellLabel,
  const std::string& arrayPrefix)
{
  const vtkIdType nCells = ds->GetNumberOfCells();
  vtkUnstructuredGrid* ug = vtkUnstructuredGrid::SafeDownCast(ds);
  vtkCellArray* ugCells = ug ? ug->GetCells() : nullptr;
  vtkUnsignedCharArray* ugTypes = ug ? ug->GetCellTypesArray() : nullptr;
  if (ugCells && ugTypes && ugTypes->GetNumberOfTuples() == nCells &&
    ugCells->GetNumberOfCells() == nCells)
  {
    const unsigned char* types = ugTypes->GetPointer(0);
    const std::string error = ugCells->IsStorage64Bit()
      ? GatherUnstructured(types, ugCells->GetOffsetsArray64()->GetPointer(0),
          ugCells->GetConnectivityArray64()->GetPointer(0), nCells, cells, cellLabel)
      : GatherUnstructured(types, ugCells->GetOffsetsArray32()->GetPointer(0),
          ugCells->GetConnectivityArray32()->GetPointer(0), nCells, cells, cellLabel);
    if (!error.empty())
    {
      return error;
    }
  }
  else
  {
    cells.Degree.resize(nCells);
    cells.Offsets.assign(nCells + 1, 0);
    cells.Ids.clear();
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < nCells; ++c)
    {
      const int type = ds->GetCellType(c);
      vtkIdType npts = 0;
      if (type == VTK_BEZIER_TRIANGLE)
      {
        ds->GetCellPoints(c, ids);
        npts = ids->GetNumberOfIds();
      }
      std::string error = AddCell(cells, c, type, npts, cellLabel);
      if (!error.empty())
      {
        return error;
      }
      cells.Ids.insert(cells.Ids.end(), ids->GetPointer(0), ids->GetPointer(0) + npts);
      cells.Offsets[c + 1] = static_cast<vtkIdType>(cells.Ids.size());
    }
  }

  const vtkIdType nPoints = ds->GetNumberOfPoints();
  // VTK's Bézier cells read the active rational weights attribute; the spec names the array.
  vtkPointData* pd = ds->GetPointData();
  vtkDataArray* w = pd->GetRationalWeights();
  if (!w)
  {
    w = FindArray(pd, "RationalWeights");
  }
  cells.Weights.clear();
  if (w)
  {
    const std::string what = arrayPrefix + "point data array '" +
      (w->GetName() ? w->GetName() : "") + "'";
    std::string error = CopyArray(w, what, 1, nPoints, "point", cells.Weights);
    if (!error.empty())
    {
      return error;
    }
  }
  CopyPoints(ds, cells.Points);
  return CheckCellValues(cells, cellLabel, arrayPrefix);
}

SamplingLattice::SamplingLattice(int level)
  : L(level)
{
  auto index = [level](int j, int k) { return k * (level + 1) - k * (k - 1) / 2 + j; };
  int interior = 0;
  for (int k = 0; k <= level; ++k)
  {
    for (int j = 0; j <= level - k; ++j)
    {
      const int i = level - j - k;
      Point p;
      // Exact zeros on edges: points there depend on the edge's control points only.
      p.T = ctk::Vec3(double(i) / level, double(j) / level, double(k) / level);
      if (j == 0 && k == 0)
      {
        p.Kind = Point::Corner, p.Local = 0, p.Step = 0;
      }
      else if (j == level)
      {
        p.Kind = Point::Corner, p.Local = 1, p.Step = 0;
      }
      else if (k == level)
      {
        p.Kind = Point::Corner, p.Local = 2, p.Step = 0;
      }
      else if (k == 0)
      {
        p.Kind = Point::Edge, p.Local = 0, p.Step = j;
      }
      else if (i == 0)
      {
        p.Kind = Point::Edge, p.Local = 1, p.Step = k;
      }
      else if (j == 0)
      {
        p.Kind = Point::Edge, p.Local = 2, p.Step = i;
      }
      else
      {
        p.Kind = Point::Interior, p.Local = 0, p.Step = interior++;
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


SharedCellTopology::SharedCellTopology(const BezierCells& cells)
{
  const vtkIdType nCells = cells.NumberOfCells();
  // Corners in order of first use, cell by cell (read cell by cell later, not at random).
  ctk::OverwriteVector<vtkIdType> cornerOf;
  ctk::AssignLarge(cornerOf, cells.Points.size(), vtkIdType(-1));
  ctk::ResizeForOverwrite(this->CellCorner, 3 * nCells);
  ctk::AssignLarge(this->CellOwns, nCells, decltype(this->CellOwns)::value_type(0));
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    const vtkIdType* ids = cells.CellIds(c);
    for (int a = 0; a < 3; ++a)
    {
      vtkIdType& corner = cornerOf[ids[a]];
      if (corner < 0)
      {
        corner = static_cast<vtkIdType>(this->CornerPoint.size());
        this->CornerPoint.push_back(ids[a]);
        this->CellOwns[c] |= 1 << a;
      }
      this->CellCorner[3 * c + a] = corner;
    }
  }
  this->NumberEdges();
}

void SharedCellTopology::NumberEdges()
{
  // Edges bucketed by their lower corner, each item with its upper corner (the matching scans
  // a bucket only, not the cells): O(n) for bounded valence.
  const vtkIdType nCells = this->NumberOfCells();
  const vtkIdType nCorners = this->NumberOfCorners();
  ctk::OverwriteVector<vtkIdType> bucketStart;
  ctk::AssignLarge(bucketStart, nCorners + 1, vtkIdType(0));
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      ++bucketStart[this->LowerUpperCorners(c, l).first + 1];
    }
  }
  for (vtkIdType v = 0; v < nCorners; ++v)
  {
    bucketStart[v + 1] += bucketStart[v];
  }
  ctk::OverwriteVector<vtkIdType> itemEdge, itemUpper, fill;
  ctk::ResizeForOverwrite(itemEdge, 3 * nCells);
  ctk::ResizeForOverwrite(itemUpper, 3 * nCells);
  ctk::ResizeForOverwrite(fill, nCorners);
  std::copy(bucketStart.begin(), bucketStart.end() - 1, fill.begin());
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      const std::pair<vtkIdType, vtkIdType> edge = this->LowerUpperCorners(c, l);
      const vtkIdType i = fill[edge.first]++;
      itemEdge[i] = 3 * c + l;
      itemUpper[i] = edge.second;
    }
  }
  ctk::ResizeForOverwrite(this->CellEdge, 3 * nCells);
  vtkIdType nEdges = 0;
  for (vtkIdType v = 0; v < nCorners; ++v)
  {
    for (vtkIdType i = bucketStart[v]; i < bucketStart[v + 1]; ++i)
    {
      const vtkIdType ce = itemEdge[i];
      vtkIdType k = bucketStart[v];
      while (k < i && itemUpper[k] != itemUpper[i])
      {
        ++k;
      }
      if (k < i)
      {
        this->CellEdge[ce] = this->CellEdge[itemEdge[k]];
      }
      else
      {
        // Items are in cell order, so the first cell seen owns the edge.
        this->CellEdge[ce] = nEdges++;
        this->CellOwns[ce / 3] |= 8 << (ce % 3);
      }
    }
  }
  this->NEdges = nEdges;
}

bool SharedCellTopology::SameCorners(const BezierCells& cells) const
{
  const vtkIdType nCells = cells.NumberOfCells();
  if (nCells != this->NumberOfCells())
  {
    return false;
  }
  std::atomic<bool> same(true);
  ParallelFor(0, nCells, GrainForCopies, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType c = begin; c < end && same.load(std::memory_order_relaxed); ++c)
    {
      const vtkIdType* ids = cells.CellIds(c);
      for (int a = 0; a < 3; ++a)
      {
        if (this->CornerPoint[this->CellCorner[3 * c + a]] != ids[a])
        {
          same = false;
        }
      }
    }
  });
  return same;
}

LatticeNumbering::LatticeNumbering(
  const BezierCells& cells, const SamplingLattice& lattice, bool shared)
  : Lattice(lattice)
{
  const vtkIdType nCells = cells.NumberOfCells();
  if (!shared)
  {
    this->NPoints = nCells * static_cast<vtkIdType>(lattice.Points.size());
    return;
  }
  this->Topology.reset(new SharedCellTopology(cells));
  this->EdgeBase = this->Topology->NumberOfCorners();
  this->InteriorBase = this->EdgeBase + this->Topology->NumberOfEdges() * (lattice.L - 1);
  this->NPoints = this->InteriorBase + nCells * lattice.NumberOfInteriorPoints();
}

vtkIdType LatticeNumbering::OutputId(vtkIdType c, int index, bool& owned) const
{
  if (!this->Topology)
  {
    owned = true;
    return c * static_cast<vtkIdType>(this->Lattice.Points.size()) + index;
  }
  const SharedCellTopology& topology = *this->Topology;
  const SamplingLattice::Point& p = this->Lattice.Points[index];
  const int L = this->Lattice.L;
  switch (p.Kind)
  {
    case SamplingLattice::Point::Corner:
    {
      const vtkIdType v = topology.CornerId(c, p.Local);
      owned = topology.OwnsCorner(c, p.Local);
      return v;
    }
    case SamplingLattice::Point::Edge:
    {
      const vtkIdType e = topology.EdgeId(c, p.Local);
      owned = topology.OwnsEdge(c, p.Local);
      const bool forward = topology.EdgeRunsForward(c, p.Local);
      return this->EdgeBase + e * (L - 1) + (forward ? p.Step : L - p.Step) - 1;
    }
    default:
      owned = true;
      return this->InteriorBase + c * this->Lattice.NumberOfInteriorPoints() + p.Step;
  }
}

void LatticeNumbering::WriteTriangles(
  vtkIdType c, vtkIdType* offsets, vtkIdType* connectivity, vtkIdType* sourceCell) const
{
  const vtkIdType perCell = static_cast<vtkIdType>(this->Lattice.L) * this->Lattice.L;
  for (vtkIdType m = 0; m < perCell; ++m)
  {
    const vtkIdType cell = c * perCell + m;
    for (int a = 0; a < 3; ++a)
    {
      bool owned = false;
      connectivity[3 * cell + a] = this->OutputId(c, this->Lattice.Triangles[3 * m + a], owned);
    }
    offsets[cell] = 3 * cell;
    sourceCell[cell] = c;
  }
}

std::string CheckCellDataArrays(vtkDataSet* input, const std::string& arrayPrefix)
{
  vtkCellData* cd = input->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* in = cd->GetAbstractArray(a);
    const std::string name = in->GetName() ? in->GetName() : "";
    const std::string what = arrayPrefix + "cell data array '" + name + "'";
    std::string error = CheckTuples(in, what, input->GetNumberOfCells(), "cell");
    if (error.empty() && (name == "MacroTriangleId" || name == "MicroTriangleId") &&
      in->GetNumberOfComponents() != 1)
    {
      error = what + " has " + std::to_string(in->GetNumberOfComponents()) +
        " components, expected 1";
    }
    if (!error.empty())
    {
      return error;
    }
  }
  return {};
}

namespace
{
// to[k] = from[source[k]] for tuples of Bytes bytes (a constant size: one move each).
template <size_t Bytes>
void CopyTuples(const char* from, char* to, const vtkIdType* source, vtkIdType begin,
  vtkIdType end)
{
  for (vtkIdType k = begin; k < end; ++k)
  {
    std::memcpy(to + k * Bytes, from + source[k] * Bytes, Bytes);
  }
}
} // namespace

vtkSmartPointer<vtkAbstractArray> GatherTuples(
  vtkAbstractArray* in, const vtkIdType* source, vtkIdType n, RecycledArrays* recycled)
{
  vtkSmartPointer<vtkAbstractArray> array;
  if (vtkDataArray* data = vtkDataArray::SafeDownCast(in))
  {
    array = NewOutputArrayLike(recycled, data, data->GetNumberOfComponents(), n);
  }
  else
  {
    array = vtkSmartPointer<vtkAbstractArray>::Take(in->NewInstance());
    array->SetNumberOfComponents(in->GetNumberOfComponents());
    array->SetNumberOfTuples(n);
  }
  array->SetName(in->GetName());
  auto copy = [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType k = begin; k < end; ++k)
    {
      array->SetTuple(k, source[k], in);
    }
  };
  // Bits share bytes and strings are not plain data: those are copied on one thread. Plain
  // arrays in VTK's standard layout are copied as bytes (no virtual call per value).
  const bool plain = vtkDataArray::SafeDownCast(array) && !vtkBitArray::SafeDownCast(array);
  if (plain && in->HasStandardMemoryLayout() && array->HasStandardMemoryLayout())
  {
    const size_t bytes = static_cast<size_t>(in->GetNumberOfComponents()) * in->GetDataTypeSize();
    const char* from = static_cast<const char*>(in->GetVoidPointer(0));
    char* to = static_cast<char*>(array->GetVoidPointer(0));
    ctsplines::ParallelFor(0, n, ctsplines::GrainForCopies, [&](vtkIdType begin, vtkIdType end) {
      switch (bytes)
      {
        case 1:
          return CopyTuples<1>(from, to, source, begin, end);
        case 2:
          return CopyTuples<2>(from, to, source, begin, end);
        case 4:
          return CopyTuples<4>(from, to, source, begin, end);
        case 8:
          return CopyTuples<8>(from, to, source, begin, end);
        default:
          for (vtkIdType k = begin; k < end; ++k)
          {
            std::memcpy(to + k * bytes, from + source[k] * bytes, bytes);
          }
      }
    });
  }
  else if (plain)
  {
    ctsplines::ParallelFor(0, n, ctsplines::GrainForCopies, copy);
  }
  else
  {
    copy(0, n);
  }
  return array;
}

void GatherAttributes(vtkDataSetAttributes* in, vtkDataSetAttributes* out,
  const vtkIdType* source, vtkIdType n, bool skipGlobalIds, RecycledArrays* recycled)
{
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* from = in->GetAbstractArray(a);
    if ((skipGlobalIds && from == in->GetGlobalIds()) || !from->GetName())
    {
      continue;
    }
    vtkSmartPointer<vtkAbstractArray> array = GatherTuples(from, source, n, recycled);
    const int attribute = in->IsArrayAnAttribute(a);
    if (attribute >= 0)
    {
      out->SetAttribute(array, attribute);
    }
    else
    {
      out->AddArray(array);
    }
  }
}

void CopyCellDataBySource(vtkDataSet* input, vtkCellData* out, const vtkIdType* sourceCell,
  vtkIdType outputCells, RecycledArrays* recycled)
{
  GatherAttributes(input->GetCellData(), out, sourceCell, outputCells, true, recycled);
}

std::string GatherBezierCellsAndCellData(vtkDataSet* ds, BezierCells& cells)
{
  std::string error = GatherBezierCells(ds, cells);
  return error.empty() ? CheckCellDataArrays(ds, "") : error;
}

std::string GatherBezierCellsWithUV(
  vtkDataSet* ds, const std::string& uvName, BezierCells& cells, const char* uvRequiredFor)
{
  std::string error = GatherBezierCellsAndCellData(ds, cells);
  return error.empty() ? ReadUV(ds, uvName, cells, uvRequiredFor) : error;
}

} // namespace ctsplines
