// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkBezierTriangleTessellator
 * @brief   Samples VTK_BEZIER_TRIANGLE cells of any order on a uniform grid into triangles.
 *
 * Input: any vtkDataSet whose cells are all VTK_BEZIER_TRIANGLE, of any order up to the
 * kernel's maximum degree (10); rational cells read the active rational weights attribute of the point data
 * (vtkPointData::GetRationalWeights(), what VTK's own Bézier cells use) or, when none is
 * active, the point data array `RationalWeights`.
 * Each cell is evaluated exactly (kernel Bézier evaluation, no linearisation) at the points
 * (i, j, k) / SubdivisionLevel of its parameter triangle and replaced by SubdivisionLevel^2
 * triangles with the cell's orientation.
 *
 * The output is conforming: a corner shared by cells (same point id) and an edge shared by cells
 * (same two corner point ids) produce their points once. Each output point is evaluated by a
 * single owner cell (the lowest cell id using it), so results do not depend on the number of
 * threads. Output points are numbered corners first (in order of first use), then the inner
 * points of the edges, then cell interiors, then (SplitSharpEdges) the copies of points split at
 * creases, which keep their coordinates bit for bit: the geometry stays watertight.
 *
 * The triangles' offsets and connectivity use 32-bit storage (vtkCellArray::ArrayType32) while
 * every id fits in it, else 64-bit (at 64 bits they are 40 % of the output's memory).
 *
 * Output arrays: point data `Normals` (unit normal from the cross product of the two parametric
 * derivatives, i.e. oriented by the cell's corner order; at a split point the normal of the
 * cells on its side), every floating-point point data array of the input interpolated with the
 * cell's Bézier basis (rational when the cell is; the array named UVArrayName comes out as
 * `UV`; integer arrays, the rational weights and input `Normals` are not carried), every cell
 * data array of the input copied to the cell's triangles (but global ids, which would not stay
 * unique), and cell data `BezierCellId` (the source cell of each triangle).
 *
 * Other cell types, point counts that are not (n+1)(n+2)/2 for a supported order n, and a
 * `RationalWeights` array that is not one finite component per point are reported with
 * vtkErrorMacro naming the cell or array, and RequestData returns 0. An input without cells gives
 * an empty output.
 */
#ifndef vtkBezierTriangleTessellator_h
#define vtkBezierTriangleTessellator_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class CTSPLINESFILTERS_EXPORT vtkBezierTriangleTessellator : public vtkPolyDataAlgorithm
{
public:
  static vtkBezierTriangleTessellator* New();
  vtkTypeMacro(vtkBezierTriangleTessellator, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Number of segments each cell edge is divided into (SubdivisionLevel^2 triangles per cell);
  /// in adaptive mode the largest level, rounded down to a power of two. Default 8.
  vtkSetClampMacro(SubdivisionLevel, int, 1, 4096);
  vtkGetMacro(SubdivisionLevel, int);
  ///@}

  ///@{
  /// Split points where the cells meeting there have exact normals more than FeatureAngle
  /// apart (creases of G0 joins, e.g. between CAD faces): each side gets its own point, with the
  /// same coordinates, and its own exact normal, so shading shows no light and dark stars along
  /// creases. Default on. Off gives the conforming mesh with one normal per point (the owner
  /// cell's).
  vtkSetMacro(SplitSharpEdges, bool);
  vtkGetMacro(SplitSharpEdges, bool);
  vtkBooleanMacro(SplitSharpEdges, bool);
  ///@}

  ///@{
  /// Angle in degrees above which the normals of cells at a point count as a crease. Default 30,
  /// as in vtkPolyDataNormals.
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  ///@}

  ///@{
  /// Adaptive mode, on when either tolerance is positive (as OCCT's BRepMesh deflections):
  /// each cell gets the smallest power-of-two level, at most SubdivisionLevel (rounded down to
  /// a power of two), at which every triangle is within ChordalTolerance of the surface
  /// (measured at its edge midpoints) and the exact normals at its corners and edge midpoints
  /// are within AngularTolerance degrees of each other. A shared cell edge gets one number of
  /// segments, the finer side's, so the mesh stays conforming. Defaults 0 (uniform).
  vtkSetClampMacro(ChordalTolerance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ChordalTolerance, double);
  vtkSetClampMacro(AngularTolerance, double, 0.0, 180.0);
  vtkGetMacro(AngularTolerance, double);
  ///@}

  ///@{
  /// Whether ChordalTolerance is relative to the input's bounding-box diagonal. Default on.
  vtkSetMacro(RelativeChordalTolerance, bool);
  vtkGetMacro(RelativeChordalTolerance, bool);
  vtkBooleanMacro(RelativeChordalTolerance, bool);
  ///@}

  ///@{
  /// Name of the 2-component point data array carried over as `UV`. Default "UV".
  vtkSetStdStringFromCharMacro(UVArrayName);
  vtkGetCharFromStdStringMacro(UVArrayName);
  ///@}

  ///@{
  /// Write the output of an execution into the previous output's large arrays (points,
  /// normals, triangles, point and cell data) when nothing else references them any more,
  /// neither the arrays nor their storage, and they have the sizes needed: time steps of one
  /// spline, a property that keeps the sizes, a sweep in a script. Their pages are resident
  /// already; a new array's first touch costs the zeroing of every page. The filter holds its
  /// output's large arrays between executions, as the output does; they are released at the
  /// next execution, when it fails, or when this is turned off. The output's data released by
  /// the pipeline (ReleaseDataFlag) is not held. Arrays that a downstream filter or the caller
  /// still holds are never written; ParaView keeps a copy of every output until the next one
  /// exists, so no array is reused there. Default on.
  ///
  /// With the arrays the filter also keeps the input's shared corners and edges (a few tens of
  /// bytes per cell): an execution on cells with the same corner point ids (another level,
  /// tolerance or feature angle, new nets on the same mesh) does not number them again, in
  /// ParaView too. One data set's are kept: the blocks of a composite input replace each
  /// other's, and are numbered every time.
  virtual void SetReuseOutputArrays(bool reuse);
  vtkGetMacro(ReuseOutputArrays, bool);
  vtkBooleanMacro(ReuseOutputArrays, bool);
  ///@}

  /// Bytes of the previous output's arrays that the last execution wrote again
  /// (ReuseOutputArrays); 0 when it allocated its output anew.
  vtkTypeUInt64 GetReusedOutputBytes() const;

  /// Executions so far that numbered the shared corners and edges of their input, rather than
  /// using the kept ones (ReuseOutputArrays).
  vtkTypeUInt64 GetNumberOfTopologyBuilds() const;

protected:
  vtkBezierTriangleTessellator();
  ~vtkBezierTriangleTessellator() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int SubdivisionLevel = 8;
  bool SplitSharpEdges = true;
  double FeatureAngle = 30.0;
  double ChordalTolerance = 0.0;
  double AngularTolerance = 0.0;
  bool RelativeChordalTolerance = true;
  std::string UVArrayName = "UV";
  bool ReuseOutputArrays = true;

private:
  struct RecycledOutput; // ctsplines::RecycledArrays, and the kept SharedCellTopology
  std::unique_ptr<RecycledOutput> Recycled;
  bool IsAdaptive() const;
  double GetAbsoluteChordalTolerance(vtkDataSet* input) const;
  vtkBezierTriangleTessellator(const vtkBezierTriangleTessellator&) = delete;
  void operator=(const vtkBezierTriangleTessellator&) = delete;
};

#endif
