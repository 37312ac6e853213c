// SPDX-License-Identifier: GPL-3.0-or-later
// Point location among planar triangles (the parameter triangles of a spline): which triangle
// contains (u, v), and its barycentric coordinates there. Pure maths: no VTK.
//
// A uniform bucket grid over the bounding box of all triangles, about one bucket per triangle;
// each triangle is listed in every bucket its (slightly enlarged) bounding box touches, stored in
// compressed rows built in two passes (count, then fill): O(n) build for meshes without extreme
// slivers, O(1) expected query. Queries only read the structure, so any number of threads may
// query one built locator concurrently.
#ifndef CTSplines_Kernel_ParameterLocator_h
#define CTSplines_Kernel_ParameterLocator_h

#include "BezierTriangle.h"
#include "MeshTopology.h" // for Id

#include <vector>

namespace ctk
{
class ParameterLocator
{
public:
  /// Result of a query: Triangle is -1 when no triangle contains the point.
  struct Hit
  {
    Id Triangle = -1;
    /// Barycentric coordinates w.r.t. the triangle's corners (may be negative by at most the
    /// tolerance on edges and vertices).
    Vec3 Barycentric = Vec3::Zero();
    bool Found() const { return this->Triangle >= 0; }
  };

  /// A point belongs to a triangle when none of its barycentric coordinates is below
  /// -Tolerance; this catches points on shared edges and vertices despite round-off.
  static constexpr double Tolerance = 1e-12;

  /// Builds over numTriangles triangles given by their corners: corners[3 t + a] is corner a of
  /// triangle t. The corners are copied. Triangles of zero area or with non-finite corners
  /// are never reported (they have no barycentric coordinates).
  void Build(Id numTriangles, const Vec2* corners);

  /// The same, taking over the corners (3 per triangle) instead of copying them. With tieRank
  /// (one value per triangle, taken over), Locate breaks ties by the lowest tieRank instead of
  /// the lowest id: a caller that stores its triangles in another order (a locality order) then
  /// gets the triangle it would get in its original numbering, tieRank being the original ids.
  void Build(std::vector<Vec2>&& corners, std::vector<Id>&& tieRank = {});
  /// The tie ranks given to Build (empty: the ids).
  const std::vector<Id>& GetTieRank() const { return this->TieRank; }

  /// Corner a of triangle t is TriangleCorners(t)[a].
  const Vec2* TriangleCorners(Id t) const { return &this->Corners[3 * t]; }

  /// Builds over an indexed mesh: uv holds the points, triangles[3 t + a] their indices.
  void Build(const std::vector<Vec2>& uv, Id numTriangles, const Id* triangles);

  /// The triangle containing (u, v). Among several candidates (shared edges and vertices), the
  /// one whose smallest barycentric coordinate is largest, then the lowest id (or tieRank):
  /// deterministic.
  Hit Locate(double u, double v) const;

  /// The bucket Locate(u, v) searches (-1 for non-finite input or an empty locator). Callers
  /// with many queries may process them in bucket order: neighbouring queries then share
  /// triangles and control points in cache.
  Id Bucket(double u, double v) const;

  Id GetNumberOfTriangles() const { return static_cast<Id>(this->Corners.size() / 3); }
  Id GetNumberOfBuckets() const { return static_cast<Id>(this->NX) * this->NY; }

private:
  bool BucketRange(Id t, Id range[4]) const;
  void BuildBuckets();

  std::vector<Vec2> Corners;
  double Origin[2] = { 0.0, 0.0 };
  double InverseSpacing[2] = { 1.0, 1.0 };
  Id NX = 0, NY = 0;
  std::vector<Id> TieRank;
  /// Compressed rows: triangles of bucket b are Items[Offsets[b] .. Offsets[b + 1]), sorted by
  /// id.
  std::vector<Id> Offsets;
  std::vector<Id> Items;
};

} // namespace ctk

#endif
