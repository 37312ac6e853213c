// SPDX-License-Identifier: GPL-3.0-or-later
#include "QuarticCloughTocher.h"

#include "SplineDataValidation.h"

#include "AffineLeastSquares.h"
#include "InnerEdgeC1Smoothing.h"
#include "LargeArrays.h"
#include "RuleA.h"

#include <algorithm>
#include <limits>
#include <string>

namespace ctk
{
namespace
{
// Canonical indices (exponents of P1, P2, S) of the points the quartic steps move.
const int C2Index = BezierIndex(4, 2, 2); // c2, the free macro-edge point
const int Row1A = BezierIndex(4, 2, 1);   // l7
const int Row1B = BezierIndex(4, 1, 2);   // l8
const int Row2Mid = BezierIndex(4, 1, 1); // l4

// Triangle-owned slots: S, inner edge i at m = 1..3, interior (2,1,1), (1,2,1), (1,1,2) of
// micro-triangle k.
Id SlotS(const QuarticSplineLayout& L, Id t)
{
  return L.TriangleBase(t);
}
Id SlotInnerEdge(const QuarticSplineLayout& L, Id t, int i, int m)
{
  return L.TriangleBase(t) + 1 + 3 * i + (m - 1);
}
Id SlotInterior(const QuarticSplineLayout& L, Id t, int k, int which)
{
  return L.TriangleBase(t) + 10 + 3 * k + which;
}

// Rule A barycentric coordinates of B's vertices (with the last repeated) w.r.t. A.
void TieArguments(const Vec2* A, const Vec2* B, const int* which, int count, Vec3* args)
{
  for (int a = 0; a < count; ++a)
  {
    args[a] = Barycentric(A[0], A[1], A[2], B[which[a]]);
  }
}

// The two micro-triangles at an interior macro-edge: left L over (P1, P2, S), right R over its own
// vertex order with S' last.
struct EdgeNets
{
  std::array<Id, 15> LIds, RIds;
  Vec3 L[15], R[15];
  Vec2 AL[3], AR[3];
};

// Eq. (7): l7, l8, r7, r8 from the middle C1 conditions (row 1) and the outer C2 conditions
// (row 2), a square system (the outer C1 conditions hold by the vertex data).
void ExteriorFairingRow1(EdgeNets& n)
{
  Vec3 X[4];
  auto residuals = [&](const Vec3* x, Vec3* out) {
    n.L[Row1A] = x[0];
    n.L[Row1B] = x[1];
    n.R[Row1A] = x[2];
    n.R[Row1B] = x[3];
    RuleAResiduals(4, n.L, n.AL, n.R, n.AR, 1, out);
    Vec3 row2[3];
    RuleAResiduals(4, n.L, n.AL, n.R, n.AR, 2, row2);
    out[4] = row2[0];
    out[5] = row2[2];
  };
  SolveAffineSystem<4>(residuals, 6, X);
  n.L[Row1A] = X[0];
  n.L[Row1B] = X[1];
  n.R[Row1A] = X[2];
  n.R[Row1B] = X[3];
}

// R's l4-type point tied to L by the middle C2 condition, eq. (8).
void Row2TieArguments(const EdgeNets& n, Vec3* args)
{
  const int which[4] = { 0, 1, 2, 2 };
  TieArguments(n.AL, n.AR, which, 4, args);
}

// Eq. (11): l4 minimising the C3 residuals (row 3), r4 tied by eq. (8).
void ExteriorFairingRow2(EdgeNets& n)
{
  auto residuals = [&](const Vec3& x, Vec3* out) {
    n.L[Row2Mid] = x;
    RuleAResiduals(4, n.L, n.AL, n.R, n.AR, 3, out);
  };
  n.L[Row2Mid] = SolveAffineResiduals(residuals, 2);
  Vec3 args[4];
  Row2TieArguments(n, args);
  n.R[Row2Mid] = Blossom(4, n.L, args);
}

// Section 4.2, eq. (12)-(15): c2 such that, after eq. (7) and moving l4, r4 least onto eq. (8),
// the C3 residuals are smallest.
void AdjustBoundaryPoint(EdgeNets& n)
{
  const EdgeNets original = n;
  const Vec3 l4 = n.L[Row2Mid], r4 = n.R[Row2Mid];
  Vec3 args[4];
  Row2TieArguments(n, args);
  auto residuals = [&](const Vec3& c2, Vec3* out) {
    n.L[C2Index] = c2;
    n.R[C2Index] = c2;
    ExteriorFairingRow1(n);
    Vec3 x = l4, xbar = r4;
    MoveLeastOntoTie(4, n.L, Row2Mid, args, x, xbar);
    n.R[Row2Mid] = xbar;
    RuleAResiduals(4, n.L, n.AL, n.R, n.AR, 3, out);
  };
  const Vec3 c2 = SolveAffineResiduals(residuals, 2);
  n = original; // only c2 moves in this stage
  n.L[C2Index] = c2;
  n.R[C2Index] = c2;
}

// Eq. (7) divides by the barycentric coordinates v, w of S' w.r.t. (S, P1, P2) and v', w' of S
// w.r.t. (S', P2, P1): when S' is nearly on the line S P1 or S P2 (irregular meshes), the
// fairing of that edge is skipped rather than blown up.
constexpr double MinimumEdgeBarycentric = 0.1;

bool WellConditioned(const EdgeNets& n)
{
  const Vec3 b = Barycentric(n.AL[0], n.AL[1], n.AL[2], n.AR[2]);
  const Vec3 bbar = Barycentric(n.AR[0], n.AR[1], n.AR[2], n.AL[2]);
  return std::min({ std::abs(b[0]), std::abs(b[1]), std::abs(bbar[0]), std::abs(bbar[1]) }) >=
    MinimumEdgeBarycentric;
}

class QuarticBuilder
{
public:
  QuarticBuilder(const SplineData& data, const MeshTopology& topo, QuarticSpline& spline,
    const ParallelFor& parallelFor)
    : Data(data)
    , Topo(topo)
    , Spline(spline)
    , For(parallelFor)
  {
  }

