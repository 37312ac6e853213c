// SPDX-License-Identifier: GPL-3.0-or-later
// The measure stage of the CAD conversion (no VTK): how far the stitched faces are from closing
// (C0 gap), from meeting smoothly (G1 angle) and from the CAD surfaces (deviation of positions
// and normals), and how far each face's own boundary cubics were from the shared edge cubics.
#ifndef CADMeasure_h
#define CADMeasure_h

#include "CADFaceMesher.h" // Deviation
#include "CADFaceSplines.h"

#include <functional>
#include <string>
#include <vector>

namespace ctcad
{
/// Angles between the two sides' normals over interface macro-edges, degrees.
struct AngleSummary
{
  double Max = 0, Sum = 0;
  ctk::Id Count = 0;
  /// Where Max is first reached: the face, macro-triangle and micro-triangle on the edge
  /// (ctk::MicroTriangleNet's k) of the edge's side met second, whose tangent flag counted the
  /// edge here (-1 before any edge).
  int Face = -1;
  ctk::Id Triangle = -1;
  int MicroTriangle = -1;
};

/// Where the faces meet: every boundary macro-edge against the first face seen at its span.
struct InterfaceMeasures
{
  /// Largest distance between the two sides' boundary cubics (at s = 0, 1/4, ..., 1).
  double MaxC0Gap = 0;
  /// [0] feature edges, [1] tangent interfaces (SampledFace::Tangent): the largest angle
  /// between the two sides' normals at nine interior points of each macro-edge.
  AngleSummary G1[2];
};
InterfaceMeasures MeasureInterfaces(
  const std::vector<SampledFace>& faces, const std::vector<FaceSpline>& splines);

/// The largest distance (at s = 1/4, 1/2, 3/4) between the face's own boundary cubics, from
/// its surface derivatives (eq. 11), and the shared edge cubics its spline follows.
double GapBeforeStitching(const SampledFace& face, const FaceSpline& spline);

/// Evaluates face f's CAD surface at parameters (s, t): point and first derivatives; false
/// with a message on failure. Called concurrently for different faces.
using FaceSurface = std::function<bool(
  int f, double s, double t, double* P, double* Ds, double* Dt, std::string& failure)>;

/// The deviation of every face's spline from its CAD surface (absolute distances, degrees) at
/// every point of the `level` lattice of every micro-triangle and `samples` pseudo-random
/// points per macro-triangle (a stream of the face's own), faces in parallel through forEach
/// (ForEachFaceInParallel by default; the same figures whatever forEach). perFace[f] is face
/// f's, all their sum. At a face's cusp nodes (two of its boundary macro-edges leave within 3
/// degrees of each other: its boundary curves touch) only the distance is measured: the normal
/// there is undefined (Deviation::CuspNodes counts them). With perTriangle, (*perTriangle)[f][t]
/// is macro-triangle t of face f's own (where to look when a maximum is large). Each face runs
/// under one RunGuarded (OpenCASCADE's signals and exceptions caught and named). On failure
/// returns false with the lowest failed face's error.
bool MeasureDeviation(const FaceSurface& surface, int level, int samples,
  const std::vector<SampledFace>& faces, const std::vector<FaceSpline>& splines,
  std::vector<Deviation>& perFace, Deviation& all, std::string& error,
  const FaceRunner& forEach = nullptr, std::vector<std::vector<Deviation>>* perTriangle = nullptr);

} // namespace ctcad

#endif
