// SPDX-License-Identifier: GPL-3.0-or-later
#include "CubicCloughTocher.h"

#include "SplineDataValidation.h"

#include "CrossDerivativeRules.h"
#include "KashyapFairing.h"
#include "LargeArrays.h"
#include "LocalityOrder.h"
#include "MacroEdgeCubicPrecision.h"
#include "MicroEdgeC2Minimisation.h"
#include "RuleA.h"

#include <cmath>
#include <limits>
#include <mutex>

namespace ctk
{
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

namespace
{
bool IsGradientMode(BoundaryMode m)
{
  return m == BoundaryMode::GradientPerpendicular || m == BoundaryMode::GradientToSplitPoint;
}

} // namespace

BoundaryMode EffectiveBoundaryMode(const SplineOptions& o)
{
  // KaG is Ka with mid-edge gradients on boundary edges; MGi, which has them on every edge,
  // uses them there too.
  const ConstructionInfo& c = Info(o.Method);
  const bool gradientsByDefault = c.EdgeGradients == EdgeGradientUse::BoundaryEdges ||
    (c.EdgeGradients == EdgeGradientUse::AllEdges && !c.Local);
  if (gradientsByDefault && !IsGradientMode(o.Boundary))
  {
    return BoundaryMode::GradientToSplitPoint;
  }
  return o.Boundary;
}

bool UsesEdgeGradients(const SplineOptions& o)
{
  const ConstructionInfo& c = Info(o.Method);
  return c.EdgeGradients == EdgeGradientUse::AllEdges ||
    (!c.Local && IsGradientMode(EffectiveBoundaryMode(o)));
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

// |a x b| > 1e-12 |a| |b|, compared squared while the squares can neither overflow nor underflow
// (the two square roots and their latency were a tenth of the pass of Step 2).
bool NotNearlyParallel(const Vec2& a, const Vec2& b)
{
  const double c = Cross2(a, b), a2 = a.squaredNorm(), b2 = b.squaredNorm();
  if (a2 > 1e-120 && a2 < 1e120 && b2 > 1e-120 && b2 < 1e120)
  {
    return c * c > 1e-24 * a2 * b2;
  }
  return std::abs(c) > 1e-12 * std::sqrt(a2) * std::sqrt(b2);
}

// Whether the 19 control points of a macro-element are finite, by S alone: S is a sum of the
// I2 with finite weights (tau), each I2 of an I1 and two C, each I1 of a V and two T, and every
// one of the 18 others enters that chain. Products and sums of finite numbers with inf or NaN
// are never finite, so one non-finite point makes S non-finite (and so does an overflow of S
// itself, which the caller's full check then finds harmless). Step 3 must have run on the
// current points. This needs IEEE infinities and NaN, which -ffinite-math-only (and -ffast-math)
// would let the compiler assume away.
#if defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "CTSplines' finiteness checks need IEEE arithmetic: do not build with -ffinite-math-only"
#endif
static_assert(std::numeric_limits<double>::is_iec559, "IEEE 754 doubles");
bool AllFinite(const MacroElementIds& ids, const Vec3* P)
{
  return P[ids.S].allFinite();
}

// Shared state of one construction run and the per-edge and per-triangle steps.
class Builder
{
public:
  Builder(const SplineData& data, const MeshTopology& topo, const SplineOptions& options,
    CubicSpline& spline, const ParallelFor& parallelFor, const std::vector<Id>& order,
    double diag2)
    : Data(data)
    , Topo(topo)
    , Options(options)
    , Boundary(EffectiveBoundaryMode(options))
    , Spline(spline)
    , For(parallelFor)
    , Order(order)
    , Diag2(diag2)
    , ScanRanges(options.ScanRanges && options.Iterations == 0 &&
        options.Method != Construction::Kashyap && order.empty())
  {
  }

  /// Runs the construction on data that passed ValidateSplineValues; its first passes check the
  /// triangles and edges (ValidateSplineData's other checks) on the way.
  BuildStatus Run();

private:
  MacroElementIds Ids(Id t) const
  {
    return GetMacroElementIds(this->Spline.Layout, this->Topo, this->Data.Triangles, t);
  }
  Vec2 U(Id t, int i) const { return UVOf(this->Data, this->Data.Triangles[3 * t + i]); }

  // Micro-triangle of t (ids) at local edge l, over (U_l, U_{l+1}, Z), from the current points.
  void MicroNet(Id t, const MacroElementIds& ids, int l, Vec3* P, Vec2* A) const
  {
    const std::array<Id, 10> net = MicroTriangleNet(ids, MicroTriangleAtEdge(l));
    for (int a = 0; a < 10; ++a)
    {
      P[a] = this->Spline.ControlPoints[net[a]];
    }
    this->MicroDomain(t, l, A);
  }
  void MicroDomain(Id t, int l, Vec2* A) const
  {
    A[0] = this->U(t, l);
    A[1] = this->U(t, (l + 1) % 3);
    A[2] = this->SplitPoints[t];
  }
  // The ids are computed once per triangle by the callers: they gather from the topology.
  Vec3& Centre(const MacroElementIds& ids, int l)
  {
    return this->Spline.ControlPoints[ids.C[(l + 2) % 3]];
  }

  void SplitPointsAndStep1();
  BuildStatus CheckFinite() const
  {
    return CheckFiniteControlPoints(this->Spline.ControlPoints, this->Topo, this->Data.Triangles,
      this->Data.NumberOfVertices, 2, CubicSplineLayout::PointsPerTriangle);
  }
  // Eq. (12) and the domain points of the triangle-owned control points of triangle t.
  void InnerRing1(Id t, const MacroElementIds& ids);
  // Step 2 at the edges of t: the one-sided rules, and the edge-based ones of the edges whose
  // first triangle is t (for both sides).
  void Step2Centres(Id t, const MacroElementIds& ids);
  void Step3();
  // The mid-edge gradient (f_u, f_v) of edge e: the mean of its triangles' (SplineData), taken
  // where it is used (boundary edges only, for most constructions), and checked there: a triangle
  // giving an unusable value is reported to BadGradients.
  void MidEdgeGradient(Id e, Vec3& gu, Vec3& gv);
  // Whether the main pass prefetches mid-edge gradients: read on every edge (MGo, MGi), in place
  // through a row map (the input's order, scattered in the visit order), the triangles visited
  // t after t.
  bool GradientRowsAreScattered() const
  {
    return Info(this->Options.Method).EdgeGradients == EdgeGradientUse::AllEdges &&
      this->Data.EdgeGradients && this->Data.EdgeGradientRows && this->Order.empty();
  }
  // Asks for the rows of mid-edge gradients (144 bytes: three cache lines) of triangle t
  // and its neighbours, which Step 2 at t reads.
  void PrefetchEdgeGradients(Id t) const
  {
    if (t >= this->Data.NumberOfTriangles)
    {
      return;
    }
    for (int l = -1; l < 3; ++l)
    {
      const Id s = l < 0 ? t : this->Topo.Neighbor(t, l);
      if (s >= 0)
      {
        const double* row = EdgeGradientsOf(this->Data, s);
        PrefetchRead(row);
        PrefetchRead(row + 8);
        PrefetchRead(row + 17);
      }
    }
  }
  // Asks for what the main pass gathers at triangle t that Step 1's passes wrote long before:
  // its vertices' and edges' control points, (u, v) rows and edges' triangles (perf put the
  // pass's stalls on these loads; CTi and CTo 2-3 % faster at 1e6 triangles). Its neighbours'
  // split points too made CTi 1 % slower.
  void PrefetchGathers(Id t) const
  {
    if (t >= this->Data.NumberOfTriangles)
    {
      return;
    }
    const Id* p = this->Data.Triangles + 3 * t;
    const Vec3* P = this->Spline.ControlPoints.data();
    const CubicSplineLayout& layout = this->Spline.Layout;
    for (int l = 0; l < 3; ++l)
    {
      const Id e = this->Topo.TriangleEdges[t][l];
      PrefetchRead(P + layout.Vertex(p[l]));
      PrefetchRead(this->Data.UV + 2 * p[l]);
      PrefetchRead(P + layout.EdgePoints(e));
      PrefetchAhead(P + layout.EdgePoints(e), 2 * sizeof(Vec3) - 1); // 48 bytes: maybe two lines
      PrefetchRead(this->Topo.EdgeTriangles.data() + e);
    }
  }
  // Central point from a cross-boundary derivative rule (eq. 15 or 25).
  Vec3 CrossDerivativeCentre(Id t, const MacroElementIds& ids, int l);
  // body(t) per triangle, in parallel, in the locality order.
  template <typename Body>
  void ForTriangles(Body&& body)
  {
    ForTrianglesInOrder(this->For, this->Data.NumberOfTriangles, this->Order, body);
  }
  // body(i) for items i in [0, n) (vertices, edges or triangles) in parallel, in their order;
  // with ScanRanges, each block's points (pointsPerItem per item, from point firstPoint +
  // pointsPerItem * i) scanned into the spline's ranges right after body ran on it (the pass that
  // writes their last values), while they are in the cache; with ScanBlockRanges, each block's
  // ranges kept as well.
  template <typename Body>
  void ForItemsScanningRanges(Id n, Id firstPoint, Id pointsPerItem, Body&& body);
  // Per interior edge: body(e, t0, l0, t1, l1), in parallel, in the locality order.
  template <typename Body>
  void ForInteriorEdges(Body&& body);
  // The macro-patch of the edge-based rules' first step (Fa's Q, or none).
  std::array<Vec3, 10> InitialMacroPatch(const MacroElementIds& ids) const;
  // Both central points at the interior edge (t0, l0) = (t1, l1) by an edge-based rule.
  void InitialEdgeCentres(
    Id t0, const MacroElementIds& ids0, const std::array<Vec3, 10>& macro0, int l0, Id t1, int l1);
  void MinimiseC2AcrossMacroEdges();
  void RestoreC1AcrossMacroEdges();

  const SplineData& Data;
  const MeshTopology& Topo;
  const SplineOptions& Options;
  const BoundaryMode Boundary;
  CubicSpline& Spline;
  const ParallelFor& For;
  // Triangles in a locality order (empty: their own); every value is still written at its
  // place in the input's numbering, so the result does not depend on it.
  const std::vector<Id>& Order;
  const double Diag2; // the (u, v) domain's squared diagonal
  // SplineOptions::ScanRanges, where nothing writes the points after the pass that scans them
  // (no IM steps, no fairing) and every item's points are written in their order.
  const bool ScanRanges;
  std::mutex RangesMerge;
  LowestId Degenerate, Folded, BadGradients;
  AreaSigns Signs;
  OverwriteVector<Vec2> SplitPoints;
};

static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Vec2) == 2 * sizeof(double),
  "points packed as the VTK arrays that adopt them");

