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

// Cell of x along one axis, clamped to [0, n) in double, so that neither huge values nor a NaN
// from an overflowing or underflowing box (inf * 0) reach the integer cast.
Id Cell(double x, double origin, double inverseSpacing, Id n)
{
  const double f = std::floor((x - origin) * inverseSpacing);
  if (!(f > 0.0))
  {
    return 0;
  }
  return f < static_cast<double>(n - 1) ? static_cast<Id>(f) : n - 1;
}
} // namespace

bool ParameterLocator::BucketRange(Id t, Id range[4]) const
{
  const Vec2* c = &this->Corners[3 * t];
  if (!IsUsable(c))
  {
    return false;
  }
  Vec2 lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]);
  Vec2 hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
  // Points accepted within the barycentric tolerance lie up to ~Tolerance * size outside the
  // triangle; a much larger margin guarantees that their bucket is one of the triangle's.
  const double margin = 1e-9 * (hi - lo).maxCoeff();
  lo.array() -= margin;
  hi.array() += margin;
  range[0] = Cell(lo.x(), this->Origin[0], this->InverseSpacing[0], this->NX);
  range[1] = Cell(hi.x(), this->Origin[0], this->InverseSpacing[0], this->NX);
  range[2] = Cell(lo.y(), this->Origin[1], this->InverseSpacing[1], this->NY);
  range[3] = Cell(hi.y(), this->Origin[1], this->InverseSpacing[1], this->NY);
  return true;
}

void ParameterLocator::Build(Id numTriangles, const Vec2* corners)
{
  ResizeForOverwrite(this->Corners, static_cast<size_t>(3 * numTriangles));
  std::copy_n(corners, 3 * numTriangles, this->Corners.data());
  this->TieRank.clear();
  this->BuildBuckets();
}

void ParameterLocator::Build(std::vector<Vec2>&& corners, std::vector<Id>&& tieRank)
{
  this->Corners = std::move(corners);
  this->TieRank = std::move(tieRank);
  if (!this->TieRank.empty() && this->TieRank.size() != this->Corners.size() / 3)
  {
    this->TieRank.clear(); // not one per triangle: ignored (ids break ties)
  }
  this->BuildBuckets();
}

void ParameterLocator::BuildBuckets()
{
  const Id numTriangles = this->GetNumberOfTriangles();
  this->Offsets.clear();
  this->Items.clear();
  this->NX = this->NY = 0;

  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  Id usable = 0;
  for (Id t = 0; t < numTriangles; ++t)
  {
    const Vec2* c = &this->Corners[3 * t];
    if (IsUsable(c))
    {
      ++usable;
      for (int a = 0; a < 3; ++a)
      {
        lo = lo.cwiseMin(c[a]);
        hi = hi.cwiseMax(c[a]);
      }
    }
  }
  if (usable == 0)
  {
    return;
  }
  // A usable triangle has positive area, so both extents are positive. Aim for square buckets,
  // about one per triangle.
  const double w = hi.x() - lo.x(), h = hi.y() - lo.y();
  double nxIdeal = std::sqrt(static_cast<double>(usable) * w / h);
  if (!std::isfinite(nxIdeal))
  {
    nxIdeal = 1.0; // an extent overflows or underflows: one column (still correct, slower)
  }
  this->NX = static_cast<Id>(std::min(std::max(std::round(nxIdeal), 1.0), double(usable)));
  this->NY = std::max<Id>(1, (usable + this->NX - 1) / this->NX);
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

  // Pass 1: bucket sizes; prefix sums give the row starts.
  const Id nBuckets = this->NX * this->NY;
  AssignLarge(this->Offsets, static_cast<size_t>(nBuckets + 1), Id(0));
  Id range[4];
  for (Id t = 0; t < numTriangles; ++t)
  {
    if (this->BucketRange(t, range))
    {
      for (Id iy = range[2]; iy <= range[3]; ++iy)
      {
        for (Id ix = range[0]; ix <= range[1]; ++ix)
        {
          ++this->Offsets[iy * this->NX + ix + 1];
        }
      }
    }
  }
  for (Id b = 0; b < nBuckets; ++b)
  {
    this->Offsets[b + 1] += this->Offsets[b];
  }
  // Pass 2: fill in triangle order, so every row is sorted by triangle id.
  ResizeForOverwrite(this->Items, static_cast<size_t>(this->Offsets[nBuckets]));
  std::vector<Id> next(this->Offsets.begin(), this->Offsets.end() - 1);
  for (Id t = 0; t < numTriangles; ++t)
  {
    if (this->BucketRange(t, range))
    {
      for (Id iy = range[2]; iy <= range[3]; ++iy)
      {
        for (Id ix = range[0]; ix <= range[1]; ++ix)
        {
          this->Items[next[iy * this->NX + ix]++] = t;
        }
      }
    }
  }
}

void ParameterLocator::Build(const std::vector<Vec2>& uv, Id numTriangles, const Id* triangles)
{
  std::vector<Vec2> corners(3 * numTriangles);
  for (Id i = 0; i < 3 * numTriangles; ++i)
  {
    corners[i] = uv[triangles[i]];
  }
  this->Build(numTriangles, corners.data());
}

Id ParameterLocator::Bucket(double u, double v) const
{
  if (this->NX == 0 || !std::isfinite(u) || !std::isfinite(v))
  {
    return -1;
  }
  const Id ix = Cell(u, this->Origin[0], this->InverseSpacing[0], this->NX);
  const Id iy = Cell(v, this->Origin[1], this->InverseSpacing[1], this->NY);
  return iy * this->NX + ix;
}

ParameterLocator::Hit ParameterLocator::Locate(double u, double v) const
{
  Hit hit;
  const Id b = this->Bucket(u, v);
  if (b < 0)
  {
    return hit;
  }
  const Vec2 X(u, v);
  double bestMin = -Tolerance;
  for (Id i = this->Offsets[b]; i < this->Offsets[b + 1]; ++i)
  {
    const Id t = this->Items[i];
    const Vec2* c = &this->Corners[3 * t];
    const Vec3 bary = Barycentric(c[0], c[1], c[2], X);
    const double m = bary.minCoeff();
    // Rows are sorted by id, so a strict comparison keeps the lowest id among ties; tie ranks
    // are compared only at exact ties (rare: no row sorting by rank).
    if (m > bestMin ||
      (m == bestMin &&
        (hit.Triangle < 0 ||
          (!this->TieRank.empty() && this->TieRank[t] < this->TieRank[hit.Triangle]))))
    {
      bestMin = m;
      hit.Triangle = t;
      hit.Barycentric = bary;
    }
  }
  return hit;
}

} // namespace ctk
