// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkCloughTocherSplineFilter
 * @brief   Converts a parametrised triangle mesh into a cubic C1 Clough-Tocher spline.
 *
 * Input: vtkPolyData of triangles (or a vtkUnstructuredGrid of VTK_TRIANGLE cells, as
 * redistribution filters output) whose points carry parameter coordinates (point data `UV`, 2
 * components; falls back to the active texture coordinates) and the first derivatives `dFdu`,
 * `dFdv` (3 components each). The MG constructions, KaG and the gradient boundary modes also
 * read the cell data `EdgeGradients` (18 components: for the local edges (p0,p1), (p1,p2),
 * (p2,p0) in that order, f_u then f_v at the edge midpoint); their values are checked where
 * read (every edge's for MGo and MGi, the boundary edges' for the others), so that KaG does not
 * pass over all 18 per triangle for the few it reads. Array names are settable.
 * Meshes without dFdu/dFdv (a scan, an exported mesh with texture coordinates) are accepted
 * when DerivativeEstimation is set: the derivatives are then estimated from the positions.
 *
 * Output: vtkUnstructuredGrid with three cubic (quartic for the Quartic construction)
 * VTK_BEZIER_TRIANGLE cells per input triangle (the Clough-Tocher micro-triangles),
 * double-precision control points shared by all cells that use
 * them, point data `UV` (each control point's domain point), cell data `MacroTriangleId` and
 * `MicroTriangleId` (k of micro-triangle T_k, the one opposite vertex k), field data naming the
 * construction, split point and boundary mode.
 *
 * Constructions follow "Watertight conversion of trimmed CAD surfaces to Clough-Tocher splines":
 * CTo, CTi, Fa, FO, Ka, MGo, MGi, KaG, the IM iteration, split points Bary, Inc2, Inc3 and four
 * boundary modes for the constructions that read neighbours (CTo and MGo are local and ignore
 * it; KaG and MGi use GradientToSplitPoint unless a gradient mode is chosen), and Kashyap's cubic
 * fairing scheme and the quartic scheme from "A Quartic Clough-Tocher Interpolant" (Fang, Mann). Bad input (non-triangles, missing or wrong-sized arrays,
 * NaN/Inf, zero-area parameter triangles, non-manifold edges, empty input) is reported with
 * vtkErrorMacro naming the offending cell, point or array, and RequestData returns 0. Cells and
 * points are the input's ids whatever the filter dropped (repeated ghost cells) or renumbered.
 *
 * Output order (OutputOrder): by default, a mesh of at least 2^15 triangles is built and output
 * in a locality order, the Morton order of its triangles' centroids in (u, v): the cells of
 * triangle t are not cells 3t..3t+2 then, and the first control points (the vertices') are
 * numbered by first use in that order. `MacroTriangleId` gives every cell's input triangle, and
 * the values are those of the input's order, bit for bit. On meshes numbered without locality
 * (a Delaunay triangulation as qhull or CGAL number it) this makes the construction 3-4x faster
 * (issue #12). InputOrder keeps the input's numbering (cells 3t + k, control point v = input point
 * v); the Bézier extraction, whose degrees of freedom are numbered by input point, implies it.
 *
 * Distributed runs: the filter asks upstream for GetRequiredGhostLevels() ghost levels, builds the
 * spline on the piece with its ghost triangles (cell data vtkGhostType, duplicate cells) and
 * outputs the micro-triangles of the piece's own triangles only, so that the pieces together
 * are the serial spline. The input's global cell ids, when present, are passed on as cell data
 * `MacroTriangleGlobalId`.
 */
#ifndef vtkCloughTocherSplineFilter_h
#define vtkCloughTocherSplineFilter_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class CTSPLINESFILTERS_EXPORT vtkCloughTocherSplineFilter : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkCloughTocherSplineFilter* New();
  vtkTypeMacro(vtkCloughTocherSplineFilter, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Constructions of the two papers: the rows of the kernel's construction table
  /// (Filters/Kernel/Constructions.h; values match ctk::Construction, which a static_assert
  /// checks). docs/constructions.md says what each gives.
  enum ConstructionType
  {
    CTo = 0,
    CTi = 1,
    Fa = 2,
    FO = 3,
    Ka = 4,
    MGo = 5,
    MGi = 6,
    KaG = 7,
    Kashyap = 8,
    Quartic = 9
  };
  enum SplitPointType
  {
    Bary = 0,
    Inc2 = 1,
    Inc3 = 2
  };
  enum BoundaryModeType
  {
    Perpendicular = 0,
    Midpoint = 1,
    GradientPerpendicular = 2,
    GradientToSplitPoint = 3
  };

  ///@{
  /// The construction that fixes the central control points (Step 2). Default CTi.
  /// Kashyap is Kashyap's cubic fairing scheme (FO, then Iterations rounds of exterior and
  /// interior fairing, then C1 smoothing).
  /// Quartic is Fang and Mann's quartic scheme (FO degree-raised, then Iterations rounds of
  /// boundary-point adjustment, exterior fairing and C1 smoothing): quartic output cells.
  vtkSetClampMacro(Construction, int, CTo, Quartic);
  vtkGetMacro(Construction, int);
  void SetConstructionToCTo() { this->SetConstruction(CTo); }
  void SetConstructionToCTi() { this->SetConstruction(CTi); }
  void SetConstructionToFa() { this->SetConstruction(Fa); }
  void SetConstructionToFO() { this->SetConstruction(FO); }
  void SetConstructionToKa() { this->SetConstruction(Ka); }
  void SetConstructionToMGo() { this->SetConstruction(MGo); }
  void SetConstructionToMGi() { this->SetConstruction(MGi); }
  void SetConstructionToKaG() { this->SetConstruction(KaG); }
  void SetConstructionToKashyap() { this->SetConstruction(Kashyap); }
  void SetConstructionToQuartic() { this->SetConstruction(Quartic); }
  ///@}

  ///@{
  /// Split point of every macro-triangle. Default Bary.
  vtkSetClampMacro(SplitPoint, int, Bary, Inc3);
  vtkGetMacro(SplitPoint, int);
  void SetSplitPointToBary() { this->SetSplitPoint(Bary); }
  void SetSplitPointToInc2() { this->SetSplitPoint(Inc2); }
  void SetSplitPointToInc3() { this->SetSplitPoint(Inc3); }
  ///@}

  ///@{
  /// Rule for boundary edges of the constructions that read neighbours. Default Midpoint
  /// (invariant to affine reparameterisation, needs no extra data).
  vtkSetClampMacro(BoundaryMode, int, Perpendicular, GradientToSplitPoint);
  vtkGetMacro(BoundaryMode, int);
  void SetBoundaryModeToPerpendicular() { this->SetBoundaryMode(Perpendicular); }
  void SetBoundaryModeToMidpoint() { this->SetBoundaryMode(Midpoint); }
  void SetBoundaryModeToGradientPerpendicular() { this->SetBoundaryMode(GradientPerpendicular); }
  void SetBoundaryModeToGradientToSplitPoint() { this->SetBoundaryMode(GradientToSplitPoint); }
  ///@}

  ///@{
  /// Number of IM steps (iterative C2 minimisation, study section 3.7) applied after the
  /// construction; for Kashyap, the number of fairing rounds. Default 0. IM converges to the
  /// data's cubic only when boundary edges are fixed by mid-edge gradients; with the
  /// Perpendicular or Midpoint boundary the boundary error stalls it and spreads inwards.
  vtkSetClampMacro(Iterations, int, 0, VTK_INT_MAX);
  vtkGetMacro(Iterations, int);
  ///@}

  /// Numbering of the output's cells and control points (see the class description).
  enum OutputOrderType
  {
    InputOrder = 0,   // cells 3t..3t+2 for input triangle t, control point v for input point v
    LocalityOrder = 1 // meshes of 2^15 triangles or more: the Morton order of the triangles
  };

  ///@{
  /// Numbering of the output (OutputOrderType). Default LocalityOrder.
  vtkSetClampMacro(OutputOrder, int, InputOrder, LocalityOrder);
  vtkGetMacro(OutputOrder, int);
  void SetOutputOrderToInput() { this->SetOutputOrder(InputOrder); }
  void SetOutputOrderToLocality() { this->SetOutputOrder(LocalityOrder); }
  ///@}

  /// How dFdu and dFdv are obtained when the input lacks them (values match
  /// ctk::DerivativeEstimation; Filters/Kernel/DerivativeEstimation.h).
  enum DerivativeEstimationType
  {
    NoEstimation = 0,   // "None": the arrays are required (missing ones are an error)
    LocalQuadratic = 1, // per vertex, least-squares quadratic over its rings
    MinimumEnergy = 2   // global, least thin-plate energy of the CTo spline (matplotlib's min_E)
  };

  ///@{
  /// Estimation of the derivatives, used when dFdu or dFdv (DuArrayName, DvArrayName) is
  /// missing: both are then estimated from the positions and (u, v), and the output's field
  /// data `DerivativeEstimation` names the method ("None" when the input's arrays were used).
  /// Given arrays are always used as they are. Default NoEstimation (named "None"): the arrays
  /// are required, and a missing one is an error naming it. LocalQuadratic is exact for
  /// quadratic surfaces and invariant to affine reparameterisation (gradient error O(h^2));
  /// MinimumEnergy is exact for planes and smoother, but global (O(h) at the boundary, O(h^2)
  /// inside); in distributed runs each piece gets the minimum over the piece and its ghosts.
  vtkSetClampMacro(DerivativeEstimation, int, NoEstimation, MinimumEnergy);
  vtkGetMacro(DerivativeEstimation, int);
  void SetDerivativeEstimationToNone() { this->SetDerivativeEstimation(NoEstimation); }
  void SetDerivativeEstimationToLocalQuadratic() { this->SetDerivativeEstimation(LocalQuadratic); }
  void SetDerivativeEstimationToMinimumEnergy() { this->SetDerivativeEstimation(MinimumEnergy); }
  /// "None", "LocalQuadratic", "MinimumEnergy" ("Unknown" outside).
  static const char* GetDerivativeEstimationName(int method);
  ///@}

  ///@{
  /// Names of the input arrays. Defaults: "UV", "dFdu", "dFdv", "EdgeGradients".
  vtkSetStdStringFromCharMacro(UVArrayName);
  vtkGetCharFromStdStringMacro(UVArrayName);
  vtkSetStdStringFromCharMacro(DuArrayName);
  vtkGetCharFromStdStringMacro(DuArrayName);
  vtkSetStdStringFromCharMacro(DvArrayName);
  vtkGetCharFromStdStringMacro(DvArrayName);
  vtkSetStdStringFromCharMacro(EdgeGradientsArrayName);
  vtkGetCharFromStdStringMacro(EdgeGradientsArrayName);
  ///@}

  ///@{
  /// Optional cell data array (18 components) prescribing the boundary curves: for each local
  /// edge (p0,p1), (p1,p2), (p2,p0) on the mesh boundary, the inner control points of the cubic
  /// the spline must follow there (near the edge's first point, then near its second); NaN
  /// (all six) leaves an edge to the vertex derivatives, values on interior edges are ignored.
  /// Each macro-patch stays C1 inside (Step 1, the boundary rule and Step 3 follow the curve);
  /// across the interior macro-edges at a boundary vertex C1 needs the prescribed points to agree
  /// with that vertex's derivatives (T - V = J (U_j - U_i) / 3, eq. 11) and is lost by their
  /// mismatch otherwise. This is how vtkWatertightSplineStitcher gives neighbouring CAD faces one
  /// boundary (the sampler's `EdgeCurvePoints`). The constructions that take boundary curves
  /// (GetConstructionTakesBoundaryCurves: the cubic ones but Kashyap), without the Bézier
  /// extraction; default empty (none).
  vtkSetStdStringFromCharMacro(BoundaryCurvePointsArrayName);
  vtkGetCharFromStdStringMacro(BoundaryCurvePointsArrayName);
  ///@}

  ///@{
  /// Also output the Bézier extraction of the spline space (for isogeometric analysis): cell
  /// data `GlobalDofIds` (21 components, -1 padded) and `BezierExtraction` (10 x 21, row-major,
  /// rows in the cell's VTK point order), field data `NumberOfDofs`, `EdgeDofIds` (per macro-edge
  /// of the input: its two vertex ids and its DOF, -1 where none) and `DegreesOfFreedom` (#DOF x 3: the input data as DOFs, so
  /// that every control point is sum_j C[row, j] d[GlobalDofIds[j]]). Degrees of freedom: value,
  /// d/du, d/dv per vertex (3 v, 3 v + 1, 3 v + 2), then one per edge carrying mid-edge data (the
  /// derivative along the construction's unit v_eps at the midpoint). Cubic constructions
  /// without iterations only. Default off.
  vtkSetMacro(ComputeBezierExtraction, bool);
  vtkGetMacro(ComputeBezierExtraction, bool);
  vtkBooleanMacro(ComputeBezierExtraction, bool);
  ///@}

  ///@{
  /// Write the control and domain points of an execution into the previous output's arrays
  /// (cubic constructions) when nothing else references them any more, neither the arrays nor
  /// their storage, and the input has the previous one's numbers of points and cells: time steps
  /// of one mesh, a property changed, a sweep in a script. Their pages are resident already; a
  /// new array's first touch costs the zeroing of every page (a tenth of CTi's time at 1e6
  /// triangles on the machine measured). The filter holds its output's large arrays between
  /// executions, as the output does; they are released at the next execution, when it fails,
  /// or when this is turned off. The output's data released by the pipeline (ReleaseDataFlag)
  /// is not held. Arrays that a downstream filter or the caller still holds are never written;
  /// ParaView keeps a copy of every output until the next one exists, so nothing is reused
  /// there. Default on.
  virtual void SetReuseOutputArrays(bool reuse);
  vtkGetMacro(ReuseOutputArrays, bool);
  vtkBooleanMacro(ReuseOutputArrays, bool);
  ///@}

  /// Bytes of the previous output's arrays that the last execution wrote again
  /// (ReuseOutputArrays); 0 when it allocated its output anew.
  vtkTypeUInt64 GetReusedOutputBytes() const;

  ///@{
  /// Process-wide, for every filter of the module: the large arrays (working arrays, the
  /// spline's points and other output arrays of 4 MiB or more: its connectivity and cell data,
  /// a tessellation's arrays) are retained when they are freed, up to RetainedMemoryLimit bytes
  /// in all, and the next large arrays are made of their pages before any fresh one (a block of
  /// the same length, a longer one's start, or several moved together with their page tables).
  /// A new filter on the same mesh (the same level or number of queries) then writes in
  /// resident memory instead of fresh pages that the kernel zeroes first (a sixth of CTi's
  /// process time at 1e6 triangles on the machine measured), and since retained pages are used
  /// first, an execution's resident peak does not grow (ctk::MapLargeBlock). A block unused for
  /// 10 s goes back to the system at the next large allocation or free; retained pages are
  /// advised MADV_FREE, so the kernel may take them back under memory pressure, but they count
  /// in the resident size until then.
  /// The default limit is a quarter of the physical memory, or CTSPLINES_LARGE_BLOCK_CACHE_MB
  /// (MiB) from the environment; 0 retains nothing. GetRetainedMemory: the bytes retained now;
  /// ReleaseRetainedMemory gives them all back (before measuring a process's memory, say).
  /// Nothing is retained in builds with AddressSanitizer (ctk::LargeBlockCacheLimit).
  static void SetRetainedMemoryLimit(vtkTypeUInt64 bytes);
  static vtkTypeUInt64 GetRetainedMemoryLimit();
  static vtkTypeUInt64 GetRetainedMemory();
  static void ReleaseRetainedMemory();
  ///@}

  /// Ghost levels the construction needs around a piece to reproduce the serial result on it
  /// (ctk::RequiredGhostRings): 0 for the local constructions (CTo, MGo) without iterations,
  /// else 2 + Iterations (neighbours' data, one more layer per iteration); with
  /// DerivativeEstimation, ctk::MaxEstimationRings (4) more for the rings the estimate reads.
  int GetRequiredGhostLevels() const;

  ///@{
  /// The construction table (Filters/Kernel/Constructions.h), for wrappers, the CAD classes and
  /// Python: the number of constructions (values 0 .. N-1), a construction's name ("Unknown"
  /// outside) and value by name (-1 when none), its one-line summary, output degree (3 or 4),
  /// whether it takes prescribed boundary curves (BoundaryCurvePointsArrayName), whether a CAD
  /// model can be stitched with it, whether it has a Bézier extraction.
  static int GetNumberOfConstructions();
  static const char* GetConstructionName(int construction);
  static int GetConstructionValue(const char* name);
  static const char* GetConstructionSummary(int construction);
  static int GetConstructionDegree(int construction);
  static bool GetConstructionTakesBoundaryCurves(int construction);
  static bool GetConstructionCanBeStitched(int construction);
  static bool GetConstructionHasBezierExtraction(int construction);
  ///@}

  /// Name of a split point or boundary mode value ("Inc3", "Midpoint", ...).
  static const char* GetSplitPointName(int splitPoint);
  static const char* GetBoundaryModeName(int mode);

protected:
  vtkCloughTocherSplineFilter();
  ~vtkCloughTocherSplineFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Construction = CTi;
  int SplitPoint = Bary;
  int BoundaryMode = Midpoint;
  int Iterations = 0;
  bool ComputeBezierExtraction = false;
  int DerivativeEstimation = NoEstimation;
  int OutputOrder = LocalityOrder;
  std::string UVArrayName = "UV";
  std::string DuArrayName = "dFdu";
  std::string DvArrayName = "dFdv";
  std::string EdgeGradientsArrayName = "EdgeGradients";
  std::string BoundaryCurvePointsArrayName;
  bool ReuseOutputArrays = true;

private:
  struct RecycledOutput; // ctsplines::RecycledArrays
  std::unique_ptr<RecycledOutput> Recycled;
  vtkCloughTocherSplineFilter(const vtkCloughTocherSplineFilter&) = delete;
  void operator=(const vtkCloughTocherSplineFilter&) = delete;
};

#endif
