// SPDX-License-Identifier: GPL-3.0-or-later
// PointRangeScan's loop on four points at a time, for CPUs with AVX2: compiled with -mavx2 and
// -ffp-contract=off (CMakeLists.txt), called only where the CPU has AVX2 (PointRanges.cxx).
#include "PointRangeLanes.h"

#if defined(CTSPLINES_AVX2_RANGES)
#if !defined(__AVX2__)
#error "PointRangesAVX2.cxx is built with -mavx2 where CTSPLINES_AVX2_RANGES is defined"
#endif
#include <immintrin.h>

namespace ctk
{
namespace
{
struct AVX2Lanes
{
  using V = __m256d;
  static constexpr int Width = 4;
  static V Load(const double* p) { return _mm256_load_pd(p); }
  static V LoadUnaligned(const double* p) { return _mm256_loadu_pd(p); }
  static void Store(double* p, V v) { _mm256_store_pd(p, v); }
  static V Zero() { return _mm256_setzero_pd(); }
  static V Min(V a, V b) { return _mm256_min_pd(a, b); }
  static V Max(V a, V b) { return _mm256_max_pd(a, b); }
  static V Or(V a, V b) { return _mm256_or_pd(a, b); }
  static V Unordered(V a) { return _mm256_cmp_pd(a, a, _CMP_UNORD_Q); }
  static bool Any(V a) { return _mm256_movemask_pd(a) != 0; }

  // Four points of three components, [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3]: their squares
  // regrouped by component, x = [t1 t2 t1 t2] lanes 0 1 2 3 of t1 = [x0 y0 x2 y2],
  // t2 = [z0 x1 z2 x3], t3 = [y1 z1 y3 z3], and so on. Then (x + y) + z, VTK's order.
  static V SquaredNorms(const V (&v)[3])
  {
    const V a = _mm256_mul_pd(v[0], v[0]), b = _mm256_mul_pd(v[1], v[1]),
            c = _mm256_mul_pd(v[2], v[2]);
    const V t1 = _mm256_blend_pd(a, b, 0xC);
    const V t2 = _mm256_permute2f128_pd(a, c, 0x21);
    const V t3 = _mm256_blend_pd(b, c, 0xC);
    const V x = _mm256_shuffle_pd(t1, t2, 0xA);
    const V y = _mm256_shuffle_pd(t1, t3, 0x5);
    const V z = _mm256_shuffle_pd(t2, t3, 0xA);
    return _mm256_add_pd(_mm256_add_pd(x, y), z);
  }
  // Four points of two components, [u0 v0 u1 v1] [u2 v2 u3 v3]: the sums of each point's two
  // squares, [p0 p2 p1 p3] (the lanes' order does not matter to the extremes).
  static V SquaredNorms(const V (&v)[2])
  {
    return _mm256_hadd_pd(_mm256_mul_pd(v[0], v[0]), _mm256_mul_pd(v[1], v[1]));
  }
};
} // namespace

bool ScanPointRangesAVX2(int nc, const double* p, Id groups, double* lo, double* hi,
  double* normLo, double* normHi)
{
  return nc == 3 ? ScanLanes<AVX2Lanes, 3>(p, groups, lo, hi, normLo, normHi)
                 : ScanLanes<AVX2Lanes, 2>(p, groups, lo, hi, normLo, normHi);
}
} // namespace ctk
#endif
