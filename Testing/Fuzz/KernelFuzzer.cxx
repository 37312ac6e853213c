// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target of the kernel (Filters/Kernel): bytes -> a parametrised triangle mesh with
// every optional array and every option of every construction, then the topology, the cubic or
// quartic spline, the Bézier extraction, the parameter locator and point-to-mesh distances.
// A failed status is a valid answer; a crash, a sanitizer report, a hang, an Ok status with
// non-finite output or ids out of range is a finding.
//
// Input layout (make_seed_corpus.py writes it; values as in FuzzInput.h):
//   construction (byte % 10; 9 = quartic), split point (% 3), boundary mode (% 4),
//   iterations (% 4), flags (bit 0 EdgeGradients, 1 BoundaryCurvePoints, 2 SplitTau,
//   3 chunked ParallelFor (bit 7: chunks of 3, else 1), 4 Bézier extraction, 5 locator,
//   6 distance), #V (% 64), #T (% 96),
//   3 #T vertex ids (byte % (#V + 1), 255 = -1),
//   values: UV (2 #V), F, Fu, Fv (3 #V each), then EdgeGradients (18 #T), BoundaryCurvePoints
//   (18 #T), SplitTau (3 #T) when flagged, then #Q (byte % 16) queries of 3 values each.
#include "FuzzInput.h"

#include "BezierExtraction.h"
#include "CubicCloughTocher.h"
#include "MeshTopology.h"
#include "ParameterLocator.h"
#include "PointToMeshDistance.h"
#include "QuarticCloughTocher.h"

#include <algorithm>
#include <vector>

namespace
{
using namespace ctsplines_fuzz;
using ctk::Id;
using ctk::Vec2;
using ctk::Vec3;

struct Mesh
{
  Id NumberOfVertices = 0;
  std::vector<Id> Triangles;
  std::vector<double> UV, F, Fu, Fv, EdgeGradients, BoundaryCurvePoints;
  std::vector<Vec3> SplitTau;
  std::vector<Vec3> Queries;

  Id NumberOfTriangles() const { return static_cast<Id>(this->Triangles.size() / 3); }
  Vec2 UVPoint(Id v) const { return Vec2(this->UV[2 * v], this->UV[2 * v + 1]); }
};

std::vector<double> Values(FuzzInput& in, std::size_t n)
{
  std::vector<double> values(n);
  for (double& x : values)
  {
    x = in.Value();
  }
  return values;
}

Mesh ReadMesh(FuzzInput& in, std::uint8_t flags)
{
  Mesh mesh;
  mesh.NumberOfVertices = in.Choice(64);
  const Id nt = in.Choice(96);
  const Id nv = mesh.NumberOfVertices;
  mesh.Triangles.resize(3 * nt);
  for (Id& id : mesh.Triangles)
  {
    const std::uint8_t b = in.Byte();
    id = b == 255 ? -1 : b % (nv + 1);
  }
  mesh.UV = Values(in, 2 * nv);
  mesh.F = Values(in, 3 * nv);
  mesh.Fu = Values(in, 3 * nv);
  mesh.Fv = Values(in, 3 * nv);
  if (in.Flag(flags, 0))
  {
    mesh.EdgeGradients = Values(in, 18 * nt);
  }
  if (in.Flag(flags, 1))
  {
    mesh.BoundaryCurvePoints = Values(in, 18 * nt);
  }
  if (in.Flag(flags, 2))
  {
    for (Id t = 0; t < nt; ++t)
    {
      const double a = in.Value(), b = in.Value();
      mesh.SplitTau.emplace_back(a, b, 1.0 - a - b);
    }
  }
  const int nq = in.Choice(16);
  for (int q = 0; q < nq; ++q)
  {
    const double x = in.Value(), y = in.Value(), z = in.Value();
    mesh.Queries.emplace_back(x, y, z);
  }
  return mesh;
}

ctk::SplineData MakeData(const Mesh& mesh)
{
  ctk::SplineData data;
  data.NumberOfVertices = mesh.NumberOfVertices;
  data.NumberOfTriangles = mesh.NumberOfTriangles();
  data.Triangles = mesh.Triangles.data();
  data.UV = mesh.UV.data();
  data.F = mesh.F.data();
  data.Fu = mesh.Fu.data();
  data.Fv = mesh.Fv.data();
  data.EdgeGradients = mesh.EdgeGradients.empty() ? nullptr : mesh.EdgeGradients.data();
  data.BoundaryCurvePoints =
    mesh.BoundaryCurvePoints.empty() ? nullptr : mesh.BoundaryCurvePoints.data();
  data.SplitTau = mesh.SplitTau.empty() ? nullptr : mesh.SplitTau.data();
  return data;
}

/// The adjacency BuildMeshTopology promises: every local edge's edge lists its triangle.
bool CheckTopology(const ctk::MeshTopology& topo, Id nv, Id nt)
{
  const Id ne = static_cast<Id>(topo.Edges.size());
  if (static_cast<Id>(topo.TriangleEdges.size()) != nt ||
    static_cast<Id>(topo.EdgeTriangles.size()) != ne ||
    static_cast<Id>(topo.EdgeLocalIndex.size()) != ne)
  {
    Finding("topology: array sizes", ne);
    return false;
  }
  for (Id e = 0; e < ne; ++e)
  {
    const auto& edge = topo.Edges[e];
    const auto& tris = topo.EdgeTriangles[e];
    if (edge[0] < 0 || edge[0] >= edge[1] || edge[1] >= nv || tris[0] < 0 || tris[0] >= nt ||
      tris[1] >= nt)
    {
      Finding("topology: edge out of range", e);
      return false;
    }
  }
  for (Id t = 0; t < nt; ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      const Id e = topo.TriangleEdges[t][l];
      if (e < 0 || e >= ne || (topo.EdgeTriangles[e][0] != t && topo.EdgeTriangles[e][1] != t))
      {
        Finding("topology: triangle edge not listing its triangle", t);
        return false;
      }
    }
  }
  return true;
}