  void DegreeRaise(const CubicSpline& cubic);
  template <typename Step>
  void ForInteriorEdges(Step&& step);
  void SmoothC1();

private:
  std::array<Id, 15> Net(Id t, int k) const
  {
    return QuarticMicroNet(this->Spline.Layout, this->Topo, this->Data.Triangles, t, k);
  }
  Vec2 U(Id t, int i) const
  {
    const Id v = this->Data.Triangles[3 * t + i];
    return Vec2(this->Data.UV[2 * v], this->Data.UV[2 * v + 1]);
  }

  const SplineData& Data;
  const MeshTopology& Topo;
  QuarticSpline& Spline;
  const ParallelFor& For;
};

void QuarticBuilder::DegreeRaise(const CubicSpline& cubic)
{
  const Id nV = this->Data.NumberOfVertices, nT = this->Data.NumberOfTriangles;
  const Id nE = static_cast<Id>(this->Topo.Edges.size());
  QuarticSplineLayout& L = this->Spline.Layout;
  L.NumberOfVertices = nV;
  L.NumberOfEdges = nE;
  L.NumberOfTriangles = nT;
  ResizeForOverwrite(this->Spline.ControlPoints, L.NumberOfPoints());
  ResizeForOverwrite(this->Spline.DomainPoints, L.NumberOfPoints());
  this->Spline.SplitTau = cubic.SplitTau;
  Vec3* P = this->Spline.ControlPoints.data();
  Vec2* D = this->Spline.DomainPoints.data();
  // Every point is written by the micro-triangles that contain it, with the same value (degree
  // raising of a shared row uses that row only); shared vertex and edge points are written by
  // their owners alone to keep the passes race-free.
  this->For(nV, [&](Id b, Id e) {
    for (Id v = b; v < e; ++v)
    {
      P[v] = cubic.ControlPoints[cubic.Layout.Vertex(v)];
      D[v] = cubic.DomainPoints[cubic.Layout.Vertex(v)];
    }
  });
  this->For(nE, [&](Id b, Id e) {
    for (Id edge = b; edge < e; ++edge)
    {
      const Id a = this->Topo.Edges[edge][0], c = this->Topo.Edges[edge][1];
      const Vec3 Va = cubic.ControlPoints[a], Vc = cubic.ControlPoints[c];
      const Vec3 Tac = cubic.ControlPoints[cubic.Layout.EdgePoint(this->Topo, edge, a)];
      const Vec3 Tca = cubic.ControlPoints[cubic.Layout.EdgePoint(this->Topo, edge, c)];
      const Vec3 q[3] = { (Va + 3.0 * Tac) / 4.0, (Tac + Tca) / 2.0, (3.0 * Tca + Vc) / 4.0 };
      for (int m = 1; m <= 3; ++m)
      {
        const Id id = L.EdgePoint(this->Topo, edge, a, m);
        P[id] = q[m - 1];
        D[id] = ((4.0 - m) * cubic.DomainPoints[a] + m * cubic.DomainPoints[c]) / 4.0;
      }
    }
  });
  const std::vector<std::array<int, 3>> exps = BezierExponents(4);
  this->For(nT, [&](Id b, Id e) {
    for (Id t = b; t < e; ++t)
    {
      const MacroElementIds cubicIds = GetMacroElementIds(cubic.Layout, this->Topo, this->Data.Triangles, t);
      const Vec3& tau = cubic.SplitTau[t];
      const Vec2 Z = tau[0] * this->U(t, 0) + tau[1] * this->U(t, 1) + tau[2] * this->U(t, 2);
      for (int k = 0; k < 3; ++k)
      {
        const std::array<Id, 10> c = MicroTriangleNet(cubicIds, k);
        Vec3 cubicNet[10], quartic[15];
        for (int a = 0; a < 10; ++a)
        {
          cubicNet[a] = cubic.ControlPoints[c[a]];
        }
        ElevateDegree(3, cubicNet, quartic);
        const std::array<Id, 15> ids = this->Net(t, k);
        const Vec2 A0 = this->U(t, (k + 1) % 3), A1 = this->U(t, (k + 2) % 3);
        for (int a = 0; a < 15; ++a)
        {
          if (exps[a][2] == 0)
          {
            continue; // macro-edge row: written per edge
          }
          P[ids[a]] = quartic[a];
          D[ids[a]] = (exps[a][0] * A0 + exps[a][1] * A1 + exps[a][2] * Z) / 4.0;
        }
      }
    }
  });
}

template <typename Step>
void QuarticBuilder::ForInteriorEdges(Step&& step)
{
  Vec3* P = this->Spline.ControlPoints.data();
  this->For(static_cast<Id>(this->Topo.Edges.size()), [&](Id b, Id e) {
    for (Id edge = b; edge < e; ++edge)
    {
      const auto& et = this->Topo.EdgeTriangles[edge];
      if (et[1] < 0)
      {
        continue;
      }
      const auto& el = this->Topo.EdgeLocalIndex[edge];
      EdgeNets n;
      n.LIds = this->Net(et[0], (el[0] + 2) % 3);
      n.RIds = this->Net(et[1], (el[1] + 2) % 3);
      for (int a = 0; a < 15; ++a)
      {
        n.L[a] = P[n.LIds[a]];
        n.R[a] = P[n.RIds[a]];
      }
      const Id ts[2] = { et[0], et[1] };
      Vec2* doms[2] = { n.AL, n.AR };
      for (int s = 0; s < 2; ++s)
      {
        const Vec3& tau = this->Spline.SplitTau[ts[s]];
        doms[s][0] = this->U(ts[s], el[s]);
        doms[s][1] = this->U(ts[s], (el[s] + 1) % 3);
        doms[s][2] = tau[0] * this->U(ts[s], 0) + tau[1] * this->U(ts[s], 1) + tau[2] * this->U(ts[s], 2);
      }
      if (!WellConditioned(n))
      {
        continue; // eq. (7) would divide by a vanishing barycentric coordinate
      }
      step(n);
      // Only points specific to this edge change: c2, l4, l7, l8, r4, r7, r8.
      for (int a : { C2Index, Row1A, Row1B, Row2Mid })
      {
        P[n.LIds[a]] = n.L[a];
        P[n.RIds[a]] = n.R[a];
      }
    }
  });
}

void QuarticBuilder::SmoothC1()
{
  Vec3* P = this->Spline.ControlPoints.data();
  this->For(this->Data.NumberOfTriangles, [&](Id b, Id e) {
    for (Id t = b; t < e; ++t)
    {
      SmoothInnerEdgesC1(4, this->Spline.SplitTau[t], [&](int k) { return this->Net(t, k); }, P);
    }
  });
}
} // namespace

std::array<Id, 15> QuarticMicroNet(
  const QuarticSplineLayout& layout, const MeshTopology& topo, const Id* triangles, Id t, int k)
{
  const int i = (k + 1) % 3, j = (k + 2) % 3; // local edge i joins U_i, U_j
  const Id* p = triangles + 3 * t;
  const Id e = topo.TriangleEdges[t][i];
  std::array<Id, 15> ids;
  int idx = 0;
  for (int r = 0; r <= 4; ++r)
  {
    const int a = 4 - r;
    for (int c = 0; c <= r; ++c, ++idx)
    {
      const int b = r - c;
      if (c == 0)
      {
        ids[idx] = a == 4 ? p[i] : (b == 4 ? p[j] : layout.EdgePoint(topo, e, p[i], b));
      }
      else if (a == 0 && b == 0)
      {
        ids[idx] = SlotS(layout, t);
      }
      else if (b == 0)
      {
        ids[idx] = SlotInnerEdge(layout, t, i, c);
      }
      else if (a == 0)
      {
        ids[idx] = SlotInnerEdge(layout, t, j, c);
      }
      else
      {
        ids[idx] = SlotInterior(layout, t, k, c == 2 ? 2 : (a == 2 ? 0 : 1));
      }
    }
  }
  return ids;
}

BuildStatus BuildQuarticCloughTocher(const SplineData& data, const MeshTopology& topo,
  const SplineOptions& options, QuarticSpline& spline, const ParallelFor& parallelFor,
  const QuarticObserver& observer)
{
  SplineOptions start = options;
  start.Method = Info(Construction::Quartic).StartsFrom; // FO
  start.Iterations = 0;
  start.ScanRanges = false; // the cubic's points are not the quartic's
  CubicSpline cubic;
  BuildStatus status = BuildCubicCloughTocher(data, topo, start, cubic, parallelFor);
  if (!status.Ok)
  {
    return status;
  }
  QuarticBuilder builder(data, topo, spline, parallelFor);
  builder.DegreeRaise(cubic);
  auto report = [&](QuarticStage s, int round) {
    if (observer)
    {
      observer(s, round, spline);
    }
  };
  report(QuarticStage::DegreeRaised, 0);
  // Fig. 11 converges on regular meshes; on irregular ones the coupling of exterior fairing and
  // C1 smoothing can amplify each round's change. A round whose change exceeds the previous
  // one's is undone and the iteration stops (reported in status.Message).
  OverwriteVector<Vec3> before;
  double previousChange = std::numeric_limits<double>::infinity();
  // Changes at round-off level (exact data: the rounds move nothing) never count as growth.
  double scale = 0.0;
  for (const Vec3& p : spline.ControlPoints)
  {
    scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  const double roundOff = 1e-12 * scale;
  for (int round = 1; round <= options.Iterations; ++round)
  {
    before = spline.ControlPoints;
    builder.ForInteriorEdges(AdjustBoundaryPoint);
    report(QuarticStage::BoundaryAdjusted, round);
    builder.ForInteriorEdges([](EdgeNets& n) {
      ExteriorFairingRow1(n);
      ExteriorFairingRow2(n);
    });
    report(QuarticStage::ExteriorFaired, round);
    builder.SmoothC1();
    double change = 0.0;
    for (size_t p = 0; p < before.size(); ++p)
    {
      change = std::max(change, (spline.ControlPoints[p] - before[p]).norm());
    }
    if (change > std::max(previousChange, roundOff))
    {
      spline.ControlPoints.swap(before);
      status.Message = "the quartic fairing diverges on this mesh: stopped after " +
        std::to_string(round - 1) + " of " + std::to_string(options.Iterations) + " rounds";
      report(QuarticStage::Smoothed, round - 1);
      break;
    }
    previousChange = change;
    report(QuarticStage::Smoothed, round);
  }
  const BuildStatus finite = CheckFiniteControlPoints(spline.ControlPoints, topo, data.Triangles,
    data.NumberOfVertices, 3, QuarticSplineLayout::PointsPerTriangle);
  return finite.Ok ? status : finite;
}

} // namespace ctk
