// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL side of the CAD import (never include OpenCASCADE here: its Handle macro breaks CGAL).
#include "CADFaceMesher.h"

#include "CloughTocherSpline.h"
#include "InterfaceTangentPlanes.h"
#include "SplineDataValidation.h"
#include "SplineInput.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <list>
#include <optional>
#include <thread>
#include <unordered_map>
#include <unordered_set>

namespace ctcad
{
void StitchEdgeGradient(const LoopSegment& seg, double gradient[6])
{
  const Point3& n = seg.MidNormal; // zero unless restored to G1
  for (int g = 0; g < 2; ++g)
  {
    double* x = gradient + 3 * g;
    const double d = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
    for (int i = 0; i < 3; ++i)
    {
      x[i] -= d * n[i];
    }
  }
}

void ForEachFaceInParallel(int n, const std::function<void(int)>& body)
{
  std::atomic<int> next(0);
  auto worker = [&]() {
    for (int f; (f = next++) < n;)
    {
      body(f);
    }
  };
  const int nThreads =
    std::max(1, std::min<int>(n, static_cast<int>(std::thread::hardware_concurrency())));
  std::vector<std::thread> threads;
  for (int i = 1; i < nThreads; ++i)
  {
    threads.emplace_back(worker);
  }
  worker();
  for (std::thread& t : threads)
  {
    t.join();
  }
}

void Deviation::Add(const Deviation& o)
{
  this->MaxDistance = std::max(this->MaxDistance, o.MaxDistance);
  this->MaxAngle = std::max(this->MaxAngle, o.MaxAngle);
  this->SumSquaredDistance += o.SumSquaredDistance;
  this->SumSquaredAngle += o.SumSquaredAngle;
  this->Count += o.Count;
  this->AngleCount += o.AngleCount;
  this->CuspNodes += o.CuspNodes;
}

void DeviationPoints(const ctk::Vec3& splitTau, int level, const std::array<bool, 3>& skipEdge,
  std::vector<ctk::Vec3>& points)
{
  points.clear();
  points.push_back(splitTau);
  // Micro-triangle k spans (U_{k+1}, U_{k+2}, Z) with weights w = (i, j, l) / level. Its points
  // with j = 0 (the inner edge to U_{k+1}) are micro-triangle k-1's with i = 0, so each takes
  // j > 0 only, and Z (j = 0 in all three) is the one point added above.
  for (int k = 0; k < 3; ++k)
  {
    const bool skip = skipEdge[(k + 1) % 3]; // the macro-edge (U_{k+1}, U_{k+2}) is l = 0 below
    for (int j = 1; j <= level; ++j)
    {
      for (int i = 0; i + j <= level; ++i)
      {
        const int l = level - i - j;
        if (l == 0 && skip)
        {
          continue;
        }
        points.push_back(
          ctk::MacroBarycentric(splitTau, k, ctk::Vec3(i, j, l) / static_cast<double>(level)));
      }
    }
  }
}

bool PointDeviation(const SurfaceFunction& surface, const ctk::Vec2& X,
  const ctk::ParametricJet& jet, bool normals, double& distance, double& angle,
  std::string& error)
{
  Point3 S, Ds, Dt;
  surface(X.x(), X.y(), S.data(), Ds.data(), Dt.data());
  distance = (jet.Value - ctk::Vec3(S[0], S[1], S[2])).norm();
  angle = -1;
  if (normals)
  {
    const ctk::Vec3 su(Ds[0], Ds[1], Ds[2]), sv(Dt[0], Dt[1], Dt[2]);
    if (!ctk::IsSingularTangentPlane(su, sv) && !ctk::IsSingularTangentPlane(jet.Du, jet.Dv))
    {
      const ctk::Vec3 a = su.cross(sv), b = jet.Du.cross(jet.Dv);
      angle = std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
    }
  }
  if (!std::isfinite(distance) || !std::isfinite(angle))
  {
    error = "non-finite surface or spline value at (" + std::to_string(X.x()) + ", " +
      std::to_string(X.y()) + ") of the face's parameter plane";
    return false;
  }
  return true;
}

bool MeasureTriangle(const ctk::CubicSpline& spline, const ctk::MeshTopology& topo,
  const ctk::Id* triangles, ctk::Id t, const std::vector<ctk::Vec3>& points,
  const SurfaceFunction& surface, bool normals, Deviation& d, std::string& error,
  ctk::Vec3* worst, double tolerance, double angularTolerance)
{
  double worstRatio = -1;
  for (const ctk::Vec3& tau : points)
  {
    ctk::Vec2 X = ctk::Vec2::Zero();
    for (int i = 0; i < 3; ++i)
    {
      X += tau[i] * spline.DomainPoints[triangles[3 * t + i]];
    }
    double e, a;
    if (!PointDeviation(surface, X,
          ctk::EvaluateSpline(spline, topo, triangles, t, tau, normals ? 1 : 0), normals, e, a,
          error))
    {
      return false;
    }
    d.MaxDistance = std::max(d.MaxDistance, e);
    d.SumSquaredDistance += e * e;
    ++d.Count;
    if (a >= 0)
    {
      d.MaxAngle = std::max(d.MaxAngle, a);
      d.SumSquaredAngle += a * a;
      ++d.AngleCount;
    }
    const double ratio = std::max(e / tolerance, a / angularTolerance);
    if (worst && ratio > worstRatio)
    {
      worstRatio = ratio;
      *worst = tau;
    }
  }
  return true;
}

namespace
{
struct VertexInfo
{
  Id Index = -1;
};
struct FaceInfo
{
  int Nesting = -1;
  bool InDomain() const { return Nesting % 2 == 1; }
};
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using TDS = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, TDS, CGAL::Exact_predicates_tag>;
using Point = CDT::Point;

std::uint64_t PairKey(Id a, Id b)
{
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) ^ lo;
}

/// How many loop segments lie on a constraint, by the PairKey of its points (1 where absent).
using Multiplicity = std::unordered_map<std::uint64_t, int>;

/// Nesting level by flood fill from the infinite face across constraints: odd levels are inside
/// the domain, so holes (inner loops) come out right without knowing loop orientations. A
/// constraint that two loops share (an inner loop touching the outer one along a collapsed edge)
/// is crossed twice: the level goes up by the number of loop segments on it.
void MarkDomains(CDT& cdt, const Multiplicity& multiplicity)
{
  for (auto f : cdt.all_face_handles())
  {
    f->info().Nesting = -1;
  }
  std::list<CDT::Edge> border;
  auto flood = [&](CDT::Face_handle start, int level) {
    std::list<CDT::Face_handle> queue{ start };
    while (!queue.empty())
    {
      CDT::Face_handle fh = queue.front();
      queue.pop_front();
      if (fh->info().Nesting != -1)
      {
        continue;
      }
      fh->info().Nesting = level;
      for (int i = 0; i < 3; ++i)
      {
        const CDT::Face_handle n = fh->neighbor(i);
        if (n->info().Nesting == -1)
        {
          if (cdt.is_constrained(CDT::Edge(fh, i)))
          {
            border.emplace_back(fh, i);
          }
          else
          {
            queue.push_back(n);
          }
        }
      }
    }
  };
  flood(cdt.infinite_face(), 0);
  while (!border.empty())
  {
    const CDT::Edge e = border.front();
    border.pop_front();
    const CDT::Face_handle n = e.first->neighbor(e.second);
    if (n->info().Nesting == -1)
    {
      const auto it = multiplicity.find(PairKey(e.first->vertex(CDT::ccw(e.second))->info().Index,
        e.first->vertex(CDT::cw(e.second))->info().Index));
      flood(n, e.first->info().Nesting + (it == multiplicity.end() ? 1 : it->second));
    }
  }
}

struct TriangleKey
{
  Id A, B, C;
  bool operator==(const TriangleKey& o) const { return A == o.A && B == o.B && C == o.C; }
};
struct TriangleKeyHash
{
  std::size_t operator()(const TriangleKey& k) const
  {
    return std::hash<Id>()(k.A) ^ (std::hash<Id>()(k.B) * 0x9e3779b97f4a7c15ULL) ^
      (std::hash<Id>()(k.C) * 0xc2b2ae3d27d4eb4fULL);
  }
};
TriangleKey MakeKey(Id a, Id b, Id c)
{
  Id v[3] = { a, b, c };
  std::sort(v, v + 3);
  return { v[0], v[1], v[2] };
}

double Dist(const Point3& a, const Point3& b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]));
}

