// SPDX-License-Identifier: GPL-3.0-or-later
// Built with -ffp-contract=off (CMakeLists.txt): a fused multiply-add in the squared norms would
// change their bits against VTK's.
#include "PointRanges.h"

#include "PointRangeLanes.h"

#include <algorithm>
#include <atomic>
#include <limits>

#if defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "PointRanges.cxx reports NaN and inf: build it without -ffinite-math-only (-ffast-math)"
#endif

#if defined(__x86_64__) && defined(__GNUC__)
#include <emmintrin.h>
#define CTK_POINT_RANGES_SSE2 1 // part of x86-64
#endif
#if defined(CTSPLINES_AVX2_RANGES) // PointRangesAVX2.cxx built with -mavx2 (CMakeLists.txt)
#define CTK_POINT_RANGES_AVX2 1
#endif

namespace ctk
{
namespace
{
constexpr double Inf = std::numeric_limits<double>::infinity();

// Points [b, e): component c into lane c, the squared norm into lane 0. Extremes by comparison,
// so that a NaN is skipped as VTK skips it (it is reported anyway).
void ScanScalar(const double* p, int nc, Id b, Id e, double* lo, double* hi, double* normLo,
  double* normHi, bool& nan)
{
  for (Id i = b; i < e; ++i)
  {
    double s = 0.0;
    for (int c = 0; c < nc; ++c)
    {
      const double x = p[nc * i + c];
      lo[c] = x < lo[c] ? x : lo[c];
      hi[c] = x > hi[c] ? x : hi[c];
      nan |= x != x;
      s += x * x;
    }
    normLo[0] = s < normLo[0] ? s : normLo[0];
    normHi[0] = s > normHi[0] ? s : normHi[0];
  }
}

PointRangeISA CPUPointRangeISA()
{
#if defined(CTK_POINT_RANGES_AVX2)
  if (__builtin_cpu_supports("avx2"))
  {
    return PointRangeISA::AVX2;
  }
#endif
#if defined(CTK_POINT_RANGES_SSE2)
  return PointRangeISA::SSE2;
#else
  return PointRangeISA::Scalar;
#endif
}

std::atomic<PointRangeISA>& UsedISA()
{
  static std::atomic<PointRangeISA> isa{ CPUPointRangeISA() };
  return isa;
}

#if defined(CTK_POINT_RANGES_SSE2)
struct SSE2Lanes
{
  using V = __m128d;
  static constexpr int Width = 2;
  static V Load(const double* p) { return _mm_load_pd(p); }
  static V LoadUnaligned(const double* p) { return _mm_loadu_pd(p); }
  static void Store(double* p, V v) { _mm_store_pd(p, v); }
  static V Zero() { return _mm_setzero_pd(); }
  static V Min(V a, V b) { return _mm_min_pd(a, b); }
  static V Max(V a, V b) { return _mm_max_pd(a, b); }
  static V Or(V a, V b) { return _mm_or_pd(a, b); }
  static V Unordered(V a) { return _mm_cmpunord_pd(a, a); }
  static bool Any(V a) { return _mm_movemask_pd(a) != 0; }

