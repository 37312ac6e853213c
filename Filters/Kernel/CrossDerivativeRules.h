// SPDX-License-Identifier: GPL-3.0-or-later
// Step 2 rules that fix the central point C of the micro-triangle (U_i, U_j, Z) at one macro-edge
// from a cross-boundary derivative condition:
// - eq. (15) (Speleers): the derivative along v_eps is linear on the edge (reduced space); v_eps is
//   given through (lambda_i, lambda_j), the barycentric coordinates on the edge of the projection
//   of Z along v_eps. CTo: v_eps perpendicular (eq. 16); CTi: v_eps along Z Zbar (eq. 17);
//   boundary: perpendicular or edge midpoint.
// - eq. (24)-(25) (mid-edge gradient, MGo/MGi, KaG and gradient boundary modes): the micro-patch
//   derivative along v_eps at the edge midpoint equals that of the sampled gradient g_eps.
#ifndef CTSplines_Kernel_CrossDerivativeRules_h
#define CTSplines_Kernel_CrossDerivativeRules_h

#include "BezierTriangle.h"

namespace ctk
{
/// The edge row and first inner row of a micro-triangle net at macro-edge (U_i, U_j):
/// V_i, T_ij, T_ji, V_j and I_i1, I_j1.
struct EdgeRows
{
  Vec3 Vi, Tij, Tji, Vj, Ii1, Ij1;
};

// Inline: Step 2 calls them three times a triangle (CTo 1-2 % faster at 1e6 triangles than
// out of line).

/// lambda_j of eq. (16): orthogonal projection of Z onto the edge (lambda_i = 1 - lambda_j).
inline double PerpendicularLambda(const Vec2& Ui, const Vec2& Uj, const Vec2& Z)
{
  const Vec2 e = Uj - Ui;
  return (Z - Ui).dot(e) / e.squaredNorm();
}

/// lambda_j of eq. (17): intersection of the line Z Zbar with the edge.
inline double SplitLineLambda(const Vec2& Ui, const Vec2& Uj, const Vec2& Z, const Vec2& Zbar)
{
  const Vec2 d = Zbar - Z;
  return Cross2(Z - Ui, d) / Cross2(Uj - Ui, d);
}

/// Eq. (15): C = l_i T_ij + l_j T_ji + (I_i1 + I_j1 - l_i (V_i + T_ji) - l_j (V_j + T_ij)) / 2.
inline Vec3 LinearCrossDerivativeCentre(const EdgeRows& r, double lambdaJ)
{
  const double li = 1.0 - lambdaJ, lj = lambdaJ;
  return li * r.Tij + lj * r.Tji + 0.5 * (r.Ii1 + r.Ij1 - li * (r.Vi + r.Tji) - lj * (r.Vj + r.Tij));
}

/// Eq. (24)-(25): the C that makes the micro-patch over (U_i, U_j, Z) have directional
/// derivative g_eps * w at the edge midpoint, with g_eps = (gu, gv) the sampled gradient and w
/// the 2D direction v_eps (not parallel to the edge).
Vec3 MidEdgeGradientCentre(const EdgeRows& rows, const Vec2& Ui, const Vec2& Uj, const Vec2& Z,
  const Vec3& gu, const Vec3& gv, const Vec2& w);

/// A direction perpendicular to the edge U_i U_j in the parameter plane.
inline Vec2 EdgePerpendicular(const Vec2& Ui, const Vec2& Uj)
{
  return Vec2(Ui.y() - Uj.y(), Uj.x() - Ui.x());
}

} // namespace ctk

#endif
