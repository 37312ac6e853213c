// SPDX-License-Identifier: GPL-3.0-or-later
#include "InterfaceTangentPlanes.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
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

/// A face's copy of a boundary node (one per face and parameter position: a seam node has two
/// in its face).
struct FaceVertex
{
  int Face;
  Id Global;
  Jacobian J0;
  Vector3 Normal;
  std::vector<std::pair<int, int>> Nodes; // (loop, node) occurrences
};

/// A face vertex and a span end at its node.
struct Incidence
{
  int Vertex;
  int SpanEnd;
};

/// Key of a span end: (B-rep edge, span, node) for edge spans (shared by all faces along the
/// edge); joints, which belong to one face, get keys of their own.
using SpanEndKey = std::tuple<Id, Id, Id>;

SpanEndKey KeyOf(const LoopSegment& seg, int face, int loop, int segment, Id node)
{
  if (seg.Edge >= 0 && seg.Span >= 0)
  {
    return { seg.Edge, seg.Span, node };
  }
  return { -1 - face, static_cast<Id>(loop) * (Id(1) << 32) + segment, node };
}

double AngleDegrees(const Vector3& a, const Vector3& b)
{
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / 3.14159265358979323846;
}

Vector3 UnitNormal(const Jacobian& J)
{
  const Vector3 n = J.col(0).cross(J.col(1));
  const double len = n.norm();
  return len > 0 ? Vector3(n / len) : Vector3::Zero();
}
} // namespace

