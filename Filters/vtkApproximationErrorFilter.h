// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkApproximationErrorFilter
 * @brief   Distance between a Bézier-triangle spline and a reference surface.
 *
 * Input port 0: the spline, a data set of VTK_BEZIER_TRIANGLE cells of any order with the point
 * data array `UV` (name settable) of domain points, as produced by vtkCloughTocherSplineFilter
 * (rational cells are read as vtkBezierTriangleTessellator and vtkSplineParameterProbe do).
 * Input port 1: the reference, a vtkPolyData (SetReferenceConnection / SetReferenceData).
 *
 * Modes:
 * - Parametric: the reference is a parametrised surface sampled at points carrying parameter
 *   values (point data `UV`, name settable, else the active texture coordinates), e.g. the output
 *   of vtkSampledSurfaceSource at a high resolution. The spline is evaluated at each reference
 *   point's (u, v) (vtkSplineParameterProbe) and the error is the distance between corresponding
 *   points. Points whose (u, v) lies outside the spline's parameter domain are left out of the
 *   statistics (their Error is 0 and `vtkValidPointMask` is 0). The output is the spline
 *   evaluated on the reference's parameter mesh (the reference's cells, spline points). The
 *   correspondence distance bounds both one-sided Hausdorff distances from above; both are
 *   reported as the maximum error.
 * - MeshDistance: the reference is any triangle mesh. The spline is tessellated at
 *   SubdivisionLevel (vtkBezierTriangleTessellator); Error at each tessellation point is its
 *   distance to the reference triangles. The reference is sampled at its vertices and, when
 *   ReferenceSampleLevel n > 1, at the points (i, j, k)/n of every triangle, and each sample's
 *   distance to the tessellation gives HausdorffReferenceToSpline. Distances are exact
 *   point-to-triangle distances (CGAL AABB tree, kernel ctk::PointToMeshDistance); the spline
 *   side is its tessellation, so refine SubdivisionLevel until the figures settle.
 *
 * Output vtkPolyData: the points described above with point data `Error` (plus what the
 * tessellator or probe provides: `Normals`, `UV`, ...) and field data (one value each):
 * `MaxError` (the larger Hausdorff distance), `RMSError` (root mean square of `Error` over the
 * valid points), `HausdorffSplineToReference`, `HausdorffReferenceToSpline`,
 * `BoundingBoxDiagonal` (of the reference's points), the same four divided by the diagonal
 * (`RelativeMaxError`, `RelativeRMSError`, `RelativeHausdorffSplineToReference`,
 * `RelativeHausdorffReferenceToSpline`), and `NumberOfReferenceSamples`.
 *
 * Bad input (no spline or reference, cells that are not Bézier triangles, an empty reference,
 * non-finite reference points, a missing or wrong-sized UV array in Parametric mode, reference
 * cells that are not triangles or have no area in MeshDistance mode, no reference point inside
 * the parameter domain) is reported with vtkErrorMacro naming the problem and RequestData
 * returns 0.
 */
#ifndef vtkApproximationErrorFilter_h
#define vtkApproximationErrorFilter_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string
#include <vector> // for std::vector

class vtkAlgorithmOutput;

class CTSPLINESFILTERS_EXPORT vtkApproximationErrorFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkApproximationErrorFilter* New();
  vtkTypeMacro(vtkApproximationErrorFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ModeType
  {
    Parametric = 0,
    MeshDistance = 1
  };

  ///@{
  /// How the reference is compared. Default MeshDistance.
  vtkSetClampMacro(Mode, int, Parametric, MeshDistance);
  vtkGetMacro(Mode, int);
  void SetModeToParametric() { this->SetMode(Parametric); }
  void SetModeToMeshDistance() { this->SetMode(MeshDistance); }
  ///@}

  ///@{
  /// The reference surface (input port 1), as a data object or a pipeline connection.
  void SetReferenceData(vtkDataObject* reference);
  vtkDataObject* GetReference();
  void SetReferenceConnection(vtkAlgorithmOutput* algOutput);
  ///@}

  ///@{
  /// MeshDistance: segments per Bézier cell edge of the spline tessellation. Default 8.
  vtkSetClampMacro(SubdivisionLevel, int, 1, 4096);
  vtkGetMacro(SubdivisionLevel, int);
  ///@}

  ///@{
  /// MeshDistance: the reference triangles are sampled at (i, j, k)/n, n = ReferenceSampleLevel;
  /// 1 samples the vertices only. Default 1.
  vtkSetClampMacro(ReferenceSampleLevel, int, 1, 4096);
  vtkGetMacro(ReferenceSampleLevel, int);
  ///@}

  ///@{
  /// Name of the spline's point data array of domain points. Default "UV".
  vtkSetStdStringFromCharMacro(UVArrayName);
  vtkGetCharFromStdStringMacro(UVArrayName);
  ///@}

  ///@{
  /// Parametric: name of the reference's point data array of parameter values (2 components);
  /// when missing, the active texture coordinates are used. Default "UV".
  vtkSetStdStringFromCharMacro(ReferenceUVArrayName);
  vtkGetCharFromStdStringMacro(ReferenceUVArrayName);
  ///@}

  static const char* GetModeName(int mode);

protected:
  vtkApproximationErrorFilter();
  ~vtkApproximationErrorFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Mode = MeshDistance;
  int SubdivisionLevel = 8;
  int ReferenceSampleLevel = 1;
  std::string UVArrayName = "UV";
  std::string ReferenceUVArrayName = "UV";

private:
  vtkApproximationErrorFilter(const vtkApproximationErrorFilter&) = delete;
  void operator=(const vtkApproximationErrorFilter&) = delete;

  int ComputeParametric(vtkDataSet* spline, vtkPolyData* reference,
    const std::vector<double>& referencePoints, vtkPolyData* output);
  int ComputeMeshDistance(vtkDataSet* spline, vtkPolyData* reference,
    const std::vector<double>& referencePoints, vtkPolyData* output);
};

#endif
