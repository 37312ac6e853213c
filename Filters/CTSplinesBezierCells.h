// SPDX-License-Identifier: GPL-3.0-or-later
// VTK_BEZIER_TRIANGLE cells flattened into plain arrays (validated once, then read concurrently),
// and the sampling lattice shared by the filters that evaluate every cell on a uniform grid
// (private header of the module).
#ifndef CTSplinesBezierCells_h
#define CTSplinesBezierCells_h

#include "BezierBasisTable.h"
#include "BezierTriangle.h" // for ctk::Vec3, ctk::MaxDegree
#include "CTSplinesSMP.h"    // for ForInBlocks

#include <Eigen/Geometry> // for cross

#include "vtkAlgorithm.h"  // for progress and abort
#include "vtkDoubleArray.h" // for the interpolated arrays
#include "vtkSmartPointer.h"
#include "vtkType.h"     // for vtkIdType

#include <algorithm>

#include <array>
#include <memory>
#include <string>
#include <utility> // for pair
#include <vector>

class vtkAbstractArray;
class vtkCellData;
class vtkDataArray;
class vtkDataSet;
class vtkDataSetAttributes;

namespace ctsplines
{
class RecycledArrays;

/// Copies the net of a cell (point ids `ids` in VTK order; order = VtkBezierTriangleOrder of its
/// degree) from points xyz (3 per point) and weights (1 per point, or nullptr) into canonical
/// order (P, and w when rational); returns the weights to pass to the kernel (w or nullptr).
template <typename IdT>
const double* GatherNet(const std::vector<int>& order, const IdT* ids, const double* xyz,
  const double* weights, ctk::Vec3* P, double* w)
{
  for (size_t p = 0; p < order.size(); ++p)
  {
    const double* x = xyz + 3 * static_cast<vtkIdType>(ids[p]);
    P[order[p]] = ctk::Vec3(x[0], x[1], x[2]);
    if (weights)
    {
      w[order[p]] = weights[ids[p]];
    }
  }
  return weights ? w : nullptr;
}

/// The Bézier triangles of a data set: connectivity, degree, points and rational weights.
struct BezierCells
{
  // OverwriteVectors: written whole after a resize, without zeroing first (LargeArrays.h).
  ctk::OverwriteVector<vtkIdType> Offsets{ 0 };
  ctk::OverwriteVector<vtkIdType> Ids;
  ctk::OverwriteVector<signed char> Degree;
  ctk::OverwriteVector<ctk::Vec3> Points; // every point of the data set
  ctk::OverwriteVector<double> Weights;   // one per point; empty: polynomial
  ctk::OverwriteVector<double> UV;        // 2 per point (ReadUV); empty: none
  std::array<std::vector<int>, ctk::MaxDegree + 1> Orders; // VtkBezierTriangleOrder, degrees used