/// Longest edge / (2 sqrt(3) inradius), 1 for an equilateral triangle, infinite if flat.
double AspectRatio(double la, double lb, double lc)
{
  const double p = 0.5 * (la + lb + lc);
  const double area = std::sqrt(std::max(0.0, p * (p - la) * (p - lb) * (p - lc)));
  return area > 0 ? std::max({ la, lb, lc }) * p / (2 * std::sqrt(3.0) * area)
                  : std::numeric_limits<double>::infinity();
}

/// A refinement point p to insert: where, and how far it must stay from the vertices it would
/// join (0: anywhere); circumcentres (Encroach) must also not encroach a boundary segment.
struct Steiner
{
  Point P;
  double MinDistance = 0;
  bool Encroach = false;
  /// Where to insert instead when P cannot go in (next to a vertex): the triangle's centroid,
  /// the midpoint of its longest unconstrained edge (so that a triangle over the tolerance is
  /// split, not skipped round after round).
  std::vector<Point> Fallbacks;
};

/// Whether a Steiner point may go into the domain: it lies in an in-domain face (not on a vertex
/// or a constraint), no vertex it would connect to, nor boundary segment on its cavity's border,
/// is closer than s.MinDistance, and, for
/// circumcentres, it encroaches no boundary segment it would connect to (is not in its diametral
/// circle), so the new triangles on segments have an angle below 90 degrees at p. If `face` is
/// given, it must be in p's conflict zone: p sees it without crossing a constraint.
bool CanInsert(const CDT& cdt, const Steiner& s, CDT::Face_handle face = CDT::Face_handle())
{
  CDT::Locate_type lt;
  int li;
  const CDT::Face_handle loc = cdt.locate(s.P, lt, li);
  if (lt == CDT::VERTEX || lt == CDT::OUTSIDE_CONVEX_HULL || lt == CDT::OUTSIDE_AFFINE_HULL ||
    !loc->info().InDomain() || (lt == CDT::EDGE && cdt.is_constrained(CDT::Edge(loc, li))))
  {
    return false;
  }
  if (s.MinDistance <= 0 && !s.Encroach && face == CDT::Face_handle())
  {
    return true;
  }
  std::vector<CDT::Face_handle> zone;
  std::vector<CDT::Edge> boundary;
  cdt.get_conflicts_and_boundary(s.P, std::back_inserter(zone), std::back_inserter(boundary), loc);
  if (face != CDT::Face_handle() && std::find(zone.begin(), zone.end(), face) == zone.end())
  {
    return false;
  }
  const double min2 = s.MinDistance * s.MinDistance;
  for (const CDT::Edge& e : boundary)
  {
    const Point& a = e.first->vertex(CDT::ccw(e.second))->point();
    const Point& b = e.first->vertex(CDT::cw(e.second))->point();
    const double ax = a.x() - s.P.x(), ay = a.y() - s.P.y(), bx = b.x() - s.P.x(), by = b.y() - s.P.y();
    if (ax * ax + ay * ay < min2 || bx * bx + by * by < min2 ||
      (s.Encroach && cdt.is_constrained(e) && ax * bx + ay * by <= 0))
    {
      return false;
    }
    if (min2 > 0 && cdt.is_constrained(e))
    {
      // Nor next to a boundary segment: the triangle on it would be flat (and, round after
      // round, of zero area).
      const double ex = bx - ax, ey = by - ay, len2 = ex * ex + ey * ey;
      const double w = len2 > 0 ? std::clamp(-(ax * ex + ay * ey) / len2, 0.0, 1.0) : 0.0;
      const double dx = ax + w * ex, dy = ay + w * ey;
      if (dx * dx + dy * dy < min2)
      {
        return false;
      }
    }
  }
  return true;
}

/// The plane the triangulation works in: (scale[0] s, scale[1] t), and the area below which a
/// triangle is not refined further (far above the spline filter's zero-area limit).
struct TriangulationPlane
{
  double Scale[2] = { 1, 1 };
  double MinArea = 0;
  bool Refinable(const CDT::Face_handle f) const
  {
    return std::abs(CGAL::area(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point())) >
      this->MinArea;
  }
};

/// Boundary segments by the (unordered) pair of point indices they join.
struct SegmentRef
{
  const LoopSegment* Segment;
  Id First; // point index of the segment's node k
};
using SegmentMap = std::unordered_map<std::uint64_t, SegmentRef>;

/// The loop segment of local edge l of face f (its points l, l+1), or nullptr; flipped when the
/// segment runs from point l+1.
const LoopSegment* FaceSegment(const CDT& cdt, const CDT::Face_handle f, int l,
  const SegmentMap& segments, bool& flipped)
{
  const Id a = f->vertex(l)->info().Index, b = f->vertex((l + 1) % 3)->info().Index;
  const auto it = segments.find(PairKey(a, b));
  // The constrained edge is the one opposite vertex l + 2.
  if (it == segments.end() || !cdt.is_constrained(CDT::Edge(f, (l + 2) % 3)))
  {
    return nullptr;
  }
  flipped = it->second.First != a;
  return it->second.Segment;
}

/// The kernel input of a spline over points of the face mesh (kernel point k is the k-th point
/// added) and its build, topology included.
struct FaceSplineInput : ctk::SplineInput
{
  ctk::Id AddPoint(const FaceMesh& mesh, Id p)
  {
    this->UV.insert(this->UV.end(), mesh.UV[p].begin(), mesh.UV[p].end());
    this->F.insert(this->F.end(), mesh.F[p].begin(), mesh.F[p].end());
    this->Fu.insert(this->Fu.end(), mesh.Fs[p].begin(), mesh.Fs[p].end());
    this->Fv.insert(this->Fv.end(), mesh.Ft[p].begin(), mesh.Ft[p].end());
    return this->NumberOfVertices() - 1;
  }
  /// The parameter point of barycentric coordinates tau in triangle t.
  ctk::Vec2 ParameterAt(ctk::Id t, const ctk::Vec3& tau) const
  {
    ctk::Vec2 X = ctk::Vec2::Zero();
    for (int i = 0; i < 3; ++i)
    {
      const ctk::Id v = this->Triangles[3 * t + i];
      X += tau[i] * ctk::Vec2(this->UV[2 * v], this->UV[2 * v + 1]);
    }
    return X;
  }

  bool Build(const ctk::SplineOptions& options, ctk::MeshTopology& topo, ctk::CubicSpline& spline,
    std::string& error) const
  {
    const ctk::SplineData data = this->View();
    const ctk::TopologyStatus ts =
      ctk::BuildMeshTopology(data.NumberOfVertices, data.NumberOfTriangles, data.Triangles, topo);
    const ctk::BuildStatus bs =
      ts.Ok ? ctk::BuildCubicCloughTocher(data, topo, options, spline) : ctk::BuildStatus{ false, ts.Message };
    if (!bs.Ok)
    {
      error = std::string(ctk::ToString(options.Method)) + " spline of the face mesh: " + bs.Message;
    }
    return bs.Ok;
  }
};

