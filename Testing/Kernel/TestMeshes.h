// SPDX-License-Identifier: GPL-3.0-or-later
// Test inputs for the kernel: sampled analytic surfaces on a suite of parameter meshes
// (regular, jittered with random diagonals, skinny), with optional affine reparameterisation.
#ifndef CTSplines_Testing_TestMeshes_h
#define CTSplines_Testing_TestMeshes_h

#include "AnalyticSurfaces.h"
#include "CloughTocherSpline.h"
#include "SplineInput.h"

#include <Eigen/Dense>

#include <algorithm>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace ctk_test
{
using namespace ctk;

/// A ParallelFor that runs chunks of `chunk` elements on `threads` threads at once (chunk c on
/// thread c % threads), to check that results do not depend on the split.
inline ParallelFor ThreadedFor(int threads, Id chunk)
{
  return [threads, chunk](Id n, const std::function<void(Id, Id)>& body) {
    std::vector<std::thread> workers;
    for (int w = 0; w < threads; ++w)
    {
      workers.emplace_back([&, w] {
        for (Id b = chunk * w; b < n; b += chunk * threads)
        {
          body(b, std::min(n, b + chunk));
        }
      });
    }
    for (std::thread& worker : workers)
    {
      worker.join();
    }
  };
}

/// The triangles of a mesh with its vertex ids and triangle order shuffled (no locality left).
inline std::vector<Id> ShuffledTriangles(const std::vector<Id>& triangles, Id numVertices, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<Id> vertex(static_cast<size_t>(numVertices)), order(triangles.size() / 3);
  std::iota(vertex.begin(), vertex.end(), Id(0));
  std::iota(order.begin(), order.end(), Id(0));
  std::shuffle(vertex.begin(), vertex.end(), rng);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<Id> out(triangles.size());
  for (size_t t = 0; t < order.size(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      out[3 * t + l] = vertex[triangles[3 * order[t] + l]];
    }
  }
  return out;
}

/// A named test input with its topology (SplineInput owns the arrays behind a SplineData).
struct SampledMesh : SplineInput
{
  std::string Name;
  MeshTopology Topology;

  SplineData Data() const { return this->View(); }
};

/// Affine reparameterisation U' = A U + t (gradients map by A^{-T}: J' = J A^{-1}).
struct Affine
{
  Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  Vec2 t = Vec2::Zero();
};

template <typename Values, typename Derivatives>
void AppendSample(Values& F, Derivatives& Fu, Derivatives& Fv, const SurfacePoint& s,
  const Eigen::Matrix2d& Ainv)
{
  Eigen::Matrix<double, 3, 2> J;
  J << s.Fu, s.Fv;
  const Eigen::Matrix<double, 3, 2> Jp = J * Ainv;
  for (int c = 0; c < 3; ++c)
  {
    F.push_back(s.F[c]);
  }
  for (int c = 0; c < 3; ++c)
  {
    Fu.push_back(Jp(c, 0));
  }
  for (int c = 0; c < 3; ++c)
  {
    Fv.push_back(Jp(c, 1));
  }
}

/// Samples surface s on the parameter mesh m (original parameters), then applies the affine map.
inline SampledMesh Sample(
  const std::string& name, const ParameterMesh& m, AnalyticSurface s, const Affine& affine = {})
{
  SampledMesh out;
  out.Name = name;
  out.Triangles.assign(m.Triangles.begin(), m.Triangles.end());
  const Eigen::Matrix2d Ainv = affine.A.inverse();
  std::vector<double> dummyF;
  for (const Vec2& U : m.UV)
  {
    const SurfacePoint p = EvaluateAnalyticSurface(s, U.x(), U.y());
    AppendSample(out.F, out.Fu, out.Fv, p, Ainv);
    const Vec2 Up = affine.A * U + affine.t;
    out.UV.push_back(Up.x());
    out.UV.push_back(Up.y());
  }
  for (Id t = 0; t < m.NumberOfTriangles(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      const Vec2 mid = 0.5 * (m.UV[m.Triangles[3 * t + l]] + m.UV[m.Triangles[3 * t + (l + 1) % 3]]);
      const SurfacePoint p = EvaluateAnalyticSurface(s, mid.x(), mid.y());
      std::vector<double> gu, gv;
      dummyF.clear();
      AppendSample(dummyF, gu, gv, p, Ainv);
      out.EdgeGradients.insert(out.EdgeGradients.end(), gu.begin(), gu.end());
      out.EdgeGradients.insert(out.EdgeGradients.end(), gv.begin(), gv.end());
    }
  }
  const TopologyStatus st = BuildMeshTopology(static_cast<Id>(m.UV.size()),
    static_cast<Id>(m.Triangles.size() / 3), out.Triangles.data(), out.Topology);
  if (!st.Ok)
  {
    throw std::runtime_error(st.Message);
  }
  return out;
}

/// Grid on [0,1]^2 with interior vertices moved by up to `jitter` cells, random diagonals.
inline ParameterMesh JitteredGrid(int n, double jitter, unsigned seed)
{
  ParameterMesh m = RegularGridMesh(n, GridDiagonal::Forward);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-jitter / n, jitter / n);
  for (int j = 1; j < n; ++j)
  {
    for (int i = 1; i < n; ++i)
    {
      // Sequenced (the order of function arguments is unspecified): v first, as g++
      // evaluated Vec2(U(rng), U(rng)), so that every compiler builds the same meshes.
      const double dv = U(rng);
      const double du = U(rng);
      m.UV[j * (n + 1) + i] += Vec2(du, dv);
    }
  }
  std::bernoulli_distribution flip(0.5);
  for (Id t = 0; t < m.NumberOfTriangles(); t += 2)
  {
    if (flip(rng))
    {
      // Cell (a, b, d), (a, d, c) -> (a, b, c), (b, d, c).
      Id* p = &m.Triangles[3 * t];
      const Id a = p[0], b = p[1], d = p[2], c = p[5];
      const Id q[6] = { a, b, c, b, d, c };
      std::copy(q, q + 6, p);
    }
  }
  return m;
}

