// SPDX-License-Identifier: GPL-3.0-or-later
// Tangent planes of the stitching data at face interfaces: which spans are smooth interfaces
// (the CAD faces meet tangentially) rather than feature edges, and, with RestoreG1 (the
// default), G1 across them (beyond the study).
//
// A span is a tangent interface when its faces' normals are within the threshold all along it:
// at both nodes (the faces' vertices there are in one group: normals within the threshold,
// transitively) and at three interior points. A span tangent at its midpoint only (two
// cylinders mitred, fillets meeting in a mitre) is a feature edge: G1 is impossible along it.
//
// The stitched spline's tangent plane at a boundary node is spanned by the node's macro-edge
// points T - V: the shared edge-cubic points on the boundary and J d / 3 inside (Step 1, eq. 11).
// With RestoreG1, the face vertices of a group with a tangent span get one plane n: their
// derivatives J and the edge cubics' inner points at the node are projected onto it, so all
// their T points lie in one plane. n is the mean normal, made perpendicular to the edge cubic
// inside a B-rep edge (the cubic does not move). At a B-rep vertex where faces within the
// threshold but not exactly tangent meet, the cubics turn into n (a crease cubic onto the line
// of its two planes): exact G1 there needs that move, which is kept below a quarter of the
// tolerance by splitting the span (SpansToSplit; the sampling re-samples and comes back).
// At the midpoint of a tangent span the shared normal (made perpendicular to the edge cubic's
// tangent there) is stored in LoopSegment::MidNormal; the stitcher's mid-edge gradients are
// projected onto its plane, so the constructions that read them on the boundary (KaG, MGo, MGi,
// gradient modes) give both faces the same tangent plane at the midpoint too. Between nodes and
// midpoint each side's cross-boundary derivative is a quadratic and G1 holds approximately: the
// error grows with the cube of the normal's turn along the span (and with the boundary
// triangles' skew), and tangent spans are split until it turns by at most 11.25 degrees, and
// where the faces are not exactly tangent until turning into the shared plane moves the surface
// by less than a quarter of the tolerance. Nodes where a face has no normal (poles) join no
// group. A projection of the data keeps every macro-patch C1 inside. At a face's cusp (its
// boundary cubics leave a node within a much smaller angle than their chords), the face's
// derivatives there are fitted to the cubics, so that its interior edges do not fold it (with
// or without RestoreG1). No OpenCASCADE or CGAL.
#ifndef CTSplines_IOCAD_InterfaceTangentPlanes_h
#define CTSplines_IOCAD_InterfaceTangentPlanes_h

#include "CADBRepSampling.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <functional>

namespace ctcad
{
/// Signed angle (radians) from a to b about the unit normal n, in (-pi, pi]; unsigned, in
/// [0, pi], with n the unit vector along a x b.
inline double AngleAbout(
  const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& n)
{
  return std::atan2(n.dot(a.cross(b)), a.dot(b));
}

/// Surface point and first derivatives of face f at its oriented parameters (s, t).
using FaceDerivatives =
  std::function<void(int face, double s, double t, double P[3], double Ds[3], double Dt[3])>;

struct TangentPlaneOptions
{
  bool RestoreG1 = false;
  double G1Threshold = 10; // degrees
  /// With RestoreG1: the spans whose stitching data move by more than this (absolute; an edge
  /// cubic's inner point, or the face's eq. 11 point along the span) are reported for
  /// splitting; 0 reports none.
  double MaxMove = 0;
};

struct TangentPlaneReport
{
  double MaxCurveChange = 0;      // largest move of an edge-cubic inner point
  double MaxDerivativeChange = 0; // largest |J - J0| d / 3 over a node's chords
  Id SmoothNodes = 0;             // nodes where several faces were given a shared tangent plane
  Id SmoothSpans = 0;             // span occurrences given a MidNormal
  /// (B-rep edge, span) of the spans that moved by more than MaxMove: where faces within the
  /// threshold but not exactly tangent meet at a B-rep vertex, the edge cubics there must turn
  /// into the shared plane, by their angle to it times their length.
  std::vector<std::pair<Id, Id>> SpansToSplit;
};

/// Sets LoopNode::Ds/Dt/Consistent of every loop node (the surface's derivatives, projected at
/// smooth nodes with RestoreG1), LoopSegment::Tangent, and with RestoreG1 projects the inner
/// points of the edge cubics at smooth nodes (the same doubles on every face sharing a span) and
/// sets LoopSegment::MidNormal.
TangentPlaneReport SetInterfaceTangentPlanes(std::vector<CADFace>& faces,
  const std::vector<Point3>& nodes, const FaceDerivatives& evaluate,
  const TangentPlaneOptions& options);

} // namespace ctcad

#endif