// 640 points: their control and domain points (25 KB) are still in the first-level cache.
constexpr Id RangeScanPoints = 640;

template <typename Body>
void Builder::ForItemsScanningRanges(Id n, Id firstPoint, Id pointsPerItem, Body&& body)
{
  if (!this->ScanRanges)
  {
    this->For(n, [&](Id begin, Id end) {
      for (Id i = begin; i < end; ++i)
      {
        body(i);
      }
    });
    return;
  }
  const double* P =
    reinterpret_cast<const double*>(this->Spline.ControlPoints.data()) + 3 * firstPoint;
  const double* D =
    reinterpret_cast<const double*>(this->Spline.DomainPoints.data()) + 2 * firstPoint;
  const Id block = RangeScanPoints / pointsPerItem;
  const bool keepBlocks = this->Options.ScanBlockRanges;
  this->For(n, [&](Id begin, Id end) {
    PointRangeScan points(3), domain(2);
    PointRanges pointsMerged(3), domainMerged(2); // of the blocks kept
    std::vector<PointBlockRanges> blocks;
    for (Id b = begin; b < end; b += block)
    {
      const Id e = std::min(end, b + block);
      for (Id i = b; i < e; ++i)
      {
        body(i);
      }
      const Id first = pointsPerItem * b, count = pointsPerItem * (e - b);
      if (keepBlocks) // a scan of its own per block: its lanes reduced for each
      {
        points = PointRangeScan(3);
        domain = PointRangeScan(2);
      }
      points.Add(P + 3 * first, count);
      domain.Add(D + 2 * first, count);
      if (keepBlocks)
      {
        blocks.push_back({ first + firstPoint, count, points.Result(), domain.Result() });
        pointsMerged.Merge(blocks.back().Points);
        domainMerged.Merge(blocks.back().Domain);
      }
    }
    std::lock_guard<std::mutex> lock(this->RangesMerge);
    this->Spline.ControlPointRanges.Merge(keepBlocks ? pointsMerged : points.Result());
    this->Spline.DomainPointRanges.Merge(keepBlocks ? domainMerged : domain.Result());
    this->Spline.BlockRanges.insert(this->Spline.BlockRanges.end(), blocks.begin(), blocks.end());
  });
}

