// SPDX-License-Identifier: GPL-3.0-or-later
// Sampling patterns of Bézier cells with a level of their own (adaptive tessellation), kept
// conforming across shared cell edges (private header of the module).
//
// A cell of level L (a power of two) is sampled on the lattice of SamplingLattice(L); a shared
// edge gets one number of segments n_e, decided once for the edge from both cells (the finer
// side's level), and a cell's level is at least that of each of its edges. Where an edge has
// fewer segments than its cell's level (n_e divides L), the lattice points on it are snapped to
// the edge's points and the triangles that collapse are dropped: the remaining ones fan from
// the first inner row to the edge, keep their orientation, and meet the neighbour's triangles
// at the same points. A uniform tessellation is the special case of one level everywhere.
#ifndef CTSplinesCellPatterns_h
#define CTSplinesCellPatterns_h

#include "CTSplinesBezierCells.h"

#include "BezierBasisTable.h"

#include <array>
#include <map>
#include <vector>

namespace ctsplines
{
/// The lattice of level L with the boundary points of edge l snapped to N[l] segments.
struct SnappedLattice
{
  int L = 0;
  std::array<int, 3> N{ 0, 0, 0 };
  /// Distinct points: corners (Step 0), edge points (Local l, Step k in 1..N[l]-1) and the
  /// lattice's interior points (Step as in SamplingLattice).
  std::vector<SamplingLattice::Point> Points;
  std::vector<int> Triangles; // 3 indices into Points each, oriented like the cell
  SnappedLattice(const SamplingLattice& lattice, const std::array<int, 3>& n);
};

/// Output numbering of the points of every cell's pattern, shared across cells as in
/// LatticeNumbering (corners, then edge points, then interiors; owned by the lowest cell id).
class CellPatterns
{
public:
  /// levels: one power of two per cell (raised where an edge needs more, see above); topology:
  /// the cells' (SharedCellTopology(cells) or one with the same corners), used while this lives.
  CellPatterns(const BezierCells& cells, const std::vector<int>& levels,
    const SharedCellTopology& topology);
  CellPatterns(const BezierCells&, const std::vector<int>&, SharedCellTopology&&) = delete;
  const SnappedLattice& Pattern(vtkIdType c) const { return *this->Of[c]; }
  /// Bernstein bases of cell c's degree at its pattern's points (shared by the cells of one
  /// pattern and degree).
  const ctk::BezierBasisTable& Basis(vtkIdType c) const { return *this->BasisOf[c]; }
  vtkIdType NumberOfPoints() const { return this->NPoints; }
  vtkIdType NumberOfTriangles() const { return this->TriangleStart.back(); }
  /// First output triangle of cell c (cells' triangles are consecutive).
  vtkIdType FirstTriangle(vtkIdType c) const { return this->TriangleStart[c]; }
  /// Output ids of the pattern points of cell c (Pattern(c).Points.size() of them), and
  /// whether c evaluates each (it is the owner).
  void OutputIds(vtkIdType c, vtkIdType* ids, unsigned char* owned) const;
  /// Writes cell c's triangles from its OutputIds: offsets, connectivity and the source cell id
  /// of each. Id: vtkIdType, or vtkTypeInt32 for a cell array of 32-bit storage.
  template <typename Id>
  void WriteTriangles(vtkIdType c, const vtkIdType* ids, Id* offsets, Id* connectivity,
    vtkIdType* sourceCell) const;

private:
  // Sets the pattern and basis of cell c from key (level, segments of its 3 edges, degree).
  void FindPattern(vtkIdType c, const std::array<int, 5>& key);

  const BezierCells& Cells;
  const SharedCellTopology& Topology; // corners, edges and their owners (level-independent)
  std::map<std::array<int, 4>, SnappedLattice> Patterns;
  std::map<int, SamplingLattice> Lattices;
  ctk::OverwriteVector<const SnappedLattice*> Of;
  std::map<std::array<int, 5>, ctk::BezierBasisTable> Bases; // pattern key and degree
  ctk::OverwriteVector<const ctk::BezierBasisTable*> BasisOf;
  ctk::OverwriteVector<int> EdgeSegments;
  ctk::OverwriteVector<vtkIdType> EdgeStart, InteriorStart, TriangleStart;
  // Per cell and local edge: EdgeStart and EdgeSegments of the edge (read in cell order).
  ctk::OverwriteVector<vtkIdType> CellEdgeStart;
  ctk::OverwriteVector<int> CellEdgeSegments;
  vtkIdType NPoints = 0;
};

} // namespace ctsplines

#endif
