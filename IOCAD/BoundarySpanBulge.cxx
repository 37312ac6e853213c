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

/// A face's loop nodes bucketed in a uniform grid over their parameter bounding box (about one
/// node a cell): the width test visits only the nodes near a span instead of all of them, which
/// made faces with thousands of boundary nodes quadratic (a quarter of ST_ACEPACK-2-CIB's time).
class LoopNodeGrid
{
public:
  explicit LoopNodeGrid(const CADFace& face)
  {
    for (const FaceLoop& loop : face.Loops)
    {
      for (const LoopNode& node : loop.Nodes)
      {
        const Vector2 uv(node.UV[0], node.UV[1]);
        this->Lo = this->Nodes.empty() ? uv : this->Lo.cwiseMin(uv);
        this->Hi = this->Nodes.empty() ? uv : this->Hi.cwiseMax(uv);
        this->Nodes.push_back(&node);
      }
    }
    const double n = static_cast<double>(std::max<std::size_t>(this->Nodes.size(), 1));
    const Vector2 size = (this->Hi - this->Lo).cwiseMax(1e-300);
    const double aspect = std::clamp(size.x() / size.y(), 1 / n, n);
    this->Nx = std::clamp(static_cast<int>(std::sqrt(n * aspect)), 1, static_cast<int>(n));
    this->Ny = std::clamp(static_cast<int>(n / this->Nx), 1, static_cast<int>(n));
    this->Scale = Vector2(this->Nx / size.x(), this->Ny / size.y());
    // Counting sort of the nodes by cell.
    std::vector<int> cellOf(this->Nodes.size());
    this->Start.assign(static_cast<std::size_t>(this->Nx) * this->Ny + 1, 0);
    for (std::size_t k = 0; k < this->Nodes.size(); ++k)
    {
      const Vector2 uv(this->Nodes[k]->UV[0], this->Nodes[k]->UV[1]);
      cellOf[k] = this->Cell(this->Column(uv.x()), this->Row(uv.y()));
      ++this->Start[cellOf[k] + 1];
    }
    for (std::size_t c = 1; c < this->Start.size(); ++c)
    {
      this->Start[c] += this->Start[c - 1];
    }
    this->Sorted.resize(this->Nodes.size());
    std::vector<int> next(this->Start.begin(), this->Start.end() - 1);
    for (std::size_t k = 0; k < this->Nodes.size(); ++k)
    {
      this->Sorted[next[cellOf[k]]++] = this->Nodes[k];
    }
  }

  /// Calls visit(node) for every node in the cells that overlap [lo, hi] (and maybe others).
  template <class Visit>
  void ForEachIn(const Vector2& lo, const Vector2& hi, Visit&& visit) const
  {
    const int i0 = this->Column(lo.x()), i1 = this->Column(hi.x());
    const int j0 = this->Row(lo.y()), j1 = this->Row(hi.y());
    for (int j = j0; j <= j1; ++j)
    {
      for (int k = this->Start[this->Cell(i0, j)]; k < this->Start[this->Cell(i1, j) + 1]; ++k)
      {
        visit(*this->Sorted[k]);
      }
    }
  }

private:
  int Column(double u) const
  {
    return static_cast<int>(std::clamp((u - this->Lo.x()) * this->Scale.x(), 0.0, this->Nx - 1.0));
  }
  int Row(double v) const
  {
    return static_cast<int>(std::clamp((v - this->Lo.y()) * this->Scale.y(), 0.0, this->Ny - 1.0));
  }
  int Cell(int i, int j) const { return j * this->Nx + i; }

  std::vector<const LoopNode*> Nodes, Sorted;
  std::vector<int> Start; // nodes of cell c: Sorted[Start[c], Start[c + 1])
  Vector2 Lo = Vector2::Zero(), Hi = Vector2::Zero(), Scale;
  int Nx = 1, Ny = 1;
};

/// Whether a node of the face other than the span's ends lies closer than `width` (in 3D,
/// through J) to the chord from ua along e. Nodes farther than width / sigma_min(J) in the
/// parameter plane cannot, so only the grid cells within that reach are visited.
bool NodeCloserThan(const LoopNodeGrid& grid, const LoopNode& a, const LoopNode& b,
  const Vector2& ua, const Vector2& e, const Jacobian& J, const Eigen::Matrix2d& G, double width)
{
  const double half = 0.5 * (G(0, 0) - G(1, 1));
  const double sigmaMin2 = 0.5 * (G(0, 0) + G(1, 1)) - std::hypot(half, G(0, 1));
  const double reach = sigmaMin2 > 0 ? 1.001 * width / std::sqrt(sigmaMin2)
                                     : std::numeric_limits<double>::infinity();
  const Vector2 lo = ua.cwiseMin(ua + e).array() - reach, hi = ua.cwiseMax(ua + e).array() + reach;
  bool closer = false;
  grid.ForEachIn(lo, hi, [&](const LoopNode& k) {
    if (closer || k.GlobalNode == a.GlobalNode || k.GlobalNode == b.GlobalNode)
    {
      return;
    }
    const Vector2 d = Vector2(k.UV[0], k.UV[1]) - ua;
    const double t = std::clamp(d.dot(e) / e.squaredNorm(), 0.0, 1.0);
    closer = (J * (d - t * e)).norm() < width;
  });
  return closer;
}

/// The spans of one face that bulge across it (see SpansBulgingAcrossFaces).
void FaceSpans(int f, const CADFace& face, const std::vector<Point3>& nodes,
  const FaceDerivatives& evaluate, double minBulge, std::vector<std::pair<Id, Id>>& spans)
{
  std::unique_ptr<LoopNodeGrid> grid; // built at the face's first bulging span
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
      if (!grid)
      {
        grid = std::make_unique<LoopNodeGrid>(face);
      }
      if (NodeCloserThan(*grid, a, b, ua, e, J, G, bulge / MaxBulgeAcrossFace))
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