BuildStatus Builder::Run()
{
  // Set also where no block is scanned: the ranges of no points, which the VTK layer does not store.
  this->Spline.ControlPointRanges = PointRanges(this->ScanRanges ? 3 : 0);
  this->Spline.DomainPointRanges = PointRanges(this->ScanRanges ? 2 : 0);
  this->Spline.BlockRanges.clear();
  this->SplitPointsAndStep1();
  const BuildStatus domain = DomainFailure(this->Data, this->Topo, this->Degenerate, this->Folded);
  if (!domain.Ok)
  {
    this->Spline = CubicSpline(); // nothing half-built is left, as when the values fail
    return domain;
  }
  // Step 2 reads the Step 1 points and split points of a triangle and its neighbours only, so it
  // runs in the pass of eq. (12), the triangle's points still in cache. An edge-based rule sets
  // both central points of its edge, from the edge's first triangle: Step 3 then needs a second
  // pass (a triangle's other central points may be its neighbours'). Every control point is
  // checked finite in the pass of Step 3: every one belongs to a triangle, but unused vertices',
  // which are the positions (checked finite).
  Vec3* P = this->Spline.ControlPoints.data();
  const bool edgeBased = Info(this->Options.Method).EdgeBased;
  std::atomic<bool> nonFinite{ false };
  auto step3 = [&](Id t, const MacroElementIds& ids) {
    ComputeInnerRing2AndSplitPoint(ids, this->Spline.SplitTau[t], P);
    if (!AllFinite(ids, P))
    {
      nonFinite.store(true, std::memory_order_relaxed);
    }
  };
  const bool prefetchGradients = this->GradientRowsAreScattered();
  const bool prefetchGathers = this->Order.empty(); // t + PrefetchDistance is visited next
  const auto mainPass = [&](Id t) {
    if (prefetchGradients)
    {
      this->PrefetchEdgeGradients(t + PrefetchDistance);
    }
    if (prefetchGathers)
    {
      this->PrefetchGathers(t + PrefetchDistance);
    }
    const MacroElementIds ids = this->Ids(t);
    this->InnerRing1(t, ids);
    this->Step2Centres(t, ids);
    if (!edgeBased)
    {
      step3(t, ids);
    }
  };
  const auto pass = [&](bool last, const auto& body) { // last: it writes Step 3's points
    if (last && this->ScanRanges)
    {
      this->ForItemsScanningRanges(
        this->Data.NumberOfTriangles, this->Spline.Layout.TrianglePoint(0, 0),
        CubicSplineLayout::PointsPerTriangle, body);
    }
    else
    {
      this->ForTriangles(body);
    }
  };
  pass(!edgeBased, mainPass);
  if (this->BadGradients.Get() >= 0) // read in Step 2 only
  {
    this->Spline = CubicSpline();
    return EdgeGradientFailure(this->Data, this->BadGradients.Get());
  }
  if (edgeBased)
  {
    pass(true, [&](Id t) { step3(t, this->Ids(t)); });
  }
  if (this->Options.Method == Construction::Kashyap)
  {
    for (int round = 0; round < this->Options.Iterations; ++round)
    {
      this->MinimiseC2AcrossMacroEdges(); // exterior fairing, eq. (1)-(3)
      this->Step3();
      this->ForTriangles([&](Id t) {
        KashyapInteriorFairing(this->Ids(t), this->Spline.SplitTau[t], P); // eq. (4)-(6)
      });
      this->Step3();
    }
    this->RestoreC1AcrossMacroEdges(); // C1 smoothing
    this->Step3();
    return this->CheckFinite();
  }
  for (int step = 0; step < this->Options.Iterations; ++step)
  {
    this->MinimiseC2AcrossMacroEdges(); // IM: Step 2 by Fa's rule on the current points
    this->Step3();
  }
  // Every control point was seen finite on the way, or they are all read again.
  return this->Options.Iterations == 0 && !nonFinite.load() ? BuildStatus() : this->CheckFinite();
}

