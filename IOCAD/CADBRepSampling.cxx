// SPDX-License-Identifier: GPL-3.0-or-later
// OpenCASCADE side of the CAD import: edge-first sampling and face loops of a shape read by
// CADFileReading.h. Every call into OCCT runs under RunGuarded, so that an OCCT exception or a
// signal in OCCT becomes an error naming the stage and the face or edge. No CGAL here.
#include "CADBRepSampling.h"

#include "CADFileReading.h"
#include "BoundarySpanBulge.h"
#include "InterfaceTangentPlanes.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <OSD.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include <cxxabi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <map>
#include <numeric>
#include <tuple>
#include <typeinfo>

namespace ctcad
{
namespace
{
/// The RunGuarded calls active on this thread: inside one, OCCT's signal handler already
/// jumps to its OCC_CATCH_SIGNALS.
thread_local int GuardDepth = 0;

/// failure = "<exception type>: <message>" of the exception being handled.
void DescribeFailure(std::string& failure)
{
  try
  {
    throw;
  }
  catch (const Standard_Failure& e)
  {
    const char* text = e.GetMessageString();
    failure = std::string(e.DynamicType()->Name()) + ": " + (text && *text ? text : "(no message)");
  }
  catch (const std::exception& e)
  {
    int status = 0;
    char* name = abi::__cxa_demangle(typeid(e).name(), nullptr, nullptr, &status);
    failure = std::string(status == 0 && name ? name : typeid(e).name()) + ": " + e.what();
    std::free(name);
  }
}
} // namespace

bool RunGuarded(const std::function<void()>& body, std::string& failure)
{
  // Only for signals nobody handles: a host's own handlers (Python's SIGINT, a sanitizer's
  // SIGSEGV) stay.
  static std::once_flag once;
  std::call_once(once, [] { SetOCCTSignals(OSD_SignalMode_SetUnhandled); });
  // The depth is restored however this call ends: also after a signal's jump out of nested
  // calls (whose frames are skipped) and an exception of another type.
  struct Restore
  {
    int Depth;
    ~Restore() { GuardDepth = this->Depth; }
  } const restore{ GuardDepth };
  try
  {
    if (restore.Depth > 0)
    {
      // Nested: exceptions are caught here, signals by the outer guard. OCC_CATCH_SIGNALS
      // registers a handler under a process-wide lock; per point of a face (the deviation
      // measurement's evaluations) that was 40 % of the work.
      body();
      return true;
    }
    GuardDepth = 1;
    OCC_CATCH_SIGNALS
    body();
    return true;
  }
  catch (const Standard_Failure&)
  {
    DescribeFailure(failure);
  }
  catch (const std::exception&)
  {
    DescribeFailure(failure);
  }
  return false;
}

namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a)
{
  return std::chrono::duration<double>(Clock::now() - a).count();
}

Point3 ToPoint(const gp_XYZ& p)
{
  return { p.X(), p.Y(), p.Z() };
}

double Distance(const Point3& a, const Point3& b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]));
}

/// Cubic Bézier (a, b, c, d) at s.
Point3 Bezier3(const Point3& a, const Point3& b, const Point3& c, const Point3& d, double s)
{
  const double r = 1 - s;
  const double w0 = r * r * r, w1 = 3 * r * r * s, w2 = 3 * r * s * s, w3 = s * s * s;
  Point3 p;
  for (int i = 0; i < 3; ++i)
  {
    p[i] = w0 * a[i] + w1 * b[i] + w2 * c[i] + w3 * d[i];
  }
  return p;
}

/// The adaptive Hermite samples of one B-rep edge, in the edge's own parameter direction.
struct EdgeSampling
{
  bool Degenerate = false;
  Id Vertex0 = -1, Vertex1 = -1; // node ids of the first and last vertex
  std::vector<double> T;
  std::vector<Id> Nodes;
  std::vector<Point3> D; // dC/dt
  /// Inner Hermite control points of span k: near sample k, near sample k+1.
  std::vector<std::array<Point3, 2>> Inner;
  /// Per pcurve use (CADModel::Impl::EdgeUses): the largest distance between its surface and
  /// the edge's mean curve seen while sampling (the face's own gap along the edge).
  std::vector<double> UseGap;
  /// Parameters sampled besides the adaptive ones (RestoreG1's splits at near-tangent joins).
  std::vector<double> Forced;
};

/// A pcurve of an edge on one face (a seam has two on the same face).
struct PCurveUse
{
  int Face;
  Handle(Geom2d_Curve) Curve;
};

/// An edge's run of nodes in one face, with the segments between them.
struct Run
{
  std::vector<LoopNode> Nodes;
  std::vector<LoopSegment> Segments;
  double Tolerance = 0; // vertex tolerance at the run's start
};

} // namespace

// Declared in CADFileReading.h: the healing on reading follows the wires too.
/// The oriented edges of wire W of face F in the order they connect, or empty if they do not
/// (naming the first that does not in `broken`). BRepTools_WireExplorer follows the pcurves and
/// stops where they jump, e.g. by a period on a periodic surface, as some exporters write them;
/// the wire's edges are then chained by their vertices (internal and external edges are no
/// part of a loop).
std::vector<TopoDS_Edge> WireEdges(const TopoDS_Wire& W, const TopoDS_Face& F, TopoDS_Edge& broken)
{
  std::vector<TopoDS_Edge> explored, stored;
  for (BRepTools_WireExplorer we(W, F); we.More(); we.Next())
  {
    explored.push_back(we.Current());
  }
  for (TopoDS_Iterator it(W); it.More(); it.Next())
  {
    const TopAbs_Orientation o = it.Value().Orientation();
    if (it.Value().ShapeType() == TopAbs_EDGE && (o == TopAbs_FORWARD || o == TopAbs_REVERSED))
    {
      stored.push_back(TopoDS::Edge(it.Value()));
    }
  }
  if (explored.size() >= stored.size())
  {
    return explored;
  }
  // From each edge's last vertex, the next unused edge (in stored order) that starts there.
  std::vector<TopoDS_Edge> chain{ stored[0] };
  std::vector<bool> used(stored.size(), false);
  used[0] = true;
  for (std::size_t last = 0; chain.size() < stored.size();)
  {
    const TopoDS_Vertex end = TopExp::LastVertex(chain.back(), Standard_True);
    std::size_t k = 1;
    for (; k <= stored.size(); ++k)
    {
      const std::size_t i = (last + k) % stored.size();
      if (!used[i] && TopExp::FirstVertex(stored[i], Standard_True).IsSame(end))
      {
        chain.push_back(stored[i]);
        used[i] = true;
        last = i;
        break;
      }
    }
    if (k > stored.size())
    {
      broken = chain.back();
      return {};
    }
  }
  return chain;
}

