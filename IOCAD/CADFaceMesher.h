// SPDX-License-Identifier: GPL-3.0-or-later
// Interior triangulation of one face's parameter domain (study section 4, second stage): a
// constrained Delaunay triangulation (CGAL) of the boundary loops, refined by inserting interior
// points only (boundary segments are never split, so neighbours keep sharing their nodes) until
// the CTo/Bary spline's error at triangle centroids and edge midpoints is below the tolerance,
// then until the spline the stitcher makes is.
// No OpenCASCADE here: the surface comes in as a callback.
#ifndef CTSplines_IOCAD_CADFaceMesher_h
#define CTSplines_IOCAD_CADFaceMesher_h

#include "CADBRepSampling.h"

#include "CubicCloughTocher.h"

#include <functional>

namespace ctcad
{
/// Surface point P and derivatives Ds, Dt at (s, t).
using SurfaceFunction =
  std::function<void(double s, double t, double P[3], double Ds[3], double Dt[3])>;

struct FaceMeshOptions
{
  double Tolerance = 0;     // absolute
  double AspectRatio = 0;   // bound on the 3D aspect ratio (1 = equilateral); 0 = none
  double MaxEdgeLength = 0; // absolute bound on 3D edge lengths; 0 = none
  int MaxRounds = 60;
  long MaxTriangles = 500000;
  /// After the CTo rounds, check the spline the stitcher makes (this construction, following
  /// the shared edge cubics) on the whole face and refine until it is within the tolerance at
  /// the check points of every micro-triangle (centre, three inner points, macro-edge midpoint).
  bool CheckConstruction = false;
  ctk::SplineOptions Spline;
};

struct FaceMesh
{
  std::vector<std::array<double, 2>> UV;
  /// Points and derivatives for stitching (at boundary nodes the consistent ones of
  /// InterfaceTangentPlanes.h), and the surface's own derivatives.
  std::vector<Point3> F, Fs, Ft;
  std::vector<Point3> SurfaceFs, SurfaceFt;
  std::vector<Id> GlobalNode; // -1 for interior points
  std::vector<std::array<Id, 3>> Triangles; // counter-clockwise in the parameter plane
  /// Per local edge (p0,p1), (p1,p2), (p2,p0): the loop segment it is, or nullptr; and whether
  /// the segment runs the other way (its Near0 is then near the edge's second point).
  std::vector<std::array<const LoopSegment*, 3>> Segments;
  std::vector<std::array<bool, 3>> SegmentFlipped;
  int Rounds = 0;
  int CheckRounds = 0; // rounds that checked the stitched spline
  bool Converged = false;
  /// Last round's largest error: of the stitched spline at its check points when checked, else
  /// the CTo estimate at centroids, micro-triangle centres and interior edge midpoints.
  double MaxEstimatedError = 0;
  std::string Error;
};

/// The mid-edge gradient (f_u then f_v) the stitched spline uses on a boundary span: the
/// surface's, projected to the span's shared tangent plane where the interface is restored to G1.
void StitchEdgeGradient(const LoopSegment& seg, double gradient[6]);

/// Meshes one face given its loops (in its oriented parameter plane), the 3D points of the
/// global boundary nodes and its surface. Returns false with mesh.Error on failure.
bool MeshFace(const std::vector<FaceLoop>& loops, const std::vector<Point3>& nodePoints,
  const SurfaceFunction& surface, const FaceMeshOptions& options, FaceMesh& mesh);

} // namespace ctcad

#endif
