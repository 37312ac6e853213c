// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkBezierCurvatureFilter
 * @brief   Exact curvatures of VTK_BEZIER_TRIANGLE cells, sampled on a tessellation.
 *
 * Input: any vtkDataSet whose cells are all VTK_BEZIER_TRIANGLE of any order up to 10 (for
 * example the output of vtkCloughTocherSplineFilter). Rational cells read the active rational
 * weights attribute of the point data, or else the point data array `RationalWeights`.
 *
 * Each cell is sampled at the points (i, j, k) / SubdivisionLevel of its parameter triangle, as
 * vtkBezierTriangleTessellator does, and at every sample the curvatures are computed from the
 * first and second fundamental forms of the cell's own parametrisation x(r, s) (exact second
 * derivatives of the kernel's Bézier evaluation, rational when the cell is), never from the
 * tessellation: the kernel's ctk::BezierTriangleCurvatures (Filters/Kernel/SurfaceCurvatures.h).
 *
 * Output: vtkPolyData of SubdivisionLevel^2 triangles per cell, with point data
 * - `Gauss_Curvature` K, `Mean_Curvature` H,
 * - `Maximum_Curvature` >= `Minimum_Curvature`, the principal curvatures (eigenvalues of the
 *   shape operator, same sign convention as H: their mean is H and their product K),
 * - `Maximum_Curvature_Direction`, `Minimum_Curvature_Direction`: unit principal directions (3D
 *   tangent vectors; their sign is arbitrary),
 * - `Normals`: the unit normal n = (x_r x x_s) / |x_r x x_s|, oriented by the cell's corner order,
 * - every floating-point point data array of the input, interpolated with the cell's Bézier
 *   basis (rational when the cell is; the array named UVArrayName comes out as `UV`; integer
 *   arrays, the rational weights and input `Normals` are not carried),
 * every cell data array of the input copied to the cell's triangles (but global ids), and cell
 * data `BezierCellId` (the source cell of each triangle).
 *
 * Sign convention: with the second fundamental form L = x_rr . n, M = x_rs . n, N = x_ss . n,
 * H = -(E N - 2 F M + G L) / (2 (E G - F^2)), so that H > 0 where the surface bends away from
 * its normal: a sphere whose normal points outwards has H = +1/R (and K = 1/R^2). This matches
 * vtkCurvatures on outward-oriented closed surfaces. At singular points (collapsed corners) the
 * values are the limit from inside the cell.
 *
 * Field data `Gauss_Curvature_RobustRange` (and likewise for the mean, maximum and minimum
 * curvatures) holds the RobustRangePercentile-th and (100 - RobustRangePercentile)-th
 * percentiles of the array: a colour range that vertex spikes do not wash out.
 *
 * Precision: the curvatures of a spline that reproduces a quadratic are exact up to the
 * round-off of its control points, amplified by the cell size h as about 1e-16 |x| / (kappa h^2)
 * (relative); 4e-13 on a 4 x 4 grid, 3e-9 on the smallest cells of 300 random points.
 *
 * By default (MergePoints off) every cell has its own output points, so the jumps of curvature
 * across cell edges of a C1 spline stay visible. With MergePoints on, a corner or edge shared by
 * cells (same point ids) gets its points once, evaluated by the lowest cell id that uses it
 * (the same numbering as vtkBezierTriangleTessellator). Every output point is written by one
 * cell, so results do not depend on the number of threads.
 *
 * Bad input (an empty data set, cells that are not VTK_BEZIER_TRIANGLE or have a point count
 * that is no supported order, a malformed weights or UV array) is reported with vtkErrorMacro
 * naming the offending cell or array, and RequestData returns 0.
 */
#ifndef vtkBezierCurvatureFilter_h
#define vtkBezierCurvatureFilter_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class CTSPLINESFILTERS_EXPORT vtkBezierCurvatureFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkBezierCurvatureFilter* New();
  vtkTypeMacro(vtkBezierCurvatureFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Number of segments each cell edge is divided into (SubdivisionLevel^2 triangles per cell).
  /// Default 8.
  vtkSetClampMacro(SubdivisionLevel, int, 1, 4096);
  vtkGetMacro(SubdivisionLevel, int);
  ///@}

  ///@{
  /// Share the points of corners and edges common to several cells (value of the owner cell).
  /// Default off: curvature jumps across cell edges remain visible.
  vtkSetMacro(MergePoints, bool);
  vtkGetMacro(MergePoints, bool);
  vtkBooleanMacro(MergePoints, bool);
  ///@}

  ///@{
  /// Percentile p of the robust colour ranges: for each scalar curvature array `X` the field
  /// data array `X_RobustRange` holds its p-th and (100 - p)-th percentiles, so that a few
  /// spikes at vertices (where the curvature of a C1 spline jumps) do not wash out a colour map.
  /// Default 1 (%), in [0, 50]; 0 gives the full range.
  vtkSetClampMacro(RobustRangePercentile, double, 0.0, 50.0);
  vtkGetMacro(RobustRangePercentile, double);
  ///@}

  ///@{
  /// Name of the 2-component point data array carried over as `UV`. Default "UV".
  vtkSetStdStringFromCharMacro(UVArrayName);
  vtkGetCharFromStdStringMacro(UVArrayName);
  ///@}

protected:
  vtkBezierCurvatureFilter();
  ~vtkBezierCurvatureFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int SubdivisionLevel = 8;
  bool MergePoints = false;
  double RobustRangePercentile = 1.0;
  std::string UVArrayName = "UV";

private:
  vtkBezierCurvatureFilter(const vtkBezierCurvatureFilter&) = delete;
  void operator=(const vtkBezierCurvatureFilter&) = delete;
};

#endif