void Builder::SplitPointsAndStep1()
{
  const SplineData& d = this->Data;
  const Id nV = d.NumberOfVertices, nT = d.NumberOfTriangles;
  const Id nE = static_cast<Id>(this->Topo.Edges.size());
  CubicSplineLayout& layout = this->Spline.Layout;
  layout.NumberOfVertices = nV;
  layout.NumberOfEdges = nE;
  layout.NumberOfTriangles = nT;
  // Every entry is written below, in parallel loops (first touch spread over the threads).
  ResizeForOverwrite(this->Spline.ControlPoints, layout.NumberOfPoints());
  ResizeForOverwrite(this->Spline.DomainPoints, layout.NumberOfPoints());
  ResizeForOverwrite(this->Spline.SplitTau, nT);
  ResizeForOverwrite(this->SplitPoints, nT);
  Vec3* P = this->Spline.ControlPoints.data();
  Vec2* D = this->Spline.DomainPoints.data();

  // ValidateSplineData's triangle and edge checks run in these passes, which read the same
  // points (a pass of their own cost a tenth of the construction). The fold check gathers every
  // edge's opposite vertices: it is skipped where no edge can fold (AreaSigns).
  this->ForTriangles([&](Id t) {
    const double area2 = SignedAreaUV(d, t);
    if (IsDegenerateArea(area2, this->Diag2))
    {
      this->Degenerate.Report(t);
    }
    this->Signs.Report(area2);
    const Id* p = d.Triangles + 3 * t;
    const Vec3 tau = d.SplitTau ? d.SplitTau[t]
                                : SplitPointBarycentric(this->Options.SplitPoint, this->U(t, 0),
                                    this->U(t, 1), this->U(t, 2), Row3(d.F, p[0]),
                                    Row3(d.F, p[1]), Row3(d.F, p[2]));
    this->Spline.SplitTau[t] = tau;
    this->SplitPoints[t] = tau[0] * this->U(t, 0) + tau[1] * this->U(t, 1) + tau[2] * this->U(t, 2);
  });

  // Eq. (11): vertices and macro-edge points, each edge once (their ranges scanned on the way).
  static_assert(CubicSplineLayout().Vertex(1) == 1, "vertex v's point is point v");
  this->ForItemsScanningRanges(nV, 0, 1, [&](Id v) {
    P[layout.Vertex(v)] = Row3(d.F, v);
    D[layout.Vertex(v)] = UVOf(d, v);
  });
  const bool checkFolds = this->Signs.FoldsPossible(this->Topo);
  const auto edgePoints = [&](Id e) {
    if (checkFolds && IsFoldedEdge(d, this->Topo, e))
    {
      this->Folded.Report(e);
    }
    for (int s = 0; s < 2; ++s)
    {
      const Id a = this->Topo.Edges[e][s], b = this->Topo.Edges[e][1 - s];
      const Id id = layout.EdgePoint(this->Topo, e, a);
      P[id] = EdgeControlPoint(Row3(d.F, a), Row3(d.Fu, a), Row3(d.Fv, a), UVOf(d, a), UVOf(d, b));
      D[id] = (2.0 * UVOf(d, a) + UVOf(d, b)) / 3.0;
    }
    const Id t = this->Topo.EdgeTriangles[e][0];
    if (d.BoundaryCurvePoints && this->Topo.EdgeTriangles[e][1] < 0 && t >= 0)
    {
      const int l = this->Topo.EdgeLocalIndex[e][0];
      const double* c = d.BoundaryCurvePoints + 18 * t + 6 * l;
      if (!std::isnan(c[0]))
      {
        // c[0..2] is near the edge's first point in the triangle, p_l.
        const Id first = d.Triangles[3 * t + l];
        for (int s = 0; s < 2; ++s)
        {
          const Id a = this->Topo.Edges[e][s];
          P[layout.EdgePoint(this->Topo, e, a)] = Row3(c, a == first ? 0 : 1);
        }
      }
    }
  };
  if (this->ScanRanges) // edge e's points are points nV + 2e and nV + 2e + 1
  {
    this->ForItemsScanningRanges(nE, nV, 2, edgePoints);
  }
  else
  {
    ForEdgesInOrder(this->For, this->Topo, this->Order, edgePoints);
  }
}

