// SPDX-License-Identifier: GPL-3.0-or-later
// Built with -ffp-contract=off (CMakeLists.txt): a fused multiply-add in the squared norms would
// change their bits against VTK's.
#include "PointRanges.h"

#include "LocalityOrder.h" // for PrefetchAhead

#include <algorithm>
#include <limits>

#if defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "PointRanges.cxx reports NaN and inf: build it without -ffinite-math-only (-ffast-math)"
#endif

#include <atomic>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define CTK_POINT_RANGES_AVX2 1
#define CTK_POINT_RANGES_SSE2 1 // part of x86-64
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
// Two points of three components in three registers, [x0 y0] [z0 x1] [y1 z1]: (x + y) + z of
// each point's squares, VTK's order.
inline __m128d SquaredNorms3(__m128d a, __m128d b, __m128d c)
{
  a = _mm_mul_pd(a, a);
  b = _mm_mul_pd(b, b);
  c = _mm_mul_pd(c, c);
  const __m128d x = _mm_shuffle_pd(a, b, 0x2); // [a0 b1]
  const __m128d y = _mm_shuffle_pd(a, c, 0x1); // [a1 c0]
  const __m128d z = _mm_shuffle_pd(b, c, 0x2); // [b0 c1]
  return _mm_add_pd(_mm_add_pd(x, y), z);
}

// Two points of two components, [u0 v0] [u1 v1]: u * u + v * v of each.
inline __m128d SquaredNorms2(__m128d a, __m128d b)
{
  a = _mm_mul_pd(a, a);
  b = _mm_mul_pd(b, b);
  return _mm_add_pd(_mm_unpacklo_pd(a, b), _mm_unpackhi_pd(a, b));
}

// Points [0, 2 n) in pairs, for CPUs without AVX2: lane j of the k-th register holds value
// 2 k + j of the pair, kept in lo[2 k + j] (component (2 k + j) % NC, as Result reads the lanes).
// Returns whether a NaN was seen.
template <int NC>
bool ScanSSE2(const double* p, Id n, double* lo, double* hi, double* normLo, double* normHi)
{
  __m128d l[NC], h[NC];
  for (int k = 0; k < NC; ++k)
  {
    l[k] = _mm_load_pd(lo + 2 * k);
    h[k] = _mm_load_pd(hi + 2 * k);
  }
  __m128d nl = _mm_load_pd(normLo), nh = _mm_load_pd(normHi);
  __m128d nan = _mm_setzero_pd();
  for (Id i = 0; i < n; ++i, p += 2 * NC)
  {
    PrefetchAhead(p, StreamPrefetchBytes);
    __m128d v[NC];
    for (int k = 0; k < NC; ++k)
    {
      v[k] = _mm_loadu_pd(p + 2 * k);
      l[k] = _mm_min_pd(v[k], l[k]); // the new value first, as in ScanAVX2
      h[k] = _mm_max_pd(v[k], h[k]);
    }
    __m128d s;
    if constexpr (NC == 3)
    {
      s = SquaredNorms3(v[0], v[1], v[2]);
    }
    else
    {
      s = SquaredNorms2(v[0], v[1]);
    }
    nl = _mm_min_pd(s, nl);
    nh = _mm_max_pd(s, nh);
    nan = _mm_or_pd(nan, _mm_cmpunord_pd(s, s));
  }
  for (int k = 0; k < NC; ++k)
  {
    _mm_store_pd(lo + 2 * k, l[k]);
    _mm_store_pd(hi + 2 * k, h[k]);
  }
  _mm_store_pd(normLo, nl);
  _mm_store_pd(normHi, nh);
  return _mm_movemask_pd(nan) != 0;
}
#endif

#if defined(CTK_POINT_RANGES_AVX2)

