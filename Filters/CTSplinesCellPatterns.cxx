// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesCellPatterns.h"

#include <algorithm>

namespace ctsplines
{
SnappedLattice::SnappedLattice(const SamplingLattice& lattice, const std::array<int, 3>& n)
  : L(lattice.L)
  , N(n)
{
  using P = SamplingLattice::Point;
  // Distinct points: corners, then each edge's points, then the lattice's interior points.
  std::array<int, 3> edgeFirst{};
  for (int a = 0; a < 3; ++a)
  {
    P corner;
    corner.T = ctk::Vec3::Zero();
    corner.T[a] = 1.0;
    corner.Kind = P::Corner, corner.Local = static_cast<signed char>(a), corner.Step = 0;
    this->Points.push_back(corner);
  }
  for (int l = 0; l < 3; ++l)
  {
    edgeFirst[l] = static_cast<int>(this->Points.size());
    for (int k = 1; k < n[l]; ++k)
    {
      // Edge l runs from corner l to corner l + 1; exact zeros off the edge.
      P p;
      p.T = ctk::Vec3::Zero();
      p.T[(l + 1) % 3] = double(k) / n[l];
      p.T[l] = double(n[l] - k) / n[l];
      p.Kind = P::Edge, p.Local = static_cast<signed char>(l), p.Step = k;
      this->Points.push_back(p);
    }
  }
  const int interiorFirst = static_cast<int>(this->Points.size());
  // Each lattice point's pattern point: edge steps s of L rounded to k of N[l] (monotone).
  std::vector<int> of(lattice.Points.size());
  for (size_t i = 0; i < lattice.Points.size(); ++i)
  {
    const P& q = lattice.Points[i];
    if (q.Kind == P::Corner)
    {
      of[i] = q.Local;
      continue;
    }
    if (q.Kind == P::Interior)
    {
      of[i] = interiorFirst + q.Step;
      if (static_cast<int>(this->Points.size()) <= of[i])
      {
        this->Points.resize(of[i] + 1);
      }
      this->Points[of[i]] = q;
      continue;
    }
    const int l = q.Local;
    const int k = (2 * q.Step * n[l] + L) / (2 * L);
    of[i] = k == 0 ? l : k == n[l] ? (l + 1) % 3 : edgeFirst[l] + k - 1;
  }
  for (size_t t = 0; t < lattice.Triangles.size(); t += 3)
  {
    const int a = of[lattice.Triangles[t]], b = of[lattice.Triangles[t + 1]],
              c = of[lattice.Triangles[t + 2]];
    if (a != b && b != c && c != a)
    {
      this->Triangles.insert(this->Triangles.end(), { a, b, c });
    }
  }
}

CellPatterns::CellPatterns(const BezierCells& cells, const std::vector<int>& levels,
  const SharedCellTopology& topology)
  : Cells(cells)
  , Topology(topology)
{
  const vtkIdType nCells = cells.NumberOfCells();
  const vtkIdType nEdges = this->Topology.NumberOfEdges();
  // Each edge: the finer side's level; each cell: at least its edges' segments.
  ctk::AssignLarge(this->EdgeSegments, nEdges, decltype(this->EdgeSegments)::value_type(1));
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      int& n = this->EdgeSegments[this->Topology.EdgeId(c, l)];
      n = std::max(n, levels[c]);
    }
  }
  ctk::ResizeForOverwrite(this->Of, nCells);
  ctk::ResizeForOverwrite(this->BasisOf, nCells);
  ctk::ResizeForOverwrite(this->InteriorStart, nCells + 1);
  ctk::ResizeForOverwrite(this->TriangleStart, nCells + 1);
  ctk::ResizeForOverwrite(this->EdgeStart, nEdges + 1);
  this->EdgeStart[0] = this->Topology.NumberOfCorners();
  for (vtkIdType e = 0; e < nEdges; ++e)
  {
    this->EdgeStart[e + 1] = this->EdgeStart[e] + this->EdgeSegments[e] - 1;
  }
  this->InteriorStart[0] = this->EdgeStart[nEdges];
  this->TriangleStart[0] = 0;
  ctk::ResizeForOverwrite(this->CellEdgeStart, 3 * nCells);
  ctk::ResizeForOverwrite(this->CellEdgeSegments, 3 * nCells);
  std::array<int, 5> lastKey{};
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    std::array<int, 3> n{};
    int level = levels[c];
    for (int l = 0; l < 3; ++l)
    {
      n[l] = this->EdgeSegments[this->Topology.EdgeId(c, l)];
      level = std::max(level, n[l]);
    }
    for (int l = 0; l < 3; ++l)
    {
      this->CellEdgeStart[3 * c + l] = this->EdgeStart[this->Topology.EdgeId(c, l)];
      this->CellEdgeSegments[3 * c + l] = n[l];
    }
    const std::array<int, 5> basisKey{ level, n[0], n[1], n[2], cells.Degree[c] };
    if (c > 0 && basisKey == lastKey)
    {
      // Uniform tessellations: one pattern and basis for all cells, no search.
      this->Of[c] = this->Of[c - 1];
      this->BasisOf[c] = this->BasisOf[c - 1];
    }
    else
    {
      this->FindPattern(c, basisKey);
      lastKey = basisKey;
    }
    const vtkIdType interior = static_cast<vtkIdType>(level - 1) * (level - 2) / 2;
    this->InteriorStart[c + 1] = this->InteriorStart[c] + interior;
    this->TriangleStart[c + 1] =
      this->TriangleStart[c] + static_cast<vtkIdType>(this->Of[c]->Triangles.size() / 3);
  }
  this->NPoints = this->InteriorStart[nCells];
}

