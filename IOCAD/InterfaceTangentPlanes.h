// SPDX-License-Identifier: GPL-3.0-or-later
// Tangent planes of the stitching data at face interfaces: which spans are smooth interfaces
// (the CAD faces meet tangentially) rather than feature edges, and, optionally, G1 across them
// (beyond the study, its future work).
//
// The stitched spline's tangent plane at a boundary node is spanned by the node's macro-edge
// points T - V: the shared edge-cubic points on the boundary and J d / 3 inside (Step 1, eq. 11).
// With RestoreG1, the faces whose normals at a node differ by less than the threshold get their
// mean normal n there: their derivatives J and the edge cubics' inner points at the node are
// projected onto the plane normal to n, so all their T points lie in one plane. At the midpoint
// of a span between such faces, the shared normal (made perpendicular to the edge cubic's
// tangent there) is stored in LoopSegment::MidNormal; the stitcher's mid-edge gradients are
// projected onto its plane, so the constructions that read them on the boundary (KaG, MGo, MGi,
// gradient modes) give both faces the same tangent plane at the midpoint too. A projection of
// the data keeps every macro-patch C1 inside. No OpenCASCADE or CGAL here.
#ifndef CTSplines_IOCAD_InterfaceTangentPlanes_h
#define CTSplines_IOCAD_InterfaceTangentPlanes_h

#include "CADBRepSampling.h"

#include <functional>

namespace ctcad
{
/// Surface point and first derivatives of face f at its oriented parameters (s, t).
using FaceDerivatives =
  std::function<void(int face, double s, double t, double P[3], double Ds[3], double Dt[3])>;

struct TangentPlaneOptions
{
  bool RestoreG1 = false;
  double G1Threshold = 10; // degrees
};

struct TangentPlaneReport
{
  double MaxCurveChange = 0;      // largest move of an edge-cubic inner point
  double MaxDerivativeChange = 0; // largest |J - J0| d / 3 over a node's chords
  Id SmoothNodes = 0;             // nodes where several faces were given a shared tangent plane
  Id SmoothSpans = 0;             // span occurrences given a MidNormal
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