/// Boundary corners of a triangle between the edge cubics (degrees) below the first or above
/// the second are flat (FlatBoundaryCorner). An ear on a boundary this close to straight is
/// about a twentieth as high as its long edge, its interior micro-triangle a sixtieth: the
/// tolerance's worth of disagreement between its nodes' derivatives and its edge cubics folds
/// it (KiCad's USB_Micro-B_Molex_47346-0001, face 70: cubics at 171 degrees, chords at 176.8,
/// the spline at the split point 1.4e-4 off on a triangle 4.2e-4 high; 180 degrees off G1).
constexpr double MinBoundaryCorner = 3, MaxBoundaryCorner = 170;

/// The vertex (0-2) of triangle f where two boundary segments meet in nearly the same 3D
/// direction (a corner below MinBoundaryCorner), nearly the opposite one (above
/// MaxBoundaryCorner; exactly opposite at a node inside a B-rep edge, whose spans share its
/// derivative) or beyond it (a reversed corner), or -1. At such a corner the stitched spline is
/// degenerate (its normal at the vertex undefined, flipping with round-off) or too thin to bear
/// its data's disagreement, and folds. The corner is measured about the normal of the stitching
/// derivatives (where they span a plane). Such triangles (ears on a curved boundary) are split
/// (CornerSplit). `cusp`: whether that corner is within MinBoundaryCorner of 0 (either side).
int FlatBoundaryCorner(const CDT& cdt, const CDT::Face_handle f, const SegmentMap& segments,
  const FaceMesh& mesh, bool& cusp)
{
  for (int l = 0; l < 3; ++l)
  {
    bool flipIn = false, flipOut = false;
    const LoopSegment* in = FaceSegment(cdt, f, (l + 2) % 3, segments, flipIn);
    const LoopSegment* out = FaceSegment(cdt, f, l, segments, flipOut);
    if (!in || !out || in->Degenerate || out->Degenerate)
    {
      continue;
    }
    const Id v = f->vertex(l)->info().Index;
    const Point3& V = mesh.F[v];
    const Point3& a = flipIn ? in->Near0 : in->Near1;   // near vertex l on edge (l + 2, l)
    const Point3& b = flipOut ? out->Near1 : out->Near0; // near vertex l on edge (l, l + 1)
    const ctk::Vec3 da(a[0] - V[0], a[1] - V[1], a[2] - V[2]);
    const ctk::Vec3 db(b[0] - V[0], b[1] - V[1], b[2] - V[2]);
    const ctk::Vec3 fs(mesh.Fs[v][0], mesh.Fs[v][1], mesh.Fs[v][2]);
    const ctk::Vec3 ft(mesh.Ft[v][0], mesh.Ft[v][1], mesh.Ft[v][2]);
    const ctk::Vec3 n = fs.cross(ft);
    // The corner from the outgoing cubic to the incoming one about the normal: the triangle is
    // counter-clockwise, so a sound corner lies in (0, 180) degrees. Unsigned where the
    // derivatives span no plane (a pole: the normal's direction is round-off).
    const ctk::Vec3 axis = n.squaredNorm() > 1e-20 * fs.squaredNorm() * ft.squaredNorm()
      ? n.normalized()
      : db.cross(da).normalized();
    const double corner = AngleAbout(db, da, axis) * 180 / M_PI;
    if (!(corner > MinBoundaryCorner && corner < MaxBoundaryCorner))
    {
      cusp = std::abs(corner) <= MinBoundaryCorner;
      return l;
    }
  }
  return -1;
}

/// The point that splits the flat boundary corner at vertex l of triangle f: inside the corner,
/// on the perpendicular to the chord of its two segments, half their mean length from the vertex
/// (or a half, a quarter of that where it cannot go in), so that the vertex joins the interior
/// by two triangles of a sound shape. The centroid of an ear on a nearly straight boundary lies
/// a third of its sagitta from it (linkrods.step: 2 % of the segment): two triangles on the
/// boundary segments that thin fold the stitched spline wherever the edge cubic leaves the
/// segment's chord by a larger angle. None where no such point can go in. The side of the
/// chord comes from the triangle's vertex order (CGAL's, counter-clockwise), not from where the
/// vertex lies: a flat triangle's vertex is on the chord up to round-off (SplitFlatTriangles).
std::optional<Steiner> CornerSplit(const CDT& cdt, const CDT::Face_handle f, int l)
{
  const Point &v = f->vertex(l)->point(), &a = f->vertex(CDT::ccw(l))->point(),
              &b = f->vertex(CDT::cw(l))->point();
  const ctk::Vec2 chord(b.x() - a.x(), b.y() - a.y());
  // The chord runs from a to b with v on its left: away from v is its right.
  const ctk::Vec2 n = ctk::Vec2(chord.y(), -chord.x()) / chord.norm();
  const double h = 0.25 *
    (std::sqrt(CGAL::squared_distance(v, a)) + std::sqrt(CGAL::squared_distance(v, b)));
  for (const double scale : { 1.0, 0.5, 0.25 })
  {
    const Steiner q{ Point(v.x() + scale * h * n.x(), v.y() + scale * h * n.y()),
      0.5 * scale * h, false, {} };
    if (n.allFinite() && CanInsert(cdt, q))
    {
      return q;
    }
  }
  return std::nullopt;
}

/// The centroid of triangle f, summed from its vertex l (as CornerSplit orders them), to split
/// a boundary corner where CornerSplit finds no place.
Steiner CornerCentroid(const CDT::Face_handle f, int l)
{
  return { CGAL::centroid(f->vertex(l)->point(), f->vertex(CDT::ccw(l))->point(),
             f->vertex(CDT::cw(l))->point()),
    0, false, {} };
}

/// A point splitting triangle f where its error is largest (parameter X), not next to a vertex
/// (a fifth of the shortest edge in the triangulation's plane), with the fallbacks of Steiner.
Steiner RefinementPoint(const CDT& cdt, const CDT::Face_handle f, const ctk::Vec2& X,
  const TriangulationPlane& plane)
{
  double shortest = std::numeric_limits<double>::infinity(), longest = 0;
  Point mid;
  for (int i = 0; i < 3; ++i)
  {
    const Point &a = f->vertex(CDT::ccw(i))->point(), &b = f->vertex(CDT::cw(i))->point();
    const double len = std::sqrt(CGAL::squared_distance(a, b));
    shortest = std::min(shortest, len);
    if (len > longest && !cdt.is_constrained(CDT::Edge(f, i)))
    {
      longest = len;
      mid = CGAL::midpoint(a, b);
    }
  }
  Steiner q{ Point(plane.Scale[0] * X.x(), plane.Scale[1] * X.y()), 0.2 * shortest, false, {} };
  q.Fallbacks.push_back(
    CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()));
  if (longest > 0)
  {
    q.Fallbacks.push_back(mid);
  }
  return q;
}

/// The angle (degrees) between a spline's normal at parameter X and the unit normal `shared`
/// of RestoreG1's tangent plane there, oriented as the surface's: 180 where the spline's normal
/// is flipped or undefined.
double TurnFromSharedPlane(const ctk::ParametricJet& jet, const ctk::Vec2& X, const Point3& shared,
  const SurfaceFunction& surface)
{
  Point3 P, Ds, Dt;
  surface(X.x(), X.y(), P.data(), Ds.data(), Dt.data());
  const ctk::Vec3 own = ctk::Vec3(Ds[0], Ds[1], Ds[2]).cross(ctk::Vec3(Dt[0], Dt[1], Dt[2]));
  ctk::Vec3 m(shared[0], shared[1], shared[2]);
  m = own.dot(m) < 0 ? ctk::Vec3(-m) : m;
  if (ctk::IsSingularTangentPlane(jet.Du, jet.Dv))
  {
    return 180;
  }
  const ctk::Vec3 n = jet.Du.cross(jet.Dv);
  return std::atan2(n.cross(m).norm(), n.dot(m)) * 180 / M_PI;
}

