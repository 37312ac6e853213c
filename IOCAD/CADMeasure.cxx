// SPDX-License-Identifier: GPL-3.0-or-later
#include "CADMeasure.h"

#include "CADStitch.h" // SpanKey, IsCollapsedEdge

#include "BezierTriangle.h"
#include "CubicMacroElement.h"

#include <Eigen/Geometry> // cross products

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

namespace ctcad
{
namespace
{
ctk::Vec3 Cubic(const ctk::Vec3& a, const ctk::Vec3& b, const ctk::Vec3& c, const ctk::Vec3& d, double s)
{
  const double r = 1 - s;
  return r * r * r * a + 3 * r * r * s * b + 3 * r * s * s * c + s * s * s * d;
}

/// One side of an interface: the boundary cubic of a face, oriented from the lower node id.
struct Side
{
  std::array<ctk::Vec3, 4> P;
  /// Unit normals of the face's boundary micro-triangle at the G1 sample points, from the lower
  /// node id (zero where the surface is degenerate, at poles).
  std::array<ctk::Vec3, 9> Normal;
  /// The face, its macro-triangle at the edge and the micro-triangle on the edge.
  int Face;
  ctk::Id Triangle;
  int MicroTriangle;
};

/// Unit normals of the boundary micro-triangle of macro-triangle t at its local edge l, at the
/// edge points s = (k + 1/2) / 9, k = 0..8, from the edge's end with the lower node id.
std::array<ctk::Vec3, 9> EdgeNormals(
  const ctk::MacroElementIds& ids, const ctk::OverwriteVector<ctk::Vec3>& P, int l, bool fromFirst)
{
  // Micro-triangle k = l + 2 spans (U_l, U_{l+1}, Z), counter-clockwise like its macro-triangle,
  // so the normal points out of the solid (the faces' parameter planes are oriented so).
  const std::array<ctk::Id, 10> net = ctk::MicroTriangleNet(ids, ctk::MicroTriangleAtEdge(l));
  ctk::Vec3 Q[10];
  for (int i = 0; i < 10; ++i)
  {
    Q[i] = P[net[i]];
  }
  std::array<ctk::Vec3, 9> normals;
  for (int k = 0; k < 9; ++k)
  {
    // Interior points only: at the edge's ends the surface may be degenerate (poles, apices).
    const double s = fromFirst ? (k + 0.5) / 9 : 1 - (k + 0.5) / 9;
    normals[k] = ctk::PatchNormal(3, Q, nullptr, ctk::Vec3(1 - s, s, 0));
  }
  return normals;
}

/// The side of boundary edge e of face f: its cubic and normals from its lower node.
Side FaceSide(const SampledFace& face, const FaceSpline& fs, int f, ctk::Id e)
{
  const ctk::MeshTopology& topo = fs.Topology;
  const ctk::OverwriteVector<ctk::Vec3>& cp = fs.Spline.ControlPoints;
  const ctk::Id a = topo.Edges[e][0], b = topo.Edges[e][1];
  const ctk::Id ta = fs.Spline.Layout.EdgePoint(topo, e, a);
  const ctk::Id tb = fs.Spline.Layout.EdgePoint(topo, e, b);
  const ctk::Id t = topo.EdgeTriangles[e][0];
  const int l = topo.EdgeLocalIndex[e][0];
  const ctk::Id* tri = face.Input.Triangles.data() + 3 * t;
  const bool forward = face.GlobalNode[a] <= face.GlobalNode[b];
  const ctk::MacroElementIds ids =
    ctk::GetMacroElementIds(fs.Spline.Layout, topo, face.Input.Triangles.data(), t);
  const bool fromFirst = face.GlobalNode[tri[l]] <= face.GlobalNode[tri[(l + 1) % 3]];
  return Side{ { forward ? cp[a] : cp[b], forward ? cp[ta] : cp[tb], forward ? cp[tb] : cp[ta],
                 forward ? cp[b] : cp[a] },
    EdgeNormals(ids, cp, l, fromFirst), f, t, ctk::MicroTriangleAtEdge(l) };
}

/// Adds the C0 gap and the G1 angle between two sides of one span to m.
void CompareSides(const Side& o, const Side& side, bool tangent, InterfaceMeasures& m)
{
  for (const double s : { 0.0, 0.25, 0.5, 0.75, 1.0 })
  {
    m.MaxC0Gap = std::max(m.MaxC0Gap,
      (Cubic(o.P[0], o.P[1], o.P[2], o.P[3], s) -
        Cubic(side.P[0], side.P[1], side.P[2], side.P[3], s))
        .norm());
  }
  double angle = 0;
  for (int k = 0; k < 9; ++k)
  {
    if (o.Normal[k].squaredNorm() > 0 && side.Normal[k].squaredNorm() > 0)
    {
      angle = std::max(angle,
        std::atan2(o.Normal[k].cross(side.Normal[k]).norm(), o.Normal[k].dot(side.Normal[k])));
    }
  }
  angle *= 180 / M_PI;
  AngleSummary& g1 = m.G1[tangent];
  if (angle > g1.Max || g1.Count == 0)
  {
    g1.Max = angle;
    g1.Face = side.Face;
    g1.Triangle = side.Triangle;
    g1.MicroTriangle = side.MicroTriangle;
  }
  g1.Sum += angle;
  ++g1.Count;
}

/// The face's cusp nodes: two of its boundary macro-edges leave the node within 3 degrees of
/// each other (their tangents T - V). There the face's boundary curves touch (an arc tangent to
/// a line, or an inner loop touching the outer one: KiCad's Heatsink_125x35x50mm, WC1602A,
/// Potentiometer_Bourns_3266Z), the face's corner is 0 and so is every triangle's corner there:
/// the normal at the node, from two nearly parallel tangents of different data (the edge cubic's,
/// the curve's, and the face's derivatives along a chord), is 180 degrees off or not as they
/// happen to fall. Undefined like at a pole.
std::vector<bool> CuspNodes(const FaceSpline& fs)
{
  const ctk::MeshTopology& topo = fs.Topology;
  const ctk::OverwriteVector<ctk::Vec3>& cp = fs.Spline.ControlPoints;
  std::vector<std::vector<ctk::Vec3>> leaving(fs.Spline.DomainPoints.size());
  for (ctk::Id e = 0; e < static_cast<ctk::Id>(topo.Edges.size()); ++e)
  {
    if (!topo.IsBoundaryEdge(e))
    {
      continue;
    }
    for (const ctk::Id v : { topo.Edges[e][0], topo.Edges[e][1] })
    {
      const ctk::Vec3 d = cp[fs.Spline.Layout.EdgePoint(topo, e, v)] - cp[v];
      if (d.squaredNorm() > 0)
      {
        leaving[v].push_back(d.normalized());
      }
    }
  }
  const double cosMax = std::cos(3 * M_PI / 180);
  std::vector<bool> cusp(leaving.size(), false);
  for (std::size_t v = 0; v < leaving.size(); ++v)
  {
    for (std::size_t i = 0; i < leaving[v].size() && !cusp[v]; ++i)
    {
      for (std::size_t j = i + 1; j < leaving[v].size() && !cusp[v]; ++j)
      {
        cusp[v] = leaving[v][i].dot(leaving[v][j]) >= cosMax;
      }
    }
  }
  return cusp;
}

/// The deviation of face f's spline at its lattice points and `samples` pseudo-random points
/// per macro-triangle (a stream of the face's own, so that faces can be measured in parallel),
/// and each macro-triangle's own into perTriangle when not null.
bool MeasureFace(const FaceSurface& evaluate, int level, int samples, const SampledFace& in,
  const FaceSpline& fs, int f, Deviation& face, std::vector<Deviation>* perTriangle,
  std::string& error)
{
  std::uint64_t state = 0x2545F4914F6CDD1DULL ^ (0x9E3779B97F4A7C15ULL * (f + 1));
  auto uniform = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  };
  std::string failure;
  const SurfaceFunction surface = [&](double s, double t, double* P, double* Ds, double* Dt) {
    if (!evaluate(f, s, t, P, Ds, Dt, failure))
    {
      P[0] = std::nan("");
    }
  };
  const ctk::Id* triangles = in.Input.Triangles.data();
  const std::vector<bool> cuspNode = CuspNodes(fs);
  face.CuspNodes += std::count(cuspNode.begin(), cuspNode.end(), true);
  std::vector<ctk::Vec3> points, cusps;
  if (perTriangle)
  {
    perTriangle->assign(fs.Spline.Layout.NumberOfTriangles, Deviation());
  }
  for (ctk::Id t = 0; t < fs.Spline.Layout.NumberOfTriangles; ++t)
  {
    DeviationPoints(fs.Spline.SplitTau[t], level, { false, false, false }, points);
    // At cusp nodes positions only (the lattice holds the vertices exactly).
    cusps.clear();
    for (int i = 0; i < 3; ++i)
    {
      if (!cuspNode[triangles[3 * t + i]])
      {
        continue;
      }
      const auto at = std::find_if(
        points.begin(), points.end(), [i](const ctk::Vec3& tau) { return tau[i] == 1; });
      if (at != points.end())
      {
        cusps.push_back(*at);
        points.erase(at);
      }
    }
    for (int r = 0; r < samples; ++r)
    {
      double a = uniform(), b = uniform();
      if (a + b > 1)
      {
        a = 1 - a;
        b = 1 - b;
      }
      points.emplace_back(1 - a - b, a, b);
    }
    Deviation triangle;
    if (!MeasureTriangle(fs.Spline, fs.Topology, triangles, t, points, surface, true, triangle,
          error) ||
      !MeasureTriangle(fs.Spline, fs.Topology, triangles, t, cusps, surface, false, triangle, error))
    {
      error = "deviation from the CAD surfaces, face " + std::to_string(f) + ": " +
        (failure.empty() ? error : failure);
      return false;
    }
    face.Add(triangle);
    if (perTriangle)
    {
      (*perTriangle)[t] = triangle;
    }
  }
  return true;
}
} // namespace