void Builder::MidEdgeGradient(Id e, Vec3& gu, Vec3& gv)
{
  gu = Vec3::Zero();
  gv = Vec3::Zero();
  int count = 0;
  for (int s = 0; s < 2; ++s)
  {
    const Id t = this->Topo.EdgeTriangles[e][s];
    if (t < 0)
    {
      continue;
    }
    const double* g = EdgeGradientsOf(this->Data, t) + 6 * this->Topo.EdgeLocalIndex[e][s];
    if (UnusableEdgeGradients(g))
    {
      this->BadGradients.Report(t);
    }
    gu += Vec3(g[0], g[1], g[2]);
    gv += Vec3(g[3], g[4], g[5]);
    ++count;
  }
  gu /= count;
  gv /= count;
}

void Builder::InnerRing1(Id t, const MacroElementIds& ids)
{
  Vec2* D = this->Spline.DomainPoints.data();
  ComputeInnerRing1(ids, this->Spline.SplitTau[t], this->Spline.ControlPoints.data());
  const Vec2& Z = this->SplitPoints[t];
  for (int i = 0; i < 3; ++i)
  {
    D[ids.I1[i]] = (2.0 * this->U(t, i) + Z) / 3.0;
    D[ids.I2[i]] = (this->U(t, i) + 2.0 * Z) / 3.0;
    D[ids.C[i]] = (this->U(t, (i + 1) % 3) + this->U(t, (i + 2) % 3) + Z) / 3.0;
  }
  D[ids.S] = Z;
}

