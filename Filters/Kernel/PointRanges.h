// SPDX-License-Identifier: GPL-3.0-or-later
// The value ranges of arrays of points of 2 or 3 doubles, as vtkDataArray computes them, for the
// VTK layer to store in its output arrays (CTSplinesArrayRanges.h) without scanning them again.
// The cubic constructions asked for them (SplineOptions::ScanRanges) scan each block of control
// and domain points right after writing it, while it is in the cache (CubicCloughTocher.cxx):
// read back from memory, the spline's 540 MB at 1e6 triangles took a tenth of the construction.
#ifndef ctk_PointRanges_h
#define ctk_PointRanges_h

#include "ParallelFor.h" // for Id

namespace ctk
{
/// Each component's extremes, the extremes of the squared L2 norms ((x*x + y*y) + z*z in double,
/// without fused multiply-adds, as VTK sums them), and whether a NaN was seen: min and max skip
/// a NaN or not depending on the order, so ranges with NaN are not VTK's. Inf shows in the
/// extremes. Min and max are exact, so ranges merge in any order; only the sign of a zero extreme
/// may depend on the order (the VTK layer stores +0).
struct PointRanges
{
  int Components = 0; // 2 or 3; 0: nothing scanned
  double Lo[3], Hi[3];
  double SquaredNormLo, SquaredNormHi;
  bool NaN = false;

  PointRanges(); // nothing scanned
  explicit PointRanges(int components);
  void Merge(const PointRanges& other);
};

/// The ranges of the control and domain points [First, First + Count) of a spline.
struct PointBlockRanges
{
  Id First = 0, Count = 0;
  PointRanges Points, Domain;
};

/// Accumulates the ranges of blocks of points: each block's extremes stay in the lanes they were
/// read in (four points at a time, two with SSE2) and go to their components only in Result,
/// since a reduction per block cost more than the scan of a block of ten points. AVX2 where the
/// CPU has it, else SSE2 (the same bits as the scalar loop: no fused multiply-adds, the same
/// order of additions).
class PointRangeScan
{
public:
  explicit PointRangeScan(int components); // 2 or 3
  /// Points [0, count) of `points` (Components doubles each). Asks for the memory
  /// StreamPrefetchBytes ahead, for arrays read from memory.
  void Add(const double* points, Id count);
  PointRanges Result() const;

private:
  int Components;
  // Lane j of the k-th register of four points: value 4 k + j of the 12 (or 8) values of four
  // points, component (4 k + j) % Components.
  alignas(32) double Lo[12], Hi[12];
  alignas(32) double NormLo[4], NormHi[4];
  bool NaN = false;
};

/// The ranges of points [0, count) in one pass on the calling thread.
PointRanges ScanPointRanges(const double* points, int components, Id count);

/// The vector instructions the scans use: AVX2 where the CPU has it, else SSE2 on x86-64, else
/// none. The bits are the same on every path.
enum class PointRangeISA
{
  Scalar,
  SSE2,
  AVX2
};
/// For tests: scans that start from now on use `isa` at most (never more than the CPU has);
/// returns the previous setting.
PointRangeISA SetPointRangeISA(PointRangeISA isa);
} // namespace ctk

#endif
