// SPDX-License-Identifier: GPL-3.0-or-later
#include "CADStitch.h"

#include "CubicMacroElement.h"

#include <array>
#include <map>
#include <unordered_map>

namespace ctcad
{
namespace
{
/// A macro-edge of the merged grid: the merged ids of its cubic's control points, from its end
/// with the lower (first point, first inner point). Two macro-edges are one only if they share
/// all four: at a pole, the interior macro-edges from two copies of the pole node to one mesh
/// point join the same two nodes but are different curves.
std::array<ctk::Id, 4> MergedEdgeKey(ctk::Id a, ctk::Id ta, ctk::Id tb, ctk::Id b)
{
  return std::make_pair(b, tb) < std::make_pair(a, ta) ? std::array<ctk::Id, 4>{ b, tb, ta, a }
                                                       : std::array<ctk::Id, 4>{ a, ta, tb, b };
}

/// How a merged macro-edge is used: by how many macro-triangles, and whether every use is a
/// boundary span of one B-rep edge (the merge keys boundary T points by B-rep edge, so they all
/// name the same one) or some use is a face's interior edge.
struct MacroEdgeUses
{
  int Uses = 0;
  ctk::Id BRepEdge = -1;
  bool Interior = false;
};

/// The merge's tables across faces.
struct MergeTables
{
  std::unordered_map<ctk::Id, ctk::Id> NodePoint;
  std::map<SpanKey, ctk::Id> EdgePoint;
  std::map<std::array<ctk::Id, 4>, MacroEdgeUses> MacroEdgeUse;
  /// B-rep edge -> (last face counted, number of faces with a boundary span on it).
  std::unordered_map<ctk::Id, std::pair<int, int>> BRepEdgeFaces;
};

/// The B-rep edge of the face's boundary edge e.
ctk::Id BoundaryBRepEdge(const SampledFace& face, const ctk::MeshTopology& topo, ctk::Id e)
{
  return face.BRepEdge[3 * topo.EdgeTriangles[e][0] + topo.EdgeLocalIndex[e][0]];
}

/// The merged id of every control point of one face (new points appended to `points`): its
/// vertices, then its boundary T points, then the rest, in the face's order.
std::vector<ctk::Id> MergeFacePoints(const SampledFace& face, const FaceSpline& fs,
  MergeTables& tables, std::vector<ctk::Vec3>& points)
{
  const ctk::CubicSpline& spline = fs.Spline;
  const ctk::MeshTopology& topo = fs.Topology;
  const ctk::OverwriteVector<ctk::Vec3>& cp = spline.ControlPoints;
  std::vector<ctk::Id> map(cp.size(), -1);
  auto next = [&points]() { return static_cast<ctk::Id>(points.size()); };
  for (ctk::Id v = 0; v < spline.Layout.NumberOfVertices; ++v)
  {
    auto it = tables.NodePoint.emplace(face.GlobalNode[v], next());
    if (it.second)
    {
      points.push_back(cp[v]);
    }
    map[v] = it.first->second;
  }
  for (ctk::Id e = 0; e < static_cast<ctk::Id>(topo.Edges.size()); ++e)
  {
    if (!topo.IsBoundaryEdge(e))
    {
      continue;
    }
    const ctk::Id a = topo.Edges[e][0], b = topo.Edges[e][1];
    const ctk::Id brep = BoundaryBRepEdge(face, topo, e);
    for (const auto& nearFar : { std::make_pair(a, b), std::make_pair(b, a) })
    {
      const ctk::Id id = spline.Layout.EdgePoint(topo, e, nearFar.first);
      auto it = tables.EdgePoint.emplace(
        SpanKey{ brep, face.GlobalNode[nearFar.first], face.GlobalNode[nearFar.second] }, next());
      if (it.second)
      {
        points.push_back(cp[id]);
      }
      map[id] = it.first->second;
    }
  }
  for (std::size_t i = 0; i < map.size(); ++i)
  {
    if (map[i] < 0)
    {
      map[i] = next();
      points.push_back(cp[i]);
    }
  }
  return map;
}

/// Counts the uses of face f's macro-edges on the merged grid (a macro-edge is used by its
/// face's triangles at it, and by other faces' only where they share its points) and the faces
/// on each B-rep edge.
void CountEdgeUses(int f, const SampledFace& face, const FaceSpline& fs,
  const std::vector<ctk::Id>& map, MergeTables& tables)
{
  const ctk::MeshTopology& topo = fs.Topology;
  for (ctk::Id e = 0; e < static_cast<ctk::Id>(topo.Edges.size()); ++e)
  {
    const ctk::Id a = topo.Edges[e][0], b = topo.Edges[e][1];
    const ctk::Id ta = fs.Spline.Layout.EdgePoint(topo, e, a);
    const ctk::Id tb = fs.Spline.Layout.EdgePoint(topo, e, b);
    if (IsCollapsedEdge(fs.Spline, a, ta, tb, b))
    {
      continue;
    }
    MacroEdgeUses& use = tables.MacroEdgeUse[MergedEdgeKey(map[a], map[ta], map[tb], map[b])];
    if (!topo.IsBoundaryEdge(e))
    {
      use.Uses += 2;
      use.Interior = true;
      continue;
    }
    use.Uses += 1;
    use.BRepEdge = BoundaryBRepEdge(face, topo, e);
    std::pair<int, int>& faces =
      tables.BRepEdgeFaces.emplace(use.BRepEdge, std::make_pair(-1, 0)).first->second;
    if (faces.first != f)
    {
      faces = { f, faces.second + 1 };
    }
  }
}

/// Appends the face's Bézier triangles (micro-triangle k of macro-triangle t is cell 3 t + k of
/// the face) with their merged point ids.
void AppendCells(int f, const SampledFace& face, const FaceSpline& fs,
  const std::vector<ctk::Id>& map, StitchedSurface& surface)
{
  static constexpr std::array<int, 10> vtkOrder = ctk::VtkBezierTriangleOrderOf<3>();
  const ctk::Id nT = fs.Spline.Layout.NumberOfTriangles;
  for (ctk::Id t = 0; t < nT; ++t)
  {
    const ctk::MacroElementIds ids =
      ctk::GetMacroElementIds(fs.Spline.Layout, fs.Topology, face.Input.Triangles.data(), t);
    for (int k = 0; k < 3; ++k)
    {
      const std::array<ctk::Id, 10> net = ctk::MicroTriangleNet(ids, k);
      for (int a = 0; a < 10; ++a)
      {
        surface.Cells.push_back(map[net[vtkOrder[a]]]);
      }
      surface.FaceIds.push_back(f);
      surface.MacroTriangles.push_back(t);
      surface.MicroTriangles.push_back(static_cast<signed char>(k));
    }
  }
  surface.NumberOfMacroTriangles += nT;
}
} // namespace

bool IsCollapsedEdge(const ctk::CubicSpline& spline, ctk::Id a, ctk::Id ta, ctk::Id tb, ctk::Id b)
{
  const ctk::OverwriteVector<ctk::Vec3>& cp = spline.ControlPoints;
  return cp[ta] == cp[a] && cp[tb] == cp[a] && cp[b] == cp[a];
}

void StitchFaces(const std::vector<SampledFace>& faces, const std::vector<FaceSpline>& splines,
  StitchedSurface& surface)
{
  surface = StitchedSurface();
  std::size_t points = 0, cells = 0;
  for (const FaceSpline& fs : splines)
  {
    points += fs.Spline.ControlPoints.size();
    cells += 3 * static_cast<std::size_t>(fs.Spline.Layout.NumberOfTriangles);
  }
  surface.Points.reserve(points);
  surface.Cells.reserve(10 * cells);
  surface.FaceIds.reserve(cells);
  surface.MacroTriangles.reserve(cells);
  surface.MicroTriangles.reserve(cells);
  MergeTables tables;
  for (std::size_t f = 0; f < faces.size(); ++f)
  {
    const std::vector<ctk::Id> map =
      MergeFacePoints(faces[f], splines[f], tables, surface.Points);
    CountEdgeUses(static_cast<int>(f), faces[f], splines[f], map, tables);
    AppendCells(static_cast<int>(f), faces[f], splines[f], map, surface);
  }
  for (const auto& edge : tables.MacroEdgeUse)
  {
    const MacroEdgeUses& use = edge.second;
    surface.FreeEdges += use.Uses == 1;
    surface.NonManifoldEdges += use.Uses > 2;
    surface.ExtraNonManifoldEdges += use.Uses > 2 &&
      (use.Interior || tables.BRepEdgeFaces.at(use.BRepEdge).second <= 2);
  }
}

} // namespace ctcad