TangentPlaneReport SetInterfaceTangentPlanes(std::vector<CADFace>& faces,
  const std::vector<Point3>& nodes, const FaceDerivatives& evaluate,
  const TangentPlaneOptions& options)
{
  TangentPlaneReport report;
  std::vector<FaceVertex> vertices;
  std::map<std::tuple<int, Id, double, double>, int> vertexIndex;
  std::vector<Incidence> incidences;
  std::map<SpanEndKey, int> spanEndIndex;
  std::vector<Vector3> tau0; // inner point - node, per span end
  const double cosThreshold = std::cos(options.G1Threshold * 3.14159265358979323846 / 180.0);

  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
  {
    for (int l = 0; l < static_cast<int>(faces[f].Loops.size()); ++l)
    {
      const FaceLoop& loop = faces[f].Loops[l];
      const int n = static_cast<int>(loop.Nodes.size());
      for (int k = 0; k < n; ++k)
      {
        const LoopNode& node = loop.Nodes[k];
        auto it = vertexIndex.emplace(
          std::make_tuple(f, node.GlobalNode, node.UV[0], node.UV[1]), static_cast<int>(vertices.size()));
        if (it.second)
        {
          FaceVertex v;
          v.Face = f;
          v.Global = node.GlobalNode;
          double P[3], Ds[3], Dt[3];
          evaluate(f, node.UV[0], node.UV[1], P, Ds, Dt);
          v.J0.col(0) = Vector3(Ds[0], Ds[1], Ds[2]);
          v.J0.col(1) = Vector3(Dt[0], Dt[1], Dt[2]);
          v.Normal = UnitNormal(v.J0);
          vertices.push_back(v);
        }
        const int vi = it.first->second;
        vertices[vi].Nodes.emplace_back(l, k);
        // The segments ending (Near1) and starting (Near0) at node k.
        for (const int s : { (k + n - 1) % n, k })
        {
          const LoopSegment& seg = loop.Segments[s];
          if (seg.Degenerate)
          {
            continue;
          }
          const bool atStart = s == k;
          auto se = spanEndIndex.emplace(KeyOf(seg, f, l, s, node.GlobalNode), static_cast<int>(tau0.size()));
          if (se.second)
          {
            tau0.push_back(V3(atStart ? seg.Near0 : seg.Near1) - V3(nodes[node.GlobalNode]));
          }
          incidences.push_back({ vi, se.first->second });
        }
      }
    }
  }

  // Per node, the face vertices whose normals agree within the threshold (transitively) form
  // a group with their mean normal.
  std::vector<Jacobian> J(vertices.size());
  std::vector<int> groupOf(vertices.size(), -1);
  std::vector<Vector3> groupNormal;
  std::map<Id, std::vector<int>> vertexOfNode;
  for (int i = 0; i < static_cast<int>(vertices.size()); ++i)
  {
    J[i] = vertices[i].J0;
    vertexOfNode[vertices[i].Global].push_back(i);
  }
  for (const auto& entry : vertexOfNode)
  {
    const std::vector<int>& vs = entry.second;
    const int nv = static_cast<int>(vs.size());
    if (!options.RestoreG1 || nv < 2)
    {
      continue;
    }
    std::vector<int> parent(nv);
    for (int a = 0; a < nv; ++a)
    {
      parent[a] = a;
    }
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
        if (vertices[vs[a]].Normal.dot(vertices[vs[b]].Normal) > cosThreshold)
        {
          parent[find(a)] = find(b);
        }
      }
    }
    bool smooth = false;
    for (int root = 0; root < nv; ++root)
    {
      Vector3 sum = Vector3::Zero();
      int members = 0;
      bool twoFaces = false; // not just the two copies of a seam node
      for (int a = 0; a < nv; ++a)
      {
        if (find(a) == root)
        {
          sum += vertices[vs[a]].Normal;
          twoFaces = twoFaces || (members > 0 && vertices[vs[a]].Face != vertices[vs[root]].Face);
          ++members;
        }
      }
      if (members < 2 || sum.norm() == 0)
      {
        continue;
      }
      smooth = smooth || twoFaces;
      const Vector3 n = sum.normalized();
      const int g = static_cast<int>(groupNormal.size());
      groupNormal.push_back(n);
      for (int a = 0; a < nv; ++a)
      {
        if (find(a) == root)
        {
          groupOf[vs[a]] = g;
          J[vs[a]] = J[vs[a]] - n * (n.transpose() * J[vs[a]]);
        }
      }
    }
    report.SmoothNodes += smooth ? 1 : 0;
  }
  // A span end lies in the plane of every group it touches: one group, its plane; two, the
  // planes' line.
  std::vector<std::vector<int>> spanGroups(tau0.size());
  for (const Incidence& in : incidences)
  {
    const int g = groupOf[in.Vertex];
    std::vector<int>& gs = spanGroups[in.SpanEnd];
    if (g >= 0 && std::find(gs.begin(), gs.end(), g) == gs.end())
    {
      gs.push_back(g);
    }
  }
  std::vector<Vector3> tau = tau0;
  for (std::size_t e = 0; e < tau.size(); ++e)
  {
    const std::vector<int>& gs = spanGroups[e];
    if (gs.size() == 1)
    {
      const Vector3& n = groupNormal[gs[0]];
      tau[e] = tau0[e] - n.dot(tau0[e]) * n;
    }
    else if (gs.size() == 2)
    {
      const Vector3 line = groupNormal[gs[0]].cross(groupNormal[gs[1]]);
      if (line.norm() > 0)
      {
        tau[e] = line.normalized().dot(tau0[e]) * line.normalized();
      }
    }
    report.MaxCurveChange = std::max(report.MaxCurveChange, (tau[e] - tau0[e]).norm());
  }
  for (const Incidence& in : incidences)
  {
    // The change of the face's T point along that span's direction.
    const double scale = tau0[in.SpanEnd].norm() / std::max(1e-300, vertices[in.Vertex].J0.norm());
    report.MaxDerivativeChange =
      std::max(report.MaxDerivativeChange, (J[in.Vertex] - vertices[in.Vertex].J0).norm() * scale);
  }

  // Write back: derivatives per loop node, inner points per segment (the same doubles on every
  // face that shares a span end).
  for (std::size_t i = 0; i < vertices.size(); ++i)
  {
    for (const auto& occurrence : vertices[i].Nodes)
    {
      LoopNode& node = faces[vertices[i].Face].Loops[occurrence.first].Nodes[occurrence.second];
      node.Ds = P3(J[i].col(0));
      node.Dt = P3(J[i].col(1));
      node.Consistent = true;
    }
  }
  // Mid-span normals of smooth interfaces: every face's surface normal at its chord midpoint.
  std::map<std::pair<Id, Id>, std::vector<Vector3>> spanNormals;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
  {
    for (int l = 0; l < static_cast<int>(faces[f].Loops.size()); ++l)
    {
      FaceLoop& loop = faces[f].Loops[l];
      const int n = static_cast<int>(loop.Nodes.size());
      for (int s = 0; s < n; ++s)
      {
        LoopSegment& seg = loop.Segments[s];
        if (seg.Degenerate)
        {
          continue;
        }
        const LoopNode &a = loop.Nodes[s], &b = loop.Nodes[(s + 1) % n];
        // Only moved points are rewritten (the others stay the edge sampling's doubles).
        const int ea = spanEndIndex.at(KeyOf(seg, f, l, s, a.GlobalNode));
        const int eb = spanEndIndex.at(KeyOf(seg, f, l, s, b.GlobalNode));
        if (tau[ea] != tau0[ea])
        {
          seg.Near0 = P3(V3(nodes[a.GlobalNode]) + tau[ea]);
        }
        if (tau[eb] != tau0[eb])
        {
          seg.Near1 = P3(V3(nodes[b.GlobalNode]) + tau[eb]);
        }
        if (seg.Edge >= 0 && seg.Span >= 0)
        {
          double P[3], Ds[3], Dt[3];
          evaluate(f, 0.5 * (a.UV[0] + b.UV[0]), 0.5 * (a.UV[1] + b.UV[1]), P, Ds, Dt);
          Jacobian Jm;
          Jm.col(0) = Vector3(Ds[0], Ds[1], Ds[2]);
          Jm.col(1) = Vector3(Dt[0], Dt[1], Dt[2]);
          spanNormals[{ seg.Edge, seg.Span }].push_back(UnitNormal(Jm));
        }
      }
    }
  }
  std::vector<FaceLoop*> loops;
  for (CADFace& face : faces)
  {
    for (FaceLoop& l : face.Loops)
    {
      loops.push_back(&l);
    }
  }
  for (FaceLoop* loop : loops)
  {
    const int n = static_cast<int>(loop->Nodes.size());
    for (int s = 0; s < n; ++s)
    {
      LoopSegment& seg = loop->Segments[s];
      const auto it = spanNormals.find({ seg.Edge, seg.Span });
      if (seg.Degenerate || it == spanNormals.end() || it->second.size() < 2)
      {
        continue;
      }
      Vector3 sum = Vector3::Zero();
      bool close = true;
      for (const Vector3& a : it->second)
      {
        sum += a;
        for (const Vector3& b : it->second)
        {
          close = close && a.dot(b) > cosThreshold;
        }
      }
      seg.Tangent = close;
      if (!close || !options.RestoreG1)
      {
        continue;
      }
      // The normal must be perpendicular to the edge cubic's tangent at its midpoint (the same
      // on both sides); orient it along the sum so that all copies agree up to round-off, then
      // compute it from the segment's canonical direction so that they agree bit for bit.
      const LoopNode &a = loop->Nodes[s], &b = loop->Nodes[(s + 1) % n];
      const bool forward = a.GlobalNode <= b.GlobalNode;
      const Vector3 b0 = V3(nodes[forward ? a.GlobalNode : b.GlobalNode]);
      const Vector3 b1 = V3(forward ? seg.Near0 : seg.Near1), b2 = V3(forward ? seg.Near1 : seg.Near0);
      const Vector3 b3 = V3(nodes[forward ? b.GlobalNode : a.GlobalNode]);
      const Vector3 tangent = (b3 + b2 - b1 - b0).normalized();
      Vector3 m = sum - sum.dot(tangent) * tangent;
      if (m.norm() == 0)
      {
        continue;
      }
      seg.MidNormal = P3(m.normalized());
      ++report.SmoothSpans;
    }
  }
  return report;
}

} // namespace ctcad
