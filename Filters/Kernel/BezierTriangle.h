// SPDX-License-Identifier: GPL-3.0-or-later
// Bézier triangles of any degree (up to MaxDegree): indexing, evaluation with first and second
// derivatives, blossoms, sub-triangles (de Casteljau subdivision), degree elevation and rational
// weights. Pure maths: no VTK.
//
// Conventions
// - A degree-n net has (n+1)(n+2)/2 control points, stored in the kernel's canonical order
//   (BezierIndex). Ordinate P_ijk belongs to the Bernstein polynomial
//   n!/(i!j!k!) t0^i t1^j t2^k, i.e. (i, j, k) are the exponents of the barycentric coordinates of
//   the domain vertices 0, 1, 2; its domain point is (i A0 + j A1 + k A2)/n.
// - Rational nets carry one weight per control point (nullptr = polynomial); the point of a
//   rational patch is sum(w P B) / sum(w B).
// - VTK's VTK_BEZIER_TRIANGLE order is available through VtkBezierTriangleOrder().
#ifndef CTSplines_Kernel_BezierTriangle_h
#define CTSplines_Kernel_BezierTriangle_h

#include <Eigen/Core>
#include <Eigen/Geometry> // for cross

#include <array>
#include <vector>

namespace ctk
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

/// Largest degree supported by the allocation-free routines below.
constexpr int MaxDegree = 10;
/// Largest number of control points of a supported net.
constexpr int MaxBezierPoints = (MaxDegree + 1) * (MaxDegree + 2) / 2;

/// Number of control points of a degree-n Bézier triangle.
constexpr int BezierPointCount(int n)
{
  return (n + 1) * (n + 2) / 2;
}

/// Canonical index of ordinate (i, j, k = n - i - j): rows by r = n - i, then by k.
constexpr int BezierIndex(int n, int i, int j)
{
  const int r = n - i;
  return r * (r + 1) / 2 + (r - j);
}

/// Exponents (i, j, k) of every canonical index of a degree-n net, in canonical order.
std::vector<std::array<int, 3>> BezierExponents(int n);

/// For a degree-n VTK_BEZIER_TRIANGLE, entry p is the canonical index of VTK point p: corners,
/// edge 0->1, 1->2, 2->0 inner points, then the interior recursively (VTK's documented order).
/// Written into order[0, BezierPointCount(n)); constexpr, so that a writer of cells of a fixed
/// degree (VtkBezierTriangleOrderOf) copies its nets without looking the order up.
constexpr void VtkBezierTriangleOrder(int n, int* order)
{
  int p = 0;
  // Corners first, then edges 0->1, 1->2, 2->0, then the interior as a triangle of degree n - 3
  // whose exponents are all offset by one, recursively (k = m - i - j).
  for (int m = n, offset = 0; m >= 0; m -= 3, ++offset)
  {
    if (m == 0)
    {
      order[p++] = BezierIndex(n, offset, offset);
      break;
    }
    order[p++] = BezierIndex(n, m + offset, offset);
    order[p++] = BezierIndex(n, offset, m + offset);
    order[p++] = BezierIndex(n, offset, offset);
    for (int s = 1; s < m; ++s)
    {
      order[p++] = BezierIndex(n, m - s + offset, s + offset);
    }
    for (int s = 1; s < m; ++s)
    {
      order[p++] = BezierIndex(n, offset, m - s + offset);
    }
    for (int s = 1; s < m; ++s)
    {
      order[p++] = BezierIndex(n, s + offset, offset);
    }
  }
}
/// The same order as a vector, and as a constant of a fixed degree.
std::vector<int> VtkBezierTriangleOrder(int n);
template <int n>
constexpr std::array<int, BezierPointCount(n)> VtkBezierTriangleOrderOf()
{
  std::array<int, BezierPointCount(n)> order{};
  VtkBezierTriangleOrder(n, order.data());
  return order;
}

/// Value and derivatives of a patch with respect to the barycentric coordinates t = (t0, t1, t2)
/// taken as independent variables (homogeneous polynomial form). Chain with dt/du to get
/// parameter derivatives: dp/du = sum_a dt_a/du * DT[a].
struct BezierJet
{
  Vec3 Value = Vec3::Zero();
  std::array<Vec3, 3> DT{ Vec3::Zero(), Vec3::Zero(), Vec3::Zero() };
  /// Second derivatives d2p/dt_a dt_b, a <= b, in the order 00, 01, 02, 11, 12, 22.
  std::array<Vec3, 6> DTT{ Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
    Vec3::Zero() };
};

/// All degree-m Bernstein polynomials at barycentric t, in canonical order (m may be 0).
void Bernstein(int m, const Vec3& t, double* out);

/// Homogeneous control points (w P, w) of a degree-n net; weights nullptr for a polynomial net.
void HomogeneousNet(int n, const Vec3* P, const double* weights, Eigen::Vector4d* H);

