// SPDX-License-Identifier: GPL-3.0-or-later
#include "SplitPoint.h"

namespace ctk
{
const char* ToString(SplitPointRule rule)
{
  switch (rule)
  {
    case SplitPointRule::Bary:
      return "Bary";
    case SplitPointRule::Inc2:
      return "Inc2";
    case SplitPointRule::Inc3:
      return "Inc3";
  }
  return "Unknown";
}

namespace
{
// The incentre's barycentric coordinates are proportional to the opposite side lengths. Where
// a side (nearly) vanishes, e.g. two coincident 3D corners for Inc3, the incentre would sit on
// an edge and flatten a micro-triangle: the barycentre is used instead.
template <typename P>
Vec3 Incentre(const P& a, const P& b, const P& c)
{
  const Vec3 len((b - c).norm(), (c - a).norm(), (a - b).norm());
  const Vec3 tau = len / len.sum();
  return tau.minCoeff() > 1e-8 && tau.allFinite() ? tau : Vec3(Vec3::Constant(1.0 / 3.0));
}
} // namespace

Vec3 SplitPointBarycentric(SplitPointRule rule, const Vec2& U0, const Vec2& U1, const Vec2& U2,
  const Vec3& f0, const Vec3& f1, const Vec3& f2)
{
  switch (rule)
  {
    case SplitPointRule::Inc2:
      return Incentre(U0, U1, U2);
    case SplitPointRule::Inc3:
      return Incentre(f0, f1, f2);
    case SplitPointRule::Bary:
    default:
      return Vec3::Constant(1.0 / 3.0);
  }
}

} // namespace ctk
