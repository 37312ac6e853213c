// SPDX-License-Identifier: GPL-3.0-or-later
#include "CloughTocherSpline.h"

#include <algorithm>
#include <limits>

namespace ctk
{
std::array<Id, 15> CloughTocherSpline::MicroNet(
  const MeshTopology& topology, const Id* triangles, Id t, int k) const
{
  if (this->Degree == 4)
  {
    return QuarticMicroNet(this->Quartic.Layout, topology, triangles, t, k);
  }
  std::array<Id, 15> net{};
  const std::array<Id, 10> cubic =
    MicroTriangleNet(GetMacroElementIds(this->Cubic.Layout, topology, triangles, t), k);
  std::copy(cubic.begin(), cubic.end(), net.begin());
  return net;
}

BuildStatus BuildCloughTocher(const SplineData& data, const MeshTopology& topology,
  const SplineOptions& options, CloughTocherSpline& spline, const ParallelFor& parallelFor,
  const QuarticObserver& observer)
{
  if (!IsConstruction(static_cast<int>(options.Method)))
  {
    return { false, "unknown construction " + std::to_string(static_cast<int>(options.Method)) };
  }
  spline.Degree = Info(options.Method).Degree;
  return spline.Degree == 4
    ? BuildQuarticCloughTocher(data, topology, options, spline.Quartic, parallelFor, observer)
    : BuildCubicCloughTocher(data, topology, options, spline.Cubic, parallelFor);
}

MicroPoint LocateMicroTriangle(const Vec3& splitTau, const Vec3& tau)
{
  // Micro-triangle k = (U_{k+1}, U_{k+2}, Z): tau = w0 e_{k+1} + w1 e_{k+2} + w2 splitTau, so
  // w2 = tau_k / splitTau_k. The one whose smallest coordinate is largest holds tau.
  MicroPoint best;
  double bestMin = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
  {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const double c = tau[k] / splitTau[k];
    const Vec3 w(tau[k1] - c * splitTau[k1], tau[k2] - c * splitTau[k2], c);
    if (w.minCoeff() > bestMin)
    {
      bestMin = w.minCoeff();
      best.K = k;
      best.W = w;
    }
  }
  return best;
}

Vec3 MacroBarycentric(const Vec3& splitTau, int k, const Vec3& w)
{
  Vec3 tau = w[2] * splitTau;
  tau[(k + 1) % 3] += w[0];
  tau[(k + 2) % 3] += w[1];
  return tau;
}

namespace
{
template <typename NetOf>
ParametricJet EvaluateMacroPoint(int degree, const OverwriteVector<Vec3>& points,
  const OverwriteVector<Vec2>& domain, const Vec3& splitTau, const Id* triangles, Id t,
  const Vec3& tau, int order, const NetOf& netOf)
{
  const MicroPoint m = LocateMicroTriangle(splitTau, tau);
  const auto net = netOf(m.K);
  Vec3 P[15];
  const int n = BezierPointCount(degree);
  for (int a = 0; a < n; ++a)
  {
    P[a] = points[net[a]];
  }
  const Vec2& A0 = domain[triangles[3 * t + (m.K + 1) % 3]];
  const Vec2& A1 = domain[triangles[3 * t + (m.K + 2) % 3]];
  const Vec2 Z = splitTau[0] * domain[triangles[3 * t]] + splitTau[1] * domain[triangles[3 * t + 1]] +
    splitTau[2] * domain[triangles[3 * t + 2]];
  return EvaluateOverDomain(degree, P, nullptr, A0, A1, Z, m.W, order);
}
} // namespace

ParametricJet EvaluateSpline(const CloughTocherSpline& spline, const MeshTopology& topology,
  const Id* triangles, Id t, const Vec3& tau, int order)
{
  return EvaluateMacroPoint(spline.Degree, spline.ControlPoints(), spline.DomainPoints(),
    spline.SplitTau()[t], triangles, t, tau, order,
    [&](int k) { return spline.MicroNet(topology, triangles, t, k); });
}

ParametricJet EvaluateSpline(const CubicSpline& spline, const MeshTopology& topology,
  const Id* triangles, Id t, const Vec3& tau, int order)
{
  const MacroElementIds ids = GetMacroElementIds(spline.Layout, topology, triangles, t);
  return EvaluateMacroPoint(3, spline.ControlPoints, spline.DomainPoints, spline.SplitTau[t],
    triangles, t, tau, order, [&](int k) { return MicroTriangleNet(ids, k); });
}

} // namespace ctk
