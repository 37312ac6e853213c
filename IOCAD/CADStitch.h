// SPDX-License-Identifier: GPL-3.0-or-later
// The stitch stage of the CAD conversion (no VTK): the faces' splines become one set of Bézier
// triangles whose interface control points are single points, merged by the model's node and
// B-rep edge ids (never by coordinates), and the merged surface's free and non-manifold
// macro-edges are counted.
#ifndef CADStitch_h
#define CADStitch_h

#include "CADFaceSplines.h"

#include <array>
#include <vector>

namespace ctcad
{
/// A boundary macro-edge's identity across faces: its B-rep edge and its end nodes (two B-rep
/// edges, an arc and its chord, can join the same two nodes).
using SpanKey = std::array<ctk::Id, 3>;

/// Whether the macro-edge (a, b) with T points ta, tb is one point (a pole segment, a joint
/// across a seam's ends): no edge of the surface, it neither closes nor opens it.
bool IsCollapsedEdge(const ctk::CubicSpline& spline, ctk::Id a, ctk::Id ta, ctk::Id tb, ctk::Id b);

/// The merged surface: cubic Bézier triangles (three per macro-triangle, faces in order).
struct StitchedSurface
{
  std::vector<ctk::Vec3> Points;
  std::vector<ctk::Id> Cells;          // 10 point ids per Bézier triangle, in VTK's point order
  std::vector<ctk::Id> FaceIds;        // per Bézier triangle
  std::vector<ctk::Id> MacroTriangles; // per Bézier triangle: its macro-triangle in its face
  std::vector<signed char> MicroTriangles; // per Bézier triangle: 0, 1, 2
  ctk::Id NumberOfMacroTriangles = 0;
  /// Macro-edges of the merged surface, identified by their merged control points, used by one
  /// macro-triangle / by more than two (collapsed macro-edges are not counted).
  ctk::Id FreeEdges = 0, NonManifoldEdges = 0;
  /// Non-manifold macro-edges that the B-rep does not explain: not boundary spans of a B-rep
  /// edge on which more than two faces lie (0 unless the merge joined what the model does not).
  ctk::Id ExtraNonManifoldEdges = 0;
};

/// Merges the faces' splines: vertices by GlobalNode, boundary T points by (B-rep edge, near
/// node, far node), every other point apart. faces[f] is what splines[f] was built from.
void StitchFaces(const std::vector<SampledFace>& faces, const std::vector<FaceSpline>& splines,
  StitchedSurface& surface);

} // namespace ctcad

#endif