InterfaceMeasures MeasureInterfaces(
  const std::vector<SampledFace>& faces, const std::vector<FaceSpline>& splines)
{
  InterfaceMeasures m;
  std::map<SpanKey, Side> firstSide;
  for (std::size_t f = 0; f < faces.size(); ++f)
  {
    const SampledFace& face = faces[f];
    const FaceSpline& fs = splines[f];
    const ctk::MeshTopology& topo = fs.Topology;
    for (ctk::Id e = 0; e < static_cast<ctk::Id>(topo.Edges.size()); ++e)
    {
      const ctk::Id a = topo.Edges[e][0], b = topo.Edges[e][1];
      if (!topo.IsBoundaryEdge(e) ||
        IsCollapsedEdge(fs.Spline, a, fs.Spline.Layout.EdgePoint(topo, e, a),
          fs.Spline.Layout.EdgePoint(topo, e, b), b))
      {
        continue;
      }
      const ctk::Id local = 3 * topo.EdgeTriangles[e][0] + topo.EdgeLocalIndex[e][0];
      const ctk::Id ga = face.GlobalNode[a], gb = face.GlobalNode[b];
      const SpanKey key{ face.BRepEdge[local], std::min(ga, gb), std::max(ga, gb) };
      const Side side = FaceSide(face, fs, static_cast<int>(f), e);
      auto first = firstSide.emplace(key, side);
      if (!first.second)
      {
        const bool tangent = !face.Tangent.empty() && face.Tangent[local] > 0;
        CompareSides(first.first->second, side, tangent, m);
      }
    }
  }
  return m;
}

