// SPDX-License-Identifier: GPL-3.0-or-later
// Point location among planar triangles (the parameter triangles of a spline): which triangle
// contains (u, v), and its barycentric coordinates there. Pure maths: no VTK.
//
// A uniform bucket grid over the bounding box of all triangles, about one bucket per two groups
// of triangles (see BucketsFor); each group is listed in every bucket its (slightly enlarged)
// bounding box touches, with the part of its box in that bucket, stored in compressed rows of
// 32-bit ids and 4-byte boxes built in two passes (count, then fill): O(n) build for meshes
// without extreme slivers, O(1) expected query. A query tests the triangles of the listed groups
// whose box holds it. The grid holds ids and boxes only: the corners come from the caller
// (TriangleBucketGrid, which reads them where they already are) or from a copy
// (ParameterLocator). Queries only read the structure, so any number of threads may query one
// built grid concurrently.
#ifndef CTSplines_Kernel_ParameterLocator_h
#define CTSplines_Kernel_ParameterLocator_h

#include "BezierTriangle.h"
#include "LargeArrays.h"  // for OverwriteVector
#include "MeshTopology.h" // for Id

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ctk
{
/// Result of a query: Triangle is -1 when no triangle contains the point.
struct LocatorHit
{
  Id Triangle = -1;
  /// Barycentric coordinates w.r.t. the triangle's corners (may be negative by at most the
  /// tolerance on edges and vertices).
  Vec3 Barycentric = Vec3::Zero();
  bool Found() const { return this->Triangle >= 0; }
};

/// The bucket column (or row) of grid coordinate f along one axis: floor(f) clamped to [0, n),
/// in double, so that neither huge values nor a NaN from an overflowing or underflowing box
/// (inf * 0) reach the integer cast. The cast truncates, which is floor for the values >= 1 it
/// gets (std::floor is a library call on baseline x86-64). Inline, with Bucket and PlaceOf:
/// the probe calls them for every query (out of line they were 2 % of its time).
inline Id GridIndex(double f, Id n)
{
  if (!(f >= 1.0))
  {
    return 0;
  }
  return f < static_cast<double>(n - 1) ? static_cast<Id>(f) : n - 1;
}

/// The bucket grid over triangles whose corners a callable gives: corners(t, c) writes corner a
/// of triangle t to c[a] (it may read them from a mesh's own arrays: nothing is copied).
class TriangleBucketGrid
{
public:
  /// A point belongs to a triangle when none of its barycentric coordinates is below
  /// -Tolerance; this catches points on shared edges and vertices despite round-off.
  static constexpr double Tolerance = 1e-12;
  /// Largest number of triangles (ids are stored in 32 bits).
  static constexpr Id MaxTriangles = Id(UINT32_MAX);

  /// Builds over numTriangles triangles; triangles of zero area or with non-finite corners are
  /// never reported (they have no barycentric coordinates). False, with an empty grid (nothing
  /// found), beyond MaxTriangles triangles or bucket entries.
  template <typename Corners>
  bool Build(Id numTriangles, const Corners& corners)
  {
    return this->BuildFrom(numTriangles, &CallCorners<Corners>, &corners, nullptr);
  }
  /// The same for a caller that has checked every triangle (finite corners, nonzero area) and
  /// knows the box [lo, hi] of all corners: one pass fewer. With groupSize k > 1 the grid lists
  /// groups of k consecutive triangles (triangles k g .. k g + k - 1, e.g. the micro-triangles
  /// of macro-triangle g), each in the buckets of the box of its triangles, and a query tests a
  /// group's triangles in id order: the same results as k = 1 (a group's box holds its
  /// triangles'), and for compact groups fewer entries to build.
  template <typename Corners>
  bool Build(
    Id numTriangles, const Corners& corners, const Vec2& lo, const Vec2& hi, Id groupSize = 1)
  {
    const Vec2 box[2] = { lo, hi };
    return this->BuildFrom(numTriangles, &CallCorners<Corners>, &corners, box, groupSize);
  }

  /// A build in steps, for a caller that reads every triangle anyway (the probe's source
  /// check), with checked triangles (as for the box build): Prepare sets the grid over [lo, hi];
  /// the caller sets spans[g] = SpanOf(box of group g's corners) for each of the
  /// GetNumberOfGroups() groups; List lists them. With the corners' box, the same grid as
  /// Build(numTriangles, corners, lo, hi, groupSize), without a second read of the corners; over
  /// another box, another grid that finds the same triangles. False, with an empty grid, beyond
  /// MaxTriangles triangles (Prepare) or entries (List).
  bool Prepare(Id numTriangles, const Vec2& lo, const Vec2& hi, Id groupSize = 1);
  /// The buckets [X0, X1] x [Y0, Y1] a group's (slightly enlarged) box touches (empty, X1 < X0,
  /// if it has no usable triangle), and its edges in 255ths of its first and last buckets (see
  /// MayHold).
  struct GroupSpan
  {
    std::uint32_t X0, X1, Y0, Y1; // columns and rows are below 2^32 (MaxTriangles)
    std::uint8_t From[2], To[2];  // x and y
  };
  /// The span of a group whose triangles' corners span [lo, hi] (lo > hi: no usable triangle).
  GroupSpan SpanOf(const Vec2& lo, const Vec2& hi) const;
  /// Every group's span, written whole after ResizeForOverwrite.
  using Spans = OverwriteVector<GroupSpan>;
  bool List(const Spans& spans);
  Id GetNumberOfGroups() const
  {
    return (this->NumTriangles + this->GroupSize - 1) / this->GroupSize;
  }

  /// The triangle containing (u, v). Among several candidates (shared edges and vertices), the
  /// one whose smallest barycentric coordinate is largest, then the lowest id: deterministic.
  /// `corners` as given to Build.
  template <typename Corners>
  LocatorHit Locate(double u, double v, const Corners& corners) const;
  /// The same among the groups [first, last) only: a bucket's groups that MayHold keeps (no
  /// other can hold the point), in the bucket's order.
  template <typename Corners>
  LocatorHit LocateAmong(const std::uint32_t* first, const std::uint32_t* last, double u,
    double v, const Corners& corners) const;
  /// The groups bucket b >= 0 lists: [RowBegin(b), RowEnd(b)), ids sorted, and the part of
  /// each group's box in the bucket, RowBoxes(b)[i] for RowBegin(b)[i] (see MayHold). A caller
  /// with many queries may prefetch what Locate will read: &RowOffset(b), then the row and its
  /// boxes, then the triangles of the groups MayHold keeps.
  const std::uint32_t& RowOffset(Id b) const { return this->Offsets[b]; }
  const std::uint32_t* RowBegin(Id b) const { return this->Items.data() + this->Offsets[b]; }
  const std::uint32_t* RowEnd(Id b) const { return this->Items.data() + this->Offsets[b + 1]; }
  using EntryBox = std::array<std::uint8_t, 4>;
  const EntryBox* RowBoxes(Id b) const { return this->ItemBoxes.data() + this->Offsets[b]; }

  /// The bucket of a point and where the point lies in it.
  struct Place
  {
    Id Bucket = -1; // -1 for non-finite input or an empty grid
    /// The position in the bucket in the units of EntryBox (0 to 255; outside the grid, clamped
    /// to the bucket), rounded down (Low) and up (High), x then y: a box with whole edges holds
    /// the position exactly when its lower edges are at most Low and its upper ones at least
    /// High.
    std::array<std::uint8_t, 2> Low = { 0, 0 }, High = { 0, 0 };
  };
  /// Where Locate(u, v) searches: one computation for the bucket and the position in it.
  Place PlaceOf(double u, double v) const;
  /// Calls visit(g) for each group of bucket place.Bucket >= 0 whose box may hold the point
  /// (MayHold), in the bucket's order: the only candidates.
  template <typename Visit>
  void ForEachCandidate(const Place& place, Visit&& visit) const;
  /// (u, v) in grid coordinates: bucket columns and rows before flooring.
  Vec2 GridPoint(double u, double v) const
  {
    return Vec2((u - this->Origin[0]) * this->InverseSpacing[0],
      (v - this->Origin[1]) * this->InverseSpacing[1]);
  }
  /// Whether a listed group may hold the point at place in the bucket: false when the point
  /// lies outside box, the part of the group's box in the bucket (x from, x to, y from, y to,
  /// in 255ths of the bucket from its lower corner, rounded outwards; 0 and 255 reach the
  /// bucket's edges and beyond), enlarged as for the buckets, so that none of the group's
  /// triangles holds the point within the tolerance. At 1e6 Delaunay macro-triangles a bucket
  /// lists 8.9 groups and this keeps 2.54.
  static bool MayHold(const EntryBox& box, const Place& place)
  {
    return box[0] <= place.Low[0] && place.High[0] <= box[1] && box[2] <= place.Low[1] &&
      place.High[1] <= box[3];
  }

  /// The bucket Locate(u, v) searches (-1 for non-finite input or an empty grid).
  Id Bucket(double u, double v) const;
  /// Its column and row (false, for -1). Callers with many queries may process them in an
  /// order of these (a Morton order): neighbouring queries then share triangles in cache.
  bool BucketCell(double u, double v, Id& ix, Id& iy) const;
  Id GetNumberOfBuckets() const { return this->NX * this->NY; }
  Id GetNumberOfColumns() const { return this->NX; }
  Id GetNumberOfRows() const { return this->NY; }
  /// Triangles per grid entry (the groupSize of the last Build).
  Id GetGroupSize() const { return this->GroupSize; }
  /// Entries over all buckets.
  Id GetNumberOfEntries() const { return static_cast<Id>(this->Items.size()); }

private:
  // Writes the corners of triangles first .. first + count - 1 to c[3 i + a]: one indirect call
  // per batch of triangles, the caller's corner function inlined in the loop.
  using CornerFunction = void (*)(const void* context, Id first, Id count, Vec2* c);
  template <typename Corners>
  static void CallCorners(const void* corners, Id first, Id count, Vec2* c)
  {
    for (Id i = 0; i < count; ++i)
    {
      (*static_cast<const Corners*>(corners))(first + i, c + 3 * i);
    }
  }
  bool BuildFrom(Id numTriangles, CornerFunction corners, const void* context, const Vec2* box,
    Id groupSize = 1);
  void SetGeometry(const Vec2& lo, const Vec2& hi, Id buckets);
  // BucketCell, also giving (u, v) in grid coordinates.
  bool BucketCell(double u, double v, Id& ix, Id& iy, Vec2& p) const;
  // The buckets of a grid over `groups` groups: about one per GroupsPerBucket. A query tests the
  // triangles of the listed groups whose box holds it (MayHold), about as many on any grid
  // (2.54 groups at 1e6 Delaunay macro-triangles, with one or two groups per bucket), so coarser
  // buckets cost a few more box tests and save entries: 4.4e6 with two groups per bucket, 6.6e6
  // with one (a first call's grid build then took 100 ms instead of 40, of fresh memory mostly),
  // 13.9e6 with a bucket per triangle (whose queries tested 13.9 triangles instead of 7.6).
  static constexpr Id GroupsPerBucket = 2;
  static Id BucketsFor(Id groups) { return std::max<Id>(1, groups / GroupsPerBucket); }
  // An empty grid for numTriangles in groups of groupSize; false beyond MaxTriangles.
  bool Reset(Id numTriangles, Id groupSize);
  // The span of count triangles' corners c (only the usable ones, or all when `checked`: the
  // caller of the box build has checked them).
  GroupSpan Span(const Vec2* c, Id count, bool checked) const;
  // Whether a point with these areas lies so far outside its triangle that Barycentric would
  // give a coordinate below -2 Tolerance: no division (most candidates fail; the few that pass
  // get Barycentric(a), the same coordinates as without this). The coordinates are the areas
  // over the triangle's, each rounded once (the first, 1 - t1 - t2, is within 1e-15 of its
  // quotient where all three reach -Tolerance), so twice the tolerance never rejects a triangle
  // Barycentric accepts. Zero-area and non-finite triangles pass on to Barycentric, which
  // rejects them.
  static bool ClearlyOutside(const BarycentricAreas& a)
  {
    const double s0 = a.Area - a.S1 - a.S2;
    const double sign = a.Area < 0.0 ? -1.0 : 1.0;
    return std::min(std::min(s0 * sign, a.S1 * sign), a.S2 * sign) <
      -2.0 * Tolerance * std::abs(a.Area);
  }
  // Tests group g's triangles for X, keeping the best in hit (see Locate).
  template <typename Corners>
  void TestGroup(std::uint32_t g, const Vec2& X, const Corners& corners, LocatorHit& hit,
    double& bestMin) const;

  double Origin[2] = { 0.0, 0.0 };
  double InverseSpacing[2] = { 1.0, 1.0 };
  Id NX = 0, NY = 0;
  Id NumTriangles = 0, GroupSize = 1;
  /// Compressed rows: groups of bucket b are Items[Offsets[b] .. Offsets[b + 1]), sorted by
  /// id.
  OverwriteVector<std::uint32_t> Offsets;
  OverwriteVector<std::uint32_t> Items;
  /// One per item (see MayHold), then BoxPadding zero entries that ForEachCandidate may read
  /// past the last row (and ignore). An array of its own: with ids and boxes in one array of
  /// 8-byte entries (53 MB at 1e6 macro-triangles, one bucket per group then), a fresh
  /// process' first build took 0.29-0.31 s instead of 0.24 s here, as glibc serves large blocks
  /// from fresh pages.
  OverwriteVector<EntryBox> ItemBoxes;
  static constexpr std::size_t BoxPadding = 3;
};

/// A TriangleBucketGrid over its own copy of the corners.
class ParameterLocator
{
public:
  using Hit = LocatorHit;
  static constexpr double Tolerance = TriangleBucketGrid::Tolerance;

  /// Builds over numTriangles triangles given by their corners: corners[3 t + a] is corner a of
  /// triangle t. The corners are copied. Triangles of zero area or with non-finite corners
  /// are never reported (they have no barycentric coordinates).
  void Build(Id numTriangles, const Vec2* corners);
  /// Builds over an indexed mesh: uv holds the points, triangles[3 t + a] their indices.
  void Build(const std::vector<Vec2>& uv, Id numTriangles, const Id* triangles);

  /// Corner a of triangle t is TriangleCorners(t)[a].
  const Vec2* TriangleCorners(Id t) const { return &this->Corners[3 * t]; }

  /// TriangleBucketGrid::Locate over the copied corners.
  Hit Locate(double u, double v) const;
  Id Bucket(double u, double v) const { return this->Grid.Bucket(u, v); }

  Id GetNumberOfTriangles() const { return static_cast<Id>(this->Corners.size() / 3); }
  Id GetNumberOfBuckets() const { return this->Grid.GetNumberOfBuckets(); }

private:
  void BuildGrid();

  std::vector<Vec2> Corners;
  TriangleBucketGrid Grid;
};

inline bool TriangleBucketGrid::BucketCell(double u, double v, Id& ix, Id& iy) const
{
  Vec2 p;
  return this->BucketCell(u, v, ix, iy, p);
}

inline bool TriangleBucketGrid::BucketCell(double u, double v, Id& ix, Id& iy, Vec2& p) const
{
  if (this->NX == 0 || !std::isfinite(u) || !std::isfinite(v))
  {
    return false;
  }
  p = this->GridPoint(u, v);
  ix = GridIndex(p.x(), this->NX);
  iy = GridIndex(p.y(), this->NY);
  return true;
}

inline Id TriangleBucketGrid::Bucket(double u, double v) const
{
  Id ix, iy;
  return this->BucketCell(u, v, ix, iy) ? iy * this->NX + ix : -1;
}

inline TriangleBucketGrid::Place TriangleBucketGrid::PlaceOf(double u, double v) const
{
  Place place;
  Id ix, iy;
  Vec2 p;
  if (!this->BucketCell(u, v, ix, iy, p))
  {
    return place;
  }
  place.Bucket = iy * this->NX + ix;
  const Vec2 f = 255.0 * (p - Vec2(double(ix), double(iy)));
  for (int a = 0; a < 2; ++a)
  {
    // Clamped to the bucket; a NaN (finite u and origin whose difference overflows, times the
    // zero spacing of an overflowing extent) is 0, as is every box edge along such an axis.
    const double x = f[a] >= 0.0 ? std::min(f[a], 255.0) : 0.0;
    place.Low[a] = static_cast<std::uint8_t>(x); // truncation: x >= 0
    place.High[a] = static_cast<std::uint8_t>(place.Low[a] + (x > place.Low[a]));
  }
  return place;
}

template <typename Visit>
void TriangleBucketGrid::ForEachCandidate(const Place& place, Visit&& visit) const
{
  const std::uint32_t* groups = this->RowBegin(place.Bucket);
  const EntryBox* boxes = this->RowBoxes(place.Bucket);
  const std::size_t n = static_cast<std::size_t>(this->RowEnd(place.Bucket) - groups);
#if defined(__SSE2__)
  // MayHold on 4 entries at once (the scalar loop's unpredictable branches and byte to double
  // conversions were 13 % of a probe). Per byte: lower edges at most Low (max(edge, low) ==
  // low; the upper-edge bytes of `low` are 255, always true), upper edges at least High
  // (min(edge, high) == high; the lower-edge bytes of `high` are 0).
  const __m128i low = _mm_set1_epi32(static_cast<int>(
    place.Low[0] | 0xFF00u | std::uint32_t(place.Low[1]) << 16 | 0xFF000000u));
  const __m128i high = _mm_set1_epi32(
    static_cast<int>(std::uint32_t(place.High[0]) << 8 | std::uint32_t(place.High[1]) << 24));
  for (std::size_t i = 0; i < n; i += 4)
  {
    const __m128i box = _mm_loadu_si128(reinterpret_cast<const __m128i*>(boxes + i));
    const __m128i ok = _mm_and_si128(_mm_cmpeq_epi8(_mm_max_epu8(box, low), low),
      _mm_cmpeq_epi8(_mm_min_epu8(box, high), high));
    const unsigned bytes = static_cast<unsigned>(_mm_movemask_epi8(ok));
    // Bit 4 k: all 4 bytes of entry k passed; entries beyond the row (padding) dropped.
    unsigned hold = bytes & bytes >> 1 & bytes >> 2 & bytes >> 3 & 0x1111u;
    if (n - i < 4)
    {
      hold &= (1u << 4 * (n - i)) - 1;
    }
    for (; hold != 0; hold &= hold - 1)
    {
      visit(groups[i + static_cast<std::size_t>(__builtin_ctz(hold)) / 4]);
    }
  }
#else
  for (std::size_t i = 0; i < n; ++i)
  {
    if (MayHold(boxes[i], place))
    {
      visit(groups[i]);
    }
  }
#endif
}

template <typename Corners>
void TriangleBucketGrid::TestGroup(
  std::uint32_t g, const Vec2& X, const Corners& corners, LocatorHit& hit, double& bestMin) const
{
  const Id first = Id(g) * this->GroupSize;
  const Id last = std::min(first + this->GroupSize, this->NumTriangles);
  for (Id t = first; t < last; ++t)
  {
    Vec2 c[3];
    corners(t, c);
    const BarycentricAreas areas = BarycentricAreasOf(c[0], c[1], c[2], X);
    if (ClearlyOutside(areas))
    {
      continue;
    }
    const Vec3 bary = Barycentric(areas);
    const double m = bary.minCoeff();
    // Groups come in id order, so a strict comparison keeps the lowest id among ties.
    if (m > bestMin || (m == bestMin && hit.Triangle < 0))
    {
      bestMin = m;
      hit.Triangle = t;
      hit.Barycentric = bary;
    }
  }
}

template <typename Corners>
LocatorHit TriangleBucketGrid::Locate(double u, double v, const Corners& corners) const
{
  LocatorHit hit;
  const Place place = this->PlaceOf(u, v);
  if (place.Bucket < 0)
  {
    return hit;
  }
  const Vec2 X(u, v);
  double bestMin = -Tolerance;
  this->ForEachCandidate(
    place, [&](std::uint32_t g) { this->TestGroup(g, X, corners, hit, bestMin); });
  return hit;
}

template <typename Corners>
LocatorHit TriangleBucketGrid::LocateAmong(const std::uint32_t* first, const std::uint32_t* last,
  double u, double v, const Corners& corners) const
{
  LocatorHit hit;
  const Vec2 X(u, v);
  double bestMin = -Tolerance;
  for (const std::uint32_t* g = first; g != last; ++g)
  {
    this->TestGroup(*g, X, corners, hit, bestMin);
  }
  return hit;
}

} // namespace ctk

#endif
