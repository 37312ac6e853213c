// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkCADFaceSampler
 * @brief   Reads a STEP or IGES model and samples every B-rep face into a parametrised triangle
 *          mesh, edge first, so that neighbouring faces share their boundary nodes.
 *
 * Study section 4. Every B-rep edge is sampled once, adaptively, as a C1 cubic Hermite spline of
 * the mean of its adjacent surfaces over their pcurves (the faces of a real model miss each other
 * by up to ~1e-4 of the diagonal, and the stored 3D curves can be farther off; the mean halves
 * what any face sees), refined while the cubic is off that mean curve by more than half the
 * tolerance, or off a surface over the pcurve chord by more than max(tol / 2, gap + tol / 4)
 * (gap: that surface's own distance from the mean curve), or, with an AngularTolerance, while
 * its tangent leaves a face's tangent plane by more than half of that; vertices are
 * the means of the surfaces at the pcurve ends. The samples are mapped into each adjacent face
 * through its pcurve. Each face's parameter domain is then triangulated (constrained Delaunay,
 * holes by nesting) and refined with interior points only (boundary segments are never split)
 * until the CTo/Bary spline's error at triangle centroids and edge midpoints is below the
 * tolerance (the study's criterion), then until the stitched spline (see RefineStitchedSpline)
 * is. Seams (an edge twice in one wire), pole (degenerate) edges and pcurve ends within the
 * vertex tolerance are handled; a face on a closed surface bounded by closed wires but without
 * a seam edge gets one (OpenCASCADE's ShapeFix_Face::FixMissingSeam), else it is an error
 * naming the face.
 *
 * Malformed files: the file's numbers are checked first, then OpenCASCADE's translation runs in a
 * child process bounded by ReadTimeout (see ctcad::CADModel::Read), so a file on which OCCT
 * crashes or loops is an error naming the file, not a crash or a hang. Every later call into
 * OCCT runs with OCCT's signal handling; an OCCT exception (or a signal OCCT converts) is an
 * error naming the stage and the face or edge, with the exception's type and message. Entities
 * OCCT failed to translate (and skipped) are a warning. Errors are reported with vtkErrorMacro
 * and RequestData returns 0.
 *
 * Output: vtkMultiBlockDataSet, one vtkPolyData block per B-rep face (block name = the STEP face
 * name or "Face i"). Points (double) are the samples: boundary nodes are the edge samples, shared
 * bit for bit by the faces at an edge. Point data: `UV` (the face's oriented parameters (s, t):
 * (u, v), or (-u, v) on a reversed face so that dFdu x dFdv points outwards), `dFdu`, `dFdv` (exact,
 * from the surface), `StitchDFdu`, `StitchDFdv` (what vtkWatertightSplineStitcher uses: the same,
 * but projected to the shared tangent plane at boundary nodes of tangent interfaces with
 * RestoreG1), `GlobalNodeId` (one id per model node; seam and pole nodes repeat within a face).
 * Cell data: `EdgeGradients` (18: per local edge (p0,p1), (p1,p2), (p2,p0), f_u then f_v at the
 * parameter midpoint, exact), `StitchEdgeGradients` (the same, projected to the shared tangent
 * plane on tangent interfaces with RestoreG1), `BRepEdgeId` (3: the B-rep edge of each local edge,
 * -1 inside the face, -2 for a joint between pcurve ends), `EdgeCurvePoints` (18: per boundary
 * local edge the inner control points of the edge's Hermite cubic near its first and second
 * point; NaN inside), `TangentInterface` (3: 1 where the CAD faces along that boundary edge meet
 * tangentially, normals within G1Threshold at its nodes and inside, 0 on feature edges and free
 * edges, -1 inside). Block field data: `FaceId`, `FaceName`, `Reversed`, `MaxGap` (largest
 * distance between this face's surface and the shared boundary curve), `Converged`,
 * `MaxEstimatedError`, `MaxEstimatedAngle` (degrees, with an AngularTolerance),
 * `RefinementRounds`, and on a face that took another construction (FallbackConstructions)
 * `FallbackConstruction` (its vtkCloughTocherSplineFilter value). Top-level field data: `Diagonal`, `AbsoluteTolerance`,
 * `NumberOfGlobalNodes`, `NumberOfBRepEdges`, `NumberOfBRepVertices`, `MaxVertexGap` (largest
 * move of a B-rep vertex to the mean of its surfaces), `MaxEdgeGap` (largest distance between
 * the adjacent surfaces along an edge: the model's own gaps; a face whose surface lies farther
 * than half the tolerance from its shared boundary is refined to twice that distance, with a
 * warning), `NumberOfSeamsAdded`, `NumberOfPCurvesReprojected` (pcurves off their edge's 3D
 * curve, replaced by its projection), `NumberOfDegeneratedEdgesDropped` (degenerated edges
 * along which the surface moves: the wire joined by whole periods without them),
 * `NumberOfSewnEdges` (pairs of free edges sewn into one),
 * `NumberOfRemovedFaces` (slivers), `NumberOfCollapsedEdges` (collapsed by the sewing),
 * `SewingTolerance` (absolute, 0 when the sewing did not run), `RestoreG1`, `NumberOfG1Nodes`,
 * `NumberOfG1Spans` (nodes where
 * several faces, and spans, got one tangent plane), `MaxBoundaryCurveChange`, `MaxBoundaryDerivativeChange` (what RestoreG1
 * changed), `RefinedConstruction` (-1 without RefineStitchedSpline), `RefinedSplitPoint`,
 * `RefinedBoundaryMode`, `StageTimes` (read, edges, loops, tangent planes, faces in seconds;
 * read includes the healing), `SewingTime` (seconds).
 */
#ifndef vtkCADFaceSampler_h
#define vtkCADFaceSampler_h

#include "CTSplinesIOCADModule.h" // For export macro
#include "vtkCloughTocherSplineFilter.h" // for the construction values
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
  /// Seconds OpenCASCADE's translation and healing of the file may take; they run in a child
  /// process that is killed after that (an error naming the file). 0 translates in this process
  /// without a time limit (and without protection from crashes that OCCT cannot convert).
  /// Default 120.
  vtkSetClampMacro(ReadTimeout, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ReadTimeout, double);
  ///@}

  ///@{
  /// Sew the faces on reading (default on): faces whose free edges lie within the tolerance
  /// (Tolerance x diagonal) of each other are joined there (OpenCASCADE's
  /// BRepBuilderAPI_Sewing; IGES surface models and STEP files of loose faces come out
  /// connected). A model without free edges is left as read. Off keeps the file's topology.
  /// Either way, sliver faces of no width (zero area, or 2 area / perimeter below a thousandth
  /// of the tolerance: they cannot be meshed) are removed where that leaves no new free edge
  /// (with Sew, the sewing closes the gap); every change is a warning naming the faces or edges
  /// (also edges shorter than half the tolerance), and counted in the field data. Openings the
  /// sewing leaves (missing faces, wider gaps) stay open: a warning describes each closed free
  /// boundary (size, plane, the faces around it).
  vtkSetMacro(Sew, bool);
  vtkGetMacro(Sew, bool);
  vtkBooleanMacro(Sew, bool);
  ///@}

  ///@{
  /// Error bound for edges and faces, relative to the bounding-box diagonal. Default 1e-4.
  vtkSetClampMacro(Tolerance, double, 1e-9, 1.0);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /// Bound in degrees on the angle between the normals of the converted spline and the CAD
  /// surface's, like OpenCASCADE's angular deflection: edge spans are split while the tangent of
  /// their cubic leaves a face's tangent plane by more than half of it, and faces are refined
  /// until the normals at their check points are within it. 0 (default): no bound, the
  /// positional Tolerance alone decides (the normal deviation is still measured by
  /// vtkWatertightSplineStitcher); a bound costs triangles on curved faces (on a cylinder of
  /// radius r at Tolerance tol, the normals are already within about sqrt(tol diagonal / r)).
  vtkSetClampMacro(AngularTolerance, double, 0.0, 90.0);
  vtkGetMacro(AngularTolerance, double);
  ///@}

  ///@{
  /// Optional bound on the 3D aspect ratio of the triangles (longest edge over 2 sqrt(3)
  /// inradius: 1 for equilateral); 0 (default) for none. Met by inserting circumcentres where
  /// they can go (in a plane scaled to the surface's mean metric), so triangles at long boundary
  /// segments may keep a larger ratio (give a MaxEdgeLength to split those).
  vtkSetClampMacro(AspectRatio, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(AspectRatio, double);
  ///@}

  ///@{
  /// Optional bound on the 3D length of triangle edges, relative to the bounding-box diagonal;
  /// 0 (default) for none. Edge spans are split to it as well (boundary segments are never split
  /// by the face meshing), so that with it an aspect bound is met next to the boundary too.
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

  ///@{
  /// The spline the faces are refined for: with RefineStitchedSpline on (default), after the
  /// study's CTo/Bary criterion each face is refined until the spline vtkWatertightSplineStitcher
  /// makes with this Construction, SplitPoint and BoundaryMode (vtkCloughTocherSplineFilter's
  /// values; give the stitcher the same, it warns otherwise) is within the tolerance (and the
  /// AngularTolerance) at 0.8 of it on a lattice of 15 points per micro-triangle (the boundary
  /// edges are the edge sampling's). Defaults KaG, Bary, Midpoint (the stitcher's).
  vtkSetMacro(RefineStitchedSpline, bool);
  vtkGetMacro(RefineStitchedSpline, bool);
  vtkBooleanMacro(RefineStitchedSpline, bool);
  /// With RefineStitchedSpline: a face that Construction leaves over the tolerances when no
  /// point can go in (or a cap is reached) is checked with every other stitchable construction
  /// on its final mesh and takes the one least over them, if that is less than Construction's
  /// and turns the normals neither from the surface's nor, at tangent interfaces, from the
  /// shared tangent planes; its block's field data `FallbackConstruction` names it, and
  /// vtkWatertightSplineStitcher builds the face with it (a warning says which face and why).
  /// Default on.
  vtkSetMacro(FallbackConstructions, bool);
  vtkGetMacro(FallbackConstructions, bool);
  vtkBooleanMacro(FallbackConstructions, bool);
  /// Constructions that cannot be stitched (vtkCloughTocherSplineFilter::
  /// GetConstructionCanBeStitched) are reported and leave the value unchanged.
  virtual void SetConstruction(int construction);
  vtkGetMacro(Construction, int);
  vtkSetClampMacro(SplitPoint, int, vtkCloughTocherSplineFilter::Bary, vtkCloughTocherSplineFilter::Inc3);
  vtkGetMacro(SplitPoint, int);
  vtkSetClampMacro(BoundaryMode, int, vtkCloughTocherSplineFilter::Perpendicular,
    vtkCloughTocherSplineFilter::GradientToSplitPoint);
  vtkGetMacro(BoundaryMode, int);
  ///@}

  ///@{
  /// G1 across smooth interfaces (beyond the study): where the faces' normals differ by less
  /// than G1Threshold degrees all along an edge span (at its nodes and inside), the faces get
  /// one tangent plane at its nodes and midpoint in the stitching data (StitchDFdu/StitchDFdv,
  /// EdgeCurvePoints, StitchEdgeGradients), so that the stitched spline's tangent planes agree
  /// there (the midpoints with the constructions that read mid-edge gradients on the boundary:
  /// KaG, MGo, MGi, gradient boundary modes), and spans are split where the normal turns along
  /// them or where faces not exactly tangent would move beyond a quarter of the tolerance
  /// (InterfaceTangentPlanes.h). Faces stay C1 inside. Default on, 10 degrees.
  vtkSetMacro(RestoreG1, bool);
  vtkGetMacro(RestoreG1, bool);
  vtkBooleanMacro(RestoreG1, bool);
  vtkSetClampMacro(G1Threshold, double, 0.0, 90.0);
  vtkGetMacro(G1Threshold, double);
  ///@}

  /// Store the value ranges of the face blocks' arrays as they are made (default on), as the
  /// module's filters do (ctsplines::CacheRanges): ParaView's data information and colour maps
  /// read them for every array of every block, and VTK 9.2 computing them itself took 0.28 ms
  /// for each 18-component array (the edge gradients). Off leaves them to VTK, computed when
  /// asked: for a pipeline whose face blocks are an intermediate that nothing displays or writes
  /// (the command line's conversion), where the stored ranges cost about 90 KB a face (150 MB
  /// of a 1,642-face model's 445 MB peak).
  vtkSetMacro(CacheArrayRanges, bool);
  vtkGetMacro(CacheArrayRanges, bool);
  vtkBooleanMacro(CacheArrayRanges, bool);

  /// After an update: the surface point of face `face` (block index) at its oriented
  /// parameters (s, t). Returns false when there is no such face or OpenCASCADE's evaluation
  /// failed (GetEvaluationError says why).
  bool EvaluateSurface(int face, double s, double t, double p[3]);
  /// The same with the derivatives with respect to s and t.
  bool EvaluateSurface(int face, double s, double t, double p[3], double ds[3], double dt[3]);
#if !defined(__VTK_WRAP__)
  /// The same, safe to call from several threads on different faces: why it failed goes into
  /// `error`, not into GetEvaluationError.
  bool EvaluateSurface(int face, double s, double t, double p[3], double ds[3], double dt[3],
    std::string& error) const;
#endif
  /// Why the last EvaluateSurface returned false.
  const char* GetEvaluationError();
  /// After an update: the bounding-box diagonal of the model (0 before).
  double GetDiagonal();

protected:
  vtkCADFaceSampler();
  ~vtkCADFaceSampler() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  double ReadTimeout = 120;
  bool Sew = true;
  double Tolerance = 1e-4;
  double AngularTolerance = 0;
  double AspectRatio = 0;
  double MaxEdgeLength = 0;
  int MaxRounds = 60;
  vtkIdType MaxTrianglesPerFace = 500000;
  bool RefineStitchedSpline = true;
  bool FallbackConstructions = true;
  int Construction = vtkCloughTocherSplineFilter::KaG;
  int SplitPoint = vtkCloughTocherSplineFilter::Bary;
  int BoundaryMode = vtkCloughTocherSplineFilter::Midpoint;
  bool RestoreG1 = true;
  double G1Threshold = 10;
  bool CacheArrayRanges = true;

private:
  vtkCADFaceSampler(const vtkCADFaceSampler&) = delete;
  /// The stages of RequestData (each reports its own errors).
  bool ReadModel();
  bool MeshFaces();
  void WarnAboutFaceMesh(int f);
  bool MakeFaceBlock(int f, vtkMultiBlockDataSet* output);
  void AddModelFields(vtkMultiBlockDataSet* output, double faceTime);
  void operator=(const vtkCADFaceSampler&) = delete;
  std::unique_ptr<vtkCADFaceSamplerInternals> Internals;
};

#endif