namespace
{

/// An edge sample: parameter, point and derivative of the mean curve; at the edge's ends, P is
/// the vertex node and Off how far it is from the mean curve's end (the model's vertex gap).
struct EdgeSample
{
  double T;
  Point3 P, D, Off;
  /// The parameter the sample's spans are measured from (their Hermite cubics' parameter
  /// lengths): T, but at a vertex into which a stalled run was dropped, the run's last one.
  double H;
};

/// An end span whose curve comes to its vertex turning back, its derivative there pointing
/// against the span's chord (a curve crawling to its vertex, as at the winding ends of Bourns 8100
/// toroids, curls within a fraction of the tolerance to reach it), gets straight inner points, the
/// chord's thirds: its Hermite cubic runs past the vertex and comes back, and the face's corner
/// there folds (normals flipped). Only spans shorter than half the tolerance: the straight cubic
/// stays within that of the curve.
void StraightenHookedEnds(
  const std::vector<EdgeSample>& samples, std::vector<std::array<Point3, 2>>& inner, double tol)
{
  const std::size_t n = samples.size();
  for (const auto& [span, end] : { std::make_pair(std::size_t(0), std::size_t(0)),
         std::make_pair(n - 2, n - 1) })
  {
    const Point3& a = samples[span].P;
    const Point3& b = samples[span + 1].P;
    const Point3& d = samples[end].D;
    const double along = (b[0] - a[0]) * d[0] + (b[1] - a[1]) * d[1] + (b[2] - a[2]) * d[2];
    if (along < 0 && Distance(a, b) < 0.5 * tol)
    {
      for (int i = 0; i < 3; ++i)
      {
        inner[span][0][i] = (2 * a[i] + b[i]) / 3;
        inner[span][1][i] = (a[i] + 2 * b[i]) / 3;
      }
    }
  }
}

/// The index of the sample at which the edge's curve first comes within `tol` of its end vertex
/// v (the last sample) when it then runs away from v by more than `tol` and comes back (on
/// Bourns 8100 toroids, 9 tolerances past the vertex): of the samples within `tol` from there
/// on, the nearest to v. The last index when the curve does not double back.
std::size_t DoublingBackStart(const std::vector<EdgeSample>& samples, const Point3& v, double tol)
{
  const std::size_t n = samples.size();
  std::size_t first = 0;
  while (first + 1 < n && Distance(samples[first].P, v) > tol)
  {
    ++first;
  }
  bool leaves = false;
  for (std::size_t k = first + 1; k + 1 < n; ++k)
  {
    leaves = leaves || Distance(samples[k].P, v) > tol;
  }
  if (!leaves)
  {
    return n - 1;
  }
  std::size_t best = first;
  for (std::size_t k = first; k + 1 < n && Distance(samples[k].P, v) <= tol; ++k)
  {
    best = Distance(samples[k].P, v) < Distance(samples[best].P, v) ? k : best;
  }
  return best;
}

/// Where the edge's curve, walked from the first sample towards the last (its end vertex v),
/// first comes within `tol` of v inside a span whose two samples are farther (it passes the
/// vertex between them), and then runs farther than `tol` from v again before it ends there: a
/// sample is added at that nearest point (`sampleAt`, found on the span's Hermite cubic), so
/// that DoublingBackStart cuts there and not only where a later sample happens to lie near v.
void AddPassingSample(std::vector<EdgeSample>& samples, const Point3& v, double tol,
  const std::function<EdgeSample(double)>& sampleAt)
{
  for (std::size_t k = 0; k + 2 < samples.size() && Distance(samples[k].P, v) > tol; ++k)
  {
    const EdgeSample& a = samples[k];
    const EdgeSample& b = samples[k + 1];
    if (Distance(b.P, v) <= tol)
    {
      return;
    }
    const double h = b.T - a.T;
    Point3 ca, cb;
    for (int i = 0; i < 3; ++i)
    {
      ca[i] = a.P[i] + h * a.D[i] / 3;
      cb[i] = b.P[i] - h * b.D[i] / 3;
    }
    // The cubic is no longer than its control polygon: a span that far stays away from v.
    if (Distance(a.P, v) > tol + Distance(a.P, ca) + Distance(ca, cb) + Distance(cb, b.P))
    {
      continue;
    }
    // The nearest of 64 points, then a golden-section search around it.
    auto distance = [&](double t) { return Distance(Bezier3(a.P, ca, cb, b.P, t), v); };
    constexpr int steps = 64;
    int nearest = 0;
    for (int j = 1; j <= steps; ++j)
    {
      nearest = distance(double(j) / steps) < distance(double(nearest) / steps) ? j : nearest;
    }
    if (nearest == 0 || nearest == steps)
    {
      continue;
    }
    double lo = double(nearest - 1) / steps, hi = double(nearest + 1) / steps;
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    for (int it = 0; it < 40; ++it)
    {
      const double s1 = hi - g * (hi - lo), s2 = lo + g * (hi - lo);
      if (distance(s1) < distance(s2))
      {
        hi = s2;
      }
      else
      {
        lo = s1;
      }
    }
    // b is farther than tol again: the curve leaves v after passing it, and comes back.
    const EdgeSample passing = sampleAt(a.T + 0.5 * (lo + hi) * h);
    if (Distance(passing.P, v) <= tol)
    {
      samples.insert(samples.begin() + k + 1, passing);
      return;
    }
  }
}
/// Samples within a hundredth of the tolerance of the sample before or of the edge's end carry
/// nothing its spans cannot; where two edges run together from their vertex (curves that stall
/// there, as on Bourns 8100 toroids) they would give the face two nodes at one point, and a
/// parameter triangle of no area: they are dropped (not for a closed edge, which needs them to
/// be a loop). Such a run at either end is dropped into the vertex, whose end span keeps the
/// cubic the splits measured from the run's last sample (its derivative and parameter, H): from
/// the curve's end, where the stalled derivative is near 0 and the span's parameter length
/// takes in the stall, the cubic overshoots (L19.3mm toroid, edge 438: a span 0.0025 long, its
/// inner control point 0.016 from its end, 0.0068 off the faces). The vertex keeps its
/// parameter T: the pcurves of a face degenerate along the stall put it elsewhere in the face's
/// plane at the run's last one, off the neighbouring edges' pcurve ends (L39.4mm: a parameter
/// triangle of no area).
void DropSamplesAtOnePoint(std::vector<EdgeSample>& samples, double tol)
{
  const std::size_t n = samples.size();
  std::size_t first = 0, last = n - 1;
  while (first + 1 < last && Distance(samples[first + 1].P, samples[0].P) < 1e-2 * tol)
  {
    ++first;
  }
  while (last > first + 1 && Distance(samples[last - 1].P, samples[n - 1].P) < 1e-2 * tol)
  {
    --last;
  }
  // The vertices take the derivatives and Hermite parameters of the runs' last samples.
  for (const auto& [inner, end] : { std::make_pair(first, std::size_t(0)),
         std::make_pair(last, n - 1) })
  {
    samples[end].D = samples[inner].D;
    samples[end].H = samples[inner].H;
  }
  samples.erase(samples.begin() + last, samples.end() - 1);
  samples.erase(samples.begin() + 1, samples.begin() + first + 1);
  std::vector<EdgeSample> kept{ samples.front() };
  for (std::size_t k = 1; k + 1 < samples.size(); ++k)
  {
    if (Distance(samples[k].P, kept.back().P) >= 1e-2 * tol &&
      Distance(samples[k].P, samples.back().P) >= 1e-2 * tol)
    {
      kept.push_back(samples[k]);
    }
  }
  kept.push_back(samples.back());
  samples.swap(kept);
}

/// An edge's mean curve: the mean of its adjacent surfaces over their pcurves (the 3D curve
/// when no face has a pcurve).
struct EdgeMeanCurve
{
  const BRepAdaptor_Curve& Curve;
  const std::vector<PCurveUse>& Uses;
  const std::vector<BRepAdaptor_Surface>& Surfaces;

