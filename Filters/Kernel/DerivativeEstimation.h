// SPDX-License-Identifier: GPL-3.0-or-later
// First derivatives f_u, f_v at the vertices of a parametrised triangle mesh that comes without
// them (a scanned or exported mesh with parameter values only), from the positions F and the
// parameter values UV. Two estimators:
// - LocalQuadratic: per vertex, the least-squares quadratic through f_i fitted to the ring
//   neighbourhood (two rings, grown to MaxEstimationRings until the fit is well-conditioned;
//   a linear fit where no quadratic is determined). Exact for quadratic data, invariant to
//   affine reparameterisation, local (the fit of vertex i reads its rings only).
// - MinimumEnergy: the gradients that minimise the thin-plate bending energy
//   int f_uu^2 + 2 f_uv^2 + f_vv^2 of the reduced Clough-Tocher interpolant (the CTo
//   construction: cubic C1, split at the barycentre, cross derivatives linear along the edges)
//   with the values fixed, per coordinate of F. One sparse SPD system, as matplotlib's
//   CubicTriInterpolator(kind='min_E') does for functional data. Exact for affine data,
//   invariant to similarity (not general affine) reparameterisation, global.
#ifndef CTSplines_Kernel_DerivativeEstimation_h
#define CTSplines_Kernel_DerivativeEstimation_h

#include "CubicCloughTocher.h"

#include <Eigen/Core>

namespace ctk
{
/// Values match vtkCloughTocherSplineFilter's DerivativeEstimation (None: derivatives required).
enum class DerivativeEstimation
{
  None = 0,
  LocalQuadratic = 1,
  MinimumEnergy = 2
};

const char* ToString(DerivativeEstimation method);

/// Rings of neighbours the LocalQuadratic fit may read (ghost levels it needs around a piece).
constexpr int MaxEstimationRings = 4;

/// Estimates the derivatives of data.F (#V by 3) over data.UV at every vertex into fu and fv
/// (caller-allocated, #V by 3 each, row-major); data.Fu, data.Fv and the optional arrays are not
/// read. topology must come from BuildMeshTopology on data.Triangles. Results do not depend on
/// how parallelFor splits the work. Vertices in no triangle (read by no construction) get zero
/// derivatives. Fails, naming the lowest offending vertex (or triangle), on non-finite or too
/// large UV/F, a vertex whose neighbours do not span the parameter plane, a degenerate
/// (zero-area) triangle or a singular system (MinimumEnergy), and non-finite results; fu and fv
/// are then unspecified.
BuildStatus EstimateDerivatives(const SplineData& data, const MeshTopology& topology,
  DerivativeEstimation method, double* fu, double* fv, const ParallelFor& parallelFor = SerialFor);

/// The bending energy of the CTo macro-patch over (U0, U1, U2) (split at the barycentre) as a
/// quadratic form in its nine degrees of freedom (f_i, f_u,i, f_v,i) of vertex i at 3 i ..
/// 3 i + 2, for one scalar coordinate: E = d^T K d. MinimumEnergy sums these.
Eigen::Matrix<double, 9, 9> ReducedCloughTocherEnergy(const Vec2& U0, const Vec2& U1, const Vec2& U2);

} // namespace ctk

#endif
