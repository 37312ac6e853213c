// SPDX-License-Identifier: GPL-3.0-or-later
// Fa (study section 3.3, eq. 20-21) and the IM step (section 3.7), also Kashyap's exterior
// fairing (quartic paper eq. 1-3): across one interior macro-edge, the central points C and Cbar
// of the two micro-triangles at the edge are tied by the C1 condition (Rule A, row 1) and C is
// chosen to minimise the two C2 residuals across the edge (Rule A, row 2).
#ifndef CTSplines_Kernel_MicroEdgeC2Minimisation_h
#define CTSplines_Kernel_MicroEdgeC2Minimisation_h

#include "BezierTriangle.h"

namespace ctk
{
/// Canonical index of the central ordinate (1, 1, 1) of a cubic net.
constexpr int CubicCentre = 4;

/// PM, PMbar: the cubic nets (canonical order) of the micro-triangles at a macro-edge, over
/// domains AM = (U_i, U_j, Z) and AMbar (the same edge, with equal coordinates, and Zbar, any
/// vertex order). Their central points are ignored and replaced by the optimum C, Cbar
/// (returned). Closed form; Testing/Kernel/CubicConstructionsTest.cxx checks it against the
/// minimisation of the Rule A residuals.
void MinimiseMicroEdgeC2Jump(
  const Vec3* PM, const Vec2* AM, const Vec3* PMbar, const Vec2* AMbar, Vec3& C, Vec3& Cbar);

/// One side of Fa's step: a cubic macro-patch (canonical net over its triangle's vertices, its
/// central point included), the macro-edge (U_l, U_l+1) and the split point Z (barycentric).
struct MacroPatchAtEdge
{
  const Vec3* Net;
  int L;
  Vec3 Tau;
};

/// Fa, eq. (19)-(21), straight from the two macro-patches (their central points eq. (18)'s Q,
/// set by the caller): what MinimiseMicroEdgeC2Jump returns for the micro-nets of the
/// macro-patches subdivided at their split points (SubTriangle), without forming them. T is the
/// patch whose micro-triangle M = (U_l, U_l+1, Z) receives C; x is Tbar's split point in M's
/// barycentric coordinates; Tbar's edge vertex U_Tbar.L is T's U_l+1 unless `sameDirection`
/// (then T's U_l).
void FaMicroEdgeCentres(const MacroPatchAtEdge& T, const MacroPatchAtEdge& Tbar, bool sameDirection,
  const Vec3& x, Vec3& C, Vec3& Cbar);

} // namespace ctk

#endif