  vtkIdType NumberOfCells() const { return static_cast<vtkIdType>(this->Degree.size()); }
  const vtkIdType* CellIds(vtkIdType c) const { return &this->Ids[this->Offsets[c]]; }
  /// Copies the net of cell c into canonical order (P, and w when rational); returns the weights
  /// to pass to the kernel (w, or nullptr for a polynomial data set).
  const double* Net(vtkIdType c, ctk::Vec3* P, double* w) const;
  /// The UV values of cell c's control points as a net (u, v, 0) in canonical order.
  void UVNet(vtkIdType c, ctk::Vec3* Q) const;
  /// Components first..first+2 (zero beyond `components`) of per-point values (#points by
  /// components) at cell c's control points, as a net in canonical order.
  void ValueNet(
    vtkIdType c, const double* values, int components, int first, ctk::Vec3* Q) const;
};

/// The floating-point point data arrays of a Bézier grid carried to sampled points: each is
/// interpolated with the cell's Bézier basis, rational where the cell is. The array named
/// uvName is output as `UV`. Not carried: integer arrays (ids and flags mean nothing between
/// control points), the rational weights (they define the geometry) and `Normals` (the filters
/// output exact ones).
class PointDataInterpolator
{
public:
  /// Reads and checks the arrays of ds (one tuple per point, finite) and allocates the outputs
  /// (from recycled when it has them).
  std::string Gather(vtkDataSet* ds, const std::string& uvName, vtkIdType outputPoints,
    RecycledArrays* recycled = nullptr);
  /// Number of 3-component nets per cell (LoadNets fills that many times MaxBezierPoints).
  int NumberOfNets() const { return this->Nets; }
  void LoadNets(const BezierCells& cells, vtkIdType c, ctk::Vec3* nets) const;
  /// Writes the values at barycentric t of a degree-n cell (nets from LoadNets) to point id.
  void Write(int n, const ctk::Vec3* nets, const double* weights, const ctk::Vec3& t,
    vtkIdType id) const;
  /// Number of components of all carried arrays.
  int NumberOfComponents() const { return this->Components; }
  /// The ordinates of every carried component at cell c's control points, in canonical order,
  /// MaxBezierPoints apart (NumberOfComponents() of them), times the weights when rational.
  void LoadOrdinates(
    const BezierCells& cells, vtkIdType c, const double* weights, double* f) const;
  /// Writes the values at table points [begin, end) (at most a Block) to points ids[0..) from
  /// LoadOrdinates' f, divided by the denominators W of BezierBasisTable::Evaluate (the values
  /// of EvaluateBezierTriangle to the bit).
  void Write(const ctk::BezierBasisTable& basis, const double* f, int begin, int end,
    const double* W, const vtkIdType* ids) const;
  /// Grows the outputs to `outputPoints` tuples, copying point from[k] to first + k.
  void Append(vtkIdType first, const std::vector<vtkIdType>& from);
  void AddTo(vtkDataSetAttributes* out) const;

private:
  struct Array
  {
    std::string Name;
    int Components = 0;
    ctk::OverwriteVector<double> Values;
    vtkSmartPointer<vtkDoubleArray> Out;
  };
  std::vector<Array> Arrays;
  int Nets = 0, Components = 0;
};

/// Checks that every cell of ds is a VTK_BEZIER_TRIANGLE of an order in 1..ctk::MaxDegree and
/// flattens connectivity and points; reads the rational weights (the active rational weights
/// attribute, else the point data array `RationalWeights`) when present. `cellLabel` names cells
/// in messages ("cell", "source cell"), `arrayPrefix` prefixes array names ("", "the source's ").
std::string GatherBezierCells(vtkDataSet* ds, BezierCells& cells,
  const std::string& cellLabel = "cell", const std::string& arrayPrefix = "");

/// Reads the 2-component point data array `name` into cells.UV. A missing array is an error
/// (saying what the array is for) when `requiredFor` is given, else leaves UV empty.
std::string ReadUV(vtkDataSet* ds, const std::string& name, BezierCells& cells,
  const char* requiredFor = nullptr);

/// GatherBezierCells, then CheckCellDataArrays: the common opening of the filters that read a
/// spline grid.
std::string GatherBezierCellsAndCellData(vtkDataSet* ds, BezierCells& cells);

/// GatherBezierCellsAndCellData, then ReadUV.
std::string GatherBezierCellsWithUV(vtkDataSet* ds, const std::string& uvName, BezierCells& cells,
  const char* uvRequiredFor = nullptr);

/// The points (i, j, k) / L of a cell's parameter triangle and the L^2 triangles between them,
/// and for each point where it lives: a corner, the inner point Step of local edge l (counted
/// from corner l), or interior point Step.
struct SamplingLattice
{
  struct Point
  {
    ctk::Vec3 T; // barycentric coordinates, exact zeros on edges
    enum KindType : signed char
    {
      Corner,
      Edge,
      Interior
    } Kind;
    signed char Local; // corner a or edge l
    int Step;
  };
  int L = 0;
  std::vector<Point> Points;
  std::vector<int> Triangles; // 3 lattice indices each, oriented like the cell

  explicit SamplingLattice(int level);
  vtkIdType NumberOfInteriorPoints() const { return static_cast<vtkIdType>(L - 1) * (L - 2) / 2; }
};

/// The corners and edges that cells share: a corner is a point id, an edge the two point ids
/// of its corners. Corners are numbered in order of first use (slot 3 c + a), edges by their
/// lower corner and then in order of first use; each is owned by the lowest cell id that uses
/// it. They depend on the cells' corner point ids only, so a kept topology serves again for
/// cells with the same corners (SameCorners), whatever their nets.
class SharedCellTopology
{
public:
  explicit SharedCellTopology(const BezierCells& cells);
  /// Whether `cells` has this topology's cell count and corner point ids, cell by cell.
  bool SameCorners(const BezierCells& cells) const;

  vtkIdType NumberOfCells() const { return static_cast<vtkIdType>(this->CellOwns.size()); }
  vtkIdType NumberOfCorners() const { return static_cast<vtkIdType>(this->CornerPoint.size()); }
  vtkIdType NumberOfEdges() const { return this->NEdges; }
  vtkIdType CornerId(vtkIdType c, int a) const { return this->CellCorner[3 * c + a]; }
  vtkIdType EdgeId(vtkIdType c, int l) const { return this->CellEdge[3 * c + l]; }
  bool OwnsCorner(vtkIdType c, int a) const { return (this->CellOwns[c] >> a) & 1; }
  bool OwnsEdge(vtkIdType c, int l) const { return (this->CellOwns[c] >> (3 + l)) & 1; }
  /// Edge points are stored from the lower corner id: whether cell c's edge l (corner l to
  /// corner l + 1) runs that way, or its points are walked backwards.
  bool EdgeRunsForward(vtkIdType c, int l) const
  {
    return RunsForward(this->CornerId(c, l), this->CornerId(c, (l + 1) % 3));
  }
  /// The same from the edge's corner ids, for callers that have loaded them.
  static bool RunsForward(vtkIdType from, vtkIdType to) { return from <= to; }

private:
  void NumberEdges();
  /// Cell c's edge l as its (lower, upper) corner ids.
  std::pair<vtkIdType, vtkIdType> LowerUpperCorners(vtkIdType c, int l) const
  {
    const vtkIdType from = this->CornerId(c, l), to = this->CornerId(c, (l + 1) % 3);
    return RunsForward(from, to) ? std::make_pair(from, to) : std::make_pair(to, from);
  }