  // Two points of three components, [x0 y0] [z0 x1] [y1 z1]: (x + y) + z of each point's
  // squares, VTK's order.
  static V SquaredNorms(const V (&v)[3])
  {
    const V a = _mm_mul_pd(v[0], v[0]), b = _mm_mul_pd(v[1], v[1]), c = _mm_mul_pd(v[2], v[2]);
    const V x = _mm_shuffle_pd(a, b, 0x2); // [a0 b1]
    const V y = _mm_shuffle_pd(a, c, 0x1); // [a1 c0]
    const V z = _mm_shuffle_pd(b, c, 0x2); // [b0 c1]
    return _mm_add_pd(_mm_add_pd(x, y), z);
  }
  // Two points of two components, [u0 v0] [u1 v1]: u * u + v * v of each.
  static V SquaredNorms(const V (&v)[2])
  {
    const V a = _mm_mul_pd(v[0], v[0]), b = _mm_mul_pd(v[1], v[1]);
    return _mm_add_pd(_mm_unpacklo_pd(a, b), _mm_unpackhi_pd(a, b));
  }
};
#endif
} // namespace

PointRanges::PointRanges()
  : PointRanges(0)
{
}

PointRanges::PointRanges(int components)
  : Components(components)
  , SquaredNormLo(Inf)
  , SquaredNormHi(-Inf)
{
  std::fill_n(this->Lo, 3, Inf);
  std::fill_n(this->Hi, 3, -Inf);
}

void PointRanges::Merge(const PointRanges& other)
{
  for (int c = 0; c < 3; ++c)
  {
    this->Lo[c] = std::min(this->Lo[c], other.Lo[c]);
    this->Hi[c] = std::max(this->Hi[c], other.Hi[c]);
  }
  this->SquaredNormLo = std::min(this->SquaredNormLo, other.SquaredNormLo);
  this->SquaredNormHi = std::max(this->SquaredNormHi, other.SquaredNormHi);
  this->NaN = this->NaN || other.NaN;
  this->Components = std::max(this->Components, other.Components);
}

PointRangeScan::PointRangeScan(int components)
  : Components(components == 2 ? 2 : 3)
{
  std::fill_n(this->Lo, 12, Inf);
  std::fill_n(this->Hi, 12, -Inf);
  std::fill_n(this->NormLo, 4, Inf);
  std::fill_n(this->NormHi, 4, -Inf);
}

void PointRangeScan::Add(const double* points, Id count)
{
  Id done = 0;
  const PointRangeISA isa = UsedISA().load(std::memory_order_relaxed);
  (void)isa;
#if defined(CTK_POINT_RANGES_AVX2)
  if (isa == PointRangeISA::AVX2 && count >= 4)
  {
    const Id groups = count / 4;
    const bool nan = ScanPointRangesAVX2(
      this->Components, points, groups, this->Lo, this->Hi, this->NormLo, this->NormHi);
    this->NaN = this->NaN || nan;
    done = 4 * groups;
  }
#endif
#if defined(CTK_POINT_RANGES_SSE2)
  if (isa == PointRangeISA::SSE2 && count >= 2)
  {
    const Id pairs = count / 2;
    const bool nan = this->Components == 3
      ? ScanLanes<SSE2Lanes, 3>(points, pairs, this->Lo, this->Hi, this->NormLo, this->NormHi)
      : ScanLanes<SSE2Lanes, 2>(points, pairs, this->Lo, this->Hi, this->NormLo, this->NormHi);
    this->NaN = this->NaN || nan;
    done = 2 * pairs;
  }
#endif
  ScanScalar(points, this->Components, done, count, this->Lo, this->Hi, this->NormLo,
    this->NormHi, this->NaN);
}

PointRanges PointRangeScan::Result() const
{
  PointRanges r(this->Components);
  for (int j = 0; j < 4 * this->Components; ++j)
  {
    const int c = j % this->Components;
    r.Lo[c] = std::min(r.Lo[c], this->Lo[j]);
    r.Hi[c] = std::max(r.Hi[c], this->Hi[j]);
  }
  r.SquaredNormLo = *std::min_element(this->NormLo, this->NormLo + 4);
  r.SquaredNormHi = *std::max_element(this->NormHi, this->NormHi + 4);
  r.NaN = this->NaN;
  return r;
}

PointRangeISA SetPointRangeISA(PointRangeISA isa)
{
  const PointRangeISA best = CPUPointRangeISA();
  return UsedISA().exchange(static_cast<int>(isa) < static_cast<int>(best) ? isa : best);
}

PointRanges ScanPointRanges(const double* points, int components, Id count)
{
  PointRangeScan scan(components);
  scan.Add(points, count);
  return scan.Result();
}
} // namespace ctk