void CellPatterns::FindPattern(vtkIdType c, const std::array<int, 5>& key)
{
  const std::array<int, 3> n{ key[1], key[2], key[3] };
  const std::array<int, 4> patternKey{ key[0], n[0], n[1], n[2] };
  auto found = this->Patterns.find(patternKey);
  if (found == this->Patterns.end())
  {
    const SamplingLattice& lattice =
      this->Lattices.emplace(key[0], SamplingLattice(key[0])).first->second;
    found = this->Patterns.emplace(patternKey, SnappedLattice(lattice, n)).first;
  }
  this->Of[c] = &found->second;
  auto basis = this->Bases.find(key);
  if (basis == this->Bases.end())
  {
    std::vector<ctk::Vec3> points;
    for (const SamplingLattice::Point& q : found->second.Points)
    {
      points.push_back(q.T);
    }
    basis = this->Bases.emplace(key, ctk::BezierBasisTable(key[4], points)).first;
  }
  this->BasisOf[c] = &basis->second;
}

void CellPatterns::OutputIds(vtkIdType c, vtkIdType* ids, unsigned char* owned) const
{
  // Per corner and edge of the cell once: ids, owners and the edges' directions.
  vtkIdType corner[3], edgeFirst[3];
  bool ownsCorner[3], ownsEdge[3], forward[3];
  int segments[3];
  for (int a = 0; a < 3; ++a)
  {
    corner[a] = this->Topology.CornerId(c, a);
    ownsCorner[a] = this->Topology.OwnsCorner(c, a);
    edgeFirst[a] = this->CellEdgeStart[3 * c + a];
    segments[a] = this->CellEdgeSegments[3 * c + a];
    ownsEdge[a] = this->Topology.OwnsEdge(c, a);
  }
  for (int l = 0; l < 3; ++l)
  {
    forward[l] = SharedCellTopology::RunsForward(corner[l], corner[(l + 1) % 3]);
  }
  const std::vector<SamplingLattice::Point>& points = this->Of[c]->Points;
  for (size_t p = 0; p < points.size(); ++p)
  {
    const SamplingLattice::Point& q = points[p];
    switch (q.Kind)
    {
      case SamplingLattice::Point::Corner:
        owned[p] = ownsCorner[q.Local];
        ids[p] = corner[q.Local];
        break;
      case SamplingLattice::Point::Edge:
        owned[p] = ownsEdge[q.Local];
        ids[p] = edgeFirst[q.Local] +
          (forward[q.Local] ? q.Step : segments[q.Local] - q.Step) - 1;
        break;
      default:
        owned[p] = true;
        ids[p] = this->InteriorStart[c] + q.Step;
    }
  }
}

template <typename Id>
void CellPatterns::WriteTriangles(
  vtkIdType c, const vtkIdType* ids, Id* offsets, Id* connectivity, vtkIdType* sourceCell) const
{
  const std::vector<int>& triangles = this->Of[c]->Triangles;
  const vtkIdType first = this->TriangleStart[c];
  const vtkIdType count = static_cast<vtkIdType>(triangles.size() / 3);
  Id* to = connectivity + 3 * first;
  for (size_t k = 0; k < triangles.size(); ++k)
  {
    to[k] = static_cast<Id>(ids[triangles[k]]);
  }
  for (vtkIdType m = first; m < first + count; ++m)
  {
    offsets[m] = static_cast<Id>(3 * m);
    sourceCell[m] = c;
  }
}

template void CellPatterns::WriteTriangles(
  vtkIdType, const vtkIdType*, vtkIdType*, vtkIdType*, vtkIdType*) const;
template void CellPatterns::WriteTriangles(
  vtkIdType, const vtkIdType*, vtkTypeInt32*, vtkTypeInt32*, vtkIdType*) const;

} // namespace ctsplines
