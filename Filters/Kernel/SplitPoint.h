// SPDX-License-Identifier: GPL-3.0-or-later
// Split points Z of the Clough-Tocher refinement (study section 2.3): Bary (barycentre), Inc2
// (incentre of the parameter triangle) and Inc3 (barycentric coordinates of the incentre of the
// 3D triangle f0 f1 f2, applied in the parameter triangle). Bary and Inc3 keep invariance to
// affine reparameterisation; Inc2 breaks it.
#ifndef CTSplines_Kernel_SplitPoint_h
#define CTSplines_Kernel_SplitPoint_h

#include "BezierTriangle.h"

namespace ctk
{
enum class SplitPointRule
{
  Bary = 0,
  Inc2 = 1,
  Inc3 = 2
};

const char* ToString(SplitPointRule rule);

/// Barycentric coordinates tau of the split point of the macro-triangle with parameter vertices
/// U0..U2 and 3D vertices f0..f2. Falls back to the barycentre when the triangle used for the
/// incentre has zero perimeter.
Vec3 SplitPointBarycentric(SplitPointRule rule, const Vec2& U0, const Vec2& U1, const Vec2& U2,
  const Vec3& f0, const Vec3& f1, const Vec3& f2);

} // namespace ctk

#endif