/// Builds the stitched spline of the current face mesh (options.Spline, boundary edges following
/// the loop segments' cubics, exact mid-edge gradients) and measures it against the surface at
/// the check points of every micro-triangle; the worst point of every triangle that is off by
/// more than the tolerance goes into `inserts`. With tangentTurn, also the largest angle
/// (degrees) between the spline's normal and the shared one at the midpoint of a boundary span
/// whose interface RestoreG1 made tangent (LoopSegment::MidNormal).
bool CheckStitchedSpline(const CDT& cdt, const std::vector<CDT::Face_handle>& faces,
  const FaceMesh& mesh, const SegmentMap& segments, const SurfaceFunction& surface,
  const FaceMeshOptions& options, const TriangulationPlane& plane, std::vector<Steiner>& inserts,
  double& maxError, double& maxAngle, std::string& error, double* tangentTurn = nullptr)
{
  const ctk::Id nT = static_cast<ctk::Id>(faces.size());
  FaceSplineInput in;
  for (Id v = 0; v < static_cast<Id>(mesh.UV.size()); ++v)
  {
    in.AddPoint(mesh, v);
  }
  in.Triangles.resize(3 * nT);
  in.EdgeGradients.resize(18 * nT);
  in.BoundaryCurvePoints.assign(18 * nT, std::nan(""));
  std::vector<std::array<bool, 3>> onBoundary(nT);
  struct TangentSpan
  {
    ctk::Id Triangle;
    int Edge;
    const LoopSegment* Segment; // with a MidNormal
  };
  std::vector<TangentSpan> tangentSpans; // only with tangentTurn
  for (ctk::Id t = 0; t < nT; ++t)
  {
    const CDT::Face_handle f = faces[t];
    for (int l = 0; l < 3; ++l)
    {
      in.Triangles[3 * t + l] = f->vertex(l)->info().Index;
    }
    for (int l = 0; l < 3; ++l)
    {
      const auto& a = mesh.UV[in.Triangles[3 * t + l]];
      const auto& b = mesh.UV[in.Triangles[3 * t + (l + 1) % 3]];
      double P[3];
      double* g = &in.EdgeGradients[18 * t + 6 * l];
      surface(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), P, g, g + 3);
      bool flipped = false;
      const LoopSegment* seg = FaceSegment(cdt, f, l, segments, flipped);
      onBoundary[t][l] = seg != nullptr;
      if (tangentTurn && seg && seg->Tangent && seg->MidNormal != Point3{})
      {
        tangentSpans.push_back({ t, l, seg });
      }
      if (seg)
      {
        StitchEdgeGradient(*seg, g);
      }
      for (int i = 0; seg && i < 3; ++i)
      {
        in.BoundaryCurvePoints[18 * t + 6 * l + i] = (flipped ? seg->Near1 : seg->Near0)[i];
        in.BoundaryCurvePoints[18 * t + 6 * l + 3 + i] = (flipped ? seg->Near0 : seg->Near1)[i];
      }
    }
  }
  ctk::MeshTopology topo;
  ctk::CubicSpline spline;
  if (!in.Build(options.Spline, topo, spline, error))
  {
    return false;
  }
  // The boundary macro-edges are left out: the face cannot split them (the edge sampling bounds
  // the error there).
  const bool normals = options.AngularTolerance > 0;
  std::vector<ctk::Vec3> points;
  for (ctk::Id t = 0; t < nT; ++t)
  {
    DeviationPoints(spline.SplitTau[t], options.CheckLevel, onBoundary[t], points);
    Deviation d;
    ctk::Vec3 worst;
    if (!MeasureTriangle(spline, topo, in.Triangles.data(), t, points, surface, normals, d, error,
          &worst, options.Tolerance, options.AngularTolerance))
    {
      return false;
    }
    maxError = std::max(maxError, d.MaxDistance);
    maxAngle = std::max(maxAngle, d.MaxAngle);
    // A margin: the lattice sees most, not all, of the error.
    if ((d.MaxDistance > 0.8 * options.Tolerance ||
          (normals && d.MaxAngle > 0.8 * options.AngularTolerance)) &&
      plane.Refinable(faces[t]))
    {
      inserts.push_back(RefinementPoint(cdt, faces[t], in.ParameterAt(t, worst), plane));
    }
  }
  for (const TangentSpan& span : tangentSpans)
  {
    ctk::Vec3 tau = ctk::Vec3::Zero();
    tau[span.Edge] = tau[(span.Edge + 1) % 3] = 0.5;
    const ctk::ParametricJet jet =
      ctk::EvaluateSpline(spline, topo, in.Triangles.data(), span.Triangle, tau, 1);
    *tangentTurn = std::max(*tangentTurn, TurnFromSharedPlane(jet, in.ParameterAt(span.Triangle, tau),
                                            span.Segment->MidNormal, surface));
  }
  return true;
}
/// Why refinement stopped: the cap reached, or triangles over the tolerances too small to split.
std::string StopReason(bool rounds, bool full, bool unrefinable, const FaceMeshOptions& options)
{
  if (full)
  {
    return "reached MaxTriangles (" + std::to_string(options.MaxTriangles) + ")";
  }
  if (rounds)
  {
    return "reached MaxRounds (" + std::to_string(options.MaxRounds) + ")";
  }
  return unrefinable ? "triangles over the tolerance are too small to split" : "";
}

/// The meshing of one face (MeshFace): its constrained triangulation, refined in rounds.
class FaceMesher
{
public:
  FaceMesher(const std::vector<FaceLoop>& loops, const std::vector<Point3>& nodePoints,
    const SurfaceFunction& surface, const FaceMeshOptions& options, FaceMesh& mesh,
    bool anisotropicScaled = false)
    : Loops(loops)
    , NodePoints(nodePoints)
    , Surface(surface)
    , Options(options)
    , Mesh(mesh)
    , AnisotropicScaled(anisotropicScaled)
  {
  }
  /// Whether the surface's metric is far from isotropic (ScalePlane), after Triangulate.
  bool Anisotropic = false;
  bool Triangulate();
  bool Refine();
  bool CheckConstruction();
  /// After CheckConstruction left the face over the tolerances: the fallback, if any.
  void TryOtherConstructions();
  void Output();

private:
  void ScalePlane();
  Id AddPoint(double s, double t, const LoopNode* node);
  void InsertInterior(const Point& p);
  void CollectFaces();
  std::size_t SplitFlatTriangles();
  void CollectSoundFaces();
  std::size_t InsertPoints(const std::vector<Steiner>& inserts);
  bool EstimateTriangles(std::vector<Steiner>& inserts, double& maxError, double& maxAngle);
  void CheckInteriorEdges(std::vector<Steiner>& inserts, double& maxError);
  Steiner GeometricSplit(const CDT::Face_handle f) const;

  const std::vector<FaceLoop>& Loops;
  const std::vector<Point3>& NodePoints;
  const SurfaceFunction& Surface;
  const FaceMeshOptions& Options;
  FaceMesh& Mesh;
  const bool AnisotropicScaled; // scale the plane where Anisotropic
  CDT Triangulation;
  TriangulationPlane Plane;
  double DiagonalUV2 = 0; // the squared diagonal of the loops' (u, v) box
  SegmentMap Segments;
  Multiplicity SegmentCount;
  std::vector<CDT::Face_handle> Faces; // in-domain, after CollectFaces
  // CTo is local (a macro-patch depends on its own triangle only) and an edge's cubic on its two
  // end points only, so triangles and edges that passed once stay passed.
  std::unordered_set<TriangleKey, TriangleKeyHash> Passed;
  std::unordered_set<std::uint64_t> PassedEdges;
  bool Unrefinable = false; // a triangle or edge over the tolerance is too small to split
};

