// SPDX-License-Identifier: GPL-3.0-or-later
// A Clough-Tocher spline of any construction of the table (Constructions.h), cubic or quartic:
// one BuildCloughTocher for both degrees, the micro-triangle nets, and evaluation at a point of
// a macro-triangle given by its barycentric coordinates.
#ifndef CTSplines_Kernel_CloughTocherSpline_h
#define CTSplines_Kernel_CloughTocherSpline_h

#include "QuarticCloughTocher.h"

namespace ctk
{
struct CloughTocherSpline
{
  int Degree = 3; // Info(options.Method).Degree
  CubicSpline Cubic;     // when Degree == 3
  QuarticSpline Quartic; // when Degree == 4

  const OverwriteVector<Vec3>& ControlPoints() const
  {
    return this->Degree == 4 ? this->Quartic.ControlPoints : this->Cubic.ControlPoints;
  }
  /// The parameter-space domain point of every control point; the first #V are the vertices'.
  const OverwriteVector<Vec2>& DomainPoints() const
  {
    return this->Degree == 4 ? this->Quartic.DomainPoints : this->Cubic.DomainPoints;
  }
  /// #T barycentric coordinates of the split points Z.
  const OverwriteVector<Vec3>& SplitTau() const
  {
    return this->Degree == 4 ? this->Quartic.SplitTau : this->Cubic.SplitTau;
  }
  /// Control point ids of micro-triangle k of macro-triangle t (the one opposite U_k, over
  /// (U_{k+1}, U_{k+2}, Z)) in canonical order; the first BezierPointCount(Degree) are used.
  std::array<Id, 15> MicroNet(const MeshTopology& topology, const Id* triangles, Id t, int k) const;
  /// The three micro-nets of macro-triangle t, MicroNet(..., k) for k = 0, 1, 2, of a spline of
  /// degree `degree` (== Degree): their size known when compiled, and a cubic macro-element's
  /// ids gathered once (the output's connectivity is written from these).
  template <int degree>
  std::array<std::array<Id, BezierPointCount(degree)>, 3> MicroNets(
    const MeshTopology& topology, const Id* triangles, Id t) const
  {
    static_assert(degree == 3 || degree == 4, "cubic or quartic");
    std::array<std::array<Id, BezierPointCount(degree)>, 3> nets;
    if constexpr (degree == 3)
    {
      const MacroElementIds ids = GetMacroElementIds(this->Cubic.Layout, topology, triangles, t);
      for (int k = 0; k < 3; ++k)
      {
        nets[k] = MicroTriangleNet(ids, k);
      }
    }
    else
    {
      for (int k = 0; k < 3; ++k)
      {
        nets[k] = QuarticMicroNet(this->Quartic.Layout, topology, triangles, t, k);
      }
    }
    return nets;
  }
};

/// Builds the spline of options.Method, cubic or quartic (options.Iterations: IM steps or
/// fairing rounds). The observer sees the quartic scheme's stages.
BuildStatus BuildCloughTocher(const SplineData& data, const MeshTopology& topology,
  const SplineOptions& options, CloughTocherSpline& spline,
  const ParallelFor& parallelFor = SerialFor, const QuarticObserver& observer = nullptr);

/// A point of macro-triangle t: its micro-triangle k and barycentric coordinates w there.
struct MicroPoint
{
  int K = 0;
  Vec3 W = Vec3::Zero();
};
/// The micro-triangle of a macro-triangle split at splitTau that holds the point of macro
/// barycentric coordinates tau (on an inner edge, either side; outside, the nearest), from the
/// barycentric coordinates alone.
MicroPoint LocateMicroTriangle(const Vec3& splitTau, const Vec3& tau);
/// Inverse of LocateMicroTriangle: the macro barycentric coordinates of w in micro-triangle k.
Vec3 MacroBarycentric(const Vec3& splitTau, int k, const Vec3& w);

/// The spline at the point of macro barycentric coordinates tau (w.r.t. the vertices
/// triangles[3t..3t+2]) of macro-triangle t: its value and parameter derivatives up to order
/// (0, 1 or 2). Allocation-free.
ParametricJet EvaluateSpline(const CloughTocherSpline& spline, const MeshTopology& topology,
  const Id* triangles, Id t, const Vec3& tau, int order = 0);
/// The same for a cubic spline (the constructions' own output).
ParametricJet EvaluateSpline(const CubicSpline& spline, const MeshTopology& topology,
  const Id* triangles, Id t, const Vec3& tau, int order = 0);

} // namespace ctk

#endif
