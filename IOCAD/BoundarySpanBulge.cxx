// SPDX-License-Identifier: GPL-3.0-or-later
#include "BoundarySpanBulge.h"

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <limits>

namespace ctcad
{
namespace
{
using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;
using Jacobian = Eigen::Matrix<double, 3, 2>;

Vector3 V3(const Point3& p)
{
  return Vector3(p[0], p[1], p[2]);
}

/// The spans of one face that bulge across it (see SpansBulgingAcrossFaces).
void FaceSpans(int f, const CADFace& face, const std::vector<Point3>& nodes,
  const FaceDerivatives& evaluate, double minBulge, std::vector<std::pair<Id, Id>>& spans)
{
  std::vector<const LoopNode*> all;
  for (const FaceLoop& loop : face.Loops)
  {
    for (const LoopNode& node : loop.Nodes)
    {
      all.push_back(&node);
    }
  }
  for (const FaceLoop& loop : face.Loops)
  {
    const std::size_t n = loop.Nodes.size();
    for (std::size_t s = 0; s < n; ++s)
    {
      const LoopSegment& seg = loop.Segments[s];
      const LoopNode& a = loop.Nodes[s];
      const LoopNode& b = loop.Nodes[(s + 1) % n];
      const Vector2 ua(a.UV[0], a.UV[1]), e = Vector2(b.UV[0], b.UV[1]) - ua;
      if (seg.Degenerate || seg.Edge < 0 || seg.Span < 0 || e.squaredNorm() == 0)
      {
        continue;
      }
      const Vector2 mid = ua + 0.5 * e;
      double P[3], Ds[3], Dt[3];
      evaluate(f, mid.x(), mid.y(), P, Ds, Dt);
      Jacobian J;
      J.col(0) = Vector3(Ds[0], Ds[1], Ds[2]);
      J.col(1) = Vector3(Dt[0], Dt[1], Dt[2]);
      const Eigen::Matrix2d G = J.transpose() * J;
      if (std::abs(G.determinant()) <= 1e-20 * G.squaredNorm())
      {
        continue; // a pole: no parameter direction for the bulge
      }
      // The cubic's midpoint against the surface at the chord's midpoint, in the parameter
      // plane: its component across the chord is the bulge (positive to the chord's left).
      const Vector3 cubicMid = (V3(nodes[a.GlobalNode]) + 3 * V3(seg.Near0) + 3 * V3(seg.Near1) +
                                 V3(nodes[b.GlobalNode])) / 8;
      const Vector2 x = G.inverse() * (J.transpose() * (cubicMid - Vector3(P[0], P[1], P[2])));
      const Vector2 left = Vector2(-e.y(), e.x()).normalized();
      const double across = x.dot(left);
      const double bulge = (J * (across * left)).norm();
      // The edge curve's own distance from the face (MaxGap) is part of what is measured, and
      // no split removes it: spans of faces that miss their edges would be split without end.
      if (bulge <= std::max(minBulge, 2 * face.MaxGap))
      {
        continue;
      }
      double width = std::numeric_limits<double>::infinity();
      for (const LoopNode* k : all)
      {
        const Vector2 d = Vector2(k->UV[0], k->UV[1]) - ua;
        if (k->GlobalNode == a.GlobalNode || k->GlobalNode == b.GlobalNode)
        {
          continue;
        }
        const double t = std::clamp(d.dot(e) / e.squaredNorm(), 0.0, 1.0);
        width = std::min(width, (J * (d - t * e)).norm());
      }
      if (bulge > MaxBulgeAcrossFace * width)
      {
        spans.emplace_back(seg.Edge, seg.Span);
      }
    }
  }
}
} // namespace

std::vector<std::pair<Id, Id>> SpansBulgingAcrossFaces(const std::vector<CADFace>& faces,
  const std::vector<Point3>& nodes, const FaceDerivatives& evaluate, double minBulge)
{
  std::vector<std::pair<Id, Id>> spans;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
  {
    FaceSpans(f, faces[f], nodes, evaluate, minBulge, spans);
  }
  std::sort(spans.begin(), spans.end());
  spans.erase(std::unique(spans.begin(), spans.end()), spans.end());
  return spans;
}

} // namespace ctcad