/// Above this ratio of the mean |F_s| and |F_t| a face that the raw parameter plane leaves
/// over the tolerance is meshed again in the scaled plane.
constexpr double MaxRawPlaneAnisotropy = 20;

/// With geometric bounds (aspect, edge length), or AnisotropicScaled where the surface's metric
/// is far from isotropic (|F_s| and |F_t| more than MaxRawPlaneAnisotropy apart), the
/// triangulation works in a plane scaled by the mean lengths of F_s and F_t over the boundary
/// nodes (point (ks s, kt t)), so that shapes there are close to the 3D ones (a cylinder's
/// (angle, height) plane becomes isometric): Delaunay refinement in it can meet a 3D bound, and
/// the distances that keep refinement points off vertices and segments (CanInsert) mean the
/// same along s and t. KiCad's L_Axial_L16.0mm_D6.3mm Fastron VHBCC: its end faces (an arc of
/// radius 327 about the axis) have F_t 270 times F_s; in the raw plane no point near their
/// inner rim, whose nodes have the shared tangent planes of a 5-degree tangent interface, was a
/// fifth of an edge away from it, and the triangles there were never split (10 times the
/// tolerance, normals folded by 88 degrees). Not by default: the G1 of a tangent interface
/// depends on the boundary triangles' shapes in the parameter plane, which the raw plane keeps
/// (C_Trimmer_Murata_TZB4-B: 0.034 degrees off G1 in the raw plane, 2.25 scaled), and thin
/// faces of TQFP-44 (re-projected pcurves, over 20 times anisotropic) converge only raw.
void FaceMesher::ScalePlane()
{
  double ss = 0, st = 0;
  long n = 0;
  for (const FaceLoop& loop : this->Loops)
  {
    for (const LoopNode& node : loop.Nodes)
    {
      Point3 P, Ds, Dt;
      this->Surface(node.UV[0], node.UV[1], P.data(), Ds.data(), Dt.data());
      ss += Ds[0] * Ds[0] + Ds[1] * Ds[1] + Ds[2] * Ds[2];
      st += Dt[0] * Dt[0] + Dt[1] * Dt[1] + Dt[2] * Dt[2];
      ++n;
    }
  }
  if (n == 0 || !(ss > 0) || !(st > 0) || !std::isfinite(ss) || !std::isfinite(st))
  {
    return;
  }
  this->Anisotropic = std::sqrt(std::max(ss, st) / std::min(ss, st)) > MaxRawPlaneAnisotropy;
  if (this->Options.AspectRatio > 0 || this->Options.MaxEdgeLength > 0 ||
    (this->Anisotropic && this->AnisotropicScaled))
  {
    this->Plane.Scale[0] = std::sqrt(ss / n);
    this->Plane.Scale[1] = std::sqrt(st / n);
  }
}

Id FaceMesher::AddPoint(double s, double t, const LoopNode* node)
{
  FaceMesh& mesh = this->Mesh;
  Point3 P, Ds, Dt;
  this->Surface(s, t, P.data(), Ds.data(), Dt.data());
  mesh.SurfaceFs.push_back(Ds);
  mesh.SurfaceFt.push_back(Dt);
  // Boundary nodes keep the shared edge sample, not the surface point under the pcurve, and
  // the derivatives that agree with the shared edge cubics.
  const Id global = node ? node->GlobalNode : -1;
  mesh.F.push_back(global >= 0 ? this->NodePoints[global] : P);
  mesh.UV.push_back({ s, t });
  mesh.Fs.push_back(node && node->Consistent ? node->Ds : Ds);
  mesh.Ft.push_back(node && node->Consistent ? node->Dt : Dt);
  mesh.GlobalNode.push_back(global);
  return static_cast<Id>(mesh.UV.size()) - 1;
}

/// Inserts interior point p of the triangulation's plane as a point of the mesh.
void FaceMesher::InsertInterior(const Point& p)
{
  const CDT::Vertex_handle v = this->Triangulation.insert(p);
  v->info().Index =
    this->AddPoint(p.x() / this->Plane.Scale[0], p.y() / this->Plane.Scale[1], nullptr);
}

/// The constrained triangulation of the loops. A B-rep vertex met twice at (nearly) the same
/// place, where an inner loop touches the outer one or itself, is one triangulation vertex: its
/// two pcurve ends differ by round-off or the vertex tolerance, and two vertices that close
/// would only bound triangles of no area (the domain is pinched there, not cut).
bool FaceMesher::Triangulate()
{
  this->ScalePlane();
  const double* scale = this->Plane.Scale;
  // The loops' box in (u, v) and in the triangulation's plane.
  ctk::Vec2 lo = ctk::Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const FaceLoop& loop : this->Loops)
  {
    for (const LoopNode& node : loop.Nodes)
    {
      lo = lo.cwiseMin(ctk::Vec2(node.UV[0], node.UV[1]));
      hi = hi.cwiseMax(ctk::Vec2(node.UV[0], node.UV[1]));
    }
  }
  this->DiagonalUV2 = (hi - lo).squaredNorm();
  const double d2 = (hi - lo).cwiseProduct(ctk::Vec2(scale[0], scale[1])).squaredNorm();
  this->Plane.MinArea = 1e-10 * d2;
  // A millionth of the diagonal: far below any boundary span, far above round-off and the
  // vertex tolerances of real models (their copies of one vertex are 1e-16 to 1e-7 apart).
  const double snap2 = 1e-12 * d2;
  std::unordered_map<Id, std::vector<CDT::Vertex_handle>> atNode;
  for (const FaceLoop& loop : this->Loops)
  {
    const std::size_t n = loop.Nodes.size();
    std::vector<CDT::Vertex_handle> handles(n);
    for (std::size_t k = 0; k < n; ++k)
    {
      const LoopNode& node = loop.Nodes[k];
      const Point p(scale[0] * node.UV[0], scale[1] * node.UV[1]);
      std::vector<CDT::Vertex_handle>& same = atNode[node.GlobalNode];
      const auto near = std::find_if(same.begin(), same.end(),
        [&](CDT::Vertex_handle v) { return CGAL::squared_distance(v->point(), p) <= snap2; });
      if (near != same.end())
      {
        handles[k] = *near;
        continue;
      }
      handles[k] = this->Triangulation.insert(p);
      same.push_back(handles[k]);
      if (handles[k]->info().Index < 0)
      {
        handles[k]->info().Index = this->AddPoint(node.UV[0], node.UV[1], &node);
      }
    }
    for (std::size_t k = 0; k < n; ++k)
    {
      const CDT::Vertex_handle a = handles[k], b = handles[(k + 1) % n];
      if (a == b)
      {
        continue;
      }
      this->Triangulation.insert_constraint(a, b);
      const std::uint64_t key = PairKey(a->info().Index, b->info().Index);
      this->Segments[key] = { &loop.Segments[k], a->info().Index };
      ++this->SegmentCount[key];
    }
  }
  if (this->Triangulation.number_of_faces() == 0)
  {
    this->Mesh.Error = "empty parameter domain";
    return false;
  }
  return true;
}

/// The in-domain faces; vertices made by intersecting constraints become points of the mesh.
void FaceMesher::CollectFaces()
{
  MarkDomains(this->Triangulation, this->SegmentCount);
  this->Faces.clear();
  for (auto f : this->Triangulation.finite_face_handles())
  {
    if (f->info().InDomain())
    {
      for (int i = 0; i < 3; ++i)
      {
        if (f->vertex(i)->info().Index < 0)
        {
          const Point& p = f->vertex(i)->point();
          f->vertex(i)->info().Index =
            this->AddPoint(p.x() / this->Plane.Scale[0], p.y() / this->Plane.Scale[1], nullptr);
        }
      }
      this->Faces.push_back(f);
    }
  }
}

