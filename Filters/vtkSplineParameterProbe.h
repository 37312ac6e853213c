// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkSplineParameterProbe
 * @brief   Evaluates a Bézier-triangle spline at given parameter values (u, v).
 *
 * Called like vtkProbeFilter: the input (port 0) is any vtkDataSet whose point coordinates x, y
 * are the parameters (u, v) to evaluate (z is ignored); the spline comes in as the source (port
 * 1, SetSourceConnection / SetSourceData): a data set of VTK_BEZIER_TRIANGLE cells of any order
 * whose point data array `UV` (name settable) gives each control point's domain point, as
 * produced by vtkCloughTocherSplineFilter. Each cell is the polynomial (or, with rational
 * weights: the active rational weights attribute, else the point data array `RationalWeights`,
 * rational) patch over the parameter triangle spanned by the UV of its three
 * corner control points.
 *
 * Output: for a vtkPointSet input, the same type with the input's structure (shallow) and its
 * points replaced by the surface points; otherwise a vtkPolyData holding only the points. The
 * input's point and cell data are passed, and point data is added:
 * `dFdu`, `dFdv` (parameter derivatives), `Normals` (dFdu x dFdv, normalised),
 * `MacroTriangleId` (the source's cell data of that name at the evaluated cell, else the
 * source cell id) and `vtkValidPointMask` (1 where (u, v) lies in a parameter triangle). Outside
 * the parameter domain the mask is 0, the point is (u, v, 0), derivatives and normal are 0 and
 * MacroTriangleId is -1.
 *
 * Points are located with a bucket grid over the parameter triangles (constant expected time per
 * query) holding only cell ids (of macro-triangles for a spline in the spline filter's layout),
 * built once per source and reused while the source is unchanged.
 * The spline is read where it is: the source's own arrays for an unstructured grid with double
 * points, UV and weights (checked, not copied), a checked copy otherwise; nothing is renumbered.
 * The check of the points, UV and weights takes the ranges a CTSplines filter stored for an
 * array whose values were all finite, while the array is unmodified since (Modified(), as for
 * VTK's own cached ranges); other arrays are read whole.
 * Queries that already come in a coherent order (at least half of them in their predecessor's
 * locator bucket or a neighbour: grid rows, polylines) are processed as they come; others in
 * the Morton order of their buckets, the results scattered back: neighbouring queries read
 * neighbouring cells, in memory order for a spline written in a locality order (as
 * vtkCloughTocherSplineFilter writes them). Points are evaluated exactly with
 * the kernel; the loop over points runs with vtkSMPTools. Ties between cells go to the lowest
 * source cell id, and no result depends on the order or the thread count. ComputeDerivatives
 * off outputs positions only.
 * A missing source, a missing or non-2-component UV array, source cells that are not Bézier
 * triangles, and zero-area parameter triangles are reported with vtkErrorMacro and RequestData
 * returns 0.
 */
#ifndef vtkSplineParameterProbe_h
#define vtkSplineParameterProbe_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkDataSetAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkAlgorithmOutput;
namespace ctsplines
{
class RecycledArrays;
}

class CTSPLINESFILTERS_EXPORT vtkSplineParameterProbe : public vtkDataSetAlgorithm
{
public:
  static vtkSplineParameterProbe* New();
  vtkTypeMacro(vtkSplineParameterProbe, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The spline to evaluate (input port 1), as a data object or a pipeline connection.
  void SetSourceData(vtkDataObject* source);
  vtkDataObject* GetSource();
  void SetSourceConnection(vtkAlgorithmOutput* algOutput);
  ///@}

  ///@{
  /// Name of the source's point data array of domain points. Default "UV".
  vtkSetStdStringFromCharMacro(UVArrayName);
  vtkGetCharFromStdStringMacro(UVArrayName);
  ///@}

  ///@{
  /// Whether to compute `dFdu`, `dFdv` and `Normals` (default on). Off: positions,
  /// `MacroTriangleId` and `vtkValidPointMask` only, and the derivative arrays are not output.
  vtkSetMacro(ComputeDerivatives, bool);
  vtkGetMacro(ComputeDerivatives, bool);
  vtkBooleanMacro(ComputeDerivatives, bool);
  ///@}

  /// The spline's cells and their locator are built once per source and reused by later
  /// updates while the source (its MTime) and UVArrayName are unchanged: this counts the builds.
  /// ReleaseSpline() frees them (the next update rebuilds).
  vtkGetMacro(NumberOfSplineBuilds, int);
  void ReleaseSpline();

  ///@{
  /// Write the output's new arrays (the surface points, `dFdu`, `dFdv`, `Normals`,
  /// `MacroTriangleId`) into the previous output's when nothing else references them any more,
  /// neither the arrays nor their storage, and they have the sizes needed: repeated probes of
  /// as many points (a moving set of queries, a time series of splines). Their pages are
  /// resident already; a new array's first touch costs the zeroing of every page (on 1e6
  /// queries, 100 MB). The filter holds these arrays between executions, as the output does;
  /// they are released at the next execution, when it fails, or when this is turned off, and
  /// are not held when the pipeline releases the output's data (ReleaseDataFlag). Arrays that a
  /// downstream filter or the caller still holds are never written. As
  /// vtkCloughTocherSplineFilter's and vtkBezierTriangleTessellator's property. Default on.
  virtual void SetReuseOutputArrays(bool reuse);
  vtkGetMacro(ReuseOutputArrays, bool);
  vtkBooleanMacro(ReuseOutputArrays, bool);
  ///@}

  /// Bytes of the previous output's arrays that the last execution wrote again
  /// (ReuseOutputArrays); 0 when it allocated its output anew.
  vtkTypeUInt64 GetReusedOutputBytes() const;

  /// Source cells per entry of the locator of the last update (0 before one): 3 when the
  /// source's cells come in vtkCloughTocherSplineFilter's layout, cells 3 i, 3 i + 1, 3 i + 2
  /// (and no others) sharing a `MacroTriangleId` (the locator then lists macro-triangles: a
  /// third of the entries, the same results), else 1.
  int GetNumberOfCellsPerLocatorEntry() const;

protected:
  vtkSplineParameterProbe();
  ~vtkSplineParameterProbe() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string UVArrayName = "UV";
  bool ComputeDerivatives = true;
  int NumberOfSplineBuilds = 0;
  bool ReuseOutputArrays = true;

private:
  struct SplineCache;
  std::unique_ptr<SplineCache> Cache;
  std::unique_ptr<ctsplines::RecycledArrays> Recycled;

  vtkSplineParameterProbe(const vtkSplineParameterProbe&) = delete;
  void operator=(const vtkSplineParameterProbe&) = delete;
};

#endif
