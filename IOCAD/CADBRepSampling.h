// SPDX-License-Identifier: GPL-3.0-or-later
// Edge-first sampling of a B-rep model (study section 4): every B-rep edge is sampled once,
// adaptively, into a C1 cubic Hermite spline of the mean of its adjacent surfaces over their
// pcurves (the model's faces miss each other; the 3D curves can be farther off); the samples are
// mapped into every adjacent face through the face's pcurve, so that neighbouring faces share
// the same boundary nodes. This header is free of OpenCASCADE types (and CGAL must never meet them): the shape
// stays behind an opaque implementation.
#ifndef CTSplines_IOCAD_CADBRepSampling_h
#define CTSplines_IOCAD_CADBRepSampling_h

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ctcad
{
using Id = std::int64_t;
using Point3 = std::array<double, 3>;

/// A boundary node of one face loop: its parameter values in the face's (oriented) parameter
/// plane and the global node it is (shared by every face through which the B-rep passes).
struct LoopNode
{
  double UV[2];
  Id GlobalNode;
  /// Derivatives for stitching (InterfaceTangentPlanes.h): the surface's, projected to the
  /// shared tangent plane where a smooth interface is restored to G1.
  Point3 Ds{}, Dt{};
  bool Consistent = false;
};

/// Loop segment k joins node k and node k+1 (cyclically). Near0 and Near1 are the inner
/// control points of the edge's cubic Hermite span (near node k, near node k+1), the same
/// doubles for every face that uses the span.
struct LoopSegment
{
  Id Edge = -1; // B-rep edge index (0-based), -1 for a joint between pcurve ends
  Id Span = -1; // index of the span within the edge's samples (-1 for joints and poles)
  bool Degenerate = false; // pole edge or joint: one 3D point
  Point3 Near0{}, Near1{};
  /// Unit normal shared by the faces at the span's midpoint when the interface is restored to
  /// G1 there (InterfaceTangentPlanes.h); zero otherwise.
  Point3 MidNormal{};
  /// Whether the CAD faces along the span meet tangentially (normals at the span midpoint
  /// within the G1 threshold): a smooth interface rather than a feature edge.
  bool Tangent = false;
  /// The span's chord along its own pcurve (end minus start, in the face's oriented parameter
  /// plane). The loop's nodes at B-rep vertices are the mean of the pcurve ends that meet there
  /// (JoinRuns), off each pcurve by half their gap: this chord is not.
  double PCurveChord[2] = { 0, 0 };
};

struct FaceLoop
{
  std::vector<LoopNode> Nodes;
  std::vector<LoopSegment> Segments;
};

/// A face in its oriented parameter plane (s, t): (u, v) for a forward face, (-u, v) for a
/// reversed one, so that F_s x F_t points out of the solid and counter-clockwise parameter
/// triangles are outward-facing.
struct CADFace
{
  int Index = 0; // 0-based B-rep face index
  std::string Name;
  bool Reversed = false;
  std::vector<FaceLoop> Loops;
  /// Largest measured distance between the shared edge curves (at the nodes and inside the
  /// spans) and the face's surface over its pcurves: the model's own gap.
  double MaxGap = 0;
};

struct SamplingOptions
{
  double Tolerance = 1e-4; // relative to the bounding-box diagonal
  /// Degrees: edge spans are split while their cubic's tangent leaves a face's tangent plane
  /// by more than half of it; 0 = no bound.
  double AngularTolerance = 0;
  double MaxSpanLength = 0; // bound on edge span chords, relative to the diagonal; 0 = none
  int MaxSamplesPerEdge = 4096;
  bool RestoreG1 = false;   // see InterfaceTangentPlanes.h
  double G1Threshold = 10;  // degrees
};

/// Seconds a file's translation and healing by OpenCASCADE may take (CADModel::Read).
constexpr double DefaultReadTimeout = 120;

/// The healing of CADModel::Read (CADFileReading.h), at the conversion's tolerance (Tolerance x
/// diagonal): sliver faces of no width (zero area, or thinner than a thousandth of it) are
/// removed with a warning naming them, then, with Sew, faces whose free edges lie within the
/// tolerance of each other are sewn (BRepBuilderAPI_Sewing), which also closes the gaps the
/// slivers leave (edges that collapse there are dropped). Removals the sewing cannot close are
/// undone. Edges shorter than half the tolerance are named in a warning. A model without free
/// edges or slivers is left exactly as read.
struct HealingOptions
{
  bool Sew = true;
  double Tolerance = 1e-4; // relative to the bounding-box diagonal
};

/// What the healing of CADModel::Read changed.
struct HealingReport
{
  int SeamsAdded = 0;      // faces given their missing seam edge (ShapeFix_Face::FixMissingSeam)
  int PCurvesReprojected = 0; // pcurves off their edge's 3D curve, replaced by its projection
  int DegeneratedEdgesDropped = 0; // degenerated edges that are no point on their surface
  int SewnEdges = 0;       // pairs of free edges sewn into one edge
  int RemovedFaces = 0;    // sliver faces removed
  int CollapsedEdges = 0;  // edges the sewing collapsed into a vertex (ends of removed slivers)
  double SewingTolerance = 0; // absolute; 0 when the sewing did not run
  double SewingSeconds = 0;
};

/// Runs `body`, which calls into OpenCASCADE, with OCCT's signal handling (OSD::SetSignal, once
/// per process, for the signals nothing else handles; OCC_CATCH_SIGNALS here): a segmentation
/// fault or another signal inside OCCT becomes its Standard_Failure. Returns false with
/// `failure` = "<exception type>: <message>" for a Standard_Failure or an std::exception.
bool RunGuarded(const std::function<void()>& body, std::string& failure);

/// Wall-clock seconds of the stages.
struct StageTimes
{
  double Read = 0, Edges = 0, Loops = 0, TangentPlanes = 0;
};

/// What the tangent-plane stage changed (InterfaceTangentPlanes.h).
struct BoundaryChanges
{
  double MaxCurveChange = 0, MaxDerivativeChange = 0;
  Id SmoothNodes = 0, SmoothSpans = 0;
};

class CADModel
{
public:
  CADModel();
  ~CADModel();
  CADModel(const CADModel&) = delete;
  CADModel& operator=(const CADModel&) = delete;

  /// Reads a STEP (.step, .stp) or IGES (.iges, .igs) file. Returns false with Error set,
  /// naming the file and the stage (and the face) that failed. The file's numbers are checked
  /// first (overflowing reals are an error naming the line and entity). With timeoutSeconds > 0
  /// the translation and healing run in a child process (fork) that is killed after that
  /// time: a file on which OpenCASCADE loops or crashes is an error, never a hang or a crash
  /// of this process; the shape comes back through a pipe (BinTools), with the same faces in
  /// the same order and the same names. 0 translates in this process without a time limit.
  /// `healing`: see HealingOptions (Healing() reports what it did, warnings name the faces).
  bool Read(const std::string& fileName, double timeoutSeconds = DefaultReadTimeout,
    const HealingOptions& healing = HealingOptions());
  /// Samples edges and builds every face's loops (absolute tolerance = relative x diagonal).
  bool Sample(const SamplingOptions& options);

  /// Surface point and first derivatives of face f in its oriented parameter plane.
  void Evaluate(int f, double s, double t, double P[3], double Ds[3], double Dt[3]) const;
  void Evaluate(int f, double s, double t, double P[3]) const;

  const std::vector<CADFace>& Faces() const { return this->FaceList; }
  const std::vector<Point3>& Nodes() const { return this->NodePoints; }
  /// Appends a node (interior points of the face meshes) and returns its global id.
  Id AddNode(const Point3& p)
  {
    this->NodePoints.push_back(p);
    return static_cast<Id>(this->NodePoints.size()) - 1;
  }
  double Diagonal() const { return this->BoxDiagonal; }
  const double* Bounds() const { return this->Box; }
  int NumberOfEdges() const;
  int NumberOfVertices() const;
  /// Measured gaps: the largest move of a B-rep vertex to the mean of its surfaces, and the
  /// largest distance between the adjacent surfaces along an edge (the model's own gaps; OCCT's
  /// stored tolerances understate them).
  double MaxVertexGap() const { return this->VertexGap; }
  double MaxEdgeGap() const { return this->EdgeGap; }
  Id NumberOfEdgeSamples() const { return this->EdgeSamples; }
  /// Faces on closed surfaces that were given their missing seam edge when read.
  int NumberOfSeamsAdded() const { return this->Healed.SeamsAdded; }
  /// Pcurves that were off their edge's 3D curve and replaced by its projection when read.
  int NumberOfPCurvesReprojected() const { return this->Healed.PCurvesReprojected; }
  int NumberOfDegeneratedEdgesDropped() const { return this->Healed.DegeneratedEdgesDropped; }
  /// What the healing on reading changed (seams, sewing, slivers, short edges).
  const HealingReport& Healing() const { return this->Healed; }
  const StageTimes& Times() const { return this->Time; }
  const BoundaryChanges& Changes() const { return this->Changed; }
  const std::string& Error() const { return this->ErrorMessage; }
  /// What Read could not translate (OCCT skipped entities it failed on: faces may be missing),
  /// then what Sample changed beyond the tolerance (edges cut where they double back).
  const std::vector<std::string>& Warnings() const { return this->WarningMessages; }

private:
  struct Impl;
  struct Stages; // the OpenCASCADE side of Read and Sample, stage by stage
  std::unique_ptr<Impl> Internal;
  std::vector<CADFace> FaceList;
  std::vector<Point3> NodePoints;
  double BoxDiagonal = 0;
  double Box[6] = { 0, 0, 0, 0, 0, 0 };
  double VertexGap = 0, EdgeGap = 0;
  Id EdgeSamples = 0;
  HealingReport Healed;
  StageTimes Time;
  BoundaryChanges Changed;
  std::string ErrorMessage;
  std::vector<std::string> WarningMessages;
};

} // namespace ctcad

#endif