/// Evaluates a degree-n net P (canonical order, n <= MaxDegree) at barycentric t.
/// weights: nullptr for polynomial nets. order: 0 value only, 1 with DT, 2 with DT and DTT.
/// Allocation-free.
BezierJet EvaluateBezierTriangle(
  int n, const Vec3* P, const double* weights, const Vec3& t, int order = 0);

/// Blossom b(X_1, ..., X_n) of a polynomial degree-n net at n barycentric arguments
/// (arguments need not lie inside the domain triangle). Allocation-free.
Vec3 Blossom(int n, const Vec3* P, const Vec3* args);

/// Homogeneous blossom of a rational net: returns (sum w P, sum w) blossomed, as 4 numbers.
Eigen::Vector4d RationalBlossom(int n, const Vec3* P, const double* weights, const Vec3* args);

/// Net of the same polynomial over the sub-triangle whose corners have barycentric coordinates
/// c0, c1, c2 with respect to the original domain (de Casteljau subdivision by blossoming).
/// out must hold BezierPointCount(n) points.
void SubTriangle(int n, const Vec3* P, const Vec3& c0, const Vec3& c1, const Vec3& c2, Vec3* out);

/// Degree elevation n -> n+1 of a polynomial net. out holds BezierPointCount(n+1) points.
void ElevateDegree(int n, const Vec3* P, Vec3* out);

/// Twice the signed area of (A0, A1, A2), positive when counter-clockwise.
inline double SignedArea2(const Vec2& A0, const Vec2& A1, const Vec2& A2)
{
  return (A1.x() - A0.x()) * (A2.y() - A0.y()) - (A1.y() - A0.y()) * (A2.x() - A0.x());
}

/// The signed areas (twice) that Barycentric divides: the triangle's, and those of X with the
/// edges opposite corners 1 and 2. Point location tests them before any division.
struct BarycentricAreas
{
  double Area, S1, S2;
};
inline BarycentricAreas BarycentricAreasOf(
  const Vec2& A0, const Vec2& A1, const Vec2& A2, const Vec2& X)
{
  return { SignedArea2(A0, A1, A2), SignedArea2(A0, X, A2), SignedArea2(A0, A1, X) };
}
/// Barycentric coordinates from those areas.
inline Vec3 Barycentric(const BarycentricAreas& a)
{
  const double t1 = a.S1 / a.Area;
  const double t2 = a.S2 / a.Area;
  return Vec3(1.0 - t1 - t2, t1, t2);
}

/// Barycentric coordinates of X with respect to the planar triangle (A0, A1, A2) from signed
/// areas (coordinates may be negative outside). The triangle must be non-degenerate. Inline:
/// point location calls it for every candidate triangle.
inline Vec3 Barycentric(const Vec2& A0, const Vec2& A1, const Vec2& A2, const Vec2& X)
{
  return Barycentric(BarycentricAreasOf(A0, A1, A2, X));
}

/// Planar cross product a x b.
inline double Cross2(const Vec2& a, const Vec2& b)
{
  return a.x() * b.y() - a.y() * b.x();
}

/// Derivatives of the barycentric coordinates of (A0, A1, A2) with respect to u and v:
/// column 0 is dt/du, column 1 is dt/dv.
Eigen::Matrix<double, 3, 2> BarycentricGradient(const Vec2& A0, const Vec2& A1, const Vec2& A2);

/// Parameter derivatives of a patch over the planar domain (A0, A1, A2) at barycentric t.
/// Returns position and dp/du, dp/dv (and second derivatives puu, puv, pvv when order 2).
struct ParametricJet
{
  Vec3 Value, Du, Dv, Duu, Duv, Dvv;
};
ParametricJet EvaluateOverDomain(int n, const Vec3* P, const double* weights, const Vec2& A0,
  const Vec2& A1, const Vec2& A2, const Vec3& t, int order);

/// Whether derivatives dr, ds span no tangent plane (e.g. at a collapsed corner).
inline bool IsSingularTangentPlane(const Vec3& dr, const Vec3& ds)
{
  return !(dr.cross(ds).norm() > 1e-12 * (dr.squaredNorm() + ds.squaredNorm()));
}
/// A point just inside the domain next to t, where a limit at a singular point is taken.
inline Vec3 NudgeInside(const Vec3& t)
{
  return (1 - 1e-7) * t + Vec3::Constant(1e-7 / 3);
}
/// out[i] = P[i] - P[0] for the degree-n net P: derivatives of a net relative to one of its own
/// points are differences of small numbers, accurate on small patches far from the origin.
void RelativeNet(int n, const Vec3* P, Vec3* out);
/// Unit normal (x_r x x_s) / |x_r x x_s| at barycentric t, x_r = dx/dt1 - dx/dt0 and
/// x_s = dx/dt2 - dx/dt0 (oriented by the corner order); where the tangent plane is singular,
/// the limit from inside (at NudgeInside(t)). Pass a RelativeNet for accuracy.
Vec3 PatchNormal(int n, const Vec3* P, const double* weights, const Vec3& t);

} // namespace ctk

#endif