  /// The point at t and its derivative; returns how far apart the faces' points are there.
  double At(double t, Point3& p, Point3& dp) const
  {
    double spread = 0;
    if (Uses.empty())
    {
      gp_Pnt q;
      gp_Vec v;
      Curve.D1(t, q, v);
      p = ToPoint(q.XYZ());
      dp = ToPoint(v.XYZ());
      return spread;
    }
    p = dp = Point3{ 0, 0, 0 };
    std::vector<Point3> onFace;
    for (const PCurveUse& u : Uses)
    {
      gp_Pnt2d q;
      gp_Vec2d dq;
      u.Curve->D1(t, q, dq);
      gp_Pnt x;
      gp_Vec xu, xv;
      Surfaces[u.Face].D1(q.X(), q.Y(), x, xu, xv);
      const gp_Vec dx = dq.X() * xu + dq.Y() * xv;
      onFace.push_back(ToPoint(x.XYZ()));
      for (int i = 0; i < 3; ++i)
      {
        p[i] += x.Coord(i + 1) / Uses.size();
        dp[i] += dx.Coord(i + 1) / Uses.size();
      }
    }
    for (std::size_t i = 0; i < onFace.size(); ++i)
    {
      for (std::size_t j = 0; j < i; ++j)
      {
        spread = std::max(spread, Distance(onFace[i], onFace[j]));
      }
    }
    return spread;
  }
};

/// A span is split while its Hermite cubic is off the mean curve by more than half the
/// tolerance (the other half is left to the face interiors), or off any adjacent surface over
/// the pcurve chord (the stitched spline's boundary lies over that chord) by more than
/// max(tol / 2, gap + tol / 4), gap being that surface's own distance from the mean curve
/// there (the face is held to max(tol, 2 gap), and its interior next to the edge must stay
/// within 0.8 of that); with an angular tolerance, also while the cubic's tangent leaves a
/// face's tangent plane by more than half of it. Measured at five points of the span. Where a
/// vertex node is off the mean curve's end (the faces at the vertex miss each other), the
/// cubic carries that offset into the span (blended by its Hermite basis function), and no
/// split removes it: it is allowed on top of a quarter of the tolerance, like the gap.
/// Returns the span's error relative to that bound (split above 1); useGap[k] takes the largest
/// distance seen between pcurve use k's surface and the mean curve.
double SpanError(const EdgeMeanCurve& mean, const EdgeSample& a, const EdgeSample& b, double tol,
  double angTol, std::vector<double>& useGap)
{
  const double h = b.T - a.T;
  Point3 ca, cb;
  for (int i = 0; i < 3; ++i)
  {
    ca[i] = a.P[i] + h * a.D[i] / 3;
    cb[i] = b.P[i] - h * b.D[i] / 3;
  }
  double err = 0; // relative to the bound: a span is split above 1
  for (const double s : { 1.0 / 6, 1.0 / 3, 0.5, 2.0 / 3, 5.0 / 6 })
  {
    const Point3 hermite = Bezier3(a.P, ca, cb, b.P, s);
    Point3 c, dc;
    mean.At(a.T + s * h, c, dc);
    const double h0 = (1 - s) * (1 - s) * (1 + 2 * s), h1 = s * s * (3 - 2 * s);
    const double off = std::hypot(h0 * a.Off[0] + h1 * b.Off[0], h0 * a.Off[1] + h1 * b.Off[1],
      h0 * a.Off[2] + h1 * b.Off[2]);
    err = std::max(err, Distance(hermite, c) / std::max(0.5 * tol, off + 0.25 * tol));
    // The cubic's tangent (the Bezier derivative, up to its length).
    const double r = 1 - s;
    gp_Vec tangent;
    for (int i = 0; i < 3; ++i)
    {
      tangent.SetCoord(i + 1,
        r * r * (ca[i] - a.P[i]) + 2 * r * s * (cb[i] - ca[i]) + s * s * (b.P[i] - cb[i]));
    }
    for (std::size_t k = 0; k < mean.Uses.size(); ++k)
    {
      const PCurveUse& u = mean.Uses[k];
      const gp_Pnt2d ua = u.Curve->Value(a.T), ub = u.Curve->Value(b.T);
      const gp_Pnt2d um = u.Curve->Value(a.T + s * h);
      const BRepAdaptor_Surface& S = mean.Surfaces[u.Face];
      gp_Pnt chord;
      gp_Vec du, dv;
      S.D1((1 - s) * ua.X() + s * ub.X(), (1 - s) * ua.Y() + s * ub.Y(), chord, du, dv);
      const double gap = Distance(ToPoint(S.Value(um.X(), um.Y()).XYZ()), c);
      useGap[k] = std::max(useGap[k], gap);
      err = std::max(err,
        Distance(ToPoint(chord.XYZ()), hermite) / std::max(0.5 * tol, gap + off + 0.25 * tol));
      const gp_Vec normal = du.Crossed(dv);
      if (angTol > 0 && normal.Magnitude() > 0 && tangent.Magnitude() > 0)
      {
        const double off = std::abs(std::asin(std::min(1.0,
          std::abs(normal.Dot(tangent)) / (normal.Magnitude() * tangent.Magnitude()))));
        err = std::max(err, off / (0.5 * angTol));
      }
    }
  }
  return err;
}

/// Largest tilt (radians) of a forced split's cubic off the mean curve by a vertex's offset.
constexpr double MaxOffsetTilt = 0.5 * M_PI / 180;

/// RestoreG1's splits (Forced) next to a vertex whose node is off the mean curve's end: the
/// end span's cubic carries that offset, fading by its Hermite basis function, and so would
/// the piece next to the vertex alone, tilted out of the faces' planes by about 1.5 offset /
/// length, more with every split, and the normal shared at its midpoint (perpendicular to the
/// cubic) with it: linkrods.step, faces 1e-4 apart at a vertex, spans halved to 5e-4 by the
/// chord-mismatch rule, normals 8 degrees off the surfaces and 0.4 off G1. The forced samples
/// keep the offset fading over a length that tilts the cubic by at most MaxOffsetTilt (or over
/// the whole end span). Not over more: boundary nodes off the surface tilt the faces' small
/// triangles next to them.
/// ends: per end of the edge, its vertex sample and the end span's other sample; s is the forced
/// sample at t, taking the faded offsets.
void FadeVertexOffsets(const EdgeSample (&ends)[2][2], double t, EdgeSample& s)
{
  for (const auto& end : ends)
  {
    const EdgeSample &v = end[0], &next = end[1]; // the vertex and the end span's other sample
    const double offset = std::hypot(v.Off[0], v.Off[1], v.Off[2]);
    const double length = Distance(v.P, next.P);
    if (offset == 0 || length == 0)
    {
      continue;
    }
    const double fade = std::min(1.0, 1.5 * offset / (std::tan(MaxOffsetTilt) * length));
    const double h = fade * (next.T - v.T), r = (t - v.T) / h;
    if (r <= 0 || r >= 1)
    {
      continue;
    }
    // The Hermite basis function (1 - r)^2 (1 + 2 r) from the vertex, and its derivative.
    const double w = (1 - r) * (1 - r) * (1 + 2 * r), dw = -6 * r * (1 - r) / h;
    for (int i = 0; i < 3; ++i)
    {
      s.Off[i] += w * v.Off[i];
      s.P[i] += w * v.Off[i];
      s.D[i] += dw * v.Off[i];
    }
  }
}
} // namespace

struct CADModel::Impl
{
  TopoDS_Shape Shape;
  TopTools_IndexedMapOfShape FaceMap, EdgeMap, VertexMap;
  TopTools_IndexedDataMapOfShapeListOfShape EdgeFaces;
  std::vector<BRepAdaptor_Surface> Surfaces;
  std::vector<std::string> Names;
  std::vector<EdgeSampling> Edges;
  std::vector<std::vector<PCurveUse>> EdgeUses;
  std::vector<Point3> VertexSum;
  std::vector<int> VertexCount;
  bool OCCTFailed = false; // an OCCT exception or signal ended a stage
};

/// The stages of Read and Sample, each on one face or edge, under RunGuarded.
struct CADModel::Stages
{
  /// Runs body under RunGuarded; an OCCT failure becomes ErrorMessage = what() + ": " + failure.
  static bool Guard(CADModel& m, const std::function<std::string()>& what, const std::function<bool()>& body)
  {
    bool ok = false;
    std::string failure;
    if (RunGuarded([&] { ok = body(); }, failure))
    {
      return ok;
    }
    m.ErrorMessage = what() + ": " + failure;
    m.Internal->OCCTFailed = true;
    return false;
  }
  static std::string FaceLabel(const CADModel& m, int f)
  {
    return "face " + std::to_string(f) + " (" + m.Internal->Names[f] + ")";
  }
  /// "edge 12 (of face 3 (NAME), face 5 (Face 5))".
  static std::string EdgeLabel(const CADModel& m, int e)
  {
    const Impl& d = *m.Internal;
    std::string label = "edge " + std::to_string(e);
    const int ef = d.EdgeFaces.FindIndex(d.EdgeMap(e + 1));
    std::string faces;
    // An lvalue either way: the iterator must not outlive a temporary list.
    static const TopTools_ListOfShape none;
    const TopTools_ListOfShape& adjacent = ef > 0 ? d.EdgeFaces(ef) : none;
    for (TopTools_ListIteratorOfListOfShape it(adjacent); it.More(); it.Next())
    {
      const int f = d.FaceMap.FindIndex(it.Value()) - 1;
      faces += (faces.empty() ? "" : ", ") + (f >= 0 ? FaceLabel(m, f) : std::string("a face"));
    }
    return label + (faces.empty() ? " (free)" : " (of " + faces + ")");
  }
  static bool Install(CADModel& m, const ShapeRead& r, const std::string& fileName);
  static bool Prepare(CADModel& m);
  static bool CollectEdge(CADModel& m, int e);
  static bool CollapseTinyEdges(CADModel& m, double length);
  static void SampleEdge(CADModel& m, int e, const SamplingOptions& options);
  static void StoreSamples(
    CADModel& m, EdgeSampling& es, const std::vector<EdgeSample>& samples, double tol);
  static void CutDoublingBack(CADModel& m, int e, std::vector<EdgeSample>& samples, double tol,
    const std::function<EdgeSample(double)>& sampleAt);
  static bool WireRuns(CADModel& m, int f, const TopoDS_Wire& W, std::vector<Run>& runs, std::vector<double>& spanLengths);
  static bool JoinRuns(CADModel& m, int f, std::vector<Run>& runs, std::vector<double>& spanLengths, double tol,
    FaceLoop& loop);
  static bool FaceLoops(CADModel& m, int f, double tol);
  static std::vector<std::pair<Id, Id>> UngradedCorners(const CADModel& m);
};

