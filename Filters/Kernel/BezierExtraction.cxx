// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierExtraction.h"

#include "SplineInput.h"

#include "CrossDerivativeRules.h"

#include <algorithm>

namespace ctk
{
namespace
{
Vec2 UVOf(const SplineData& d, Id v)
{
  return Vec2(d.UV[2 * v], d.UV[2 * v + 1]);
}

// The unit v_eps of an edge carrying mid-edge data, as the construction uses it (up to sign).
Vec2 EdgeDirection(const SplineData& d, const MeshTopology& topo, const SplineOptions& o,
  const std::vector<Vec2>& splitPoints, Id e)
{
  const Vec2 Ua = UVOf(d, topo.Edges[e][0]), Ub = UVOf(d, topo.Edges[e][1]);
  const Id t0 = topo.EdgeTriangles[e][0], t1 = topo.EdgeTriangles[e][1];
  Vec2 v = EdgePerpendicular(Ua, Ub);
  if (o.Method == Construction::MGi && t1 >= 0)
  {
    v = splitPoints[t1] - splitPoints[t0];
  }
  else if (o.Method != Construction::MGo && t1 < 0 &&
    EffectiveBoundaryMode(o) == BoundaryMode::GradientToSplitPoint)
  {
    v = 0.5 * (Ua + Ub) - splitPoints[t0];
  }
  return v.normalized();
}
} // namespace

std::vector<Vec3> DegreesOfFreedom(
  const SplineData& data, const MeshTopology& topo, const BezierExtraction& x)
{
  std::vector<Vec3> dofs(x.NumberOfDofs, Vec3::Zero());
  for (Id v = 0; v < data.NumberOfVertices; ++v)
  {
    dofs[3 * v] = Vec3(data.F + 3 * v);
    dofs[3 * v + 1] = Vec3(data.Fu + 3 * v);
    dofs[3 * v + 2] = Vec3(data.Fv + 3 * v);
  }
  for (Id e = 0; e < static_cast<Id>(x.EdgeDofs.size()); ++e)
  {
    const Id dof = x.EdgeDofs[e];
    if (dof < 0)
    {
      continue;
    }
    // The kernel's mean of the two sides' gradients, projected on v_eps.
    const Vec2& w = x.EdgeDirections[dof - 3 * data.NumberOfVertices];
    Vec3 g = Vec3::Zero();
    int count = 0;
    for (int s = 0; s < 2; ++s)
    {
      const Id t = topo.EdgeTriangles[e][s];
      if (t >= 0)
      {
        const double* eg = EdgeGradientsOf(data, t) + 6 * topo.EdgeLocalIndex[e][s];
        g += w.x() * Vec3(eg) + w.y() * Vec3(eg + 3);
        ++count;
      }
    }
    dofs[dof] = g / count;
  }
  return dofs;
}

namespace
{
// The rows of triangle t's three cells: the local construction over t and the neighbours it
// reads, probed with unit data, three degrees of freedom per build. False where the local
// build fails.
bool ExtractTriangle(const SplineData& data, const MeshTopology& topo, const SplineOptions& options,
  const CubicSpline& real, Id t, BezierExtraction& x)
{
  constexpr int M = BezierExtraction::MaxElementDofs;
  const Id nV = data.NumberOfVertices;
  const bool neighbours = !Info(options.Method).Local;
  const bool boundaryEdges = UsesEdgeGradients(options);
  // The patch: t first, then its neighbours (the only triangles whose data t reads).
  Id patch[4] = { t, -1, -1, -1 };
  int nPatch = 1;
  for (int l = 0; neighbours && l < 3; ++l)
  {
    const Id nb = topo.Neighbor(t, l);
    if (nb >= 0)
    {
      patch[nPatch++] = nb;
    }
  }
  Id vertices[6];
  int nLocal = 0;
  SplineInput probe; // the patch with unit data, one probe per three dofs
  probe.Triangles.resize(3 * nPatch);
  for (int s = 0; s < nPatch; ++s)
  {
    for (int i = 0; i < 3; ++i)
    {
      const Id v = data.Triangles[3 * patch[s] + i];
      const Id* found = std::find(vertices, vertices + nLocal, v);
      if (found == vertices + nLocal)
      {
        vertices[nLocal++] = v;
      }
      probe.Triangles[3 * s + i] = std::find(vertices, vertices + nLocal, v) - vertices;
    }
  }
  // Element degrees of freedom: 3 per patch vertex, then t's edges that carry one.
  Id dofs[M], dofEdge[M];
  int nDofs = 0;
  for (int a = 0; a < nLocal; ++a)
  {
    for (int c = 0; c < 3; ++c)
    {
      dofs[nDofs++] = 3 * vertices[a] + c;
    }
  }
  for (int l = 0; l < 3; ++l)
  {
    const Id e = topo.TriangleEdges[t][l];
    if (x.EdgeDofs[e] >= 0)
    {
      dofEdge[nDofs] = e;
      dofs[nDofs++] = x.EdgeDofs[e];
    }
  }
  probe.UV.resize(2 * nLocal);
  probe.F.resize(3 * nLocal);
  probe.Fu.resize(3 * nLocal);
  probe.Fv.resize(3 * nLocal);
  probe.EdgeGradients.resize(boundaryEdges ? 18 * nPatch : 0);
  probe.SplitTau.resize(nPatch);
  OverwriteVector<Id>& tris = probe.Triangles;
  OverwriteVector<double>&uv = probe.UV, &F = probe.F, &Fu = probe.Fu, &Fv = probe.Fv;
  std::vector<double>& eg = probe.EdgeGradients;
  std::vector<Vec3>& tau = probe.SplitTau;
  for (int a = 0; a < nLocal; ++a)
  {
    uv[2 * a] = data.UV[2 * vertices[a]];
    uv[2 * a + 1] = data.UV[2 * vertices[a] + 1];
  }
  for (int s = 0; s < nPatch; ++s)
  {
    tau[s] = real.SplitTau[patch[s]];
  }
  MeshTopology local;
  if (!BuildMeshTopology(nLocal, nPatch, tris.data(), local).Ok)
  {
    return false;
  }
  const SplineData view = probe.View();
  // Three degrees of freedom per run, one per coordinate (the constructions act on each
  // coordinate alike).
  for (int first = 0; first < nDofs; first += 3)
  {
    std::fill(F.begin(), F.end(), 0.0);
    std::fill(Fu.begin(), Fu.end(), 0.0);
    std::fill(Fv.begin(), Fv.end(), 0.0);
    std::fill(eg.begin(), eg.end(), 0.0);
    for (int c = 0; c < 3 && first + c < nDofs; ++c)
    {
      const Id dof = dofs[first + c];
      if (dof < 3 * nV)
      {
        const int a = static_cast<int>(std::find(vertices, vertices + nLocal, dof / 3) - vertices);
        OverwriteVector<double>& target = dof % 3 == 0 ? F : (dof % 3 == 1 ? Fu : Fv);
        target[3 * a + c] = 1.0;
        continue;
      }
      // Mid-edge gradient g = v_eps on every side of the edge: g . v_eps = 1.
      const Vec2& w = x.EdgeDirections[dof - 3 * nV];
      const Id edge = dofEdge[first + c];
      for (int s = 0; s < nPatch; ++s)
      {
        for (int l = 0; l < 3; ++l)
        {
          if (topo.TriangleEdges[patch[s]][l] == edge)
          {
            eg[18 * s + 6 * l + c] = w.x();
            eg[18 * s + 6 * l + 3 + c] = w.y();
          }
        }
      }
    }
    CubicSpline spline;
    if (!BuildCubicCloughTocher(view, local, options, spline).Ok)
    {
      return false;
    }
    const MacroElementIds ids = GetMacroElementIds(spline.Layout, local, tris.data(), 0);
    for (int k = 0; k < 3; ++k)
    {
      const std::array<Id, 10> net = MicroTriangleNet(ids, k);
      double* op = &x.CellOperators[(3 * t + k) * 10 * M];
      for (int a = 0; a < 10; ++a)
      {
        for (int c = 0; c < 3 && first + c < nDofs; ++c)
        {
          op[a * M + first + c] = spline.ControlPoints[net[a]][c];
        }
      }
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    std::copy(dofs, dofs + nDofs, &x.CellDofs[(3 * t + k) * M]);
  }
  return true;
}

} // namespace

BuildStatus BuildBezierExtraction(const SplineData& data, const MeshTopology& topo,
  const SplineOptions& options, BezierExtraction& x, const ParallelFor& parallelFor)
{
  BuildStatus status;
  if (options.Iterations > 0)
  {
    status.Ok = false;
    status.Message = "Bézier extraction needs a construction without iterations (IM steps and "
                     "fairing rounds couple all elements)";
    return status;
  }
  // The real data fixes the split points (Inc3 depends on positions) and checks the input.
  CubicSpline real;
  status = BuildCubicCloughTocher(data, topo, options, real, parallelFor);
  if (!status.Ok)
  {
    return status;
  }
  const Id nV = data.NumberOfVertices, nT = data.NumberOfTriangles;
  const Id nE = static_cast<Id>(topo.Edges.size());
  std::vector<Vec2> splitPoints(nT);
  for (Id t = 0; t < nT; ++t)
  {
    const Id* p = data.Triangles + 3 * t;
    const Vec3& tau = real.SplitTau[t];
    splitPoints[t] = tau[0] * UVOf(data, p[0]) + tau[1] * UVOf(data, p[1]) + tau[2] * UVOf(data, p[2]);
  }

  // Edges with a degree of freedom.
  const bool allEdges = Info(options.Method).EdgeGradients == EdgeGradientUse::AllEdges;
  const bool boundaryEdges = UsesEdgeGradients(options);
  x.EdgeDofs.assign(nE, -1);
  x.EdgeDirections.clear();
  x.NumberOfDofs = 3 * nV;
  // The gradients of these edges, which DegreesOfFreedom reads, were checked by the build above:
  // it reads every one of them (MGo, MGi: every edge; the others: the boundary edges, where the
  // boundary mode is a gradient mode whenever these edges carry degrees of freedom).
  for (Id e = 0; e < nE; ++e)
  {
    if (allEdges || (boundaryEdges && topo.IsBoundaryEdge(e)))
    {
      x.EdgeDofs[e] = x.NumberOfDofs++;
      x.EdgeDirections.push_back(EdgeDirection(data, topo, options, splitPoints, e));
    }
  }

  constexpr int M = BezierExtraction::MaxElementDofs;
  x.CellDofs.assign(3 * nT * M, -1);
  x.CellOperators.assign(3 * nT * 10 * M, 0.0);
  LowestId firstFailure;
  parallelFor(nT, [&](Id begin, Id end) {
    for (Id t = begin; t < end; ++t)
    {
      if (!ExtractTriangle(data, topo, options, real, t, x))
      {
        firstFailure.Report(t);
      }
    }
  });
  if (firstFailure.Get() >= 0)
  {
    MessageBuilder os;
    os << "Bezier extraction: the local construction around triangle "
       << TriangleId{ firstFailure.Get() } << " failed (its neighbourhood is not a valid mesh)";
    status = os.Failure<BuildStatus>();
  }
  return status;
}

} // namespace ctk
