// SPDX-License-Identifier: GPL-3.0-or-later
#include "InterfaceTangentPlanes.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace ctcad
{
namespace
{
using Vector3 = Eigen::Vector3d;
using Jacobian = Eigen::Matrix<double, 3, 2>;

Vector3 V3(const Point3& p)
{
  return Vector3(p[0], p[1], p[2]);
}
Point3 P3(const Vector3& v)
{
  return { v.x(), v.y(), v.z() };
}

/// Zero where the derivatives span no plane: at a pole or a cone's apex their cross product is
/// round-off, whose direction means nothing (it grouped an apex with unrelated faces).
Vector3 UnitNormal(const Jacobian& J)
{
  const Vector3 n = J.col(0).cross(J.col(1));
  const double len = n.norm();
  return len > 1e-10 * J.squaredNorm() ? Vector3(n / len) : Vector3::Zero();
}

/// A face's copy of a boundary node (one per face and parameter position: a seam node has two
/// in its face).
struct FaceVertex
{
  int Face;
  Id Global;
  Jacobian J0;
  Vector3 Normal; // zero where the surface is degenerate (a pole)
  int Group = -1;
  std::vector<std::pair<int, int>> Nodes; // (loop, node) occurrences
  /// The node's shared point minus the face's surface point at the node's (u, v): the vertex
  /// tolerance where B-rep edges end apart, and the pcurve ends' gap (DropSkewingSplits).
  Vector3 Offset = Vector3::Zero();
};

/// One end of an edge span at a node, shared by every face along the span (joints, which
/// belong to one face, have their own): its inner cubic point minus the node, and the face
/// vertices there.
struct SpanEnd
{
  Vector3 Tau0, Tau;
  std::vector<int> Vertices;
};

/// A loop segment that is not degenerate, with its end vertices and span ends.
struct SegmentUse
{
  int Face, Loop, Segment;
  int Vertex[2];
  int End[2];
};

/// Faces meeting at a node within the threshold (transitively): their mean normal, and the
/// plane all their stitching data get at the node when the group has a tangent span.
struct Group
{
  std::vector<int> Vertices;
  Vector3 Normal;
  bool Tangent = false; // a tangent span ends here
};

using SpanEndKey = std::tuple<Id, Id, Id>;

/// Largest turn of the surface normal along a tangent span (radians) with RestoreG1.
constexpr double MaxTurnPerSpan = 3.14159265358979323846 / 16;
/// Largest difference, relative to its length, between an edge cubic's end tangent and the face's
/// derivative along the span's chord at a node where the faces share a tangent plane.
constexpr double MaxChordMismatch = 0.05;
/// Largest offset of a span's chord in its face's loop from its pcurve's (the loop's nodes at
/// B-rep vertices are the mean of the pcurve ends), relative to the chord of either half, for
/// which the span is split (DropSkewingSplits).
constexpr double MaxSplitSkew = 0.05;

/// Key of a span end: (B-rep edge, span, node) for edge spans; joints get keys of their own.
SpanEndKey KeyOf(const LoopSegment& seg, int face, int loop, int segment, Id node)
{
  if (seg.Edge >= 0 && seg.Span >= 0)
  {
    return { seg.Edge, seg.Span, node };
  }
  return { -1 - face, static_cast<Id>(loop) * (Id(1) << 32) + segment, node };
}

class TangentPlanes
{
public:
  TangentPlanes(std::vector<CADFace>& faces, const std::vector<Point3>& nodes,
    const FaceDerivatives& evaluate, const TangentPlaneOptions& options)
    : Faces(faces)
    , Nodes(nodes)
    , Evaluate(evaluate)
    , Options(options)
    , CosThreshold(std::cos(options.G1Threshold * 3.14159265358979323846 / 180.0))
  {
  }

  TangentPlaneReport Run();

private:
  Jacobian Derivatives(int face, double s, double t, Vector3* point = nullptr) const;
  Vector3 NormalAtEnd(const SegmentUse& use, int side) const;
  double CurvatureAcross(const SegmentUse& use) const;
  bool TurnsTooFar(const std::vector<int>& uses, double length) const;
  void Collect();
  void FormGroups();
  void ClassifySpans();
  void ChoosePlanes();
  void Project();
  void FitCuspDerivatives();
  void DropSkewingSplits();
  void WriteBack();
  void SetMidNormals();

  std::vector<CADFace>& Faces;
  const std::vector<Point3>& Nodes;
  const FaceDerivatives& Evaluate;
  const TangentPlaneOptions& Options;
  const double CosThreshold;
  std::vector<FaceVertex> Vertices;
  std::vector<SpanEnd> Ends;
  std::vector<SegmentUse> Uses;
  std::vector<Group> Groups;
  std::vector<Jacobian> J; // the stitching derivatives per face vertex
  std::map<std::pair<Id, Id>, std::vector<int>> SpanUses; // (edge, span) -> uses
  std::map<std::pair<Id, Id>, bool> TangentSpan;
  TangentPlaneReport Report;
};

Jacobian TangentPlanes::Derivatives(int face, double s, double t, Vector3* point) const
{
  double P[3], Ds[3], Dt[3];
  this->Evaluate(face, s, t, P, Ds, Dt);
  if (point)
  {
    *point = Vector3(P[0], P[1], P[2]);
  }
  Jacobian D;
  D.col(0) = Vector3(Ds[0], Ds[1], Ds[2]);
  D.col(1) = Vector3(Dt[0], Dt[1], Dt[2]);
  return D;
}

void TangentPlanes::Collect()
{
  std::map<std::tuple<int, Id, double, double>, int> vertexIndex;
  std::map<SpanEndKey, int> endIndex;
  // At most one vertex, segment use and two span ends per loop node: reserved, the stage's
  // arrays are written once (grown, they were copied into fresh pages round after round).
  std::size_t loopNodes = 0;
  for (const CADFace& face : this->Faces)
  {
    for (const FaceLoop& loop : face.Loops)
    {
      loopNodes += loop.Nodes.size();
    }
  }
  this->Vertices.reserve(loopNodes);
  this->Uses.reserve(loopNodes);
  this->Ends.reserve(2 * loopNodes);
  for (int f = 0; f < static_cast<int>(this->Faces.size()); ++f)
  {
    for (int l = 0; l < static_cast<int>(this->Faces[f].Loops.size()); ++l)
    {
      const FaceLoop& loop = this->Faces[f].Loops[l];
      const int n = static_cast<int>(loop.Nodes.size());
      std::vector<int> vertexOf(n);
      for (int k = 0; k < n; ++k)
      {
        const LoopNode& node = loop.Nodes[k];
        const auto key = std::make_tuple(f, node.GlobalNode, node.UV[0], node.UV[1]);
        const auto it = vertexIndex.emplace(key, static_cast<int>(this->Vertices.size()));
        if (it.second)
        {
          Vector3 P;
          FaceVertex v{ f, node.GlobalNode, this->Derivatives(f, node.UV[0], node.UV[1], &P), {},
            -1, {} };
          v.Normal = UnitNormal(v.J0);
          v.Offset = V3(this->Nodes[node.GlobalNode]) - P;
          this->Vertices.push_back(v);
        }
        vertexOf[k] = it.first->second;
        this->Vertices[vertexOf[k]].Nodes.emplace_back(l, k);
      }
      for (int s = 0; s < n; ++s)
      {
        const LoopSegment& seg = loop.Segments[s];
        if (seg.Degenerate)
        {
          continue;
        }
        SegmentUse use{ f, l, s, { vertexOf[s], vertexOf[(s + 1) % n] }, { -1, -1 } };
        for (int side = 0; side < 2; ++side)
        {
          const Id node = loop.Nodes[(s + side) % n].GlobalNode;
          const auto it =
            endIndex.emplace(KeyOf(seg, f, l, s, node), static_cast<int>(this->Ends.size()));
          if (it.second)
          {
            const Vector3 tau = V3(side == 0 ? seg.Near0 : seg.Near1) - V3(this->Nodes[node]);
            this->Ends.push_back({ tau, tau, {} });
          }
          use.End[side] = it.first->second;
          this->Ends[use.End[side]].Vertices.push_back(use.Vertex[side]);
        }
        if (seg.Edge >= 0 && seg.Span >= 0)
        {
          this->SpanUses[{ seg.Edge, seg.Span }].push_back(static_cast<int>(this->Uses.size()));
        }
        this->Uses.push_back(use);
      }
    }
  }
}

void TangentPlanes::FormGroups()
{
  // The vertices with a normal by node (ascending), each node's in index order.
  std::vector<std::pair<Id, int>> byNode;
  byNode.reserve(this->Vertices.size());
  for (int i = 0; i < static_cast<int>(this->Vertices.size()); ++i)
  {
    if (this->Vertices[i].Normal.squaredNorm() > 0)
    {
      byNode.emplace_back(this->Vertices[i].Global, i);
    }
  }
  std::sort(byNode.begin(), byNode.end());
  this->Groups.reserve(byNode.size());
  std::vector<int> vs, parent;
  for (std::size_t first = 0, last = 0; first < byNode.size(); first = last)
  {
    vs.clear();
    for (last = first; last < byNode.size() && byNode[last].first == byNode[first].first; ++last)
    {
      vs.push_back(byNode[last].second);
    }
    const int nv = static_cast<int>(vs.size());
    parent.resize(nv);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int a) {
      while (parent[a] != a)
      {
        a = parent[a] = parent[parent[a]];
      }
      return a;
    };
    for (int a = 0; a < nv; ++a)
    {
      for (int b = 0; b < a; ++b)
      {
        if (this->Vertices[vs[a]].Normal.dot(this->Vertices[vs[b]].Normal) > this->CosThreshold)
        {
          parent[find(a)] = find(b);
        }
      }
    }
    std::map<int, int> groupOfRoot;
    for (int a = 0; a < nv; ++a)
    {
      const auto it = groupOfRoot.emplace(find(a), static_cast<int>(this->Groups.size()));
      if (it.second)
      {
        this->Groups.emplace_back();
      }
      this->Groups[it.first->second].Vertices.push_back(vs[a]);
      this->Vertices[vs[a]].Group = it.first->second;
    }
  }
  for (Group& g : this->Groups)
  {
    Vector3 sum = Vector3::Zero();
    for (const int v : g.Vertices)
    {
      sum += this->Vertices[v].Normal;
    }
    g.Normal = sum.norm() > 0 ? Vector3(sum.normalized()) : Vector3::Zero();
  }
}

/// A span is a tangent interface when the faces along it meet within the threshold all along
/// it: at both nodes (their vertices there are in one group; a pole, where a face has no
/// normal, does not count) and at three interior points (the faces' normals over their chords).
/// A span whose faces are tangent at its midpoint only (two cylinders mitred, a fillet running
/// out into a crease) is a feature edge: no tangent plane can be shared along it.
void TangentPlanes::ClassifySpans()
{
  for (const auto& entry : this->SpanUses)
  {
    const std::vector<int>& uses = entry.second;
    bool tangent = uses.size() >= 2;
    // Uses may run either way along the span: compare the vertices at the same global node.
    const Id firstNode = this->Vertices[this->Uses[uses[0]].Vertex[0]].Global;
    for (int side = 0; side < 2 && tangent; ++side)
    {
      int group = -1;
      for (const int u : uses)
      {
        const int* ends = this->Uses[u].Vertex;
        const bool same = this->Vertices[ends[0]].Global == firstNode;
        const FaceVertex& v = this->Vertices[ends[same == (side == 0) ? 0 : 1]];
        if (v.Group >= 0)
        {
          tangent = tangent && (group < 0 || group == v.Group);
          group = v.Group;
        }
      }
    }
    double minCos = 1; // of the angle between the faces' normals
    for (const double s : { 0.25, 0.5, 0.75 })
    {
      std::vector<Vector3> normals;
      for (const int u : uses)
      {
        if (!tangent)
        {
          break;
        }
        const SegmentUse& use = this->Uses[u];
        const FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
        const LoopNode& a = loop.Nodes[use.Segment];
        const LoopNode& b = loop.Nodes[(use.Segment + 1) % loop.Nodes.size()];
        // The same 3D position on every face: s from the lower global node.
        const double r = a.GlobalNode <= b.GlobalNode ? s : 1 - s;
        normals.push_back(UnitNormal(this->Derivatives(use.Face, (1 - r) * a.UV[0] + r * b.UV[0],
          (1 - r) * a.UV[1] + r * b.UV[1])));
        for (std::size_t i = 0; i + 1 < normals.size(); ++i)
        {
          minCos = std::min(minCos, normals[i].dot(normals.back()));
          tangent = tangent && minCos > this->CosThreshold;
        }
      }
    }
    this->TangentSpan[entry.first] = tangent;
    if (!tangent)
    {
      continue;
    }
    for (const int u : uses)
    {
      for (const int v : this->Uses[u].Vertex)
      {
        if (this->Vertices[v].Group >= 0)
        {
          this->Groups[this->Vertices[v].Group].Tangent = true;
        }
      }
    }
    // Spans to split, with RestoreG1. Between its nodes and midpoint a boundary micro-patch's
    // cross-boundary derivative is a quadratic: where the normal turns along the span (an arc
    // of a fillet), each side leaves the shared plane by about the cube of that turn (0.08
    // degrees at 45 degrees on KiCad's L_Bourns-SRN4018, 0.026 at 22.5); spans are split to
    // 11.25 degrees, and further where the boundary triangles are skewed (TurnsTooFar).
    // Where the faces are not exactly tangent, each side turns by half their angle within its
    // boundary triangles: the surface moves by about their width (a third of the span) times
    // the sine of that.
    const FaceVertex& a = this->Vertices[this->Uses[uses[0]].Vertex[0]];
    const FaceVertex& b = this->Vertices[this->Uses[uses[0]].Vertex[1]];
    const double halfSine = std::sqrt(std::max(0.0, 0.5 * (1 - minCos)));
    const double length = (V3(this->Nodes[a.Global]) - V3(this->Nodes[b.Global])).norm();
    if (this->Options.RestoreG1 && this->Options.MaxMove > 0 &&
      (length * halfSine / 3 > this->Options.MaxMove || this->TurnsTooFar(uses, length)))
    {
      this->Report.SpansToSplit.push_back(entry.first);
    }
  }
}

/// Whether the normal turns too far along a tangent span (its uses, its chord's length) for
/// G1 between its nodes and midpoint (ClassifySpans).
bool TangentPlanes::TurnsTooFar(const std::vector<int>& uses, double length) const
{
  // On every face: at a pole, where it has no normal, from its normal next to the pole
  // along the span (a seam from a sphere's pole, 54 degrees on the balls of KiCad's BGA-100:
  // 0.14 degrees off G1; along the other face, 26 degrees on Altech_AK300's corner patches, 1
  // degree off G1). The pole face's degenerate macro-triangles follow the turn less closely:
  // half of it next to a pole (DirectFET_MP: 0.12 degrees off G1 at 11.25, 0.008 at 5.6).
  bool pole = false;
  for (const int u : uses)
  {
    for (const int v : this->Uses[u].Vertex)
    {
      pole = pole || this->Vertices[v].Normal.squaredNorm() == 0;
    }
  }
  // A boundary micro-triangle's normal is the edge cubic's tangent E' times its derivative D
  // toward the triangle's inside. Where the face curves much faster across the span than
  // along it, its boundary triangles are much longer than wide (the mesher turns by about as
  // many degrees each way), and D runs mostly along E': where E' leaves the face's tangent
  // plane (not at the nodes and midpoint, where the planes are imposed; between them by an
  // error of the cubic, which shrinks with the turn), each side's normal tilts by that times
  // the triangle's length over its width, the two sides opposite ways. So the bound is
  // turn^2 * max(turn, turn across) <= maxTurn^3, with the normal's turn across the face over
  // the span's length (the turn rule where the face curves alike both ways). KiCad's
  // LairdTech_28C0236, a bent wire's seam: 7.6 degrees along, 84 across, triangles 15 times
  // longer than wide, 0.118 degrees off G1 (a torus's seam, of uniform speed, stays at 1e-5).
  const double maxTurn = pole ? MaxTurnPerSpan / 2 : MaxTurnPerSpan;
  double turn = 0, across = 0;
  for (const int u : uses)
  {
    const Vector3 p = this->NormalAtEnd(this->Uses[u], 0);
    const Vector3 q = this->NormalAtEnd(this->Uses[u], 1);
    if (p.squaredNorm() > 0 && q.squaredNorm() > 0)
    {
      turn = std::max(turn, std::atan2(p.cross(q).norm(), p.dot(q)));
    }
    across = std::max(across, this->CurvatureAcross(this->Uses[u]) * length);
  }
  return turn * turn * std::max(turn, across) > maxTurn * maxTurn * maxTurn;
}

/// The face's unit normal at one end of a segment; at a pole (no normal there) its limit along
/// the segment: the normal a thousandth of the chord away (exact for a sphere or a cone's
/// generator up to that thousandth of their turn).
Vector3 TangentPlanes::NormalAtEnd(const SegmentUse& use, int side) const
{
  const Vector3& n = this->Vertices[use.Vertex[side]].Normal;
  if (n.squaredNorm() > 0)
  {
    return n;
  }
  const FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
  const LoopNode& a = loop.Nodes[use.Segment];
  const LoopNode& b = loop.Nodes[(use.Segment + 1) % loop.Nodes.size()];
  const double r = side == 0 ? 1e-3 : 1 - 1e-3;
  return UnitNormal(
    this->Derivatives(use.Face, (1 - r) * a.UV[0] + r * b.UV[0], (1 - r) * a.UV[1] + r * b.UV[1]));
}

/// How fast (radians per unit length) the face's normal turns across a segment, into the face
/// at its chord's midpoint; 0 where the face has no normal there.
double TangentPlanes::CurvatureAcross(const SegmentUse& use) const
{
  const FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
  const LoopNode& a = loop.Nodes[use.Segment];
  const LoopNode& b = loop.Nodes[(use.Segment + 1) % loop.Nodes.size()];
  const Eigen::Vector2d mid(0.5 * (a.UV[0] + b.UV[0]), 0.5 * (a.UV[1] + b.UV[1]));
  // A thousandth of the chord to its left, into the face (faces lie left of their loops).
  const Eigen::Vector2d step = 1e-3 * Eigen::Vector2d(a.UV[1] - b.UV[1], b.UV[0] - a.UV[0]);
  const Jacobian J0 = this->Derivatives(use.Face, mid.x(), mid.y());
  const Vector3 n0 = UnitNormal(J0);
  const Vector3 n1 = UnitNormal(this->Derivatives(use.Face, mid.x() + step.x(), mid.y() + step.y()));
  const double distance = (J0 * step).norm();
  if (n0.squaredNorm() == 0 || n1.squaredNorm() == 0 || distance == 0)
  {
    return 0;
  }
  return std::atan2(n0.cross(n1).norm(), n0.dot(n1)) / distance;
}

/// The plane of a tangent group: the faces' mean normal; where every edge cubic at the node
/// runs along one line (inside a B-rep edge, where the node's two span ends are one Hermite
/// tangent), made perpendicular to that line, so that the cubics do not move at all. Elsewhere
/// (a B-rep vertex) they move by their angle to the plane: nothing where the faces are exactly
/// tangent.
void TangentPlanes::ChoosePlanes()
{
  std::vector<std::vector<int>> endsOfVertex(this->Vertices.size());
  for (int e = 0; e < static_cast<int>(this->Ends.size()); ++e)
  {
    for (const int v : this->Ends[e].Vertices)
    {
      endsOfVertex[v].push_back(e);
    }
  }
  for (Group& g : this->Groups)
  {
    Vector3 line = Vector3::Zero();
    bool oneLine = g.Tangent;
    for (const int v : g.Vertices)
    {
      for (const int e : endsOfVertex[v])
      {
        const Vector3& tau = this->Ends[e].Tau0;
        if (tau.squaredNorm() == 0)
        {
          continue;
        }
        if (line.squaredNorm() == 0)
        {
          line = tau.normalized();
        }
        oneLine = oneLine && line.cross(tau.normalized()).norm() < 1e-6;
      }
    }
    if (oneLine && line.squaredNorm() > 0)
    {
      const Vector3 n = g.Normal - g.Normal.dot(line) * line;
      g.Normal = n.norm() > 0 ? Vector3(n.normalized()) : g.Normal;
    }
  }
}

/// Derivatives of tangent groups onto their plane; each span end onto the planes of the
/// vertices it touches (a tangent group's, or the face's own where the face's vertex is in no
/// tangent group): one plane, or the line of two.
void TangentPlanes::Project()
{
  this->J.resize(this->Vertices.size());
  for (std::size_t i = 0; i < this->Vertices.size(); ++i)
  {
    const FaceVertex& v = this->Vertices[i];
    this->J[i] = v.J0;
    if (v.Group >= 0 && this->Groups[v.Group].Tangent)
    {
      const Vector3& n = this->Groups[v.Group].Normal;
      this->J[i] = v.J0 - n * (n.transpose() * v.J0);
    }
  }
  const double sinThreshold = std::sqrt(1 - this->CosThreshold * this->CosThreshold);
  std::vector<Vector3> planes;
  for (SpanEnd& end : this->Ends)
  {
    // Tangent groups' planes first, so that where two planes are one, theirs is kept. Faces
    // of different groups at a node differ by more than the threshold, unless their normals
    // are opposite (a face oriented against its neighbour: KiCad's Bourns 8100 pins); such
    // planes are one: their line, from the mean normals' rounding (1e-7), ran anywhere in
    // the plane and turned the cubic by up to 90 degrees (45 on L19's edge 540), so the
    // span was halved down to the shortest and left needle triangles (G1 0.71 degrees).
    planes.clear();
    bool moved = false;
    for (const bool groupedPass : { true, false })
    {
      for (const int v : end.Vertices)
      {
        const FaceVertex& vertex = this->Vertices[v];
        const bool grouped = vertex.Group >= 0 && this->Groups[vertex.Group].Tangent;
        if (grouped != groupedPass)
        {
          continue;
        }
        moved = moved || grouped;
        const Vector3& n = grouped ? this->Groups[vertex.Group].Normal : vertex.Normal;
        bool seen = n.squaredNorm() == 0;
        for (const Vector3& m : planes)
        {
          seen = seen || m.cross(n).norm() < (m.dot(n) < 0 ? sinThreshold : 1e-12);
        }
        if (!seen)
        {
          planes.push_back(n);
        }
      }
    }
    if (!moved || planes.empty())
    {
      continue;
    }
    if (planes.size() == 1)
    {
      end.Tau = end.Tau0 - planes[0].dot(end.Tau0) * planes[0];
    }
    else
    {
      // Two faces in different groups: the planes' line (they differ by more than the
      // threshold, so it is well defined). A span end touches at most two faces' planes.
      const Vector3 line = planes[0].cross(planes[1]).normalized();
      end.Tau = line.dot(end.Tau0) * line;
    }
    this->Report.MaxCurveChange =
      std::max(this->Report.MaxCurveChange, (end.Tau - end.Tau0).norm());
  }
  this->FitCuspDerivatives();
  for (const SegmentUse& use : this->Uses)
  {
    const LoopSegment& seg = this->Faces[use.Face].Loops[use.Loop].Segments[use.Segment];
    const FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
    const LoopNode& a = loop.Nodes[use.Segment];
    const LoopNode& b = loop.Nodes[(use.Segment + 1) % loop.Nodes.size()];
    const Eigen::Vector2d chord(b.UV[0] - a.UV[0], b.UV[1] - a.UV[1]);
    double move = 0;
    bool mismatch = false;
    for (int side = 0; side < 2; ++side)
    {
      const int v = use.Vertex[side];
      const SpanEnd& end = this->Ends[use.End[side]];
      // The change of the face's T point along that span's direction.
      const double scale = end.Tau0.norm() / std::max(1e-300, this->Vertices[v].J0.norm());
      const Jacobian dJ = this->J[v] - this->Vertices[v].J0;
      this->Report.MaxDerivativeChange =
        std::max(this->Report.MaxDerivativeChange, dJ.norm() * scale);
      move = std::max({ move, (end.Tau - end.Tau0).norm(), (dJ * chord).norm() / 3 });
      // Where the span's cubic leaves a smooth node off the face's derivative along the chord
      // (its pcurve curves within the span), the node's T points disagree: the boundary
      // micro-triangle there reads the cubic, the one across the tangent span the derivative,
      // and the span's cross-boundary derivative gets an along-edge kink that, as the normal
      // turns along the span, tilts it out of the shared plane (0.2 degrees on KiCad's
      // Crystal_SMD_0603-4Pin). Halving the span halves the mismatch. The chord is the span's
      // pcurve's: the loop's, off it at B-rep vertices by a constant (DropSkewingSplits), made
      // the mismatch grow with every split (KiCad's TQFP-44, split 7 times).
      const int group = this->Vertices[v].Group;
      const Eigen::Vector2d own(seg.PCurveChord[0], seg.PCurveChord[1]);
      const Vector3 alongChord = this->Vertices[v].J0 * (side == 0 ? own : (-own).eval()) / 3;
      mismatch = mismatch ||
        (group >= 0 && this->Groups[group].Tangent &&
          (alongChord - end.Tau0).norm() >
            std::max(MaxChordMismatch * end.Tau0.norm(), 0.1 * this->Options.MaxMove));
    }
    if (this->Options.MaxMove > 0 && move > this->Options.MaxMove && seg.Edge >= 0 && seg.Span >= 0)
    {
      this->Report.SpansToSplit.emplace_back(seg.Edge, seg.Span);
    }
    if (this->Options.MaxMove > 0 && mismatch && seg.Edge >= 0 && seg.Span >= 0)
    {
      this->Report.SpansToSplit.emplace_back(seg.Edge, seg.Span);
    }
  }
  this->DropSkewingSplits();
  for (const Group& g : this->Groups)
  {
    bool twoFaces = false; // not just the two copies of a seam node
    for (const int v : g.Vertices)
    {
      twoFaces = twoFaces || this->Vertices[v].Face != this->Vertices[g.Vertices[0]].Face;
    }
    this->Report.SmoothNodes += g.Tangent && twoFaces ? 1 : 0;
  }
}

/// The spans to split, sorted and unique, less those a split would skew. A loop node at a B-rep
/// vertex is the mean of the pcurve ends that meet there (JoinRuns), off each by half their gap:
/// a span's chord in the loop is its pcurve's plus that offset, which a split does not halve.
/// Where the pcurves of a face miss each other (re-projected pcurves: KiCad's QFP packages, off
/// by 3e-4 of 17 at a corner), halving the span next to the vertex again and again (its cubic
/// disagrees with the face's derivative there) leaves a span whose chord runs across the edge
/// and whose boundary micro-triangles fold (180 degrees). A span is not split where the offset
/// (through the face's derivatives) would exceed MaxSplitSkew of the halves' chords. The same
/// in 3D: where B-rep edges end apart (KiCad's Bourns 8100 toroids: gaps of 3e-3), a vertex node
/// is off its faces' surfaces by up to the vertex tolerance, which no split halves either: spans
/// split down to that length (4e-4 in 3D, 1.4e-5 in (u, v) on the L43.2's plane face 47) make
/// boundary triangles whose 3D points and (u, v) disagree 30-fold, and their splines overshoot
/// by the triangle's length (2 units). A span is not split where the difference of its nodes'
/// offsets from their surface points (FaceVertex::Offset) would exceed MaxSplitSkew of the
/// halves' chords either.
void TangentPlanes::DropSkewingSplits()
{
  std::vector<std::pair<Id, Id>>& split = this->Report.SpansToSplit;
  std::sort(split.begin(), split.end());
  split.erase(std::unique(split.begin(), split.end()), split.end());
  std::vector<std::pair<Id, Id>> skewing;
  for (const SegmentUse& use : this->Uses)
  {
    const FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
    const LoopSegment& seg = loop.Segments[use.Segment];
    const LoopNode& a = loop.Nodes[use.Segment];
    const LoopNode& b = loop.Nodes[(use.Segment + 1) % loop.Nodes.size()];
    const Eigen::Vector2d own(seg.PCurveChord[0], seg.PCurveChord[1]);
    const Eigen::Vector2d offset =
      Eigen::Vector2d(b.UV[0] - a.UV[0], b.UV[1] - a.UV[1]) - own;
    const Jacobian& J0 = this->Vertices[use.Vertex[0]].J0;
    const FaceVertex &va = this->Vertices[use.Vertex[0]], &vb = this->Vertices[use.Vertex[1]];
    // In 3D against the nodes' chord (J0 may span no plane at a pole).
    const double chord3 = (V3(this->Nodes[vb.Global]) - V3(this->Nodes[va.Global])).norm();
    if ((J0 * offset).norm() > MaxSplitSkew * 0.5 * (J0 * own).norm() ||
      (vb.Offset - va.Offset).norm() > MaxSplitSkew * 0.5 * chord3)
    {
      skewing.emplace_back(seg.Edge, seg.Span);
    }
  }
  std::sort(skewing.begin(), skewing.end());
  split.erase(std::remove_if(split.begin(), split.end(),
                [&](const std::pair<Id, Id>& span) {
                  return std::binary_search(skewing.begin(), skewing.end(), span);
                }),
    split.end());
}

/// Face corners where the boundary cubics leave the node within a much smaller angle than their
/// chords do in the parameter plane: a cusp (an arc tangent to a line, KiCad's pads and
/// spandrels), where the 3D corner is 0 while the chords keep an angle. Every interior edge there
/// gets its T point from the derivatives through its chord, and lies outside the boundary
/// cubics' corner: the micro-patches fold over (normals flipped by 180 degrees). The face's
/// vertex derivatives are fitted to the boundary instead, J d = 3 tau for both boundary chords
/// d (in the face's plane there), so that the interior edges fan out within the cubics' corner.
void TangentPlanes::FitCuspDerivatives()
{
  std::map<std::tuple<int, int, int>, int> useOf;
  for (int u = 0; u < static_cast<int>(this->Uses.size()); ++u)
  {
    useOf[{ this->Uses[u].Face, this->Uses[u].Loop, this->Uses[u].Segment }] = u;
  }
  for (const SegmentUse& in : this->Uses)
  {
    const FaceLoop& loop = this->Faces[in.Face].Loops[in.Loop];
    const int n = static_cast<int>(loop.Nodes.size());
    const auto next = useOf.find({ in.Face, in.Loop, (in.Segment + 1) % n });
    const int v = in.Vertex[1];
    const Vector3 normal = UnitNormal(this->J[v]);
    if (next == useOf.end() || n < 3 || normal.squaredNorm() == 0)
    {
      continue;
    }
    const SegmentUse& out = this->Uses[next->second];
    auto uv = [&](int k) {
      const LoopNode& node = loop.Nodes[(k + n) % n];
      return Eigen::Vector2d(node.UV[0], node.UV[1]);
    };
    const int k = (in.Segment + 1) % n;
    const Eigen::Vector2d dIn = uv(k - 1) - uv(k), dOut = uv(k + 1) - uv(k);
    // In the plane of the face's derivatives there.
    auto inPlane = [&](const Vector3& t) { return Vector3(t - normal.dot(t) * normal); };
    const Vector3 tIn = inPlane(this->Ends[in.End[1]].Tau);
    const Vector3 tOut = inPlane(this->Ends[out.End[0]].Tau);
    const double det = dOut.x() * dIn.y() - dOut.y() * dIn.x();
    if (tIn.squaredNorm() == 0 || tOut.squaredNorm() == 0 ||
      std::abs(det) <= 1e-12 * dIn.norm() * dOut.norm())
    {
      continue;
    }
    // The face's corner (counter-clockwise from the outgoing to the incoming chord: the face
    // lies to the left of its loops), through the derivatives and along the cubics.
    double chords = AngleAbout(this->J[v] * dOut, this->J[v] * dIn, normal);
    chords += chords < 0 ? 2 * 3.14159265358979323846 : 0;
    const double cubics =
      chords + std::remainder(AngleAbout(tOut, tIn, normal) - chords, 2 * 3.14159265358979323846);
    if (cubics >= 0.5 * chords)
    {
      continue;
    }
    Eigen::Matrix2d D;
    D << dOut, dIn;
    Jacobian T;
    T << 3 * tOut, 3 * tIn;
    const Jacobian fitted = T * D.inverse();
    // Interior chords within the corner move by up to this (as combinations of the boundary
    // chords, as long as the longer one): the spans at the corner are split until it is small.
    const Jacobian dJ = fitted - this->J[v];
    const double longest = std::max(dIn.norm(), dOut.norm());
    const double move = longest *
      ((dJ * dIn).norm() / dIn.norm() + (dJ * dOut).norm() / dOut.norm()) / 3;
    for (const LoopSegment* seg : { &loop.Segments[in.Segment], &loop.Segments[out.Segment] })
    {
      if (this->Options.MaxMove > 0 && move > this->Options.MaxMove && seg->Edge >= 0 &&
        seg->Span >= 0)
      {
        this->Report.SpansToSplit.emplace_back(seg->Edge, seg->Span);
      }
    }
    this->J[v] = fitted;
  }
}

/// Derivatives per loop node; inner points of moved span ends (the same doubles on every face
/// that shares a span end; the others stay the edge sampling's doubles).
void TangentPlanes::WriteBack()
{
  for (std::size_t i = 0; i < this->Vertices.size(); ++i)
  {
    for (const auto& occurrence : this->Vertices[i].Nodes)
    {
      FaceLoop& loop = this->Faces[this->Vertices[i].Face].Loops[occurrence.first];
      LoopNode& node = loop.Nodes[occurrence.second];
      node.Ds = P3(this->J[i].col(0));
      node.Dt = P3(this->J[i].col(1));
      node.Consistent = true;
    }
  }
  for (const SegmentUse& use : this->Uses)
  {
    FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
    LoopSegment& seg = loop.Segments[use.Segment];
    for (int side = 0; side < 2; ++side)
    {
      const SpanEnd& end = this->Ends[use.End[side]];
      if (end.Tau != end.Tau0)
      {
        const Id node = this->Vertices[use.Vertex[side]].Global;
        (side == 0 ? seg.Near0 : seg.Near1) = P3(V3(this->Nodes[node]) + end.Tau);
      }
    }
    seg.Tangent = seg.Edge >= 0 && seg.Span >= 0 && this->TangentSpan[{ seg.Edge, seg.Span }];
  }
}

/// The shared normal at the midpoint of each tangent span (RestoreG1): the faces' mean normal
/// at their chord midpoints, perpendicular to the edge cubic's tangent there, computed from
/// the span's canonical direction so that every copy agrees bit for bit.
void TangentPlanes::SetMidNormals()
{
  for (const auto& entry : this->SpanUses)
  {
    if (!this->TangentSpan[entry.first])
    {
      continue;
    }
    Vector3 sum = Vector3::Zero();
    for (const int u : entry.second)
    {
      const SegmentUse& use = this->Uses[u];
      const FaceLoop& loop = this->Faces[use.Face].Loops[use.Loop];
      const LoopNode& a = loop.Nodes[use.Segment];
      const LoopNode& b = loop.Nodes[(use.Segment + 1) % loop.Nodes.size()];
      sum += UnitNormal(this->Derivatives(
        use.Face, 0.5 * (a.UV[0] + b.UV[0]), 0.5 * (a.UV[1] + b.UV[1])));
    }
    const SegmentUse& first = this->Uses[entry.second[0]];
    const FaceLoop& loop = this->Faces[first.Face].Loops[first.Loop];
    const LoopSegment& seg = loop.Segments[first.Segment];
    const Id ga = loop.Nodes[first.Segment].GlobalNode;
    const Id gb = loop.Nodes[(first.Segment + 1) % loop.Nodes.size()].GlobalNode;
    const bool forward = ga <= gb;
    const Vector3 b0 = V3(this->Nodes[forward ? ga : gb]), b3 = V3(this->Nodes[forward ? gb : ga]);
    const Vector3 b1 = V3(forward ? seg.Near0 : seg.Near1);
    const Vector3 b2 = V3(forward ? seg.Near1 : seg.Near0);
    const Vector3 tangent = (b3 + b2 - b1 - b0).normalized();
    const Vector3 m = sum - sum.dot(tangent) * tangent;
    if (m.norm() == 0)
    {
      continue;
    }
    for (const int u : entry.second)
    {
      const SegmentUse& use = this->Uses[u];
      this->Faces[use.Face].Loops[use.Loop].Segments[use.Segment].MidNormal = P3(m.normalized());
    }
    this->Report.SmoothSpans += static_cast<Id>(entry.second.size());
  }
}

TangentPlaneReport TangentPlanes::Run()
{
  this->Collect();
  this->FormGroups();
  this->ClassifySpans();
  if (this->Options.RestoreG1)
  {
    this->ChoosePlanes();
  }
  else
  {
    for (Group& g : this->Groups)
    {
      g.Tangent = false; // classification only: the data stay the surfaces'
    }
  }
  this->Project();
  this->WriteBack();
  if (this->Options.RestoreG1)
  {
    this->SetMidNormals();
  }
  return this->Report;
}
} // namespace

TangentPlaneReport SetInterfaceTangentPlanes(std::vector<CADFace>& faces,
  const std::vector<Point3>& nodes, const FaceDerivatives& evaluate,
  const TangentPlaneOptions& options)
{
  return TangentPlanes(faces, nodes, evaluate, options).Run();
}

} // namespace ctcad