CADModel::CADModel()
  : Internal(new Impl)
{
}

CADModel::~CADModel() = default;

int CADModel::NumberOfEdges() const
{
  return this->Internal->EdgeMap.Extent();
}

int CADModel::NumberOfVertices() const
{
  return this->Internal->VertexMap.Extent();
}

bool CADModel::Read(const std::string& fileName, double timeoutSeconds, const HealingOptions& healing)
{
  const auto start = Clock::now();
  // In the reading child: the sampling at a coarse tolerance, which makes every kind of OCCT
  // query Sample makes. Some malformed files give shapes on which those queries crash, and
  // OCCT's recovery from such a crash (inside its own handlers) can leave its handler stack
  // broken, so a later signal aborts: such a file is an error found in the child. Errors that
  // are the model's (no pcurve, no seam) are left to the Sample of this process.
  const ShapeCheck probe = [&](const ShapeRead& shape, std::string& error) {
    CADModel m;
    SamplingOptions coarse;
    coarse.Tolerance = 1e-2;
    if (!Stages::Install(m, shape, fileName) || (!m.Sample(coarse) && m.Internal->OCCTFailed))
    {
      error = "cannot read " + fileName + ": its shape fails OpenCASCADE's queries: " + m.Error();
      return false;
    }
    return true;
  };
  ShapeRead r;
  if (!ReadCADFile(fileName, timeoutSeconds, healing, probe, r, this->ErrorMessage) ||
    !Stages::Install(*this, r, fileName))
  {
    return false;
  }
  this->Time.Read = Seconds(start);
  return true;
}

/// The shape read, its maps of faces, edges and vertices, face names and bounding box.
bool CADModel::Stages::Install(CADModel& m, const ShapeRead& r, const std::string& fileName)
{
  Impl& d = *m.Internal;
  d = Impl();
  d.Shape = r.Shape;
  m.Healed = r.Healing;
  m.WarningMessages = r.Warnings;
  const bool ok = Guard(m, [&] { return "cannot read " + fileName + ": mapping its faces, edges and vertices"; },
    [&] {
      TopExp::MapShapes(d.Shape, TopAbs_FACE, d.FaceMap);
      TopExp::MapShapes(d.Shape, TopAbs_EDGE, d.EdgeMap);
      TopExp::MapShapes(d.Shape, TopAbs_VERTEX, d.VertexMap);
      TopExp::MapShapesAndAncestors(d.Shape, TopAbs_EDGE, TopAbs_FACE, d.EdgeFaces);
      return true;
    });
  if (!ok)
  {
    return false;
  }
  if (d.FaceMap.Extent() == 0 || d.FaceMap.Extent() != static_cast<int>(r.FaceNames.size()))
  {
    m.ErrorMessage = "no faces in " + fileName;
    return false;
  }
  for (int i = 0; i < d.FaceMap.Extent(); ++i)
  {
    const std::string& n = r.FaceNames[i];
    const bool useful = !n.empty() && n != "NONE" && n != "''";
    d.Names.push_back(useful ? n : "Face " + std::to_string(i));
  }
  std::copy_n(r.Box, 6, m.Box);
  m.BoxDiagonal = std::sqrt(std::pow(m.Box[1] - m.Box[0], 2) + std::pow(m.Box[3] - m.Box[2], 2) +
    std::pow(m.Box[5] - m.Box[4], 2));
  return true;
}

void CADModel::Evaluate(int f, double s, double t, double P[3], double Ds[3], double Dt[3]) const
{
  const bool rev = this->FaceList[f].Reversed;
  gp_Pnt p;
  gp_Vec du, dv;
  this->Internal->Surfaces[f].D1(rev ? -s : s, t, p, du, dv);
  const double sign = rev ? -1.0 : 1.0;
  for (int i = 0; i < 3; ++i)
  {
    P[i] = p.Coord(i + 1);
    Ds[i] = sign * du.Coord(i + 1);
    Dt[i] = dv.Coord(i + 1);
  }
}

void CADModel::Evaluate(int f, double s, double t, double P[3]) const
{
  const gp_Pnt p = this->Internal->Surfaces[f].Value(this->FaceList[f].Reversed ? -s : s, t);
  P[0] = p.X();
  P[1] = p.Y();
  P[2] = p.Z();
}

/// The face adaptors, the vertex points, and the edge and vertex records.
bool CADModel::Stages::Prepare(CADModel& m)
{
  Impl& d = *m.Internal;
  const int nF = d.FaceMap.Extent(), nE = d.EdgeMap.Extent(), nV = d.VertexMap.Extent();
  m.FaceList.assign(nF, CADFace());
  d.Surfaces.clear();
  d.Surfaces.reserve(nF);
  for (int f = 0; f < nF; ++f)
  {
    const TopoDS_Face& F = TopoDS::Face(d.FaceMap(f + 1));
    if (!Guard(m, [&] { return "preparing " + FaceLabel(m, f) + " (its surface)"; },
          [&] {
            d.Surfaces.emplace_back(F, Standard_False);
            return true;
          }))
    {
      return false;
    }
    m.FaceList[f].Index = f;
    m.FaceList[f].Name = d.Names[f];
    m.FaceList[f].Reversed = F.Orientation() == TopAbs_REVERSED;
  }
  m.NodePoints.clear();
  for (int v = 1; v <= nV; ++v)
  {
    if (!Guard(m, [&] { return "reading vertex " + std::to_string(v - 1); },
          [&] {
            m.NodePoints.push_back(ToPoint(BRep_Tool::Pnt(TopoDS::Vertex(d.VertexMap(v))).XYZ()));
            return true;
          }))
    {
      return false;
    }
  }
  d.Edges.assign(nE, EdgeSampling());
  d.EdgeUses.assign(nE, std::vector<PCurveUse>());
  d.VertexSum.assign(nV, Point3{ 0, 0, 0 });
  d.VertexCount.assign(nV, 0);
  m.VertexGap = 0;
  m.EdgeGap = 0;
  m.EdgeSamples = 0;
  return true;
}

/// Pass 1 of the edge sampling for edge e: its pcurves (a seam has two on its face), its end
/// vertices, and the surfaces' points at the pcurve ends (summed into the vertex means).
bool CADModel::Stages::CollectEdge(CADModel& m, int e)
{
  Impl& d = *m.Internal;
  EdgeSampling& es = d.Edges[e];
  const TopoDS_Edge E = TopoDS::Edge(d.EdgeMap(e + 1).Oriented(TopAbs_FORWARD));
  TopoDS_Vertex v0, v1;
  TopExp::Vertices(E, v0, v1);
  if (v0.IsNull() || v1.IsNull())
  {
    m.ErrorMessage = EdgeLabel(m, e) + " has no vertices";
    return false;
  }
  es.Vertex0 = d.VertexMap.FindIndex(v0) - 1;
  es.Vertex1 = d.VertexMap.FindIndex(v1) - 1;
  if (es.Vertex0 < 0 || es.Vertex1 < 0)
  {
    m.ErrorMessage = EdgeLabel(m, e) + ": a vertex of the edge is not in the shape's vertex map";
    return false;
  }
  if (BRep_Tool::Degenerated(E))
  {
    es.Degenerate = true;
    return true;
  }
  std::vector<PCurveUse>& uses = d.EdgeUses[e];
  const int ef = d.EdgeFaces.FindIndex(E);
  if (ef > 0)
  {
    for (const TopoDS_Shape& s : d.EdgeFaces(ef))
    {
      const TopoDS_Face F = TopoDS::Face(s.Oriented(TopAbs_FORWARD));
      const int f = d.FaceMap.FindIndex(s) - 1;
      if (f < 0 || std::any_of(uses.begin(), uses.end(), [&](const PCurveUse& u) { return u.Face == f; }))
      {
        continue;
      }
      double a, b;
      for (const TopoDS_Edge& oriented : { E, TopoDS::Edge(E.Reversed()) })
      {
        Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(oriented, F, a, b);
        if (!pc.IsNull())
        {
          uses.push_back({ f, pc });
        }
        if (!BRep_Tool::IsClosed(E, F))
        {
          break;
        }
      }
    }
  }
  const BRepAdaptor_Curve curve(E);
  for (const PCurveUse& u : uses)
  {
    for (int end = 0; end < 2; ++end)
    {
      const double t = end ? curve.LastParameter() : curve.FirstParameter();
      const gp_Pnt2d q = u.Curve->Value(t);
      const Point3 p = ToPoint(d.Surfaces[u.Face].Value(q.X(), q.Y()).XYZ());
      const Id v = end ? es.Vertex1 : es.Vertex0;
      for (int i = 0; i < 3; ++i)
      {
        d.VertexSum[v][i] += p[i];
      }
      ++d.VertexCount[v];
    }
  }
  return true;
}

