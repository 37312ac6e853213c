// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkReflectionLinesFilter
 * @brief   Reflection lines and isophotes of a surface with point normals, as point scalars.
 *
 * Input: a vtkPolyData with point normals (the active normals, or the 3-component point data
 * array NormalsArrayName, default "Normals"), e.g. the output of vtkBezierTriangleTessellator or
 * vtkBezierCurvatureFilter. The output is the input plus point data:
 *
 * - `ReflectionLineParameter`: the eye ray from EyePosition to the point x is reflected at x about
 *   the unit normal n, r = d - 2 (d . n) n, and the reflected line x + lambda r is intersected
 *   with the light plane (LightPlaneOrigin, LightPlaneNormal). The light lines lie in that plane,
 *   parallel to LightLineDirection (projected onto the plane); the parameter is the signed offset
 *   of the hit point from LightPlaneOrigin across the lines, along m = normalize(N x D). NaN
 *   where the reflected ray does not reach the plane (lambda < 0, or r parallel to it): that
 *   point reflects no light line.
 * - `ReflectionLines` = cos(2 pi parameter / Spacing) in [-1, 1]: its level sets (e.g. the
 *   maxima) are the reflection lines of light lines Spacing apart. NaN where the parameter is.
 * - `Isophotes` = cos(2 pi angle / IsophoteSpacing), angle in degrees between n and
 *   LightDirection, and the raw angle as `IsophoteAngle`.
 *
 * Reflection lines are a classic check of G1/G2 continuity: they are continuous across an edge
 * where the surface is G1 and kink where curvature jumps.
 *
 * Each point is computed independently (vtkSMPTools), so results do not depend on the thread
 * count. Bad input (no points, missing or malformed normals) and a light line direction parallel
 * to the plane normal are reported with vtkErrorMacro, and RequestData returns 0.
 */
#ifndef vtkReflectionLinesFilter_h
#define vtkReflectionLinesFilter_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class CTSPLINESFILTERS_EXPORT vtkReflectionLinesFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkReflectionLinesFilter* New();
  vtkTypeMacro(vtkReflectionLinesFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Position of the eye. Default (0, 0, 10).
  vtkSetVector3Macro(EyePosition, double);
  vtkGetVector3Macro(EyePosition, double);
  ///@}

  ///@{
  /// Direction of the light lines (projected onto the light plane). Default (1, 0, 0).
  vtkSetVector3Macro(LightLineDirection, double);
  vtkGetVector3Macro(LightLineDirection, double);
  ///@}

  ///@{
  /// The plane holding the light lines. Defaults: origin (0, 0, 5), normal (0, 0, 1).
  vtkSetVector3Macro(LightPlaneOrigin, double);
  vtkGetVector3Macro(LightPlaneOrigin, double);
  vtkSetVector3Macro(LightPlaneNormal, double);
  vtkGetVector3Macro(LightPlaneNormal, double);
  ///@}

  ///@{
  /// Distance between neighbouring light lines in the plane. Default 1.
  vtkSetClampMacro(Spacing, double, 1e-300, VTK_DOUBLE_MAX);
  vtkGetMacro(Spacing, double);
  ///@}

  ///@{
  /// Light direction of the isophotes and their spacing in degrees. Defaults (0, 0, 1), 10.
  vtkSetVector3Macro(LightDirection, double);
  vtkGetVector3Macro(LightDirection, double);
  vtkSetClampMacro(IsophoteSpacing, double, 1e-6, 360.0);
  vtkGetMacro(IsophoteSpacing, double);
  ///@}

  ///@{
  /// Name of the point normals array used when the input has no active normals. Default
  /// "Normals".
  vtkSetStdStringFromCharMacro(NormalsArrayName);
  vtkGetCharFromStdStringMacro(NormalsArrayName);
  ///@}

protected:
  vtkReflectionLinesFilter();
  ~vtkReflectionLinesFilter() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double EyePosition[3] = { 0.0, 0.0, 10.0 };
  double LightLineDirection[3] = { 1.0, 0.0, 0.0 };
  double LightPlaneOrigin[3] = { 0.0, 0.0, 5.0 };
  double LightPlaneNormal[3] = { 0.0, 0.0, 1.0 };
  double Spacing = 1.0;
  double LightDirection[3] = { 0.0, 0.0, 1.0 };
  double IsophoteSpacing = 10.0;
  std::string NormalsArrayName = "Normals";

private:
  vtkReflectionLinesFilter(const vtkReflectionLinesFilter&) = delete;
  void operator=(const vtkReflectionLinesFilter&) = delete;
};

#endif