/// A triangle is flat for SplitFlatTriangles when the kernel would find it degenerate in a box
/// of ten times the face's squared diagonal (IsDegenerateArea; the rounds build splines over
/// subsets of the face, whose boxes are smaller: the face's is the worst case, and the margin
/// is for round-off) and it is thin: its height at most MaxFlatHeight of its longest edge. A
/// tiny triangle of a sound shape is not split (its pieces would be smaller still).
constexpr double FlatTriangleMargin = 10, MaxFlatHeight = 0.01;
/// Flat triangles are split in at most this many passes per collection.
constexpr int MaxFlatSplitPasses = 4;

/// Splits the triangles that are flat in (u, v) for the kernel (IsDegenerateArea, with
/// FlatTriangleMargin), which the refinement never reaches (their area is far below MinArea):
/// ears of three boundary nodes on a pcurve that is a straight line, the middle one off the
/// chord of the others by round-off. KiCad's Bourns 8100 toroids (L38.1 face 71, L43.2 face 47):
/// spans halved towards a B-rep vertex, the last two nodes 1.45e-5 and 5.6e-4 from the next on
/// a pcurve of constant v, the ear 2e-8 high; no vertex lay in its circumcircle, so the
/// triangulation kept it, and the face's spline could not be built. A point beyond the long edge,
/// in front of the middle vertex (CornerSplit), is in that circumcircle and joins the vertex to
/// the interior. A flat triangle whose long edge is a boundary segment cannot be split away (the
/// kernel then names it). Returns how many points went in.
std::size_t FaceMesher::SplitFlatTriangles()
{
  std::vector<Steiner> splits;
  for (const CDT::Face_handle f : this->Faces)
  {
    ctk::Vec2 uv[3];
    for (int l = 0; l < 3; ++l)
    {
      const std::array<double, 2>& p = this->Mesh.UV[f->vertex(l)->info().Index];
      uv[l] = ctk::Vec2(p[0], p[1]);
    }
    const double area2 = ctk::SignedArea2(uv[0], uv[1], uv[2]);
    if (!ctk::IsDegenerateArea(area2, FlatTriangleMargin * this->DiagonalUV2))
    {
      continue;
    }
    int middle = 0; // the vertex opposite the longest edge (in (u, v), as the area)
    double longest = -1;
    for (int l = 0; l < 3; ++l)
    {
      const double len2 = (uv[CDT::ccw(l)] - uv[CDT::cw(l)]).squaredNorm();
      if (len2 > longest)
      {
        longest = len2;
        middle = l;
      }
    }
    if (std::abs(area2) <= MaxFlatHeight * longest &&
      !this->Triangulation.is_constrained(CDT::Edge(f, middle)))
    {
      // Where the corner has no place, a centroid would lie in the flat triangle: none.
      if (std::optional<Steiner> q = CornerSplit(this->Triangulation, f, middle))
      {
        splits.push_back(std::move(*q));
      }
    }
  }
  std::size_t added = 0;
  for (const Steiner& q : splits)
  {
    // Not a point an earlier split of this pass has moved next to.
    if (CanInsert(this->Triangulation, q))
    {
      this->InsertInterior(q.P);
      ++added;
    }
  }
  return added;
}

/// CollectFaces, with the flat triangles split first (SplitFlatTriangles).
void FaceMesher::CollectSoundFaces()
{
  this->CollectFaces();
  for (int pass = 0; pass < MaxFlatSplitPasses && this->SplitFlatTriangles() > 0; ++pass)
  {
    this->CollectFaces();
  }
}

/// Interior points only: a point on a constraint would split a boundary segment. Guarded points
/// are checked again against this round's earlier insertions (neighbours often share one
/// circumcircle). Returns how many went in.
std::size_t FaceMesher::InsertPoints(const std::vector<Steiner>& inserts)
{
  std::size_t added = 0;
  for (Steiner q : inserts)
  {
    // Never next to another point (two triangles can ask for the same point up to round-off).
    q.MinDistance = std::max(q.MinDistance, std::sqrt(this->Plane.MinArea));
    bool can = CanInsert(this->Triangulation, q);
    for (std::size_t i = 0; !can && i < q.Fallbacks.size(); ++i)
    {
      q.P = q.Fallbacks[i];
      can = CanInsert(this->Triangulation, q);
    }
    if (!can)
    {
      continue;
    }
    this->InsertInterior(q.P);
    ++added;
  }
  return added;
}

/// Geometric bounds: a triangle within the tolerances is refined by its circumcentre in the
/// triangulation's plane (Chew, Ruppert), and only where that can help: the triangle is also bad
/// in that plane (else the 3D defect comes from the surface's metric, which refinement in the
/// plane cannot remove), and the circumcentre is a valid interior point (boundary segments are
/// never split, so a triangle whose circumcentre is outside the domain or encroaches a segment
/// keeps its shape). Centroids must not be used: inserted next to a segment they give a triangle
/// on the same segment three times flatter, round after round, until the parameter triangles
/// are flat. Returns the circumcentre to insert (Encroach set), or a point with Encroach false.
Steiner FaceMesher::GeometricSplit(const CDT::Face_handle f) const
{
  const FaceMesh& mesh = this->Mesh;
  const Id a = f->vertex(0)->info().Index, b = f->vertex(1)->info().Index,
           c = f->vertex(2)->info().Index;
  bool bad = false;
  const Point3 &pa = mesh.F[a], &pb = mesh.F[b], &pc = mesh.F[c];
  const double la = Dist(pb, pc), lb = Dist(pc, pa), lc = Dist(pa, pb);
  const Point &qa = f->vertex(0)->point(), &qb = f->vertex(1)->point(), &qc = f->vertex(2)->point();
  const double ma = std::sqrt(CGAL::squared_distance(qb, qc)),
               mb = std::sqrt(CGAL::squared_distance(qc, qa)),
               mc = std::sqrt(CGAL::squared_distance(qa, qb));
  if (this->Options.MaxEdgeLength > 0 && std::max({ la, lb, lc }) > this->Options.MaxEdgeLength)
  {
    bad = true;
  }
  if (this->Options.AspectRatio > 0 && AspectRatio(la, lb, lc) > this->Options.AspectRatio &&
    AspectRatio(ma, mb, mc) > this->Options.AspectRatio)
  {
    bad = true;
  }
  if (bad && !CGAL::collinear(qa, qb, qc))
  {
    const Point cc = CGAL::circumcenter(qa, qb, qc);
    const Steiner q{ cc, 0.5 * std::sqrt(CGAL::squared_distance(cc, qa)), true };
    if (CanInsert(this->Triangulation, q, f))
    {
      return q;
    }
  }
  return Steiner{};
}