/// Edges whose 3D curve stays within `length` of its start (a closed edge around nothing, an
/// edge between two vertices that close) become degenerate: one node, as at a pole, their
/// vertices one. Such an edge cannot be meshed: two of them, imprinted where a circle touches a
/// line (an inner loop touching the outer one), bound a region of no width in their face.
bool CADModel::Stages::CollapseTinyEdges(CADModel& m, double length)
{
  Impl& d = *m.Internal;
  const int nE = d.EdgeMap.Extent();
  std::vector<Id> root(d.VertexSum.size());
  std::iota(root.begin(), root.end(), Id(0));
  auto find = [&](Id v) {
    while (root[v] != v)
    {
      v = root[v] = root[root[v]];
    }
    return v;
  };
  bool any = false;
  for (int e = 0; e < nE; ++e)
  {
    EdgeSampling& es = d.Edges[e];
    bool tiny = !es.Degenerate;
    if (tiny &&
      !Guard(m, [&] { return "edge sampling (its extent), " + EdgeLabel(m, e); },
        [&] {
          const BRepAdaptor_Curve curve(TopoDS::Edge(d.EdgeMap(e + 1)));
          const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
          const gp_Pnt start = curve.Value(t0);
          for (int k = 1; k <= 4 && tiny; ++k)
          {
            tiny = start.Distance(curve.Value(t0 + (t1 - t0) * k / 4)) <= length;
          }
          return true;
        }))
    {
      return false;
    }
    if (tiny)
    {
      es.Degenerate = any = true;
      const Id a = find(es.Vertex0), b = find(es.Vertex1);
      root[std::max(a, b)] = std::min(a, b);
    }
  }
  for (EdgeSampling& es : d.Edges)
  {
    es.Vertex0 = find(es.Vertex0);
    es.Vertex1 = find(es.Vertex1);
  }
  for (Id v = 0; any && v < static_cast<Id>(root.size()); ++v)
  {
    const Id r = find(v);
    if (r != v)
    {
      for (int i = 0; i < 3; ++i)
      {
        d.VertexSum[r][i] += d.VertexSum[v][i];
      }
      d.VertexCount[r] += d.VertexCount[v];
      d.VertexCount[v] = 0;
    }
  }
  return true;
}

/// Where edge e's curve runs past an end vertex and comes back (DoublingBackStart, at either
/// end), its samples end where it first reaches the vertex: the loops of the faces at the edge
/// would cross themselves there (the edges of both sides of a face double back across each
/// other), and their triangulations would not match the neighbours'. The new end sample is the
/// vertex node, its offset from the curve (within `tol`) carried as at any vertex. Where the
/// curve first passes the vertex between two samples, a sample is added there first
/// (AddPassingSample): the samples alone can miss that pass and leave the run out uncut. A curve
/// whose vertices are within 2 tol of each other comes back to its start by design and is kept.
void CADModel::Stages::CutDoublingBack(CADModel& m, int e, std::vector<EdgeSample>& samples,
  double tol, const std::function<EdgeSample(double)>& sampleAt)
{
  EdgeSampling& es = m.Internal->Edges[e];
  const Point3 p0 = samples.front().P, p1 = samples.back().P;
  if (es.Vertex0 == es.Vertex1 || Distance(p0, p1) <= 2 * tol || samples.size() < 3)
  {
    return;
  }
  AddPassingSample(samples, p1, tol, sampleAt);
  std::reverse(samples.begin(), samples.end());
  AddPassingSample(samples, p0, tol, sampleAt);
  const std::size_t begin = samples.size() - 1 - DoublingBackStart(samples, p0, tol);
  std::reverse(samples.begin(), samples.end());
  const std::size_t end = DoublingBackStart(samples, p1, tol);
  if (begin >= end || (begin == 0 && end + 1 == samples.size()))
  {
    return;
  }
  // Reported once: RestoreG1's re-samplings cut the same part.
  if (es.T.empty())
  {
    for (const auto& [from, to, v] : { std::make_tuple(std::size_t(0), begin, es.Vertex0),
           std::make_tuple(end, samples.size() - 1, es.Vertex1) })
    {
      double length = 0, farthest = 0;
      const Point3& at = v == es.Vertex0 ? p0 : p1;
      for (std::size_t k = from; k < to; ++k)
      {
        length += Distance(samples[k].P, samples[k + 1].P);
        farthest = std::max(farthest, Distance(samples[k].P, at));
      }
      if (to > from)
      {
        m.WarningMessages.push_back(EdgeLabel(m, e) + ": its curve runs " + Number(farthest) +
          " past vertex " + std::to_string(v) + " and comes back; that part (" + Number(length) +
          " long, parameters " + Number(samples[from].T) + " to " + Number(samples[to].T) +
          ") is cut");
      }
    }
  }
  for (auto [k, p] : { std::make_pair(begin, p0), std::make_pair(end, p1) })
  {
    if (k != 0 && k + 1 != samples.size())
    {
      for (int i = 0; i < 3; ++i)
      {
        samples[k].Off[i] = p[i] - samples[k].P[i];
      }
      samples[k].P = p;
    }
  }
  samples.erase(samples.begin() + end + 1, samples.end());
  samples.erase(samples.begin(), samples.begin() + begin);
}

/// Pass 2 for edge e: adaptive Hermite samples of its mean curve.
void CADModel::Stages::SampleEdge(CADModel& m, int e, const SamplingOptions& options)
{
  const double tol = options.Tolerance * m.BoxDiagonal;
  const double maxSpan = options.MaxSpanLength * m.BoxDiagonal;
  const int maxSamples = options.MaxSamplesPerEdge;
  Impl& d = *m.Internal;
  EdgeSampling& es = d.Edges[e];
  if (es.Degenerate)
  {
    return;
  }
  const TopoDS_Edge E = TopoDS::Edge(d.EdgeMap(e + 1).Oriented(TopAbs_FORWARD));
  const std::vector<PCurveUse>& uses = d.EdgeUses[e];
  const BRepAdaptor_Curve curve(E);
  const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
  const Point3 p0 = m.NodePoints[es.Vertex0], p1 = m.NodePoints[es.Vertex1];
  const EdgeMeanCurve mean{ curve, uses, d.Surfaces };
  auto makeSample = [&](double t) {
    EdgeSample s{ t, {}, {}, {}, t };
    m.EdgeGap = std::max(m.EdgeGap, mean.At(t, s.P, s.D));
    return s;
  };
  // Shared vertices: the curve ends are the vertex nodes (means over all faces at the vertex).
  EdgeSample first = makeSample(t0), last = makeSample(t1);
  for (int i = 0; i < 3; ++i)
  {
    first.Off[i] = p0[i] - first.P[i];
    last.Off[i] = p1[i] - last.P[i];
  }
  first.P = p0;
  last.P = p1;
  const int n0 = es.Vertex0 == es.Vertex1 ? 3 : 2;
  std::vector<EdgeSample> samples{ first };
  for (int k = 1; k < n0; ++k)
  {
    samples.push_back(makeSample(t0 + (t1 - t0) * k / n0));
  }
  samples.push_back(last);
  es.UseGap.assign(uses.size(), 0.0);
  const double angTol = options.AngularTolerance * M_PI / 180;
  const double minSpan = 1e-9 * std::abs(t1 - t0);
  for (bool changed = true; changed && static_cast<int>(samples.size()) < maxSamples;)
  {
    changed = false;
    std::vector<EdgeSample> next{ samples.front() };
    for (std::size_t k = 0; k + 1 < samples.size(); ++k)
    {
      const EdgeSample& a = samples[k];
      const EdgeSample& b = samples[k + 1];
      // Long spans are split too under a length bound: boundary segments are never split by
      // the face mesher, so a face's triangles can meet that bound (and an aspect bound near
      // the boundary) only if the edge samples do.
      const bool tooLong = maxSpan > 0 && Distance(a.P, b.P) > maxSpan;
      if (std::abs(b.T - a.T) > minSpan &&
        (tooLong || SpanError(mean, a, b, tol, angTol, es.UseGap) > 1) &&
        static_cast<int>(samples.size() + next.size()) < 2 * maxSamples)
      {
        next.push_back(makeSample(0.5 * (a.T + b.T)));
        changed = true;
      }
      next.push_back(b);
    }
    samples.swap(next);
  }
  const EdgeSample ends[2][2] = { { samples[0], samples[1] },
    { samples[samples.size() - 1], samples[samples.size() - 2] } };
  for (const double t : es.Forced)
  {
    const auto at = std::lower_bound(samples.begin(), samples.end(), t,
      [&](const EdgeSample& a, double b) { return (a.T - b) * (t1 - t0) < 0; });
    if (at != samples.begin() && at != samples.end() && at->T != t)
    {
      EdgeSample forced = makeSample(t);
      FadeVertexOffsets(ends, t, forced);
      samples.insert(at, forced);
    }
  }
  CutDoublingBack(m, e, samples, tol, makeSample);
  if (es.Vertex0 != es.Vertex1)
  {
    DropSamplesAtOnePoint(samples, tol);
  }
  StoreSamples(m, es, samples, tol);
}

