// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkSplineContinuityFilter
 * @brief   Measures the continuity of a Bézier-triangle spline across every cell edge.
 *
 * Input: a vtkDataSet of polynomial VTK_BEZIER_TRIANGLE cells (any order up to 10, orders may
 * differ between cells), typically the output of vtkCloughTocherSplineFilter: point data `UV` (the
 * domain point of each control point; only the corners' values are used) and optionally cell data
 * `MacroTriangleId` and a face id array (FaceIdArrayName, default "FaceId"). Rational cells
 * whose weights are not constant are rejected (Rule A compares polynomial nets).
 *
 * Edges are found by the point ids of the cells' corners; with MatchCoincidentEdges (default on)
 * corners closer than Tolerance (relative to the diagonal of the corners' bounding box) count as
 * one, so that separate faces stitched along coincident edges are analysed as neighbours.
 *
 * Output: vtkPolyData with one point per (matched) corner and one line cell per edge, with cell
 * data
 * - `EdgeKind`: 0 macro-edge (the two cells have different MacroTriangleId, or there is no such
 *   array), 1 micro-edge (same macro-triangle: an inner edge of the Clough-Tocher split),
 *   2 boundary (one cell), 3 interface (the two cells have different face ids);
 * - `Cells` (2 components): the two cells, lower id first (-1 on the boundary);
 * - `C0Gap`, `C1Jump`, `C2Jump`: Rule A (ctk::RuleAJumps) jumps of rows 0, 1, 2, i.e. the largest
 *   distance between an ordinate of the higher-id cell B within r rows of the edge and the
 *   extension of the lower-id cell A's polynomial to the same domain point. The domains are the
 *   corners' UV; when B's UV of the shared corners differ from A's (separate faces), B's
 *   parameter triangle is first moved by the similarity that puts its copy of the edge onto A's.
 *   Cells of lower order are degree-elevated to the higher one;
 * - `G1Angle`: the largest angle in degrees between the two sides' unit normals
 *   (x_r x x_s of each cell, so it is 180 where orientations disagree), sampled at G1Samples
 *   points inside the edge;
 * - `C2JumpEq7`: for macro-edges between two cubic cells, the study's eq. (7) measure: with A over
 *   (U0, U1, U2) and B over (U1, U0, U3), the largest of |b_A(Ui, U2, U3) - b_B(Ui, U2, U3)|,
 *   i = 0, 1 (b the blossoms: each side's second-row sub-triangle at Ui extrapolated to the
 *   other's apex); NaN on other edges.
 * Boundary edges have zero jumps and angle. Field data summarises each kind K in Macro, Micro,
 * Boundary, Interface: `K_EdgeCount` and `K_<measure>_Max`, `K_<measure>_Mean` for C0Gap,
 * C1Jump, C2Jump, G1Angle (and C2JumpEq7 for Macro); 0 when a kind has no edges.
 *
 * The measures of an edge are the kernel's ctk::MeasureEdgeContinuity (Filters/Kernel/
 * EdgeContinuity.h); the filter finds the edges, maps cells to its inputs and fills the output.
 *
 * Each edge is computed and written by one task, so results do not depend on the number of
 * threads. Bad input (an empty data set, non-Bézier cells, a missing or malformed UV array,
 * non-constant rational weights, edges shared by three cells, a cell at an interior edge whose
 * corners' UV span no area) is reported with vtkErrorMacro naming the problem and the cells,
 * and RequestData returns 0.
 */
#ifndef vtkSplineContinuityFilter_h
#define vtkSplineContinuityFilter_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class CTSPLINESFILTERS_EXPORT vtkSplineContinuityFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkSplineContinuityFilter* New();
  vtkTypeMacro(vtkSplineContinuityFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Values of the `EdgeKind` cell data.
  enum EdgeKinds
  {
    Macro = 0,
    Micro = 1,
    Boundary = 2,
    Interface = 3
  };

  ///@{
  /// Match edges of cells that do not share corner point ids but whose corners coincide within
  /// Tolerance. Default on.
  vtkSetMacro(MatchCoincidentEdges, bool);
  vtkGetMacro(MatchCoincidentEdges, bool);
  vtkBooleanMacro(MatchCoincidentEdges, bool);
  ///@}

  ///@{
  /// Distance under which corners coincide, relative to the diagonal of the corners' bounding
  /// box. Default 1e-6.
  vtkSetClampMacro(Tolerance, double, 0.0, 1.0);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /// Number of points inside each edge where the normals are compared for G1Angle. Default 5.
  vtkSetClampMacro(G1Samples, int, 1, 1000);
  vtkGetMacro(G1Samples, int);
  ///@}

  ///@{
  /// Array names. Defaults: point data "UV", cell data "MacroTriangleId" and "FaceId" (both
  /// optional).
  vtkSetStdStringFromCharMacro(UVArrayName);
  vtkGetCharFromStdStringMacro(UVArrayName);
  vtkSetStdStringFromCharMacro(MacroTriangleIdArrayName);
  vtkGetCharFromStdStringMacro(MacroTriangleIdArrayName);
  vtkSetStdStringFromCharMacro(FaceIdArrayName);
  vtkGetCharFromStdStringMacro(FaceIdArrayName);
  ///@}

  /// Name of an EdgeKind value ("Macro", "Micro", "Boundary", "Interface").
  static const char* GetEdgeKindName(int kind);

protected:
  vtkSplineContinuityFilter();
  ~vtkSplineContinuityFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  bool MatchCoincidentEdges = true;
  double Tolerance = 1e-6;
  int G1Samples = 5;
  std::string UVArrayName = "UV";
  std::string MacroTriangleIdArrayName = "MacroTriangleId";
  std::string FaceIdArrayName = "FaceId";

private:
  vtkSplineContinuityFilter(const vtkSplineContinuityFilter&) = delete;
  void operator=(const vtkSplineContinuityFilter&) = delete;
};

#endif
