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

} // namespace

bool TriangleBucketGrid::BucketRange(const Vec2* c, Id count, Id range[4]) const
{
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (Id t = 0; t < count; ++t, c += 3)
  {
    if (IsUsable(c))
    {
      lo = lo.cwiseMin(c[0]).cwiseMin(c[1]).cwiseMin(c[2]);
      hi = hi.cwiseMax(c[0]).cwiseMax(c[1]).cwiseMax(c[2]);
    }
  }
  if (!(lo.x() <= hi.x()))
  {
    return false; // no usable triangle
  }
  // Points accepted within the barycentric tolerance lie up to ~Tolerance * size outside a
  // triangle; a much larger margin guarantees that their bucket is one of the triangle's.
  const double margin = 1e-9 * (hi - lo).maxCoeff();
  lo.array() -= margin;
  hi.array() += margin;
  range[0] = BucketCoordinate(lo.x(), this->Origin[0], this->InverseSpacing[0], this->NX);
  range[1] = BucketCoordinate(hi.x(), this->Origin[0], this->InverseSpacing[0], this->NX);
  range[2] = BucketCoordinate(lo.y(), this->Origin[1], this->InverseSpacing[1], this->NY);
  range[3] = BucketCoordinate(hi.y(), this->Origin[1], this->InverseSpacing[1], this->NY);
  return true;
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

bool TriangleBucketGrid::BuildFrom(
  Id numTriangles, CornerFunction corners, const void* context, const Vec2* box, Id groupSize)
{
  this->Offsets.clear(); // keeps the storage of a previous build
  this->Items.clear();
  this->NX = this->NY = 0;
  const Id k = std::max<Id>(groupSize, 1);
  const Id numGroups = (numTriangles + k - 1) / k;
  this->NumTriangles = numTriangles;
  this->GroupSize = k;
  if (numTriangles > MaxTriangles)
  {
    return false;
  }

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
  // About one bucket per triangle, also for groups (see Build).
  this->SetGeometry(lo, hi, usable);

  // Pass 1: every group's bucket range (kept for pass 2: ranges are ~16 B per group, and
  // computing them again cost about as much as the rest of the build), bucket sizes (counted
  // from index 1); prefix sums give the row starts. Unusable groups get an empty range.
  const Id nBuckets = this->NX * this->NY;
  AssignLarge(this->Offsets, static_cast<size_t>(nBuckets + 1), std::uint32_t(0));
  std::vector<std::uint32_t> ranges;
  ResizeForOverwrite(ranges, static_cast<size_t>(4 * numGroups));
  std::uint64_t total = 0;
  forGroups([&](Id g, const Vec2* a, Id n) {
    Id range[4] = { 1, 0, 1, 0 };
    if (this->BucketRange(a, n, range))
    {
      for (Id iy = range[2]; iy <= range[3]; ++iy)
      {
        for (Id ix = range[0]; ix <= range[1]; ++ix)
        {
          ++this->Offsets[iy * this->NX + ix + 1];
        }
      }
      total += static_cast<std::uint64_t>(range[1] - range[0] + 1) * (range[3] - range[2] + 1);
    }
    std::copy_n(range, 4, &ranges[4 * g]); // columns and rows are below 2^32 (MaxTriangles)
  });
  if (total > UINT32_MAX)
  {
    *this = TriangleBucketGrid();
    return false;
  }
  for (Id b = 0; b < nBuckets; ++b)
  {
    this->Offsets[b + 1] += this->Offsets[b];
  }
  // Pass 2: fill in group order, so every row is sorted by id. Offsets[b] serves as the fill
  // position of row b (ending at the start of row b + 1), then is shifted back.
  ResizeForOverwrite(this->Items, static_cast<size_t>(total));
  for (Id g = 0; g < numGroups; ++g)
  {
    const std::uint32_t* range = &ranges[4 * g];
    for (Id iy = range[2]; iy <= Id(range[3]); ++iy)
    {
      for (Id ix = range[0]; ix <= Id(range[1]); ++ix)
      {
        this->Items[this->Offsets[iy * this->NX + ix]++] = static_cast<std::uint32_t>(g);
      }
    }
  }
  for (Id b = nBuckets; b > 0; --b)
  {
    this->Offsets[b] = this->Offsets[b - 1];
  }
  this->Offsets[0] = 0;
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