/// Keeps edge es's samples: parameters, derivatives, nodes (a sample of an earlier sampling keeps
/// its node) and the spans' inner Hermite control points.
void CADModel::Stages::StoreSamples(
  CADModel& m, EdgeSampling& es, const std::vector<EdgeSample>& samples, double tol)
{
  // RestoreG1's splits re-sample the edge.
  std::map<double, Id> earlier;
  for (std::size_t k = 0; k < es.T.size(); ++k)
  {
    earlier.emplace(es.T[k], es.Nodes[k]);
  }
  m.EdgeSamples -= static_cast<Id>(es.T.size());
  const std::size_t n = samples.size();
  es.T.resize(n);
  es.D.resize(n);
  es.Nodes.resize(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    es.T[k] = samples[k].T;
    es.D[k] = samples[k].D;
    const auto old = earlier.find(es.T[k]);
    es.Nodes[k] = k == 0 ? es.Vertex0
      : k + 1 == n       ? es.Vertex1
      : old != earlier.end() ? old->second
                             : m.AddNode(samples[k].P);
  }
  es.Inner.resize(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k)
  {
    const double h = samples[k + 1].H - samples[k].H;
    for (int i = 0; i < 3; ++i)
    {
      es.Inner[k][0][i] = samples[k].P[i] + h * es.D[k][i] / 3;
      es.Inner[k][1][i] = samples[k + 1].P[i] - h * es.D[k + 1][i] / 3;
    }
  }
  StraightenHookedEnds(samples, es.Inner, tol);
  m.EdgeSamples += static_cast<Id>(n);
}

/// The runs of wire W of face f: each edge's samples through the face's pcurve, in wire order,
/// and the parameter-space lengths of their spans.
bool CADModel::Stages::WireRuns(CADModel& m, int f, const TopoDS_Wire& W, std::vector<Run>& runs,
  std::vector<double>& spanLengths)
{
  Impl& d = *m.Internal;
  CADFace& face = m.FaceList[f];
  const TopoDS_Face& F = TopoDS::Face(d.FaceMap(f + 1));
  const double sign = face.Reversed ? -1.0 : 1.0;
  auto surfaceAt = [&](const double uv[2]) {
    double P[3];
    m.Evaluate(f, uv[0], uv[1], P);
    return Point3{ P[0], P[1], P[2] };
  };
  TopoDS_Edge broken;
  const std::vector<TopoDS_Edge> edges = WireEdges(W, F, broken);
  if (edges.empty())
  {
    const int e = d.EdgeMap.FindIndex(broken) - 1;
    m.ErrorMessage = FaceLabel(m, f) + ": a wire's edges do not connect (nothing starts where " +
      (e >= 0 ? EdgeLabel(m, e) : std::string("an edge")) + " ends)";
    return false;
  }
  // A run whose pcurve starts a whole number of periods away from where the previous one ended
  // (the same 3D point) is moved by those periods: the loop must be closed in the plane.
  const std::array<double, 2> period = SurfacePeriods(d.Surfaces[f]);
  auto pushRun = [&](Run& run) {
    for (int i = 0; i < 2 && !runs.empty(); ++i)
    {
      const double shift =
        WholePeriods(runs.back().Nodes.back().UV[i] - run.Nodes.front().UV[i], period[i]);
      for (LoopNode& node : run.Nodes)
      {
        node.UV[i] += shift;
      }
    }
    runs.push_back(run);
  };
  for (const TopoDS_Edge& E : edges)
  {
    const int e = d.EdgeMap.FindIndex(E) - 1;
    if (e < 0)
    {
      m.ErrorMessage = FaceLabel(m, f) + ": a wire has an edge that is not in the shape's edge map";
      return false;
    }
    const EdgeSampling& es = d.Edges[e];
    double a, b;
    Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
    if (pc.IsNull())
    {
      m.ErrorMessage = EdgeLabel(m, e) + " has no pcurve on " + FaceLabel(m, f);
      return false;
    }
    const bool reversed = E.Orientation() == TopAbs_REVERSED;
    Run run;
    run.Tolerance = BRep_Tool::Tolerance(TopExp::FirstVertex(E, Standard_True));
    if (es.Degenerate)
    {
      // A pole: one 3D point, a segment in the parameter plane. Its sample count is fixed
      // below from the face's other spans, so that the pole triangles are not slivers.
      for (const double t : { reversed ? b : a, reversed ? a : b })
      {
        const gp_Pnt2d q = pc->Value(t);
        run.Nodes.push_back({ { sign * q.X(), q.Y() }, es.Vertex0 });
      }
      LoopSegment seg;
      seg.Edge = e;
      seg.Degenerate = true;
      seg.Near0 = seg.Near1 = m.NodePoints[es.Vertex0];
      run.Segments.push_back(seg);
      pushRun(run);
      continue;
    }
    const std::size_t n = es.T.size();
    if (n < 2)
    {
      m.ErrorMessage = EdgeLabel(m, e) + " has no samples (it has no end vertices)";
      return false;
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::size_t k = reversed ? n - 1 - i : i;
      const gp_Pnt2d q = pc->Value(es.T[k]);
      LoopNode node{ { sign * q.X(), q.Y() }, es.Nodes[k] };
      run.Nodes.push_back(node);
      const double gap = Distance(surfaceAt(node.UV), m.NodePoints[node.GlobalNode]);
      face.MaxGap = std::max(face.MaxGap, gap);
      if (i + 1 < n)
      {
        const std::size_t span = reversed ? k - 1 : k;
        LoopSegment seg;
        seg.Edge = e;
        seg.Span = static_cast<Id>(span);
        seg.Near0 = es.Inner[span][reversed ? 1 : 0];
        seg.Near1 = es.Inner[span][reversed ? 0 : 1];
        run.Segments.push_back(seg);
      }
    }
    for (std::size_t k = 0; k < es.UseGap.size(); ++k)
    {
      if (d.EdgeUses[e][k].Face == f)
      {
        face.MaxGap = std::max(face.MaxGap, es.UseGap[k]);
      }
    }
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      double* chord = run.Segments[i].PCurveChord;
      chord[0] = run.Nodes[i + 1].UV[0] - run.Nodes[i].UV[0];
      chord[1] = run.Nodes[i + 1].UV[1] - run.Nodes[i].UV[1];
      spanLengths.push_back(std::hypot(chord[0], chord[1]));
    }
    pushRun(run);
  }
  return true;
}

