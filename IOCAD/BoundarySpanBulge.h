// SPDX-License-Identifier: GPL-3.0-or-later
// Boundary spans that bulge across their face. A face is meshed over the chords of its loop
// segments in the parameter plane, but its spline follows the shared edge cubic: the boundary
// micro-triangles must carry the cubic's bulge from its chord. Where the face is narrow next to
// a span (a strip between two close curves, KiCad's pad and trace outlines), its boundary
// triangles are no wider than the face, and a bulge of a sizeable part of that width folds the
// micro-patches over (normals flipped by 180 degrees) or keeps them from the surface however
// far the interior is refined. Halving a span divides its bulge by four: the spans whose bulge
// towards the face exceeds a fraction of the face's width there are split (CADModel::Sample's
// split rounds). No OpenCASCADE or CGAL.
#ifndef CTSplines_IOCAD_BoundarySpanBulge_h
#define CTSplines_IOCAD_BoundarySpanBulge_h

#include "InterfaceTangentPlanes.h"

#include <utility>
#include <vector>

namespace ctcad
{
/// Largest bulge of a span towards its face, as a fraction of the distance from the span's
/// chord to the nearest other node of the face's loops on that side.
constexpr double MaxBulgeAcrossFace = 0.25;

/// The (B-rep edge, span) pairs, sorted and unique, whose cubic bulges from its chord towards
/// the inside of a face by more than MaxBulgeAcrossFace of the face's width there (in 3D,
/// through the surface's derivatives at the chord's midpoint), and by more than minBulge
/// (absolute: below it a span is not split, which bounds the rounds) and twice the face's
/// MaxGap (the distance of its edge curves from it, which splitting does not reduce).
std::vector<std::pair<Id, Id>> SpansBulgingAcrossFaces(const std::vector<CADFace>& faces,
  const std::vector<Point3>& nodes, const FaceDerivatives& evaluate, double minBulge);

} // namespace ctcad

#endif
