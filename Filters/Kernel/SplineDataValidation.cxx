// SPDX-License-Identifier: GPL-3.0-or-later
#include "SplineDataValidation.h"

#include "LocalityOrder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <sstream>

namespace ctk
{
namespace
{
BuildStatus Failure(const std::string& message)
{
  BuildStatus status;
  status.Ok = false;
  status.Message = message;
  return status;
}

// The first value of rows x columns that is non-finite or too large, or -1. With nanRows, an
// all-NaN group of nanGroup values means "no value".
Id FirstBadValue(const double* values, Id rows, int columns, int nanGroup = 0)
{
  if (!values)
  {
    return -1;
  }
  for (Id k = 0; k < rows * columns; ++k)
  {
    if (!IsUsableValue(values[k]))
    {
      if (nanGroup > 0 && std::isnan(values[k]))
      {
        const Id g = k - k % nanGroup;
        if (std::all_of(values + g, values + g + nanGroup, [](double x) { return std::isnan(x); }))
        {
          k = g + nanGroup - 1;
          continue;
        }
      }
      return k;
    }
  }
  return -1;
}

BuildStatus UnusableValueFailure(const char* name, IdKind element, Id row, double value)
{
  MessageBuilder os;
  os << "the " << name << " of ";
  if (element == IdKind::Vertex)
  {
    os << "vertex " << VertexId{ row };
  }
  else
  {
    os << "triangle " << TriangleId{ row };
  }
  os << " include " << value;
  os << (std::isfinite(value) ? "; magnitudes must stay below 1e100 (rescale the data)"
                              : ": values must be finite");
  return os.Failure<BuildStatus>();
}

BuildStatus CheckValues(const SplineData& data)
{
  struct Array
  {
    const double* Values;
    Id Rows;
    int Columns, NanGroup;
    const char* Name;
    IdKind Element;
  };
  const Id nV = data.NumberOfVertices, nT = data.NumberOfTriangles;
  constexpr IdKind V = IdKind::Vertex, T = IdKind::Triangle;
  // Not the mid-edge gradients: most constructions read a few of them, and those who read all
  // read each once (UnusableEdgeGradients).
  const Array arrays[] = { { data.UV, nV, 2, 0, "parameter coordinates (u, v)", V },
    { data.F, nV, 3, 0, "positions", V }, { data.Fu, nV, 3, 0, "derivatives d/du", V },
    { data.Fv, nV, 3, 0, "derivatives d/dv", V },
    { data.BoundaryCurvePoints, nT, 18, 6, "boundary curve points", T } };
  for (const Array& a : arrays)
  {
    const Id k = FirstBadValue(a.Values, a.Rows, a.Columns, a.NanGroup);
    if (k >= 0)
    {
      return UnusableValueFailure(a.Name, a.Element, k / a.Columns, a.Values[k]);
    }
  }
  return {};
}

// Given split points must lie inside their triangles: barycentric coordinates that are
// positive and sum to 1.
BuildStatus CheckSplitPoints(const SplineData& data)
{
  for (Id t = 0; data.SplitTau && t < data.NumberOfTriangles; ++t)
  {
    const Vec3& tau = data.SplitTau[t];
    if (!(tau.minCoeff() > 0 && tau.allFinite() && std::abs(tau.sum() - 1) < 1e-9))
    {
      MessageBuilder os;
      os << "the split point of triangle " << TriangleId{ t } << " has barycentric coordinates ("
         << tau.transpose() << "): they must be positive and sum to 1";
      return os.Failure<BuildStatus>();
    }
  }
  return {};
}

} // namespace

BuildStatus EdgeGradientFailure(const SplineData& data, Id t)
{
  const double* row = EdgeGradientsOf(data, t);
  const Id k = std::max<Id>(FirstBadValue(row, 1, 18), 0);
  return UnusableValueFailure("mid-edge gradients", IdKind::Triangle, t, row[k]);
}

BuildStatus CheckDomainSize(const SplineData& data, const ParallelFor& parallelFor, double& diag2)
{
  double lo[2], hi[2]; // the values are finite here
  BoundingBoxUV(data.NumberOfVertices, data.UV, lo, hi, parallelFor);
  diag2 = (Vec2(hi[0], hi[1]) - Vec2(lo[0], lo[1])).squaredNorm();
  if (!(std::sqrt(diag2) >= MinDomainDiagonal))
  {
    std::ostringstream os;
    os << "the parameter domain is too small: its diagonal is " << std::sqrt(diag2)
       << " (at least " << MinDomainDiagonal << " is needed; rescale (u, v))";
    return Failure(os.str());
  }
  return {};
}

BuildStatus DomainFailure(const SplineData& data, const MeshTopology& topology,
  const LowestId& degenerate, const LowestId& folded)
{
  if (degenerate.Get() >= 0)
  {
    const Id t = degenerate.Get();
    const Id* p = data.Triangles + 3 * t;
    MessageBuilder os;
    os << "degenerate parameter triangle: cell " << TriangleId{ t } << " (points "
       << VertexId{ p[0] } << ", " << VertexId{ p[1] } << ", " << VertexId{ p[2] }
       << ") has zero area in (u, v)";
    return os.Failure<BuildStatus>();
  }
  if (folded.Get() >= 0)
  {
    const Id e = folded.Get();
    MessageBuilder os;
    os << "folded parameterisation: triangles " << TriangleId{ topology.EdgeTriangles[e][0] }
       << " and " << TriangleId{ topology.EdgeTriangles[e][1] }
       << " lie on the same side of their shared edge (" << VertexId{ topology.Edges[e][0] }
       << ", " << VertexId{ topology.Edges[e][1] } << ") in (u, v)";
    return os.Failure<BuildStatus>();
  }
  return {};
}

// IsUsableValue as a select on doubles, which the compiler vectorises (a bool reduction, or an
// early exit, stays scalar: a third of a probe's first call on 1e6 triangles).
// These three read arrays of up to hundreds of MB in sequence: ForStreamChunks.
bool AllUsableValues(const double* values, Id n, bool positive)
{
  const double lowest = positive ? 0.0 : -std::numeric_limits<double>::infinity();
  double bad = 0.0;
  ForStreamChunks(values, n, 1, [&](Id begin, Id end) {
    double chunkBad = 0.0; // a local: a reduction into `bad` itself stayed scalar
    for (Id i = begin; i < end; ++i)
    {
      const double x = values[i];
      chunkBad = IsUsableValue(x) && x > lowest ? chunkBad : 1.0; // NaN compares false
    }
    bad = std::max(bad, chunkBad);
  });
  return bad == 0.0;
}

bool AllUsablePairs(const double* uv, Id n, Vec2& lo, Vec2& hi)
{
  Vec2 l = Vec2::Constant(std::numeric_limits<double>::infinity()), h = -l;
  double bad = 0.0;
  ForStreamChunks(uv, n, 2, [&](Id begin, Id end) {
    Vec2 chunkLo = l, chunkHi = h; // locals, as above
    double chunkBad = 0.0;
    for (Id i = begin; i < end; ++i)
    {
      const Vec2 x(uv[2 * i], uv[2 * i + 1]);
      chunkLo = chunkLo.cwiseMin(x);
      chunkHi = chunkHi.cwiseMax(x);
      chunkBad = IsUsableValue(x.x()) && IsUsableValue(x.y()) ? chunkBad : 1.0;
    }
    l = chunkLo;
    h = chunkHi;
    bad = std::max(bad, chunkBad);
  });
  lo = l;
  hi = h;
  return bad == 0.0;
}

// An id is in range when neither id nor last - id has its top bit set (unsigned, wrapping;
// last: nPoints - 1, or the type's largest id), so one OR over both tests them all, in the
// ids' own width (32-bit ids widened to 64 bits stay scalar).
template <typename IdT>
bool AllIdsInRange(const IdT* ids, Id n, Id nPoints)
{
  using U = std::make_unsigned_t<IdT>;
  const U last = static_cast<U>(std::min<std::uint64_t>(static_cast<std::uint64_t>(nPoints - 1),
    static_cast<std::uint64_t>(std::numeric_limits<IdT>::max())));
  U any = 0;
  ForStreamChunks(ids, n, 1, [&](Id begin, Id end) {
    U chunkAny = 0; // a local, as above
    for (Id i = begin; i < end; ++i)
    {
      const U id = static_cast<U>(ids[i]);
      chunkAny |= id | static_cast<U>(last - id);
    }
    any |= chunkAny;
  });
  return (any >> (8 * sizeof(U) - 1)) == 0;
}

template bool AllIdsInRange<int>(const int*, Id, Id);
template bool AllIdsInRange<long>(const long*, Id, Id);
template bool AllIdsInRange<long long>(const long long*, Id, Id);

BuildStatus ValidateSplineValues(
  const SplineData& data, const MeshTopology& topology, const ParallelFor& parallelFor, double& diag2)
{
  if (data.NumberOfVertices <= 0 || data.NumberOfTriangles <= 0 || !data.Triangles || !data.UV ||
    !data.F || !data.Fu || !data.Fv)
  {
    return Failure("empty spline input: vertices, triangles, (u, v), positions and both "
                   "derivatives are needed");
  }
  if (static_cast<Id>(topology.TriangleEdges.size()) != data.NumberOfTriangles)
  {
    return Failure("the mesh topology was not built from these triangles");
  }
  BuildStatus status = data.ValuesChecked ? BuildStatus() : CheckValues(data);
  if (status.Ok)
  {
    status = CheckSplitPoints(data);
  }
  if (status.Ok)
  {
    status = CheckDomainSize(data, parallelFor, diag2);
  }
  return status;
}

BuildStatus ValidateSplineData(const SplineData& data, const MeshTopology& topology,
  const std::vector<Id>& order, const ParallelFor& parallelFor)
{
  double diag2 = 0.0;
  const BuildStatus status = ValidateSplineValues(data, topology, parallelFor, diag2);
  if (!status.Ok)
  {
    return status;
  }
  // The lowest degenerate triangle and folded edge, found in the locality order.
  LowestId degenerate, folded;
  AreaSigns signs;
  ForTrianglesInOrder(parallelFor, data.NumberOfTriangles, order, [&](Id t) {
    const double area2 = SignedAreaUV(data, t);
    if (IsDegenerateArea(area2, diag2))
    {
      degenerate.Report(t);
    }
    signs.Report(area2);
  });
  if (degenerate.Get() < 0 && signs.FoldsPossible(topology))
  {
    ForEdgesInOrder(parallelFor, topology, order, [&](Id e) {
      if (IsFoldedEdge(data, topology, e))
      {
        folded.Report(e);
      }
    });
  }
  return DomainFailure(data, topology, degenerate, folded);
}

BuildStatus CheckFiniteControlPoints(const OverwriteVector<Vec3>& points,
  const MeshTopology& topology, const Id* triangles, Id numberOfVertices, int pointsPerEdge,
  int pointsPerTriangle)
{
  const auto bad = std::find_if(
    points.begin(), points.end(), [](const Vec3& p) { return !p.allFinite(); });
  if (bad == points.end())
  {
    return {};
  }
  const Id i = static_cast<Id>(bad - points.begin());
  const Id nE = static_cast<Id>(topology.Edges.size());
  const Id nT = static_cast<Id>(topology.TriangleEdges.size());
  Id t = -1;
  if (i < numberOfVertices)
  {
    const Id* end = triangles + 3 * nT;
    t = static_cast<Id>(std::find(triangles, end, i) - triangles) / 3;
  }
  else if (i < numberOfVertices + pointsPerEdge * nE)
  {
    t = topology.EdgeTriangles[(i - numberOfVertices) / pointsPerEdge][0];
  }
  else
  {
    t = (i - numberOfVertices - pointsPerEdge * nE) / pointsPerTriangle;
  }
  MessageBuilder os;
  os << "the construction produced a non-finite control point (" << bad->transpose()
     << ") in the macro-element of triangle " << TriangleId{ t }
     << ": the data there is degenerate or too large";
  return os.Failure<BuildStatus>();
}

} // namespace ctk