Vec3 Builder::CrossDerivativeCentre(Id t, const MacroElementIds& ids, int l)
{
  const Vec3* P = this->Spline.ControlPoints.data();
  const int i = l, j = (l + 1) % 3;
  const Vec2 Ui = this->U(t, i), Uj = this->U(t, j);
  const Vec2& Z = this->SplitPoints[t];
  const EdgeRows rows{ P[ids.V[i]], P[ids.T[i][j]], P[ids.T[j][i]], P[ids.V[j]], P[ids.I1[i]],
    P[ids.I1[j]] };
  const Id e = this->Topo.TriangleEdges[t][l];
  const Id nb = this->Topo.Neighbor(t, l);
  auto gradientRule = [&](const Vec2& w) {
    Vec3 gu, gv;
    this->MidEdgeGradient(e, gu, gv);
    return MidEdgeGradientCentre(rows, Ui, Uj, Z, gu, gv, w);
  };
  // v_eps along Z Zbar (CTi, MGi), unless that line is (nearly) parallel to the edge.
  const bool alongSplitLine = (this->Options.Method == Construction::CTi ||
                                this->Options.Method == Construction::MGi) && nb >= 0;
  const Vec2 d = alongSplitLine ? Vec2(this->SplitPoints[nb] - Z) : Vec2::Zero();
  const bool splitLine = alongSplitLine && NotNearlyParallel(Uj - Ui, d);
  switch (this->Options.Method)
  {
    case Construction::CTo:
      return LinearCrossDerivativeCentre(rows, PerpendicularLambda(Ui, Uj, Z));
    case Construction::MGo:
      return gradientRule(EdgePerpendicular(Ui, Uj));
    case Construction::CTi:
      if (splitLine)
      {
        return LinearCrossDerivativeCentre(rows, SplitLineLambda(Ui, Uj, Z, this->SplitPoints[nb]));
      }
      break;
    case Construction::MGi:
      if (splitLine)
      {
        return gradientRule(d);
      }
      break;
    default:
      break;
  }
  switch (this->Boundary)
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

template <typename Body>
void Builder::ForInteriorEdges(Body&& body)
{
  ForEdgesInOrder(this->For, this->Topo, this->Order, [&](Id e) {
    const auto& et = this->Topo.EdgeTriangles[e];
    if (et[1] >= 0)
    {
      const auto& el = this->Topo.EdgeLocalIndex[e];
      body(e, et[0], int(el[0]), et[1], int(el[1]));
    }
  });
}

void Builder::Step2Centres(Id t, const MacroElementIds& ids)
{
  const bool edgeBased = Info(this->Options.Method).EdgeBased;
  std::array<Vec3, 10> macro; // t's macro-patch, formed once for its edges
  bool haveMacro = false;
  for (int l = 0; l < 3; ++l)
  {
    const Id e = this->Topo.TriangleEdges[t][l];
    const auto& et = this->Topo.EdgeTriangles[e];
    if (!edgeBased || et[1] < 0)
    {
      this->Centre(ids, l) = this->CrossDerivativeCentre(t, ids, l);
    }
    else if (et[0] == t && this->Topo.EdgeLocalIndex[e][0] == l)
    {
      if (!haveMacro)
      {
        macro = this->InitialMacroPatch(ids);
        haveMacro = true;
      }
      this->InitialEdgeCentres(t, ids, macro, l, et[1], this->Topo.EdgeLocalIndex[e][1]);
    }
  }
}

std::array<Vec3, 10> Builder::InitialMacroPatch(const MacroElementIds& ids) const
{
  // Fa: the quadratic-precision macro-patch, eq. (18); FO, Ka, KaG and Kashyap's start: its
  // central point is the unknown (MacroEdgeQ ignores it).
  std::array<Vec3, 10> macro = MacroNet(ids, this->Spline.ControlPoints.data(), Vec3::Zero());
  if (this->Options.Method == Construction::Fa)
  {
    macro[CubicCentre] = QuadraticPrecisionQ(macro.data());
  }
  return macro;
}

void Builder::InitialEdgeCentres(
  Id t0, const MacroElementIds& ids0, const std::array<Vec3, 10>& macro0, int l0, Id t1, int l1)
{
  const MacroElementIds ids1 = this->Ids(t1);
  const std::array<Vec3, 10> macro1 = this->InitialMacroPatch(ids1);
  const Vec3& tau0 = this->Spline.SplitTau[t0];
  const Vec3& tau1 = this->Spline.SplitTau[t1];
  if (this->Options.Method == Construction::Fa)
  {
    // Eq. (19)-(21) on the quadratic-precision macro-patches subdivided at Z and Zbar.
    Vec2 AM[3];
    this->MicroDomain(t0, l0, AM);
    const Vec3 x = Barycentric(AM[0], AM[1], AM[2], this->SplitPoints[t1]);
    const bool sameDirection = this->Data.Triangles[3 * t1 + l1] == this->Data.Triangles[3 * t0 + l0];
    FaMicroEdgeCentres({ macro0.data(), l0, tau0 }, { macro1.data(), l1, tau1 }, sameDirection, x,
      this->Centre(ids0, l0), this->Centre(ids1, l1));
    return;
  }
  // FO (eq. 22), Ka and KaG (eq. 23); Kashyap's scheme starts from FO's cubic precision.
  const Vec2 A[3] = { this->U(t0, 0), this->U(t0, 1), this->U(t0, 2) };
  const Vec2 B[3] = { this->U(t1, 0), this->U(t1, 1), this->U(t1, 2) };
  const MacroEdgeRule rule = Info(this->Options.Method).EdgeRule;
  SharedCubicEdge edge;
  const Vec3 Q = MacroEdgeQ(rule, macro0.data(), A, macro1.data(), B, edge);
  const Vec3 Qbar = CubicRuleARow1(macro0.data(), Q, edge.A, edge.B, edge.X); // C1 (eq. 6)
  // C = the macro-patch blossomed at the micro-triangle's vertices (its centre): b(U_l, U_l+1, Z).
  this->Centre(ids0, l0) = CubicRuleARow1(macro0.data(), Q, l0, (l0 + 1) % 3, tau0);
  this->Centre(ids1, l1) = CubicRuleARow1(macro1.data(), Qbar, l1, (l1 + 1) % 3, tau1);
}

void Builder::MinimiseC2AcrossMacroEdges()
{
  this->ForInteriorEdges([&](Id, Id t0, int l0, Id t1, int l1) {
    Vec3 PM[10], PMbar[10];
    Vec2 AM[3], AMbar[3];
    const MacroElementIds ids0 = this->Ids(t0), ids1 = this->Ids(t1);
    this->MicroNet(t0, ids0, l0, PM, AM);
    this->MicroNet(t1, ids1, l1, PMbar, AMbar);
    MinimiseMicroEdgeC2Jump(PM, AM, PMbar, AMbar, this->Centre(ids0, l0), this->Centre(ids1, l1));
  });
}

void Builder::RestoreC1AcrossMacroEdges()
{
  this->ForInteriorEdges([&](Id, Id t0, int l0, Id t1, int l1) {
    Vec3 PM[10];
    Vec2 AM[3], AMbar[3];
    const MacroElementIds ids0 = this->Ids(t0);
    this->MicroNet(t0, ids0, l0, PM, AM);
    this->MicroDomain(t1, l1, AMbar);
    RestoreMacroEdgeC1(PM, AM, AMbar, this->Centre(ids0, l0), this->Centre(this->Ids(t1), l1));
  });
}

void Builder::Step3()
{
  Vec3* P = this->Spline.ControlPoints.data();
  this->ForTriangles(
    [&](Id t) { ComputeInnerRing2AndSplitPoint(this->Ids(t), this->Spline.SplitTau[t], P); });
}
} // namespace

