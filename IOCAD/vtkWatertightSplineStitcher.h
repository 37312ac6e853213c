// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkWatertightSplineStitcher
 * @brief   Converts every face of a vtkCADFaceSampler output into a cubic Clough-Tocher spline
 *          and stitches the faces with C0 continuity.
 *
 * Study section 4: each face is converted on its own (by the kernel, faces in parallel: the
 * VTK-free stages CADFaceSplines, CADStitch and CADMeasure, which this class only feeds and
 * reads) with its boundary macro-edges following the B-rep edges' cubic Hermite spans (the
 * sampler's `EdgeCurvePoints` as the construction's boundary curve points): vertices V are the
 * shared edge samples, boundary T points the Hermite inner points, and Step 1's inner ring, the
 * boundary rule and Step 3 follow them, so each macro-patch stays C1 inside. Both sides of an interface
 * then carry the same doubles: C0 without gaps. C1 is lost across the interface (G1 where the
 * sampler's RestoreG1 gave tangent interfaces one tangent plane) and, by the mismatch between the
 * edge cubic and the face's own derivatives at a boundary vertex (O(h^2) where the pcurves are
 * curved), across the interior macro-edges at boundary vertices.
 *
 * Input: the vtkMultiBlockDataSet of vtkCADFaceSampler (per face: UV, dFdu, dFdv, StitchDFdu,
 * StitchDFdv, GlobalNodeId, StitchEdgeGradients, EdgeCurvePoints, BRepEdgeId, TangentInterface).
 * The spline reads the Stitch* arrays; the faces should have been refined for this Construction,
 * SplitPoint and BoundaryMode (the sampler's; a warning says when not). A face block with field
 * data `FallbackConstruction` (vtkCADFaceSampler::FallbackConstructions) is built with that
 * construction instead, unless the faces were refined for another spline.
 * Output port 0: vtkMultiBlockDataSet of per-face splines (as vtkCloughTocherSplineFilter's
 * output, after the sampler's field data of the face).
 * Output port 1: one vtkUnstructuredGrid of all faces where interface control points are single
 * points (vertices merged by GlobalNodeId, boundary edge points by B-rep edge and end nodes,
 * never by coordinates); cell data `FaceId`,
 * `MacroTriangleId`, `MicroTriangleId`; field data `NumberOfFreeEdges`,
 * `NumberOfNonManifoldEdges` (macro-edges of the merged grid, identified by their merged control
 * points, used by one macro-triangle / more than two; collapsed macro-edges, one point like a
 * pole's, are not edges), `NumberOfExtraNonManifoldEdges` (those of them that are not spans of
 * a B-rep edge on which more than two faces lie: 0 unless the merge joined what the model does
 * not), `MaxC0Gap`
 * (largest distance between the two sides' boundary cubics, evaluated on the per-face outputs),
 * `MaxGapBeforeStitching` (largest distance between a face's own boundary cubic, from its exact
 * derivatives, and the shared edge cubic), `NumberOfMacroTriangles`, `NumberOfFallbackFaces`
 * (faces built with their FallbackConstruction; each face block's `Construction` names its own), `MaxG1Angle` (degrees, the
 * largest angle between the two sides' normals at nine interior points of every interface
 * macro-edge),
 * `NumberOfTangentInterfaceEdges`, `MaxG1AngleTangent`, `MeanG1AngleTangent` (the same over the
 * interfaces where the CAD faces meet tangentially), `MaxG1AngleTangentCell` (the cell on one
 * side of the first macro-edge where MaxG1AngleTangent is reached; none without tangent
 * interfaces), `StageTimes` (splines, stitch data, merge,
 * deviation in seconds) and, with a SurfaceSource, `MaxDeviation` and `RMSDeviation` (relative to
 * the diagonal) of the stitched splines from the CAD surfaces and `MaxNormalDeviation`,
 * `RMSNormalDeviation` (degrees between their normals, not at poles nor at the
 * `NumberOfCuspNodes` nodes where a face's boundary curves touch and the spline's normal is
 * undefined: ctcad::MeasureDeviation), measured on a dense lattice of every micro-triangle
 * (DeviationLevel), each face's own maxima in its block; then both outputs also get cell data
 * `Deviation` (relative to the diagonal) and `NormalDeviation` (degrees): the maxima over the
 * cell's macro-triangle, to see where the spline leaves its surface (threshold them in ParaView),
 * and field data `MaxDeviationCell`, `MaxNormalDeviationCell` (the first cell where each is
 * largest).
 */
#ifndef vtkWatertightSplineStitcher_h
#define vtkWatertightSplineStitcher_h

#include "CTSplinesIOCADModule.h" // For export macro
#include "vtkCloughTocherSplineFilter.h" // for the construction values
#include "vtkMultiBlockDataSetAlgorithm.h"

class vtkCADFaceSampler;

class CTSPLINESIOCAD_EXPORT vtkWatertightSplineStitcher : public vtkMultiBlockDataSetAlgorithm
{
public:
  static vtkWatertightSplineStitcher* New();
  vtkTypeMacro(vtkWatertightSplineStitcher, vtkMultiBlockDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Construction of every face (vtkCloughTocherSplineFilter's values; those that take
  /// prescribed boundary curves can be stitched). Default KaG, the
  /// study's recommendation (uses the sampler's exact boundary mid-edge gradients).
  /// Constructions that cannot be stitched (vtkCloughTocherSplineFilter::
  /// GetConstructionCanBeStitched) are reported and leave the value unchanged.
  virtual void SetConstruction(int construction);
  vtkGetMacro(Construction, int);
  ///@}

  ///@{
  /// Split point (Bary, Inc2, Inc3) and boundary rule, as in vtkCloughTocherSplineFilter.
  vtkSetClampMacro(SplitPoint, int, vtkCloughTocherSplineFilter::Bary, vtkCloughTocherSplineFilter::Inc3);
  vtkGetMacro(SplitPoint, int);
  vtkSetClampMacro(BoundaryMode, int, vtkCloughTocherSplineFilter::Perpendicular,
    vtkCloughTocherSplineFilter::GradientToSplitPoint);
  vtkGetMacro(BoundaryMode, int);
  vtkSetClampMacro(Iterations, int, 0, VTK_INT_MAX);
  vtkGetMacro(Iterations, int);
  ///@}

  ///@{
  /// The sampler whose surfaces the deviation is measured against (optional; not a pipeline
  /// connection); the subdivisions of the lattice measured on every micro-triangle (its
  /// interior, its edges, macro-edges included, and vertices: (L + 1)(L + 2) / 2 points each,
  /// 3 L (L + 1) / 2 + 1 per macro-triangle); and the number of pseudo-random points per
  /// macro-triangle besides. Default none, 6 (64 points per macro-triangle), 0.
  void SetSurfaceSource(vtkCADFaceSampler* sampler);
  vtkGetObjectMacro(SurfaceSource, vtkCADFaceSampler);
  vtkSetClampMacro(DeviationLevel, int, 1, 64);
  vtkGetMacro(DeviationLevel, int);
  vtkSetClampMacro(DeviationSamples, int, 0, 1000);
  vtkGetMacro(DeviationSamples, int);
  ///@}

  /// The merged grid (output port 1).
  vtkDataObject* GetMergedOutput() { return this->GetOutputDataObject(1); }

protected:
  vtkWatertightSplineStitcher();
  ~vtkWatertightSplineStitcher() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Construction = vtkCloughTocherSplineFilter::KaG;
  int SplitPoint = vtkCloughTocherSplineFilter::Bary;
  int BoundaryMode = vtkCloughTocherSplineFilter::Midpoint;
  int Iterations = 0;
  int DeviationLevel = 6;
  int DeviationSamples = 0;
  vtkCADFaceSampler* SurfaceSource = nullptr;

private:
  vtkWatertightSplineStitcher(const vtkWatertightSplineStitcher&) = delete;
  void operator=(const vtkWatertightSplineStitcher&) = delete;
};

#endif