/// The standard suite of parameter meshes: regular, jittered, skinny (aspect 1:20), equilateral.
inline std::vector<std::pair<std::string, ParameterMesh>> MeshSuite()
{
  std::vector<std::pair<std::string, ParameterMesh>> suite;
  suite.emplace_back("grid", RegularGridMesh(4, GridDiagonal::Alternating));
  suite.emplace_back("jittered", JitteredGrid(5, 0.35, 7u));
  ParameterMesh skinny = RegularGridMesh(6, GridDiagonal::Backward);
  for (Vec2& U : skinny.UV)
  {
    U.y() *= 0.05;
  }
  suite.emplace_back("skinny", skinny);
  const std::array<Vec2, 3> A = SphereOctantDomain();
  suite.emplace_back("equilateral", RefinedTriangleMesh(A[0], A[1], A[2], 2));
  return suite;
}

/// The same mesh with each triangle's vertices listed otherwise: triangle t rotated by t % 3 and,
/// every other triple, reversed (so that interior edges also run the same way in both of their
/// triangles).
inline ParameterMesh WithTrianglesReordered(const ParameterMesh& m)
{
  ParameterMesh out = m;
  for (Id t = 0; t < m.NumberOfTriangles(); ++t)
  {
    Id* p = out.Triangles.data() + 3 * t;
    std::rotate(p, p + t % 3, p + 3);
    if ((t / 3) % 2 == 1)
    {
      std::swap(p[1], p[2]);
    }
  }
  return out;
}

/// Evaluates the spline at parameter X inside macro-triangle t.
inline ParametricJet EvaluateSpline(
  const SampledMesh& mesh, const CubicSpline& spline, Id t, const Vec2& X, int order = 1)
{
  const Id* tri = mesh.Triangles.data() + 3 * t;
  const Vec3 tau = Barycentric(spline.DomainPoints[tri[0]], spline.DomainPoints[tri[1]],
    spline.DomainPoints[tri[2]], X);
  return ctk::EvaluateSpline(spline, mesh.Topology, mesh.Triangles.data(), t, tau, order);
}

} // namespace ctk_test

#endif
