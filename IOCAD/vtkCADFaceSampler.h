// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkCADFaceSampler
 * @brief   Reads a STEP or IGES model and samples every B-rep face into a parametrised triangle
 *          mesh, edge first, so that neighbouring faces share their boundary nodes.
 *
 * Study section 4. Every B-rep edge is sampled once, adaptively, as a C1 cubic Hermite spline of
 * its 3D curve (refined while it is off the curve, or off the surface over the pcurve chord of an
 * adjacent face, by more than the tolerance); the samples are mapped into each adjacent face
 * through its pcurve. Each face's parameter domain is then triangulated (constrained Delaunay,
 * holes by nesting) and refined with interior points only until the CTo/Bary spline's error at
 * triangle centroids and edge midpoints is below the tolerance. Seams (an edge twice in one wire),
 * pole (degenerate) edges and pcurve ends within the vertex tolerance are handled.
 *
 * Output: vtkMultiBlockDataSet, one vtkPolyData block per B-rep face (block name = the STEP face
 * name or "Face i"). Points (double) are the samples: boundary nodes are the edge samples, shared
 * bit for bit by the faces at an edge. Point data: `UV` (the face's oriented parameters (s, t):
 * (u, v), or (-u, v) on a reversed face so that dFdu x dFdv points outwards), `dFdu`, `dFdv` (exact,
 * from the surface), `GlobalNodeId` (one id per model node; seam and pole nodes repeat within a
 * face). Cell data: `EdgeGradients` (18: per local edge (p0,p1), (p1,p2), (p2,p0), f_u then f_v at
 * the parameter midpoint, exact), `BRepEdgeId` (3: the B-rep edge of each local edge, -1 inside
 * the face, -2 for a joint between pcurve ends), `EdgeCurvePoints` (18: per boundary local edge the
 * inner control points of the edge's Hermite cubic near its first and second point; NaN inside).
 * Block field data: `FaceId`, `FaceName`, `Reversed`, `MaxGap` (largest measured distance between
 * the edge curves and this face's surface), `Converged`, `MaxEstimatedError`. Top-level field data:
 * `Diagonal`, `AbsoluteTolerance`, `NumberOfGlobalNodes`, `NumberOfBRepEdges`,
 * `NumberOfBRepVertices`, `MaxVertexGap`, `MaxEdgeGap`, `StageTimes` (read, edges, loops, faces in
 * seconds).
 */
#ifndef vtkCADFaceSampler_h
#define vtkCADFaceSampler_h

#include "CTSplinesIOCADModule.h" // For export macro
#include "vtkMultiBlockDataSetAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkCADFaceSamplerInternals;

class CTSPLINESIOCAD_EXPORT vtkCADFaceSampler : public vtkMultiBlockDataSetAlgorithm
{
public:
  static vtkCADFaceSampler* New();
  vtkTypeMacro(vtkCADFaceSampler, vtkMultiBlockDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The model: .step/.stp or .iges/.igs.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// Error bound for edges and faces, relative to the bounding-box diagonal. Default 1e-4.
  vtkSetClampMacro(Tolerance, double, 1e-9, 1.0);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /// Optional bound on the 3D aspect ratio of the triangles (longest edge over 2 sqrt(3)
  /// inradius: 1 for equilateral); 0 (default) for none. Met by inserting interior points, so
  /// triangles at boundary segments may keep a larger ratio.
  vtkSetClampMacro(AspectRatio, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(AspectRatio, double);
  ///@}

  ///@{
  /// Optional bound on the 3D length of triangle edges, relative to the bounding-box diagonal;
  /// 0 (default) for none.
  vtkSetClampMacro(MaxEdgeLength, double, 0.0, 1.0);
  vtkGetMacro(MaxEdgeLength, double);
  ///@}

  ///@{
  /// Refinement limits per face. Defaults 60 rounds, 500000 triangles.
  vtkSetClampMacro(MaxRounds, int, 0, VTK_INT_MAX);
  vtkGetMacro(MaxRounds, int);
  vtkSetClampMacro(MaxTrianglesPerFace, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MaxTrianglesPerFace, vtkIdType);
  ///@}

  /// After an update: the surface point of face `face` (block index) at its oriented
  /// parameters (s, t). Returns false when there is no such face.
  bool EvaluateSurface(int face, double s, double t, double p[3]);
  /// After an update: the bounding-box diagonal of the model (0 before).
  double GetDiagonal();

protected:
  vtkCADFaceSampler();
  ~vtkCADFaceSampler() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  double Tolerance = 1e-4;
  double AspectRatio = 0;
  double MaxEdgeLength = 0;
  int MaxRounds = 60;
  vtkIdType MaxTrianglesPerFace = 500000;

private:
  vtkCADFaceSampler(const vtkCADFaceSampler&) = delete;
  void operator=(const vtkCADFaceSampler&) = delete;
  std::unique_ptr<vtkCADFaceSamplerInternals> Internals;
};

#endif
