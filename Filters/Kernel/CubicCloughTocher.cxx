// SPDX-License-Identifier: GPL-3.0-or-later
#include "CubicCloughTocher.h"

#include "CrossDerivativeRules.h"

#include <cmath>

namespace ctk
{
const char* ToString(Construction c)
{
  switch (c)
  {
    case Construction::CTo:
      return "CTo";
    case Construction::CTi:
      return "CTi";
    case Construction::Fa:
      return "Fa";
    case Construction::FO:
      return "FO";
    case Construction::Ka:
      return "Ka";
    case Construction::MGo:
      return "MGo";
    case Construction::MGi:
      return "MGi";
    case Construction::KaG:
      return "KaG";
  }
  return "Unknown";
}

const char* ToString(BoundaryMode m)
{
  switch (m)
  {
    case BoundaryMode::Perpendicular:
      return "Perpendicular";
    case BoundaryMode::Midpoint:
      return "Midpoint";
    case BoundaryMode::GradientPerpendicular:
      return "GradientPerpendicular";
    case BoundaryMode::GradientToSplitPoint:
      return "GradientToSplitPoint";
  }
  return "Unknown";
}

bool UsesEdgeGradients(const SplineOptions& o)
{
  return o.Method == Construction::MGo || o.Method == Construction::MGi ||
    o.Method == Construction::KaG ||
    ((o.Boundary == BoundaryMode::GradientPerpendicular ||
       o.Boundary == BoundaryMode::GradientToSplitPoint) &&
      o.Method != Construction::CTo);
}

void SerialFor(Id n, const std::function<void(Id, Id)>& body)
{
  body(0, n);
}

namespace
{
inline Vec2 UVOf(const SplineData& d, Id v)
{
  return Vec2(d.UV[2 * v], d.UV[2 * v + 1]);
}
inline Vec3 Row3(const double* a, Id v)
{
  return Vec3(a[3 * v], a[3 * v + 1], a[3 * v + 2]);
}

// Step 2 of one macro-triangle for the constructions whose central points follow from a
// cross-boundary derivative rule (eq. 15 or eq. 25).
class CrossDerivativeStep2
{
public:
  CrossDerivativeStep2(const SplineData& data, const MeshTopology& topo, const SplineOptions& o,
    const std::vector<Vec2>& splitPoints, const std::vector<Vec3>& edgeGradients)
    : Data(data)
    , Topo(topo)
    , Options(o)
    , SplitPoints(splitPoints)
    , EdgeGradients(edgeGradients)
  {
  }

