// SPDX-License-Identifier: GPL-3.0-or-later
// The vector loop of PointRangeScan (PointRanges.h), written once for every instruction set:
// Lanes is a register of Lanes::Width doubles with its operations. PointRanges.cxx instantiates
// it for SSE2 and PointRangesAVX2.cxx, compiled with -mavx2, for AVX2; both are built with
// -ffp-contract=off (no fused multiply-add in the squared norms, whose bits are VTK's). Private
// to those two files: everything here has internal linkage, so that each keeps the code its own
// flags compiled.
#ifndef ctk_PointRangeLanes_h
#define ctk_PointRangeLanes_h

#include "LocalityOrder.h" // for PrefetchAhead

namespace ctk
{
namespace
{
// Points [0, W n) in groups of W = Lanes::Width: lane j of the k-th register holds value W k + j
// of a group (component (W k + j) % NC), its extremes kept in lo[W k + j] and hi[W k + j] (as
// PointRangeScan::Result reads them), the squared norms' in normLo and normHi. Returns whether
// a NaN was seen.
template <class Lanes, int NC>
inline bool ScanLanes(const double* p, Id n, double* lo, double* hi, double* normLo, double* normHi)
{
  using V = typename Lanes::V;
  constexpr int W = Lanes::Width;
  V l[NC], h[NC];
  for (int k = 0; k < NC; ++k)
  {
    l[k] = Lanes::Load(lo + W * k);
    h[k] = Lanes::Load(hi + W * k);
  }
  V nl = Lanes::Load(normLo), nh = Lanes::Load(normHi);
  V nan = Lanes::Zero();
  for (Id i = 0; i < n; ++i, p += W * NC)
  {
    PrefetchAhead(p, StreamPrefetchBytes); // one line in 1.5 (or 2): its neighbour comes along
    V v[NC];
    for (int k = 0; k < NC; ++k)
    {
      v[k] = Lanes::LoadUnaligned(p + W * k);
      // The new value first: on a NaN or a tie (zeros of both signs) the lane keeps what it
      // had, as the scalar loop does.
      l[k] = Lanes::Min(v[k], l[k]);
      h[k] = Lanes::Max(v[k], h[k]);
    }
    const V s = Lanes::SquaredNorms(v);
    nl = Lanes::Min(s, nl);
    nh = Lanes::Max(s, nh);
    // A NaN component makes its norm NaN; squares are never -inf, so inf + -inf cannot.
    nan = Lanes::Or(nan, Lanes::Unordered(s));
  }
  for (int k = 0; k < NC; ++k)
  {
    Lanes::Store(lo + W * k, l[k]);
    Lanes::Store(hi + W * k, h[k]);
  }
  Lanes::Store(normLo, nl);
  Lanes::Store(normHi, nh);
  return Lanes::Any(nan);
}
} // namespace

/// ScanLanes with AVX2 (PointRangesAVX2.cxx): groups of four points of nc (2 or 3) components.
/// Call only where the CPU has AVX2.
bool ScanPointRangesAVX2(int nc, const double* p, Id groups, double* lo, double* hi,
  double* normLo, double* normHi);
} // namespace ctk

#endif