/// One CTo round over the triangles that have not passed: one kernel CTo/Bary spline over all
/// of them (its S point is the value at the centroid), measured at the split point and the
/// centres of the three micro-triangles, which lie next to the macro-edges where the error of CT
/// patches concentrates. Triangles over the tolerances, flat boundary corners and geometrically
/// bad triangles ask for a point in `inserts`; the others pass.
bool FaceMesher::EstimateTriangles(
  std::vector<Steiner>& inserts, double& maxError, double& maxAngle)
{
  FaceMesh& mesh = this->Mesh;
  const double tol = this->Options.Tolerance;
  const bool normals = this->Options.AngularTolerance > 0;
  FaceSplineInput in;
  std::vector<std::size_t> triFace;
  std::unordered_map<Id, ctk::Id> local;
  auto localIndex = [&](Id p) {
    auto it = local.emplace(p, in.NumberOfVertices());
    if (it.second)
    {
      in.AddPoint(mesh, p);
    }
    return it.first->second;
  };
  for (std::size_t i = 0; i < this->Faces.size(); ++i)
  {
    const CDT::Face_handle f = this->Faces[i];
    const Id a = f->vertex(0)->info().Index, b = f->vertex(1)->info().Index,
             c = f->vertex(2)->info().Index;
    if (this->Passed.count(MakeKey(a, b, c)))
    {
      continue;
    }
    for (const Id p : { a, b, c })
    {
      in.Triangles.push_back(localIndex(p));
    }
    triFace.push_back(i);
  }
  if (triFace.empty())
  {
    return true;
  }
  ctk::SplineOptions ctOptions;
  ctOptions.Method = ctk::Construction::CTo;
  ctOptions.SplitPoint = ctk::SplitPointRule::Bary;
  ctk::MeshTopology topo;
  ctk::CubicSpline spline;
  if (!in.Build(ctOptions, topo, spline, mesh.Error))
  {
    return false;
  }
  for (std::size_t j = 0; j < triFace.size(); ++j)
  {
    const CDT::Face_handle f = this->Faces[triFace[j]];
    const TriangleKey key = MakeKey(
      f->vertex(0)->info().Index, f->vertex(1)->info().Index, f->vertex(2)->info().Index);
    bool cusp = false;
    const int corner = this->Plane.Refinable(f)
      ? FlatBoundaryCorner(this->Triangulation, f, this->Segments, mesh, cusp)
      : -1;
    std::optional<Steiner> cornerSplit =
      corner >= 0 ? CornerSplit(this->Triangulation, f, corner) : std::nullopt;
    // Where CornerSplit finds no point that opens the corner, the triangle's centroid splits it,
    // except at a cusp (two boundary curves leaving a node in one direction): there the centroid
    // would lie inside the needle, the tip of a fan of needles from the spans beside it (KiCad's
    // RC1602A, 32 pads where an arc meets a line tangentially: a 30:1 triangle's corner of 2
    // degrees next to an edge cubic turning 2.8, its patches folded), and the triangle is
    // measured as any other instead.
    if (corner >= 0 && !cornerSplit && !cusp)
    {
      cornerSplit = CornerCentroid(f, corner);
    }
    if (cornerSplit)
    {
      inserts.push_back(std::move(*cornerSplit));
      continue;
    }
    const ctk::Id tj = static_cast<ctk::Id>(j);
    const ctk::Vec3& split = spline.SplitTau[tj];
    std::vector<ctk::Vec3> points{ split };
    for (int k = 0; k < 3; ++k)
    {
      points.push_back(ctk::MacroBarycentric(split, k, ctk::Vec3(1, 1, 1) / 3));
    }
    Deviation d;
    ctk::Vec3 worst;
    if (!MeasureTriangle(spline, topo, in.Triangles.data(), tj, points, this->Surface, normals, d,
          mesh.Error, &worst, tol, this->Options.AngularTolerance))
    {
      return false;
    }
    maxError = std::max(maxError, d.MaxDistance);
    maxAngle = std::max(maxAngle, d.MaxAngle);
    if (d.MaxDistance > tol || (normals && d.MaxAngle > this->Options.AngularTolerance))
    {
      if (this->Plane.Refinable(f))
      {
        const ctk::Vec2 X = in.ParameterAt(tj, worst);
        inserts.push_back(
          { Point(this->Plane.Scale[0] * X.x(), this->Plane.Scale[1] * X.y()), 0, false, {} });
        continue;
      }
      this->Unrefinable = true; // too small to refine further
      this->Passed.insert(key);
      continue;
    }
    const Steiner q = this->GeometricSplit(f);
    if (q.Encroach)
    {
      inserts.push_back(q);
      continue;
    }
    this->Passed.insert(key);
  }
  return true;
}

/// Interior edges: the spline along a macro-edge is the Hermite cubic of its two ends; an edge
/// whose midpoint is off the surface by more than the tolerance asks for its midpoint.
void FaceMesher::CheckInteriorEdges(std::vector<Steiner>& inserts, double& maxError)
{
  const FaceMesh& mesh = this->Mesh;
  const double tol = this->Options.Tolerance;
  for (const CDT::Face_handle f : this->Faces)
  {
    for (int i = 0; i < 3; ++i)
    {
      const CDT::Face_handle n = f->neighbor(i);
      const Id a = f->vertex(CDT::ccw(i))->info().Index, b = f->vertex(CDT::cw(i))->info().Index;
      // Each edge once, from the side where it runs upwards (not by address: the insertion
      // order, hence the mesh, must not depend on memory layout).
      if (!n->info().InDomain() || this->Triangulation.is_constrained(CDT::Edge(f, i)) || a > b)
      {
        continue;
      }
      if (this->PassedEdges.count(PairKey(a, b)))
      {
        continue;
      }
      const double du = mesh.UV[b][0] - mesh.UV[a][0], dv = mesh.UV[b][1] - mesh.UV[a][1];
      Point3 mid;
      for (int k = 0; k < 3; ++k)
      {
        const double ta = mesh.F[a][k] + (du * mesh.Fs[a][k] + dv * mesh.Ft[a][k]) / 3;
        const double tb = mesh.F[b][k] - (du * mesh.Fs[b][k] + dv * mesh.Ft[b][k]) / 3;
        mid[k] = (mesh.F[a][k] + 3 * ta + 3 * tb + mesh.F[b][k]) / 8;
      }
      const double s = 0.5 * (mesh.UV[a][0] + mesh.UV[b][0]);
      const double t = 0.5 * (mesh.UV[a][1] + mesh.UV[b][1]);
      Point3 P, Ds, Dt;
      this->Surface(s, t, P.data(), Ds.data(), Dt.data());
      const double err = Dist(mid, P);
      maxError = std::max(maxError, err);
      if (err > tol && CGAL::squared_distance(f->vertex(CDT::ccw(i))->point(),
                         f->vertex(CDT::cw(i))->point()) > this->Plane.MinArea)
      {
        inserts.push_back(
          { Point(this->Plane.Scale[0] * s, this->Plane.Scale[1] * t), 0, false, {} });
      }
      else
      {
        this->Unrefinable = this->Unrefinable || err > tol;
        this->PassedEdges.insert(PairKey(a, b));
      }
    }
  }
}

/// The CTo rounds: refined until every triangle and interior edge is within the tolerances, the
/// caps are reached or nothing more can be inserted.
bool FaceMesher::Refine()
{
  FaceMesh& mesh = this->Mesh;
  for (int round = 0;; ++round)
  {
    this->CollectSoundFaces();
    mesh.Rounds = round;
    std::vector<Steiner> inserts;
    double maxError = 0, maxAngle = 0;
    if (!this->EstimateTriangles(inserts, maxError, maxAngle))
    {
      return false;
    }
    this->CheckInteriorEdges(inserts, maxError);
    mesh.MaxEstimatedError = maxError;
    mesh.MaxEstimatedAngle = maxAngle;
    const bool full = static_cast<long>(this->Faces.size()) >= this->Options.MaxTriangles;
    if (inserts.empty() || round >= this->Options.MaxRounds || full)
    {
      mesh.Converged = inserts.empty() && !this->Unrefinable;
      mesh.StopReason = StopReason(!inserts.empty() && round >= this->Options.MaxRounds, full,
        this->Unrefinable, this->Options);
      return true;
    }
    if (this->InsertPoints(inserts) == 0)
    {
      mesh.StopReason = StopReason(false, false, true, this->Options);
      return true;
    }
  }
}

