// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierTriangle.h"

#include <cassert>

namespace ctk
{
namespace
{
constexpr double Factorial(int n)
{
  double f = 1.0;
  for (int i = 2; i <= n; ++i)
  {
    f *= i;
  }
  return f;
}

struct FactorialTable
{
  double Value[MaxDegree + 1];
  constexpr FactorialTable()
    : Value()
  {
    for (int i = 0; i <= MaxDegree; ++i)
    {
      Value[i] = Factorial(i);
    }
  }
};
constexpr FactorialTable Factorials;

// Multinomial coefficients m!/(i! j! k!) by degree and canonical index, so that Bernstein does
// no divisions. All factors are exact integers in double, so the values are the same as the
// former run-time quotients (results unchanged to the bit).
struct MultinomialTable
{
  double Value[MaxDegree + 1][MaxBezierPoints];
  constexpr MultinomialTable()
    : Value()
  {
    for (int m = 0; m <= MaxDegree; ++m)
    {
      int idx = 0;
      for (int r = 0; r <= m; ++r)
      {
        for (int k = 0; k <= r; ++k, ++idx)
        {
          const int i = m - r, j = r - k;
          Value[m][idx] = Factorials.Value[m] /
            (Factorials.Value[i] * Factorials.Value[j] * Factorials.Value[k]);
        }
      }
    }
  }
};
constexpr MultinomialTable Multinomials;

#if defined(__GNUC__) && !defined(__clang__)
#define CTK_UNROLL _Pragma("GCC unroll 12")
#elif defined(__clang__)
#define CTK_UNROLL _Pragma("unroll")
#else
#define CTK_UNROLL
#endif

// Sum over degree-m multi-indices of B^m_i(t) H[i + shift], the shift adding d0 and d1 to the
// first two exponents (the third follows from the degree n). H: homogeneous points (Vector4d)
// or plain ones (Vec3).
template <typename Point>
inline Point ShiftedSum(int n, int m, const double* B, const Point* H, int d0, int d1)
{
  Point s = Point::Zero();
  int idx = 0;
  // Unrolled for a degree known at compile time: the indices are then constants (otherwise
  // computing them was a sixth of a cubic jet's instructions). Same operations, same order.
  CTK_UNROLL
  for (int r = 0; r <= m; ++r)
  {
    const int i = m - r;
    CTK_UNROLL
    for (int k = 0; k <= r; ++k, ++idx)
    {
      const int j = r - k;
      s += B[idx] * H[BezierIndex(n, i + d0, j + d1)];
    }
  }
  return s;
}

inline void HomogeneousNetImpl(int n, const Vec3* P, const double* w, Eigen::Vector4d* H)
{
  const int count = BezierPointCount(n);
  for (int a = 0; a < count; ++a)
  {
    const double wa = w ? w[a] : 1.0;
    H[a] << wa * P[a], wa;
  }
}

// A homogeneous sum (sum B w P, sum B w) as its point part and its weight part.
struct HomogeneousSum
{
  Vec3 Point;
  double Weight;
};

// The homogeneous sums of a rational net, from its homogeneous points.
struct RationalSums
{
  Eigen::Vector4d H[MaxBezierPoints];
  RationalSums(int n, const Vec3* P, const double* w) { HomogeneousNetImpl(n, P, w, this->H); }
  HomogeneousSum operator()(int n, int m, const double* B, int d0, int d1) const
  {
    const Eigen::Vector4d s = ShiftedSum(n, m, B, this->H, d0, d1);
    return { s.head<3>(), s[3] };
  }
};

// The same for a polynomial net (all weights 1), read in place: the weight part is the sum of
// the B's in the same order, so every value has the bits of RationalSums with weights 1 (the
// net is not copied into homogeneous points, which cost a third of a probe's evaluation).
struct PolynomialSums
{
  const Vec3* P;
  PolynomialSums(int, const Vec3* points, const double*)
    : P(points)
  {
  }
  HomogeneousSum operator()(int n, int m, const double* B, int d0, int d1) const
  {
    double weight = 0.0;
    for (int idx = 0; idx < BezierPointCount(m); ++idx)
    {
      weight += B[idx];
    }
    return { ShiftedSum(n, m, B, this->P, d0, d1), weight };
  }
};

inline void BernsteinImpl(int m, const Vec3& t, double* out)
{
  double p0[MaxDegree + 1], p1[MaxDegree + 1], p2[MaxDegree + 1];
  p0[0] = p1[0] = p2[0] = 1.0;
  for (int e = 1; e <= m; ++e)
  {
    p0[e] = p0[e - 1] * t[0];
    p1[e] = p1[e - 1] * t[1];
    p2[e] = p2[e - 1] * t[2];
  }
  int idx = 0;
  CTK_UNROLL
  for (int r = 0; r <= m; ++r)
  {
    const int i = m - r;
    CTK_UNROLL
    for (int k = 0; k <= r; ++k, ++idx)
    {
      const int j = r - k;
      out[idx] = Multinomials.Value[m][idx] * p0[i] * p1[j] * p2[k];
    }
  }
}

// The degree is N when N >= 0 (known at compile time: the loops unroll, with the same operations
// in the same order, so the same bits), else n. Sums: RationalSums or PolynomialSums.
template <int N, typename Sums>
BezierJet EvaluateImpl(int n, const Vec3* P, const double* weights, const Vec3& t, int order)
{
  if (N >= 0)
  {
    n = N;
  }
  assert(n >= 0 && n <= MaxDegree);
  const Sums sums(n, P, weights);
  double B[MaxBezierPoints];

  BezierJet jet;
  BernsteinImpl(n, t, B);
  const HomogeneousSum h = sums(n, n, B, 0, 0);
  const double W = h.Weight;
  jet.Value = h.Point / W;
  if (order < 1 || n == 0)
  {
    return jet;
  }

  BernsteinImpl(n - 1, t, B);
  HomogeneousSum hd[3];
  for (int a = 0; a < 3; ++a)
  {
    const HomogeneousSum d = sums(n, n - 1, B, a == 0, a == 1);
    hd[a] = { double(n) * d.Point, double(n) * d.Weight };
    jet.DT[a] = (hd[a].Point - jet.Value * hd[a].Weight) / W;
  }
  if (order < 2)
  {
    return jet;
  }

  // Homogeneous second derivatives vanish for n = 1, but a rational patch still curves.
  if (n >= 2)
  {
    BernsteinImpl(n - 2, t, B);
  }
  int ab = 0;
  for (int a = 0; a < 3; ++a)
  {
    for (int b = a; b < 3; ++b, ++ab)
    {
      HomogeneousSum hdd{ Vec3::Zero(), 0.0 };
      if (n >= 2)
      {
        const HomogeneousSum d =
          sums(n, n - 2, B, (a == 0) + (b == 0), (a == 1) + (b == 1));
        hdd = { double(n * (n - 1)) * d.Point, double(n * (n - 1)) * d.Weight };
      }
      // Quotient rule, second order: p_ab = (h_ab - p_a W_b - p_b W_a - p W_ab) / W.
      jet.DTT[ab] = (hdd.Point - jet.DT[a] * hd[b].Weight - jet.DT[b] * hd[a].Weight -
                      jet.Value * hdd.Weight) /
        W;
    }
  }
  return jet;
}

// EvaluateImpl with the degree fixed for cubic nets (every Clough-Tocher spline) and the sums
// of the net's kind.
BezierJet Evaluate(int n, const Vec3* P, const double* weights, const Vec3& t, int order)
{
  if (weights)
  {
    return n == 3 ? EvaluateImpl<3, RationalSums>(n, P, weights, t, order)
                  : EvaluateImpl<-1, RationalSums>(n, P, weights, t, order);
  }
  return n == 3 ? EvaluateImpl<3, PolynomialSums>(n, P, weights, t, order)
                : EvaluateImpl<-1, PolynomialSums>(n, P, weights, t, order);
}

} // namespace

void Bernstein(int m, const Vec3& t, double* out)
{
  BernsteinImpl(m, t, out);
}

void HomogeneousNet(int n, const Vec3* P, const double* w, Eigen::Vector4d* H)
{
  HomogeneousNetImpl(n, P, w, H);
}

BezierJet EvaluateBezierTriangle(int n, const Vec3* P, const double* weights, const Vec3& t, int order)
{
  return Evaluate(n, P, weights, t, order);
}


std::vector<std::array<int, 3>> BezierExponents(int n)
{
  std::vector<std::array<int, 3>> e;
  e.reserve(BezierPointCount(n));
  for (int r = 0; r <= n; ++r)
  {
    for (int k = 0; k <= r; ++k)
    {
      e.push_back({ n - r, r - k, k });
    }
  }
  return e;
}

std::vector<int> VtkBezierTriangleOrder(int n)
{
  std::vector<int> order(static_cast<size_t>(BezierPointCount(n)));
  VtkBezierTriangleOrder(n, order.data());
  return order;
}

namespace
{
// de Casteljau with one argument per level, on homogeneous or plain points.
template <typename Point>
Point BlossomImpl(int n, Point* b, const Vec3* args)
{
  for (int level = n; level >= 1; --level)
  {
    const Vec3& x = args[n - level];
    const int m = level - 1;
    for (int r = 0; r <= m; ++r)
    {
      const int i = m - r;
      for (int k = 0; k <= r; ++k)
      {
        const int j = r - k;
        // In-place: the target index (degree m, rows r) never overwrites a source still needed,
        // because sources of later targets have larger row numbers or equal row and larger k.
        b[BezierIndex(m, i, j)] = x[0] * b[BezierIndex(level, i + 1, j)] +
          x[1] * b[BezierIndex(level, i, j + 1)] + x[2] * b[BezierIndex(level, i, j)];
      }
    }
  }
  return b[0];
}
} // namespace

Vec3 Blossom(int n, const Vec3* P, const Vec3* args)
{
  Vec3 b[MaxBezierPoints];
  for (int a = 0; a < BezierPointCount(n); ++a)
  {
    b[a] = P[a];
  }
  return BlossomImpl(n, b, args);
}

Eigen::Vector4d RationalBlossom(int n, const Vec3* P, const double* weights, const Vec3* args)
{
  Eigen::Vector4d H[MaxBezierPoints];
  HomogeneousNet(n, P, weights, H);
  return BlossomImpl(n, H, args);
}

void SubTriangle(int n, const Vec3* P, const Vec3& c0, const Vec3& c1, const Vec3& c2, Vec3* out)
{
  Vec3 args[MaxDegree];
  int idx = 0;
  for (int r = 0; r <= n; ++r)
  {
    const int i = n - r;
    for (int k = 0; k <= r; ++k, ++idx)
    {
      const int j = r - k;
      int a = 0;
      for (int s = 0; s < i; ++s)
      {
        args[a++] = c0;
      }
      for (int s = 0; s < j; ++s)
      {
        args[a++] = c1;
      }
      for (int s = 0; s < k; ++s)
      {
        args[a++] = c2;
      }
      out[idx] = Blossom(n, P, args);
    }
  }
}

void ElevateDegree(int n, const Vec3* P, Vec3* out)
{
  const int m = n + 1;
  int idx = 0;
  for (int r = 0; r <= m; ++r)
  {
    const int i = m - r;
    for (int k = 0; k <= r; ++k, ++idx)
    {
      const int j = r - k;
      Vec3 q = Vec3::Zero();
      if (i > 0)
      {
        q += double(i) / m * P[BezierIndex(n, i - 1, j)];
      }
      if (j > 0)
      {
        q += double(j) / m * P[BezierIndex(n, i, j - 1)];
      }
      if (k > 0)
      {
        q += double(k) / m * P[BezierIndex(n, i, j)];
      }
      out[idx] = q;
    }
  }
}

Eigen::Matrix<double, 3, 2> BarycentricGradient(const Vec2& A0, const Vec2& A1, const Vec2& A2)
{
  const double area = SignedArea2(A0, A1, A2);
  Eigen::Matrix<double, 3, 2> G;
  // t1 = cross(A2 - A0, X - A0)... written out: dt1/dX = perp(A0 - A2)/area, etc.
  G(1, 0) = (A2.y() - A0.y()) / area;
  G(1, 1) = (A0.x() - A2.x()) / area;
  G(2, 0) = (A0.y() - A1.y()) / area;
  G(2, 1) = (A1.x() - A0.x()) / area;
  G(0, 0) = -G(1, 0) - G(2, 0);
  G(0, 1) = -G(1, 1) - G(2, 1);
  return G;
}

ParametricJet EvaluateOverDomain(int n, const Vec3* P, const double* weights, const Vec2& A0,
  const Vec2& A1, const Vec2& A2, const Vec3& t, int order)
{
  const BezierJet jet = Evaluate(n, P, weights, t, order);
  ParametricJet out;
  out.Value = jet.Value;
  out.Du = out.Dv = out.Duu = out.Duv = out.Dvv = Vec3::Zero();
  if (order < 1)
  {
    return out; // positions only (a probe without derivatives): no gradient, no divisions
  }
  const Eigen::Matrix<double, 3, 2> G = BarycentricGradient(A0, A1, A2);
  for (int a = 0; a < 3; ++a)
  {
    out.Du += G(a, 0) * jet.DT[a];
    out.Dv += G(a, 1) * jet.DT[a];
  }
  if (order >= 2)
  {
    static constexpr int pair[3][3] = { { 0, 1, 2 }, { 1, 3, 4 }, { 2, 4, 5 } };
    for (int a = 0; a < 3; ++a)
    {
      for (int b = 0; b < 3; ++b)
      {
        const Vec3& d = jet.DTT[pair[a][b]];
        out.Duu += G(a, 0) * G(b, 0) * d;
        out.Duv += G(a, 0) * G(b, 1) * d;
        out.Dvv += G(a, 1) * G(b, 1) * d;
      }
    }
  }
  return out;
}

void RelativeNet(int n, const Vec3* P, Vec3* out)
{
  const Vec3 origin = P[0];
  for (int i = 0; i < BezierPointCount(n); ++i)
  {
    out[i] = P[i] - origin;
  }
}

Vec3 PatchNormal(int n, const Vec3* P, const double* weights, const Vec3& t)
{
  BezierJet jet = EvaluateBezierTriangle(n, P, weights, t, 1);
  Vec3 dr = jet.DT[1] - jet.DT[0], ds = jet.DT[2] - jet.DT[0];
  if (IsSingularTangentPlane(dr, ds))
  {
    jet = EvaluateBezierTriangle(n, P, weights, NudgeInside(t), 1);
    dr = jet.DT[1] - jet.DT[0];
    ds = jet.DT[2] - jet.DT[0];
  }
  return dr.cross(ds).normalized(); // Eigen leaves a zero vector zero
}

} // namespace ctk