  Vec3 Centre(Id t, int l, const MacroElementIds& ids, const Vec3* points) const
  {
    const int i = l, j = (l + 1) % 3;
    const Id* p = this->Data.Triangles + 3 * t;
    const Vec2 Ui = UVOf(this->Data, p[i]), Uj = UVOf(this->Data, p[j]);
    const Vec2& Z = this->SplitPoints[t];
    const EdgeRows rows{ points[ids.V[i]], points[ids.T[i][j]], points[ids.T[j][i]],
      points[ids.V[j]], points[ids.I1[i]], points[ids.I1[j]] };
    const Id e = this->Topo.TriangleEdges[t][l];
    const Id nb = this->Topo.Neighbor(t, l);

    auto gradientRule = [&](const Vec2& w) {
      return MidEdgeGradientCentre(
        rows, Ui, Uj, Z, this->EdgeGradients[2 * e], this->EdgeGradients[2 * e + 1], w);
    };
    // v_eps along Z Zbar, unless that line is (nearly) parallel to the edge.
    auto splitLine = [&](Vec2& d) {
      d = this->SplitPoints[nb] - Z;
      return std::abs(Cross2(Uj - Ui, d)) > 1e-12 * (Uj - Ui).norm() * d.norm();
    };

    switch (this->Options.Method)
    {
      case Construction::CTo:
        return LinearCrossDerivativeCentre(rows, PerpendicularLambda(Ui, Uj, Z));
      case Construction::MGo:
        return gradientRule(EdgePerpendicular(Ui, Uj));
      case Construction::CTi:
      {
        Vec2 d;
        if (nb >= 0 && splitLine(d))
        {
          return LinearCrossDerivativeCentre(rows, SplitLineLambda(Ui, Uj, Z, this->SplitPoints[nb]));
        }
        break;
      }
      case Construction::MGi:
      {
        Vec2 d;
        if (nb >= 0 && splitLine(d))
        {
          return gradientRule(d);
        }
        break;
      }
      default:
        break;
    }
    switch (this->Options.Boundary)
    {
      case BoundaryMode::Perpendicular:
        return LinearCrossDerivativeCentre(rows, PerpendicularLambda(Ui, Uj, Z));
      case BoundaryMode::Midpoint:
        return LinearCrossDerivativeCentre(rows, 0.5);
      case BoundaryMode::GradientPerpendicular:
        return gradientRule(EdgePerpendicular(Ui, Uj));
      case BoundaryMode::GradientToSplitPoint:
      default:
        return gradientRule(0.5 * (Ui + Uj) - Z);
    }
  }

private:
  const SplineData& Data;
  const MeshTopology& Topo;
  const SplineOptions& Options;
  const std::vector<Vec2>& SplitPoints;
  const std::vector<Vec3>& EdgeGradients;
};
} // namespace

BuildStatus BuildCubicCloughTocher(const SplineData& data, const MeshTopology& topo,
  const SplineOptions& options, CubicSpline& spline, const ParallelFor& parallelFor)
{
  BuildStatus status;
  switch (options.Method)
  {
    case Construction::CTo:
    case Construction::CTi:
    case Construction::MGo:
    case Construction::MGi:
      break;
    default:
      status.Ok = false;
      status.Message = std::string("construction ") + ToString(options.Method) +
        " is not available in this version (available: CTo, CTi, MGo, MGi)";
      return status;
  }
  if (options.Iterations > 0)
  {
    status.Ok = false;
    status.Message = "the IM iteration is not available in this version (Iterations must be 0)";
    return status;
  }
  if (UsesEdgeGradients(options) && !data.EdgeGradients)
  {
    status.Ok = false;
    status.Message = std::string("construction ") + ToString(options.Method) + " with boundary mode " +
      ToString(options.Boundary) + " needs mid-edge gradients";
    return status;
  }

  const Id nV = data.NumberOfVertices, nT = data.NumberOfTriangles;
  const Id nE = static_cast<Id>(topo.Edges.size());
  CubicSplineLayout& layout = spline.Layout;
  layout.NumberOfVertices = nV;
  layout.NumberOfEdges = nE;
  layout.NumberOfTriangles = nT;
  spline.ControlPoints.resize(layout.NumberOfPoints());
  spline.DomainPoints.resize(layout.NumberOfPoints());
  spline.SplitTau.resize(nT);
  std::vector<Vec2> splitPoints(nT);
  Vec3* P = spline.ControlPoints.data();
  Vec2* D = spline.DomainPoints.data();

  // Split points.
  parallelFor(nT, [&](Id begin, Id end) {
    for (Id t = begin; t < end; ++t)
    {
      const Id* p = data.Triangles + 3 * t;
      const Vec2 U0 = UVOf(data, p[0]), U1 = UVOf(data, p[1]), U2 = UVOf(data, p[2]);
      const Vec3 tau = SplitPointBarycentric(options.SplitPoint, U0, U1, U2, Row3(data.F, p[0]),
        Row3(data.F, p[1]), Row3(data.F, p[2]));
      spline.SplitTau[t] = tau;
      splitPoints[t] = tau[0] * U0 + tau[1] * U1 + tau[2] * U2;
    }
  });

  // Step 1, eq. (11): vertices and macro-edge points (each edge once).
  parallelFor(nV, [&](Id begin, Id end) {
    for (Id v = begin; v < end; ++v)
    {
      P[layout.Vertex(v)] = Row3(data.F, v);
      D[layout.Vertex(v)] = UVOf(data, v);
    }
  });
  std::vector<Vec3> edgeGradients(data.EdgeGradients ? 2 * nE : 0);
  parallelFor(nE, [&](Id begin, Id end) {
    for (Id e = begin; e < end; ++e)
    {
      for (int s = 0; s < 2; ++s)
      {
        const Id a = topo.Edges[e][s], b = topo.Edges[e][1 - s];
        const Id id = layout.EdgePoint(topo, e, a);
        P[id] = EdgeControlPoint(
          Row3(data.F, a), Row3(data.Fu, a), Row3(data.Fv, a), UVOf(data, a), UVOf(data, b));
        D[id] = (2.0 * UVOf(data, a) + UVOf(data, b)) / 3.0;
      }
      if (data.EdgeGradients)
      {
        Vec3 gu = Vec3::Zero(), gv = Vec3::Zero();
        int count = 0;
        for (int s = 0; s < 2; ++s)
        {
          const Id t = topo.EdgeTriangles[e][s];
          if (t < 0)
          {
            continue;
          }
          const double* g = data.EdgeGradients + 18 * t + 6 * topo.EdgeLocalIndex[e][s];
          gu += Vec3(g[0], g[1], g[2]);
          gv += Vec3(g[3], g[4], g[5]);
          ++count;
        }
        edgeGradients[2 * e] = gu / count;
        edgeGradients[2 * e + 1] = gv / count;
      }
    }
  });

  // Step 1, eq. (12), then Step 2 and Step 3 (eq. 13-14) per macro-triangle. Step 2 reads only
  // this triangle's points and the neighbours' split points, so one pass suffices.
  const CrossDerivativeStep2 step2(data, topo, options, splitPoints, edgeGradients);
  parallelFor(nT, [&](Id begin, Id end) {
    for (Id t = begin; t < end; ++t)
    {
      const MacroElementIds ids = GetMacroElementIds(layout, topo, data.Triangles, t);
      const Vec3& tau = spline.SplitTau[t];
      ComputeInnerRing1(ids, tau, P);
      for (int l = 0; l < 3; ++l)
      {
        P[ids.C[(l + 2) % 3]] = step2.Centre(t, l, ids, P);
      }
      ComputeInnerRing2AndSplitPoint(ids, tau, P);

      const Id* p = data.Triangles + 3 * t;
      const Vec2 U[3] = { UVOf(data, p[0]), UVOf(data, p[1]), UVOf(data, p[2]) };
      const Vec2& Z = splitPoints[t];
      for (int i = 0; i < 3; ++i)
      {
        D[ids.I1[i]] = (2.0 * U[i] + Z) / 3.0;
        D[ids.I2[i]] = (U[i] + 2.0 * Z) / 3.0;
        D[ids.C[i]] = (U[(i + 1) % 3] + U[(i + 2) % 3] + Z) / 3.0;
      }
      D[ids.S] = Z;
    }
  });
  return status;
}

} // namespace ctk