/// Check rounds: the estimate of Refine is CTo's without the shared boundary curves; the spline
/// the stitcher makes (the chosen construction, following the edge cubics) is checked on the
/// whole face and refined where it is off. Non-local constructions: every triangle, every round.
bool FaceMesher::CheckConstruction()
{
  FaceMesh& mesh = this->Mesh;
  const FaceMeshOptions& options = this->Options;
  for (int check = 0; options.CheckConstruction; ++check)
  {
    this->CollectSoundFaces();
    std::vector<Steiner> inserts;
    double maxError = 0, maxAngle = 0;
    if (!CheckStitchedSpline(this->Triangulation, this->Faces, mesh, this->Segments, this->Surface,
          options, this->Plane, inserts, maxError, maxAngle, mesh.Error))
    {
      return false;
    }
    mesh.MaxEstimatedError = maxError;
    mesh.MaxEstimatedAngle = maxAngle;
    mesh.CheckRounds = check + 1;
    const bool within = maxError <= options.Tolerance &&
      (options.AngularTolerance <= 0 || maxAngle <= options.AngularTolerance);
    // Within 0.8 of the tolerances where refinable; the rest too small to split.
    const bool rounds = check >= options.MaxRounds;
    const bool full = static_cast<long>(this->Faces.size()) >= options.MaxTriangles;
    if (inserts.empty() || rounds || full || this->InsertPoints(inserts) == 0)
    {
      mesh.Converged = inserts.empty() && within;
      mesh.StopReason =
        mesh.Converged ? std::string() : StopReason(rounds, full, !rounds && !full, options);
      break;
    }
  }
  return true;
}

/// How far over the tolerances an error and angle are (<= 1: within).
double Excess(double error, double angle, const FaceMeshOptions& options)
{
  return std::max(error / options.Tolerance,
    options.AngularTolerance > 0 ? angle / options.AngularTolerance : 0.0);
}

/// A fallback must not turn the face's normals further from the surface's than this many times
/// the chosen construction's largest angle, or 1 degree: ESP-WROOM-02's face 250 (below) is a
/// plane that MGo and MGi fold (180 degrees) within the distance tolerance, which KaG did not.
constexpr double FallbackAngleGrowth = 2, FallbackAngleFloor = 1;
/// Nor turn its normal at a tangent span's midpoint from the tangent plane RestoreG1 shares
/// there by more than this (degrees), or than the chosen construction does: a tenth of the G1
/// that RestoreG1 aims at. KiCad's USB_Micro-B_Molex_47346-0001 went 2.3 degrees off G1 at a
/// face built with CTi instead of KaG (CTi reads no mid-edge gradient).
constexpr double FallbackTangentTurn = 0.01;

/// A face the chosen construction leaves over the tolerances (FallbackConstructions): every
/// other stitchable construction is checked on the mesh as it is (no more refinement: its
/// guards hold for this mesh only); the one least over the tolerances (the first in the table
/// among equals), if less than the chosen one and without turning the normals
/// (FallbackAngleGrowth, FallbackTangentTurn), is the face's. ESP-WROOM-02 (KiCad), face 250: a
/// plane face whose domain narrows to a wedge as wide as its triangles, where KaG's
/// least-squares central points stay 1.26e-4 of the diagonal off the plane's parametrisation and
/// no point can go in; CTi is within.
void FaceMesher::TryOtherConstructions()
{
  FaceMesh& mesh = this->Mesh;
  const FaceMeshOptions& chosen = this->Options;
  if (chosen.Tolerance <= 0 ||
    Excess(mesh.MaxEstimatedError, mesh.MaxEstimatedAngle, chosen) <= 1)
  {
    return; // no tolerance, or within it short of the margin refinement aims at
  }
  // Every candidate measured with its normals (the excess counts them only with an
  // AngularTolerance, against which the inserts are also taken).
  FaceMeshOptions measured = chosen;
  measured.AngularTolerance = chosen.AngularTolerance > 0 ? chosen.AngularTolerance : 180;
  struct Check
  {
    double Error = 0, Angle = 0, Turn = 0;
    bool Inserts = false; // triangles over 0.8 of the tolerances that could be split
  };
  auto measure = [&](ctk::Construction method, Check& check) {
    measured.Spline.Method = method;
    std::vector<Steiner> inserts;
    std::string error; // a construction that fails on this mesh is not a fallback
    const bool ok = CheckStitchedSpline(this->Triangulation, this->Faces, mesh, this->Segments,
      this->Surface, measured, this->Plane, inserts, check.Error, check.Angle, error, &check.Turn);
    check.Inserts = !inserts.empty();
    return ok;
  };
  Check own;
  if (!measure(chosen.Spline.Method, own))
  {
    return;
  }
  const double maxAngle = std::max(FallbackAngleGrowth * own.Angle, FallbackAngleFloor);
  const double maxTurn = std::max(own.Turn, FallbackTangentTurn);
  double least = Excess(own.Error, own.Angle, chosen);
  int bestMethod = -1;
  Check best;
  for (int c = 0; c < ctk::NumberOfConstructions; ++c)
  {
    const auto method = static_cast<ctk::Construction>(c);
    Check other;
    if (method == chosen.Spline.Method || !ctk::CanBeStitched(method) || !measure(method, other) ||
      other.Angle > maxAngle || other.Turn > maxTurn)
    {
      continue;
    }
    const double excess = Excess(other.Error, other.Angle, chosen);
    if (excess < least)
    {
      least = excess;
      bestMethod = c;
      best = other;
    }
  }
  if (bestMethod >= 0)
  {
    mesh.FallbackConstruction = bestMethod;
    mesh.ChosenError = mesh.MaxEstimatedError;
    mesh.ChosenStopReason = mesh.StopReason;
    mesh.MaxEstimatedError = best.Error;
    mesh.MaxEstimatedAngle = chosen.AngularTolerance > 0 ? best.Angle : 0.0;
    mesh.Converged = least <= 1 && !best.Inserts;
    mesh.StopReason = mesh.Converged ? std::string() : mesh.ChosenStopReason;
  }
}

/// The mesh: in-domain triangles and their boundary segments.
void FaceMesher::Output()
{
  this->CollectFaces();
  FaceMesh& mesh = this->Mesh;
  mesh.Triangles.reserve(this->Faces.size());
  for (const CDT::Face_handle f : this->Faces)
  {
    std::array<Id, 3> t{ f->vertex(0)->info().Index, f->vertex(1)->info().Index,
      f->vertex(2)->info().Index };
    std::array<const LoopSegment*, 3> seg{ nullptr, nullptr, nullptr };
    std::array<bool, 3> flipped{ false, false, false };
    for (int l = 0; l < 3; ++l)
    {
      seg[l] = FaceSegment(this->Triangulation, f, l, this->Segments, flipped[l]);
    }
    mesh.Triangles.push_back(t);
    mesh.Segments.push_back(seg);
    mesh.SegmentFlipped.push_back(flipped);
  }
}
} // namespace

bool MeshFace(const std::vector<FaceLoop>& loops, const std::vector<Point3>& nodePoints,
  const SurfaceFunction& surface, const FaceMeshOptions& options, FaceMesh& mesh)
{
  mesh = FaceMesh();
  FaceMesher mesher(loops, nodePoints, surface, options, mesh);
  if (!mesher.Triangulate() || !mesher.Refine() || !mesher.CheckConstruction())
  {
    return false;
  }
  // Left over the tolerances in the raw plane of a far from isotropic surface: the scaled
  // plane's mesh where it does better (ScalePlane). Only then another construction.
  FaceMesh scaled;
  FaceMesher again(loops, nodePoints, surface, options, scaled, true);
  const bool useScaled = !mesh.Converged && mesher.Anisotropic && again.Triangulate() &&
    again.Refine() && again.CheckConstruction() &&
    (scaled.Converged || scaled.MaxEstimatedError < mesh.MaxEstimatedError);
  FaceMesher& kept = useScaled ? again : mesher;
  if (!(useScaled ? scaled : mesh).Converged && options.CheckConstruction &&
    options.FallbackConstructions)
  {
    kept.TryOtherConstructions();
  }
  kept.Output();
  if (useScaled)
  {
    mesh = std::move(scaled);
  }
  return true;
}

} // namespace ctcad
