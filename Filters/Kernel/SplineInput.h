// SPDX-License-Identifier: GPL-3.0-or-later
// The owning form of a construction's input: the arrays behind a SplineData, for callers that
// gather their data (the VTK filter, the CAD face mesher, the Bézier extraction's probes, tests).
#ifndef CTSplines_Kernel_SplineInput_h
#define CTSplines_Kernel_SplineInput_h

#include "CubicCloughTocher.h"
#include "LocalityOrder.h"

#include <vector>

namespace ctk
{
struct SplineInput
{
  // The large arrays are OverwriteVectors: filled in parallel loops after resize.
  OverwriteVector<Id> Triangles;     // #T by 3
  OverwriteVector<double> UV;        // #V by 2
  OverwriteVector<double> F, Fu, Fv; // #V by 3 each
  std::vector<double> EdgeGradients;       // empty or #T by 18 (rows: EdgeGradientRows)
  /// Instead of EdgeGradients: the caller's rows, read in place (it keeps them alive).
  const double* SharedEdgeGradients = nullptr;
  /// Empty, or #T: triangle t's row of the edge gradients (SplineData::EdgeGradientRows).
  std::vector<Id> EdgeGradientRows;
  std::vector<double> BoundaryCurvePoints; // empty or #T by 18
  std::vector<Vec3> SplitTau;              // empty or #T
  bool ValuesChecked = false;              // see SplineData::ValuesChecked

  Id NumberOfVertices() const { return static_cast<Id>(this->UV.size() / 2); }
  Id NumberOfTriangles() const { return static_cast<Id>(this->Triangles.size() / 3); }
  /// The non-owning view the constructions read (empty optional arrays become nullptr).
  SplineData View() const;
  /// Array sizes consistent with the vertex and triangle counts (naming the array that is not),
  /// then ValidateSplineData: finite values, no zero-area or folded triangle.
  BuildStatus Validate(const MeshTopology& topology) const;
  /// Puts the mesh and every array in the numbering of r (triangles' vertex order kept), or back
  /// in the input's numbering (back = true), chunked by parallelFor over the rows. r must be this
  /// mesh's (MakeLocalityRenumbering): its maps are permutations of the triangles and vertices. The edge
  /// gradients stay in place: their row map is renumbered (18 values per triangle are not worth
  /// moving; most constructions read few).
  void Renumber(
    const LocalityRenumbering& r, bool back = false, const ParallelFor& parallelFor = SerialFor);
  /// MakeLocalityRenumbering, then Renumber, with one gather of the triangles instead of two;
  /// returns the renumbering (the identity, nothing moved, where MakeLocalityRenumbering's is).
  LocalityRenumbering RenumberToLocalityOrder(const ParallelFor& parallelFor = SerialFor);
  /// Whether there are edge gradients, owned or shared.
  bool HasEdgeGradients() const
  {
    return !this->EdgeGradients.empty() || this->SharedEdgeGradients;
  }
  /// EdgeGradientRows, made explicit (triangle t at row t) when empty, for a caller that
  /// renumbers or drops triangles.
  std::vector<Id>& EdgeGradientRowMap();

private:
  // The rows per triangle (triangles, edge gradients' row map, boundary curves, split points).
  void PermuteTriangleRows(const LocalityRenumbering& r, bool back, const ParallelFor& parallelFor);
  // The ids in the triangles and the rows per vertex ((u, v), values, derivatives).
  void RenumberVertices(const LocalityRenumbering& r, bool back, const ParallelFor& parallelFor);
};

} // namespace ctk

#endif