// Four points of three components in three registers, [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3],
// their squares regrouped by component: x = [t1 t2 t1 t2] lanes 0 1 2 3 of t1 = [x0 y0 x2 y2],
// t2 = [z0 x1 z2 x3], t3 = [y1 z1 y3 z3], and so on. Then (x + y) + z, VTK's order.
__attribute__((target("avx2"))) inline __m256d SquaredNorms3(__m256d a, __m256d b, __m256d c)
{
  a = _mm256_mul_pd(a, a);
  b = _mm256_mul_pd(b, b);
  c = _mm256_mul_pd(c, c);
  const __m256d t1 = _mm256_blend_pd(a, b, 0xC);
  const __m256d t2 = _mm256_permute2f128_pd(a, c, 0x21);
  const __m256d t3 = _mm256_blend_pd(b, c, 0xC);
  const __m256d x = _mm256_shuffle_pd(t1, t2, 0xA);
  const __m256d y = _mm256_shuffle_pd(t1, t3, 0x5);
  const __m256d z = _mm256_shuffle_pd(t2, t3, 0xA);
  return _mm256_add_pd(_mm256_add_pd(x, y), z);
}

// Four points of two components in two registers, [u0 v0 u1 v1] [u2 v2 u3 v3]: the sums of
// each point's two squares, [p0 p2 p1 p3] (the lanes' order does not matter to the extremes).
__attribute__((target("avx2"))) inline __m256d SquaredNorms2(__m256d a, __m256d b)
{
  return _mm256_hadd_pd(_mm256_mul_pd(a, a), _mm256_mul_pd(b, b));
}

// Points [0, 4 n) in groups of four; returns whether a NaN was seen.
template <int NC>
__attribute__((target("avx2"))) bool ScanAVX2(
  const double* p, Id n, double* lo, double* hi, double* normLo, double* normHi)
{
  __m256d l[NC], h[NC];
  for (int k = 0; k < NC; ++k)
  {
    l[k] = _mm256_load_pd(lo + 4 * k);
    h[k] = _mm256_load_pd(hi + 4 * k);
  }
  __m256d nl = _mm256_load_pd(normLo), nh = _mm256_load_pd(normHi);
  __m256d nan = _mm256_setzero_pd();
  for (Id i = 0; i < n; ++i, p += 4 * NC)
  {
    PrefetchAhead(p, StreamPrefetchBytes); // one line in 1.5 (or 2): its neighbour comes along
    __m256d v[NC];
    for (int k = 0; k < NC; ++k)
    {
      v[k] = _mm256_loadu_pd(p + 4 * k);
      // The new value first: on a NaN or a tie (zeros of both signs) the lane keeps what it
      // had, as the scalar loop does.
      l[k] = _mm256_min_pd(v[k], l[k]);
      h[k] = _mm256_max_pd(v[k], h[k]);
    }
    __m256d s;
    if constexpr (NC == 3)
    {
      s = SquaredNorms3(v[0], v[1], v[2]);
    }
    else
    {
      s = SquaredNorms2(v[0], v[1]);
    }
    nl = _mm256_min_pd(s, nl);
    nh = _mm256_max_pd(s, nh);
    // A NaN component makes its norm NaN; squares are never -inf, so inf + -inf cannot.
    nan = _mm256_or_pd(nan, _mm256_cmp_pd(s, s, _CMP_UNORD_Q));
  }
  for (int k = 0; k < NC; ++k)
  {
    _mm256_store_pd(lo + 4 * k, l[k]);
    _mm256_store_pd(hi + 4 * k, h[k]);
  }
  _mm256_store_pd(normLo, nl);
  _mm256_store_pd(normHi, nh);
  return _mm256_movemask_pd(nan) != 0;
}
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
    const bool nan = this->Components == 3
      ? ScanAVX2<3>(points, groups, this->Lo, this->Hi, this->NormLo, this->NormHi)
      : ScanAVX2<2>(points, groups, this->Lo, this->Hi, this->NormLo, this->NormHi);
    this->NaN = this->NaN || nan;
    done = 4 * groups;
  }
#endif
#if defined(CTK_POINT_RANGES_SSE2)
  if (isa == PointRangeISA::SSE2 && count >= 2)
  {
    const Id pairs = count / 2;
    const bool nan = this->Components == 3
      ? ScanSSE2<3>(points, pairs, this->Lo, this->Hi, this->NormLo, this->NormHi)
      : ScanSSE2<2>(points, pairs, this->Lo, this->Hi, this->NormLo, this->NormHi);
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