/// The loop of a wire of face f from its runs: the pole segments subdivided, the runs joined.
bool CADModel::Stages::JoinRuns(CADModel& m, int f, std::vector<Run>& runs, std::vector<double>& spanLengths,
  double tol, FaceLoop& loop)
{
  Impl& d = *m.Internal;
  auto surfaceAt = [&](const double uv[2]) {
    double P[3];
    m.Evaluate(f, uv[0], uv[1], P);
    return Point3{ P[0], P[1], P[2] };
  };
  // Subdivide the pole segments to the median parameter-space span of the other edges.
  double median = 0;
  if (!spanLengths.empty())
  {
    std::nth_element(spanLengths.begin(), spanLengths.begin() + spanLengths.size() / 2, spanLengths.end());
    median = spanLengths[spanLengths.size() / 2];
  }
  for (Run& run : runs)
  {
    if (run.Segments.size() != 1 || !run.Segments[0].Degenerate || median <= 0)
    {
      continue;
    }
    const LoopNode a = run.Nodes[0], b = run.Nodes[1];
    const double len = std::hypot(b.UV[0] - a.UV[0], b.UV[1] - a.UV[1]);
    const int count = std::max(1, std::min(1024, static_cast<int>(std::ceil(len / median))));
    run.Nodes.clear();
    for (int i = 0; i <= count; ++i)
    {
      const double s = static_cast<double>(i) / count;
      run.Nodes.push_back({ { (1 - s) * a.UV[0] + s * b.UV[0], (1 - s) * a.UV[1] + s * b.UV[1] }, a.GlobalNode });
    }
    run.Segments.assign(count, run.Segments[0]);
  }
  // Join the runs: a run's last node and the next run's first are the same B-rep vertex;
  // pcurve ends within the vertex tolerance (in 3D) are merged at their mean, farther ones
  // (a jump across a seam) stay apart, joined by a degenerate segment.
  const std::size_t nr = runs.size();
  for (std::size_t r = 0; r < nr; ++r)
  {
    Run& cur = runs[r];
    const Run& nxt = runs[(r + 1) % nr];
    loop.Nodes.insert(loop.Nodes.end(), cur.Nodes.begin(), cur.Nodes.end() - 1);
    loop.Segments.insert(loop.Segments.end(), cur.Segments.begin(), cur.Segments.end());
    const LoopNode& end = cur.Nodes.back();
    const LoopNode& begin = nxt.Nodes.front();
    const double uvGap = std::hypot(end.UV[0] - begin.UV[0], end.UV[1] - begin.UV[1]);
    const double gap3 = Distance(surfaceAt(end.UV), surfaceAt(begin.UV));
    const bool merge = end.GlobalNode == begin.GlobalNode &&
      (uvGap == 0 || gap3 <= std::max(2 * nxt.Tolerance, tol));
    // Same point in 3D, half a period or more apart in the plane: the wire goes round a
    // closed surface, and without a seam edge the face's loops are open (its domain would
    // come out empty).
    const BRepAdaptor_Surface& S = d.Surfaces[f];
    const double du = std::abs(end.UV[0] - begin.UV[0]), dv = std::abs(end.UV[1] - begin.UV[1]);
    const double uRange = S.IsUPeriodic() ? S.UPeriod() : S.LastUParameter() - S.FirstUParameter();
    const double vRange = S.IsVPeriodic() ? S.VPeriod() : S.LastVParameter() - S.FirstVParameter();
    if (merge && uvGap > 0 &&
      ((S.IsUClosed() && du >= 0.5 * uRange) || (S.IsVClosed() && dv >= 0.5 * vRange)))
    {
      m.ErrorMessage = FaceLabel(m, f) +
        ": a wire closed in 3D is open in the parameter plane (a closed surface without a seam edge)";
      return false;
    }
    if (merge)
    {
      // Node shared with the next run: its first node becomes the mean.
      LoopNode& head = runs[(r + 1) % nr].Nodes.front();
      head.UV[0] = 0.5 * (end.UV[0] + head.UV[0]);
      head.UV[1] = 0.5 * (end.UV[1] + head.UV[1]);
    }
    else
    {
      loop.Nodes.push_back(end);
      LoopSegment seg;
      seg.Degenerate = end.GlobalNode == begin.GlobalNode;
      const Point3& pa = m.NodePoints[end.GlobalNode];
      const Point3& pb = m.NodePoints[begin.GlobalNode];
      for (int i = 0; i < 3; ++i)
      {
        seg.Near0[i] = (2 * pa[i] + pb[i]) / 3;
        seg.Near1[i] = (pa[i] + 2 * pb[i]) / 3;
      }
      loop.Segments.push_back(seg);
    }
  }
  // The first run's head may have been moved by the last join: it is loop node 0.
  loop.Nodes[0] = runs[0].Nodes.front();
  return true;
}

/// Face f's loops, wire by wire, in wire order.
bool CADModel::Stages::FaceLoops(CADModel& m, int f, double tol)
{
  Impl& d = *m.Internal;
  CADFace& face = m.FaceList[f];
  const TopoDS_Face& F = TopoDS::Face(d.FaceMap(f + 1));
  for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
  {
    std::vector<Run> runs;
    std::vector<double> spanLengths;
    if (!WireRuns(m, f, TopoDS::Wire(wx.Current()), runs, spanLengths))
    {
      return false;
    }
    if (runs.empty())
    {
      continue;
    }
    FaceLoop loop;
    if (!JoinRuns(m, f, runs, spanLengths, tol, loop))
    {
      return false;
    }
    face.Loops.push_back(std::move(loop));
  }
  m.EdgeGap = std::max(m.EdgeGap, face.MaxGap);
  return true;
}

/// UngradedCorners: where a tangent span b meets a shorter span a at a face corner of angle
/// alpha, the face mesher's corner triangle joins a's far node to b's far end; its split point
/// lies off b's midpoint by (b / 2 - a cos alpha) / 3 along b and a sin alpha / 3 across, and
/// the boundary micro-patch's derivative toward it, mostly along b where that skew is large,
/// tilts the normal by the edge cubic's error times the skew (TurnsTooFar). Corners from
/// MinSkewedCorner to MaxGradedCorner degrees are graded to a skew of MaxCornerSkew: a
/// right-angled corner of KiCad's EA_eDIP320X (face 39, spans 0.039 and 0.0099: skew 1.98) missed
/// G1 by 0.13 degrees, 0.018 graded (7 % more triangles). Sharper corners make thin triangles
/// whatever their spans (their skew grows as 1 / sin alpha: a cusp's spans would be halved round
/// after round, and KiCad's C_Trimmer_Murata_TZR1 folded where they were): there b is graded to
/// at most MaxCornerSpanRatio times a. 8 left Bourns L43.2 a 45-degree corner of face 218 with
/// spans 0.022 and 0.0033 long (6.7 to 1) whose triangle missed G1 by 0.104 degrees (0.052 at 4,
/// with 1 % more triangles).
constexpr double MaxCornerSkew = 1.5;
constexpr double MaxCornerSpanRatio = 4;
constexpr double MinSkewedCorner = 60;
constexpr double MaxGradedCorner = 100;

/// Whether a corner whose spans are `shorter` and `longer` long (3D chords, shorter > 0) with
/// the cosine `cosine` of the angle between them is to be graded (see MaxCornerSkew).
bool CornerToGrade(double shorter, double longer, double cosine)
{
  if (cosine <= std::cos(MaxGradedCorner * M_PI / 180))
  {
    return false;
  }
  if (cosine > std::cos(MinSkewedCorner * M_PI / 180))
  {
    return longer > MaxCornerSpanRatio * shorter;
  }
  const double sine = std::sqrt(std::max(0.0, 1 - cosine * cosine));
  return 0.5 * longer / shorter - cosine > MaxCornerSkew * sine;
}