BuildStatus BuildCubicCloughTocher(const SplineData& data, const MeshTopology& topo,
  const SplineOptions& options, CubicSpline& spline, const ParallelFor& parallelFor)
{
  BuildStatus status;
  if (options.Iterations < 0)
  {
    status.Ok = false;
    status.Message = "Iterations must be >= 0";
    return status;
  }
  if (!IsConstruction(static_cast<int>(options.Method)) || Info(options.Method).Degree != 3)
  {
    status.Ok = false;
    status.Message = std::string("construction ") + ToString(options.Method) +
      " is not a cubic construction (BuildCloughTocher builds every degree)";
    return status;
  }
  if (UsesEdgeGradients(options) && !data.EdgeGradients)
  {
    status.Ok = false;
    status.Message = std::string("construction ") + ToString(options.Method) +
      " with boundary mode " + ToString(EffectiveBoundaryMode(options)) + " needs mid-edge gradients";
    return status;
  }
  // Ids are in range once the topology matches the triangles (checked by BuildMeshTopology).
  const bool ordered = options.LocalityOrder && data.Triangles && data.UV &&
    static_cast<Id>(topo.TriangleEdges.size()) == data.NumberOfTriangles;
  const std::vector<Id> order = ordered
    ? TriangleLocalityOrder(
        data.NumberOfVertices, data.NumberOfTriangles, data.Triangles, data.UV, parallelFor)
    : std::vector<Id>();
  double diag2 = 0.0;
  status = ValidateSplineValues(data, topo, parallelFor, diag2);
  if (!status.Ok)
  {
    return status;
  }
  return Builder(data, topo, options, spline, parallelFor, order, diag2).Run();
}

} // namespace ctk