double GapBeforeStitching(const SampledFace& face, const FaceSpline& fs)
{
  const ctk::SplineInput& in = face.Input;
  if (in.BoundaryCurvePoints.empty())
  {
    return 0;
  }
  const ctk::OverwriteVector<ctk::Vec3>& cp = fs.Spline.ControlPoints;
  auto uvOf = [&](ctk::Id v) { return ctk::Vec2(in.UV[2 * v], in.UV[2 * v + 1]); };
  auto row = [](const std::vector<double>& a, ctk::Id v) {
    return ctk::Vec3(a[3 * v], a[3 * v + 1], a[3 * v + 2]);
  };
  double gap = 0;
  for (ctk::Id t = 0; t < in.NumberOfTriangles(); ++t)
  {
    const ctk::Id* tri = in.Triangles.data() + 3 * t;
    const double* c = in.BoundaryCurvePoints.data() + 18 * t;
    for (int l = 0; l < 3; ++l)
    {
      if (std::isnan(c[6 * l]) || fs.Topology.Neighbor(t, l) >= 0)
      {
        continue;
      }
      const ctk::Id a = tri[l], b = tri[(l + 1) % 3];
      const ctk::Vec3 va = cp[a], vb = cp[b];
      const ctk::Vec3 ta =
        ctk::EdgeControlPoint(va, row(face.SurfaceFu, a), row(face.SurfaceFv, a), uvOf(a), uvOf(b));
      const ctk::Vec3 tb =
        ctk::EdgeControlPoint(vb, row(face.SurfaceFu, b), row(face.SurfaceFv, b), uvOf(b), uvOf(a));
      const ctk::Vec3 near0(c[6 * l], c[6 * l + 1], c[6 * l + 2]);
      const ctk::Vec3 near1(c[6 * l + 3], c[6 * l + 4], c[6 * l + 5]);
      for (const double s : { 0.25, 0.5, 0.75 })
      {
        gap = std::max(gap, (Cubic(va, ta, tb, vb, s) - Cubic(va, near0, near1, vb, s)).norm());
      }
    }
  }
  return gap;
}

bool MeasureDeviation(const FaceSurface& surface, int level, int samples,
  const std::vector<SampledFace>& faces, const std::vector<FaceSpline>& splines,
  std::vector<Deviation>& perFace, Deviation& all, std::string& error, const FaceRunner& forEach,
  std::vector<std::vector<Deviation>>* perTriangle)
{
  perFace.assign(splines.size(), Deviation());
  all = Deviation();
  if (perTriangle)
  {
    perTriangle->assign(splines.size(), {});
  }
  // One OpenCASCADE signal guard per face, around its thousands of surface evaluations (each of
  // which, nested in it, only catches exceptions: RunGuarded).
  auto measure = [&](int f, std::string& message) {
    bool ok = false;
    std::string failure;
    if (!RunGuarded(
          [&] {
            ok = MeasureFace(surface, level, samples, faces[f], splines[f], f, perFace[f],
              perTriangle ? &(*perTriangle)[f] : nullptr, message);
          },
          failure))
    {
      message = "face " + std::to_string(f) + ": the deviation measurement failed: " + failure;
      return false;
    }
    return ok;
  };
  if (!RunOnFaces(static_cast<int>(splines.size()), measure, error, forEach))
  {
    return false;
  }
  for (const Deviation& face : perFace)
  {
    all.Add(face);
  }
  return true;
}

} // namespace ctcad