ctk::ParallelFor ChunkedFor(int chunk)
{
  return [chunk](Id n, const std::function<void(Id, Id)>& body) {
    for (Id begin = 0; begin < n; begin += chunk)
    {
      body(begin, std::min<Id>(n, begin + chunk));
    }
  };
}

/// Bit for bit (NaN equals NaN: a NaN is reported by CheckSpline, not as a split dependence).
bool SameBits(const ctk::OverwriteVector<Vec3>& a, const ctk::OverwriteVector<Vec3>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

template <typename Spline>
void CheckSpline(const Spline& spline, Id nt)
{
  if (static_cast<Id>(spline.ControlPoints.size()) != spline.Layout.NumberOfPoints() ||
    spline.DomainPoints.size() != spline.ControlPoints.size() ||
    static_cast<Id>(spline.SplitTau.size()) != nt)
  {
    Finding("spline Ok with wrong array sizes", static_cast<long long>(nt));
    return;
  }
  RequireFinite(spline.ControlPoints, "spline Ok with a non-finite control point");
  RequireFinite(spline.DomainPoints, "spline Ok with a non-finite domain point");
  RequireFinite(spline.SplitTau, "spline Ok with a non-finite split point");
}

/// Builds the spline with `build` (cubic or quartic); with a chunk size, builds it again split in
/// chunks and requires the same control points. Returns whether the build succeeded.
template <typename Spline, typename Build>
bool RunConstructionWith(const Build& build, const char* name, Id nt, int chunk)
{
  Spline spline, again;
  const auto status = build(spline, ctk::ParallelFor(ctk::SerialFor));
  Trace(name, status.Ok, status.Message);
  if (!status.Ok)
  {
    return false;
  }
  CheckSpline(spline, nt);
  if (chunk > 0 && build(again, ChunkedFor(chunk)).Ok &&
    !SameBits(again.ControlPoints, spline.ControlPoints))
  {
    Finding("spline depends on the parallel split", chunk);
  }
  return true;
}

bool RunConstruction(const ctk::SplineData& data, const ctk::MeshTopology& topo,
  const ctk::SplineOptions& options, bool quartic, int chunk)
{
  if (quartic)
  {
    return RunConstructionWith<ctk::QuarticSpline>(
      [&](ctk::QuarticSpline& spline, const ctk::ParallelFor& parallelFor) {
        return ctk::BuildQuarticCloughTocher(data, topo, options, spline, parallelFor);
      },
      "quartic", data.NumberOfTriangles, chunk);
  }
  return RunConstructionWith<ctk::CubicSpline>(
    [&](ctk::CubicSpline& spline, const ctk::ParallelFor& parallelFor) {
      return ctk::BuildCubicCloughTocher(data, topo, options, spline, parallelFor);
    },
    ctk::ToString(options.Method), data.NumberOfTriangles, chunk);
}

void RunExtraction(const ctk::SplineData& data, const ctk::MeshTopology& topo,
  const ctk::SplineOptions& options, bool inputValid)
{
  ctk::BezierExtraction extraction;
  const auto status = ctk::BuildBezierExtraction(data, topo, options, extraction);
  Trace("extraction", status.Ok, status.Message);
  if (!status.Ok)
  {
    return;
  }
  const std::size_t cells = 3 * static_cast<std::size_t>(data.NumberOfTriangles);
  const int width = ctk::BezierExtraction::MaxElementDofs;
  if (extraction.CellDofs.size() != cells * width ||
    extraction.CellOperators.size() != cells * 10 * width ||
    extraction.EdgeDofs.size() != topo.Edges.size())
  {
    Finding("extraction Ok with wrong array sizes", static_cast<long long>(cells));
    return;
  }
  for (std::size_t i = 0; i < extraction.CellDofs.size(); ++i)
  {
    if (extraction.CellDofs[i] < -1 || extraction.CellDofs[i] >= extraction.NumberOfDofs)
    {
      Finding("extraction Ok with a degree of freedom out of range", static_cast<long long>(i));
      return;
    }
  }
  for (std::size_t i = 0; i < extraction.CellOperators.size(); ++i)
  {
    if (!std::isfinite(extraction.CellOperators[i]))
    {
      Finding("extraction Ok with a non-finite operator entry", static_cast<long long>(i));
      return;
    }
  }
  RequireFinite(extraction.EdgeDirections, "extraction Ok with a non-finite edge direction");
  const auto dofs = ctk::DegreesOfFreedom(data, topo, extraction);
  if (static_cast<Id>(dofs.size()) != extraction.NumberOfDofs)
  {
    Finding("DegreesOfFreedom: wrong count", static_cast<long long>(dofs.size()));
    return;
  }
  if (inputValid)
  {
    RequireFinite(dofs, "DegreesOfFreedom non-finite for data the construction accepted");
  }
}

void CheckHit(const ctk::ParameterLocator& locator, const ctk::ParameterLocator::Hit& hit)
{
  if (hit.Triangle < -1 || hit.Triangle >= locator.GetNumberOfTriangles())
  {
    Finding("locator: triangle out of range", hit.Triangle);
    return;
  }
  if (hit.Found() &&
    (!hit.Barycentric.allFinite() || hit.Barycentric.minCoeff() < -1e-9))
  {
    Finding("locator: hit with bad barycentric coordinates", hit.Triangle);
    return;
  }
}

/// Every well-shaped, moderately sized triangle contains its centroid: Locate must find a
/// triangle there. Fuzzed queries (any value) must stay in range.
void RunLocator(const Mesh& mesh)
{
  ctk::ParameterLocator locator;
  std::vector<Vec2> uv(mesh.NumberOfVertices);
  for (Id v = 0; v < mesh.NumberOfVertices; ++v)
  {
    uv[v] = mesh.UVPoint(v);
  }
  locator.Build(uv, mesh.NumberOfTriangles(), mesh.Triangles.data());
  for (Id t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Vec2 a = uv[mesh.Triangles[3 * t]], b = uv[mesh.Triangles[3 * t + 1]],
               c = uv[mesh.Triangles[3 * t + 2]];
    const double size =
      std::max({ (b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm() });
    const bool wellShaped = a.allFinite() && b.allFinite() && c.allFinite() &&
      a.cwiseAbs().maxCoeff() < 1e6 && b.cwiseAbs().maxCoeff() < 1e6 &&
      c.cwiseAbs().maxCoeff() < 1e6 && std::abs(ctk::SignedArea2(a, b, c)) > 1e-6 * size &&
      size > 1e-12;
    const Vec2 centroid = (a + b + c) / 3.0;
    const auto hit = locator.Locate(centroid.x(), centroid.y());
    CheckHit(locator, hit);
    if (wellShaped && !hit.Found())
    {
      Finding("locator: centroid of a well-shaped triangle not found", t);
      return;
    }
  }
  for (const Vec3& q : mesh.Queries)
  {
    CheckHit(locator, locator.Locate(q.x(), q.y()));
    const Id bucket = locator.Bucket(q.x(), q.y());
    if (bucket < -1 || bucket >= locator.GetNumberOfBuckets())
    {
      Finding("locator: bucket out of range", bucket);
      return;
    }
  }
}

void RunDistance(const Mesh& mesh)
{
  ctk::PointToMeshDistance distance;
  const std::string error = distance.Build(
    mesh.NumberOfVertices, mesh.F.data(), mesh.NumberOfTriangles(), mesh.Triangles.data());
  Trace("distance", error.empty(), error);
  if (!error.empty())
  {
    return;
  }
  std::vector<Vec3> queries = mesh.Queries;
  for (Id v = 0; v < mesh.NumberOfVertices; ++v)
  {
    queries.emplace_back(mesh.F[3 * v], mesh.F[3 * v + 1], mesh.F[3 * v + 2]);
  }
  for (const Vec3& q : queries)
  {
    if (!q.allFinite())
    {
      continue; // the promise covers finite queries
    }
    const auto result = distance.Query(q);
    if (!std::isfinite(result.Distance) || result.Distance < 0 || !result.Closest.allFinite() ||
      result.Triangle < 0 || result.Triangle >= mesh.NumberOfTriangles())
    {
      Finding("distance: non-finite or out-of-range result for a finite query", result.Triangle);
      return;
    }
  }
}
} // namespace

static int RunOne(const std::uint8_t* bytes, std::size_t size)
{
  FuzzInput in(bytes, size);
  const int construction = in.Choice(10);
  ctk::SplineOptions options;
  options.SplitPoint = static_cast<ctk::SplitPointRule>(in.Choice(3));
  options.Boundary = static_cast<ctk::BoundaryMode>(in.Choice(4));
  options.Iterations = in.Choice(4);
  const std::uint8_t flags = in.Byte();
  const bool quartic = construction == 9;
  options.Method = static_cast<ctk::Construction>(quartic ? 3 : construction);
  const int chunk = in.Flag(flags, 3) ? 1 + (flags >> 7) * 2 : 0;
  const Mesh mesh = ReadMesh(in, flags);
  const ctk::SplineData data = MakeData(mesh);
  Trace("values", !in.NonFinite, "max |x| " + std::to_string(in.MaxAbs));

  ctk::MeshTopology topo;
  const auto topoStatus =
    ctk::BuildMeshTopology(data.NumberOfVertices, data.NumberOfTriangles, data.Triangles, topo);
  Trace("topology", topoStatus.Ok, topoStatus.Message);
  if (!topoStatus.Ok)
  {
    return 0;
  }
  if (!CheckTopology(topo, data.NumberOfVertices, data.NumberOfTriangles))
  {
    return 0;
  }
  const bool built = RunConstruction(data, topo, options, quartic, chunk);
  if (in.Flag(flags, 4) && !quartic)
  {
    RunExtraction(data, topo, options, built);
  }
  if (in.Flag(flags, 5))
  {
    RunLocator(mesh);
  }
  if (in.Flag(flags, 6))
  {
    RunDistance(mesh);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size)
{
  return ctsplines_fuzz::RunGuarded(bytes, size, RunOne);
}
