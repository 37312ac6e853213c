// SPDX-License-Identifier: GPL-3.0-or-later
// FO (study section 3.4, eq. 22; Foley-Opitz as modified by Mann) and Ka (section 3.5, eq. 23;
// Kashyap, Mann): per macro-edge, the central point Q of the cubic macro-patch over T is chosen
// from the neighbour's data so that the macro-patch has cubic precision across that edge; the
// micro-triangle's centre C is then read off the macro-patch subdivided at Z.
// Both compare the neighbour macro-patch's second row (its edge points T30, T31 at U3, fixed by
// U3's data) with T's macro-patch extended there (Rule A, row 2): FO solves the sum of the two
// residuals (eq. 22), Ka minimises their squares (eq. 23).
#ifndef CTSplines_Kernel_MacroEdgeCubicPrecision_h
#define CTSplines_Kernel_MacroEdgeCubicPrecision_h

#include "BezierTriangle.h"
#include "Constructions.h" // MacroEdgeRule
#include "RuleA.h"         // SharedCubicEdge

namespace ctk
{
/// macroT, macroTbar: cubic macro nets (canonical order) over domains A (T's vertices) and B
/// (Tbar's vertices, any order, the shared two with equal coordinates); their central points are
/// ignored. Returns T's Q by rule (ZeroResidualSum or LeastSquares), in closed form
/// (SolveCubicRuleARow2); edge receives the shared edge for Tbar's tied Qbar (CubicRuleARow1).
Vec3 MacroEdgeQ(MacroEdgeRule rule, const Vec3* macroT, const Vec2* A, const Vec3* macroTbar,
  const Vec2* B, SharedCubicEdge& edge);

} // namespace ctk

#endif
