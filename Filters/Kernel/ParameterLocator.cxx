// SPDX-License-Identifier: GPL-3.0-or-later
#include "ParameterLocator.h"

#include "LargeArrays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace ctk
{
namespace
{
bool IsUsable(const Vec2* c)
{
  for (int a = 0; a < 3; ++a)
  {
    if (!std::isfinite(c[a].x()) || !std::isfinite(c[a].y()))
    {
      return false;
    }
  }
  return SignedArea2(c[0], c[1], c[2]) != 0.0;
}

// A box edge at grid coordinate x in 255ths of bucket i from its lower edge, (x - i) * 255
// rounded down (From) or up (To), within [0, 255]; a NaN (an overflowing extent) gives the
// widest bound. PlaceOf computes a query's position with the same monotone operations, so a
// point in the box passes MayHold.
std::uint8_t From(double x, Id i)
{
  const double f = (x - double(i)) * 255.0;
  return f >= 0.0 ? static_cast<std::uint8_t>(std::min(f, 255.0)) : 0;
}

std::uint8_t To(double x, Id i)
{
  const double f = (x - double(i)) * 255.0;
  if (!(f <= 255.0))
  {
    return 255;
  }
  if (!(f > 0.0))
  {
    return 0;
  }
  const auto q = static_cast<std::uint8_t>(f);
  return q < f ? static_cast<std::uint8_t>(q + 1) : q;
}

} // namespace

TriangleBucketGrid::GroupSpan TriangleBucketGrid::Span(const Vec2* c, Id count, bool checked) const
{
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (Id t = 0; t < count; ++t, c += 3)
  {
    if (checked || IsUsable(c))
    {
      lo = lo.cwiseMin(c[0]).cwiseMin(c[1]).cwiseMin(c[2]);
      hi = hi.cwiseMax(c[0]).cwiseMax(c[1]).cwiseMax(c[2]);
    }
  }
  return this->SpanOf(lo, hi);
}

TriangleBucketGrid::GroupSpan TriangleBucketGrid::SpanOf(const Vec2& lo, const Vec2& hi) const
{
  if (!(lo.x() <= hi.x()))
  {
    return GroupSpan{ 1, 0, 1, 0, { 0, 0 }, { 0, 0 } }; // no usable triangle: in no bucket
  }
  // Points accepted within the barycentric tolerance lie up to ~Tolerance * size outside a
  // triangle; a much larger margin guarantees that their bucket is one of the triangle's, and
  // that MayHold keeps them.
  const double margin = 1e-9 * (hi - lo).maxCoeff();
  const Vec2 a = this->GridPoint(lo.x() - margin, lo.y() - margin);
  const Vec2 b = this->GridPoint(hi.x() + margin, hi.y() + margin);
  GroupSpan s;
  s.X0 = static_cast<std::uint32_t>(GridIndex(a.x(), this->NX));
  s.X1 = static_cast<std::uint32_t>(GridIndex(b.x(), this->NX));
  s.Y0 = static_cast<std::uint32_t>(GridIndex(a.y(), this->NY));
  s.Y1 = static_cast<std::uint32_t>(GridIndex(b.y(), this->NY));
  s.From[0] = From(a.x(), s.X0);
  s.From[1] = From(a.y(), s.Y0);
  s.To[0] = To(b.x(), s.X1);
  s.To[1] = To(b.y(), s.Y1);
  return s;
}

void TriangleBucketGrid::SetGeometry(const Vec2& lo, const Vec2& hi, Id buckets)
{
  // A usable triangle has positive area, so both extents are positive. Aim for square buckets.
  const double w = hi.x() - lo.x(), h = hi.y() - lo.y();
  double nxIdeal = std::sqrt(static_cast<double>(buckets) * w / h);
  if (!std::isfinite(nxIdeal))
  {
    nxIdeal = 1.0; // an extent overflows or underflows: one column (still correct, slower)
  }
  this->NX = static_cast<Id>(std::min(std::max(std::round(nxIdeal), 1.0), double(buckets)));
  this->NY = std::max<Id>(1, (buckets + this->NX - 1) / this->NX);
  this->Origin[0] = lo.x();
  this->Origin[1] = lo.y();
  // Infinite or NaN spacings (extents that overflow or underflow) become one bucket row.
  this->InverseSpacing[0] = static_cast<double>(this->NX) / w;
  this->InverseSpacing[1] = static_cast<double>(this->NY) / h;
  for (int a = 0; a < 2; ++a)
  {
    if (!std::isfinite(this->InverseSpacing[a]))
    {
      this->InverseSpacing[a] = 0.0;
    }
  }
}

bool TriangleBucketGrid::Reset(Id numTriangles, Id groupSize)
{
  this->Offsets.clear(); // keeps the storage of a previous build
  this->Items.clear();
  this->ItemBoxes.clear();
  this->NX = this->NY = 0;
  this->NumTriangles = numTriangles;
  this->GroupSize = std::max<Id>(groupSize, 1);
  return numTriangles <= MaxTriangles;
}

bool TriangleBucketGrid::Prepare(Id numTriangles, const Vec2& lo, const Vec2& hi, Id groupSize)
{
  if (!this->Reset(numTriangles, groupSize))
  {
    return false;
  }
  if (numTriangles > 0)
  {
    this->SetGeometry(lo, hi, BucketsFor(this->GetNumberOfGroups()));
  }
  return true;
}

bool TriangleBucketGrid::BuildFrom(
  Id numTriangles, CornerFunction corners, const void* context, const Vec2* box, Id groupSize)
{
  if (!this->Reset(numTriangles, groupSize))
  {
    return false;
  }
  const Id k = this->GroupSize;
  // Corners are read in batches of whole groups (one indirect call per batch); body(g, c, n)
  // gets group g's n triangles' corners c.
  constexpr Id MaxBatch = 256;
  const Id batch = std::max<Id>(MaxBatch / k, 1) * k;
  std::vector<Vec2> cornerBuffer(static_cast<size_t>(3 * std::max(batch, MaxBatch)));
  Vec2* c = cornerBuffer.data();
  auto forGroups = [&](auto&& body) {
    for (Id first = 0; first < numTriangles; first += batch)
    {
      const Id count = std::min(batch, numTriangles - first);
      corners(context, first, count, c);
      for (Id i = 0; i < count; i += k)
      {
        body((first + i) / k, c + 3 * i, std::min(k, count - i));
      }
    }
  };
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  Id usable = box ? numTriangles : 0;
  if (box)
  {
    lo = box[0];
    hi = box[1];
  }
  else
  {
    forGroups([&](Id, const Vec2* a, Id n) {
      for (Id t = 0; t < n; ++t, a += 3)
      {
        if (IsUsable(a))
        {
          ++usable;
          lo = lo.cwiseMin(a[0]).cwiseMin(a[1]).cwiseMin(a[2]);
          hi = hi.cwiseMax(a[0]).cwiseMax(a[1]).cwiseMax(a[2]);
        }
      }
    });
  }
  if (usable == 0)
  {
    return true;
  }
  this->SetGeometry(lo, hi, BucketsFor((usable + k - 1) / k));
  Spans spans;
  ResizeForOverwrite(spans, static_cast<size_t>(this->GetNumberOfGroups()));
  forGroups([&](Id g, const Vec2* a, Id n) { spans[g] = this->Span(a, n, box != nullptr); });
  return this->List(spans);
}

bool TriangleBucketGrid::List(const Spans& spans)
{
  // Pass 1: bucket sizes (counted from index 1); prefix sums give the row starts. Through
  // local pointers: the compiler reloaded the vectors' data pointers after every store.
  const Id nx = this->NX, nBuckets = nx * this->NY;
  AssignLarge(this->Offsets, static_cast<size_t>(nBuckets + 1), std::uint32_t(0));
  std::uint32_t* const offsets = this->Offsets.data();
  std::uint64_t total = 0;
  for (const GroupSpan& s : spans)
  {
    if (s.X1 < s.X0)
    {
      continue; // no usable triangle
    }
    std::uint32_t* row = offsets + 1 + Id(s.Y0) * nx;
    for (std::uint32_t iy = s.Y0; iy <= s.Y1; ++iy, row += nx)
    {
      for (std::uint32_t ix = s.X0; ix <= s.X1; ++ix)
      {
        ++row[ix];
      }
    }
    total += std::uint64_t(s.X1 - s.X0 + 1) * std::uint64_t(s.Y1 - s.Y0 + 1);
  }
  if (total > UINT32_MAX)
  {
    *this = TriangleBucketGrid();
    return false;
  }
  for (Id b = 0; b < nBuckets; ++b)
  {
    offsets[b + 1] += offsets[b];
  }
  // Pass 2: fill in group order, so every row is sorted by id, each entry with the part of the
  // group's box in its bucket (see MayHold: the span's edges in its first and last buckets, the
  // whole bucket in between). Offsets[b] serves as the fill position of row b (ending at the
  // start of row b + 1), then is shifted back.
  ResizeForOverwrite(this->Items, static_cast<size_t>(total));
  ResizeForOverwrite(this->ItemBoxes, static_cast<size_t>(total) + BoxPadding);
  std::fill(this->ItemBoxes.end() - BoxPadding, this->ItemBoxes.end(), EntryBox{});
  std::uint32_t* const items = this->Items.data();
  EntryBox* const boxes = this->ItemBoxes.data();
  for (std::size_t g = 0; g < spans.size(); ++g)
  {
    const GroupSpan& s = spans[g];
    if (s.X1 < s.X0)
    {
      continue;
    }
    std::uint32_t* row = offsets + Id(s.Y0) * nx;
    for (std::uint32_t iy = s.Y0; iy <= s.Y1; ++iy, row += nx)
    {
      const std::uint8_t y0 = iy == s.Y0 ? s.From[1] : 0, y1 = iy == s.Y1 ? s.To[1] : 255;
      for (std::uint32_t ix = s.X0; ix <= s.X1; ++ix)
      {
        const std::uint32_t i = row[ix]++;
        items[i] = static_cast<std::uint32_t>(g);
        boxes[i] = { ix == s.X0 ? s.From[0] : std::uint8_t(0),
          ix == s.X1 ? s.To[0] : std::uint8_t(255), y0, y1 };
      }
    }
  }
  for (Id b = nBuckets; b > 0; --b)
  {
    offsets[b] = offsets[b - 1];
  }
  offsets[0] = 0;
  return true;
}

void ParameterLocator::Build(Id numTriangles, const Vec2* corners)
{
  ResizeForOverwrite(this->Corners, static_cast<size_t>(3 * numTriangles));
  std::copy_n(corners, 3 * numTriangles, this->Corners.data());
  this->BuildGrid();
}

void ParameterLocator::Build(const std::vector<Vec2>& uv, Id numTriangles, const Id* triangles)
{
  ResizeForOverwrite(this->Corners, static_cast<size_t>(3 * numTriangles));
  for (Id i = 0; i < 3 * numTriangles; ++i)
  {
    this->Corners[i] = uv[triangles[i]];
  }
  this->BuildGrid();
}

void ParameterLocator::BuildGrid()
{
  if (!this->Grid.Build(this->GetNumberOfTriangles(),
        [this](Id t, Vec2* c) { std::copy_n(this->TriangleCorners(t), 3, c); }))
  {
    this->Corners.clear(); // too many triangles for the grid: nothing is found
  }
}

ParameterLocator::Hit ParameterLocator::Locate(double u, double v) const
{
  return this->Grid.Locate(
    u, v, [this](Id t, Vec2* c) { std::copy_n(this->TriangleCorners(t), 3, c); });
}

} // namespace ctk