/// The spans to halve so that face corners are graded: a tangent span at a corner that
/// CornerToGrade names, where the shorter span comes from the rounds' splits (one of its nodes
/// a forced sample: RestoreG1's, a bulging span's, or this grading's, which so carries on to the
/// next corner). The face mesher never splits boundary segments, and in such a corner it joins
/// the short spans' nodes to the far end of the long one: a needle along the tangent interface
/// (KiCad's muRATA 5100 toroid L21.0, faces 126 and 127: 2e-4 high on a span 0.037 long, beside
/// spans halved to 3.4e-4 at a vertex of three nearly tangent faces; G1 0.37 degrees, 0.036
/// graded). Wider corners leave the mesher room for interior points.
std::vector<std::pair<Id, Id>> CADModel::Stages::UngradedCorners(const CADModel& m)
{
  const Impl& d = *m.Internal;
  auto forcedSplit = [&](const LoopSegment& seg) {
    if (seg.Edge < 0 || seg.Span < 0)
    {
      return false;
    }
    const EdgeSampling& es = d.Edges[seg.Edge];
    const auto isForced = [&](double t) {
      return std::find(es.Forced.begin(), es.Forced.end(), t) != es.Forced.end();
    };
    return isForced(es.T[seg.Span]) || isForced(es.T[seg.Span + 1]);
  };
  std::vector<std::pair<Id, Id>> split;
  for (const CADFace& face : m.FaceList)
  {
    for (const FaceLoop& loop : face.Loops)
    {
      const std::size_t n = loop.Nodes.size();
      auto at = [&](std::size_t k) -> const Point3& {
        return m.NodePoints[loop.Nodes[k % n].GlobalNode];
      };
      for (std::size_t k = 0; n >= 3 && k < n; ++k)
      {
        // Segments k (into node k + 1) and k + 1 (out of it), and the corner between them.
        const Point3 &P0 = at(k), &P1 = at(k + 1), &P2 = at(k + 2);
        const LoopSegment *a = &loop.Segments[k], *b = &loop.Segments[(k + 1) % n];
        double la = Distance(P0, P1), lb = Distance(P1, P2);
        const double dot = (P0[0] - P1[0]) * (P2[0] - P1[0]) + (P0[1] - P1[1]) * (P2[1] - P1[1]) +
          (P0[2] - P1[2]) * (P2[2] - P1[2]);
        if (la > lb)
        {
          std::swap(a, b);
          std::swap(la, lb);
        }
        if (b->Tangent && b->Edge >= 0 && b->Span >= 0 && la > 0 &&
          CornerToGrade(la, lb, dot / (la * lb)) && forcedSplit(*a))
        {
          split.emplace_back(b->Edge, b->Span);
        }
      }
    }
  }
  return split;
}

/// Rounds of RestoreG1's span splits (each halves the spans that still move too much).
constexpr int MaxG1SplitRounds = 16;

bool CADModel::Sample(const SamplingOptions& options)
{
  Impl& d = *this->Internal;
  const double tol = options.Tolerance * this->BoxDiagonal;
  const int nF = d.FaceMap.Extent(), nE = d.EdgeMap.Extent(), nV = d.VertexMap.Extent();
  if (!Stages::Prepare(*this))
  {
    return false;
  }
  // 1. Edges, each once: adaptive cubic Hermite samples of the mean of the adjacent surfaces
  // over their pcurves (the stitched spline's boundary is that cubic over each face's pcurve
  // chord), split as described at spanError in SampleEdge.
  auto start = Clock::now();
  // Pass 1: pcurves, end vertices and the vertex positions: the mean of the adjacent surfaces
  // at the pcurve ends. The faces of a real model miss each other and the edge curves by up to
  // ~1e-4 of the diagonal; the mean halves what any one face sees.
  for (int e = 0; e < nE; ++e)
  {
    if (!Stages::Guard(*this, [&] { return "edge sampling (pcurves and vertices), " + Stages::EdgeLabel(*this, e); },
          [&] { return Stages::CollectEdge(*this, e); }))
    {
      return false;
    }
  }
  if (!Stages::CollapseTinyEdges(*this, 1e-3 * tol))
  {
    return false;
  }
  for (int v = 0; v < nV; ++v)
  {
    if (d.VertexCount[v] > 0)
    {
      const Point3 mean{ d.VertexSum[v][0] / d.VertexCount[v], d.VertexSum[v][1] / d.VertexCount[v],
        d.VertexSum[v][2] / d.VertexCount[v] };
      this->VertexGap = std::max(this->VertexGap, Distance(mean, this->NodePoints[v]));
      this->NodePoints[v] = mean;
    }
  }
  // Pass 2: adaptive Hermite samples of each edge's mean curve.
  for (int e = 0; e < nE; ++e)
  {
    if (!Stages::Guard(*this, [&] { return "edge sampling, " + Stages::EdgeLabel(*this, e); },
          [&] {
            Stages::SampleEdge(*this, e, options);
            return true;
          }))
    {
      return false;
    }
  }
  this->Time.Edges = Seconds(start);

  // 2. Face loops: the edge samples through each face's pcurves, wire by wire, in wire order.
  // 3. Smooth interfaces, and their tangent planes in the stitching data (RestoreG1). Where
  // faces within the threshold but not exactly tangent meet at a B-rep vertex, the edge cubics
  // there turn into the shared plane: spans that move by more than a quarter of the tolerance
  // are halved and the edge re-sampled, then 2 and 3 again (the move halves with the span).
  // So are spans whose cubic bulges across a narrow face (BoundarySpanBulge.h).
  TangentPlaneOptions planes;
  planes.RestoreG1 = options.RestoreG1;
  planes.G1Threshold = options.G1Threshold;
  planes.MaxMove = 0.25 * tol;
  TangentPlaneReport report;
  this->Time.Loops = this->Time.TangentPlanes = 0;
  // After the first round only the faces of re-sampled edges are rebuilt; the others get their
  // loops as built back (the tangent planes start from the edge sampling's data).
  std::vector<char> rebuild(nF, 1);
  std::vector<std::vector<FaceLoop>> built(nF);
  for (int round = 0;; ++round)
  {
    start = Clock::now();
    for (int f = 0; f < nF; ++f)
    {
      if (!rebuild[f])
      {
        this->FaceList[f].Loops = built[f];
        continue;
      }
      this->FaceList[f].Loops.clear();
      this->FaceList[f].MaxGap = 0;
      if (!Stages::Guard(*this, [&] { return "loop building, " + Stages::FaceLabel(*this, f); },
            [&] { return Stages::FaceLoops(*this, f, tol); }))
      {
        return false;
      }
      built[f] = this->FaceList[f].Loops;
    }
    this->Time.Loops += Seconds(start);
    start = Clock::now();
    int lastFace = -1;
    if (!Stages::Guard(*this,
          [&] {
            return "tangent planes at the interfaces, evaluating " +
              (lastFace >= 0 ? Stages::FaceLabel(*this, lastFace) : std::string("a face"));
          },
          [&] {
            const FaceDerivatives evaluate = [&](int f, double s, double t, double* P,
                                               double* Ds, double* Dt) {
              lastFace = f;
              this->Evaluate(f, s, t, P, Ds, Dt);
            };
            report = SetInterfaceTangentPlanes(this->FaceList, this->NodePoints, evaluate, planes);
            // Spans bulging across narrow faces are split too, with or without RestoreG1.
            std::vector<std::pair<Id, Id>>& split = report.SpansToSplit;
            const auto bulging =
              SpansBulgingAcrossFaces(this->FaceList, this->NodePoints, evaluate, 0.01 * tol);
            split.insert(split.end(), bulging.begin(), bulging.end());
            if (planes.RestoreG1)
            {
              const auto ungraded = Stages::UngradedCorners(*this);
              split.insert(split.end(), ungraded.begin(), ungraded.end());
            }
            std::sort(split.begin(), split.end());
            split.erase(std::unique(split.begin(), split.end()), split.end());
            return true;
          }))
    {
      return false;
    }
    this->Time.TangentPlanes += Seconds(start);
    if (report.SpansToSplit.empty() || round == MaxG1SplitRounds)
    {
      break;
    }
    start = Clock::now();
    std::vector<int> edges;
    for (const auto& span : report.SpansToSplit)
    {
      EdgeSampling& es = d.Edges[span.first];
      es.Forced.push_back(0.5 * (es.T[span.second] + es.T[span.second + 1]));
      edges.push_back(static_cast<int>(span.first));
    }
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::fill(rebuild.begin(), rebuild.end(), 0);
    for (const int e : edges)
    {
      for (const PCurveUse& use : d.EdgeUses[e])
      {
        rebuild[use.Face] = 1;
      }
      if (!Stages::Guard(*this, [&] { return "edge sampling, " + Stages::EdgeLabel(*this, e); },
            [&] {
              Stages::SampleEdge(*this, e, options);
              return true;
            }))
      {
        return false;
      }
    }
    this->Time.Edges += Seconds(start);
  }
  this->Changed = { report.MaxCurveChange, report.MaxDerivativeChange, report.SmoothNodes, report.SmoothSpans };
  return true;
}

} // namespace ctcad