  ctk::OverwriteVector<vtkIdType> CellCorner, CellEdge; // written whole after ResizeForOverwrite
  std::vector<vtkIdType> CornerPoint; // the point id of each corner
  std::vector<unsigned char> CellOwns; // bits 0-2: corners, 3-5: edges the cell owns
  vtkIdType NEdges = 0;
};

/// Output numbering of the lattice points of every cell. Shared: the points of a shared corner
/// or edge (SharedCellTopology) are output once and evaluated by its owner; points are numbered
/// corners first (in order of first use), then edge inner points, then cell interiors. Not
/// shared: every cell owns all its points, numbered cell by cell.
class LatticeNumbering
{
public:
  LatticeNumbering(const BezierCells& cells, const SamplingLattice& lattice, bool shared);
  vtkIdType NumberOfPoints() const { return this->NPoints; }
  /// Output id of lattice point p of cell c, and whether c evaluates it.
  vtkIdType OutputId(vtkIdType c, int p, bool& owned) const;
  /// Writes the L^2 output triangles of cell c (triangles c L^2 ..): offsets, connectivity and
  /// the source cell id of each.
  void WriteTriangles(vtkIdType c, vtkIdType* offsets, vtkIdType* connectivity,
    vtkIdType* sourceCell) const;

private:
  const SamplingLattice& Lattice;
  std::unique_ptr<SharedCellTopology> Topology; // shared numbering only
  vtkIdType NPoints = 0, EdgeBase = 0, InteriorBase = 0;
};

/// Checks the input's cell data arrays: one tuple per cell each, and one component for
/// MacroTriangleId and MicroTriangleId.
std::string CheckCellDataArrays(vtkDataSet* input, const std::string& arrayPrefix);

/// Adds to `out` every cell data array of the input (CheckCellDataArrays must have passed;
/// GatherBezierCellsWithUV checks them), output cell k taking the tuple of input cell
/// sourceCell[k]; the active attributes stay active. Global ids are not copied: they would no
/// longer be unique. Data arrays are allocated from recycled when it has them.
void CopyCellDataBySource(vtkDataSet* input, vtkCellData* out, const vtkIdType* sourceCell,
  vtkIdType outputCells, RecycledArrays* recycled = nullptr);

/// A new array of the same type, name and components holding in's tuples source[0..n) (a data
/// array from recycled when it has one).
vtkSmartPointer<vtkAbstractArray> GatherTuples(
  vtkAbstractArray* in, const vtkIdType* source, vtkIdType n, RecycledArrays* recycled = nullptr);

/// Adds to `out` every named array of `in` gathered by GatherTuples, the active attributes
/// staying active; the global ids are left out when skipGlobalIds is set.
void GatherAttributes(vtkDataSetAttributes* in, vtkDataSetAttributes* out,
  const vtkIdType* source, vtkIdType n, bool skipGlobalIds, RecycledArrays* recycled = nullptr);

/// Runs body (a kernel evaluation per element) over [0, n) in at most `blocks` consecutive
/// parallel loops (ParallelFor), reporting progress from progress0 to progress1 and checking
/// GetAbortExecute() between blocks on the calling thread. Returns false when aborted. Blocks
/// are large enough to split over all threads, or one block runs serially.
template <typename Body>
bool ForInBlocks(vtkAlgorithm* algorithm, vtkIdType n, vtkIdType blocks, double progress0,
  double progress1, Body&& body)
{
  const vtkIdType splittable = GrainForEvaluations * LoopThreads();
  const vtkIdType nBlocks =
    n > 0 ? std::max<vtkIdType>(1, std::min<vtkIdType>(blocks, n / splittable)) : 0;
  for (vtkIdType b = 0; b < nBlocks; ++b)
  {
    ParallelFor(b * n / nBlocks, (b + 1) * n / nBlocks, GrainForEvaluations, body);
    algorithm->UpdateProgress(progress0 + (progress1 - progress0) * double(b + 1) / nBlocks);
    if (algorithm->GetAbortExecute())
    {
      return false;
    }
  }
  return true;
}

} // namespace ctsplines

#endif
