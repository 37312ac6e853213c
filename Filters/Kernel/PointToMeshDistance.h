// SPDX-License-Identifier: GPL-3.0-or-later
// Unsigned distance from points to a triangle mesh in 3D, for approximation errors (study
// section 4: point-to-mesh distances over dense samples, computed with CGAL). CGAL's AABB tree
// (Simple_cartesian<double>) is hidden behind this interface so that only this translation unit
// includes CGAL. No VTK.
#ifndef CTSplines_Kernel_PointToMeshDistance_h
#define CTSplines_Kernel_PointToMeshDistance_h

#include "BezierTriangle.h"
#include "MeshTopology.h" // for Id

#include <memory>
#include <string>

namespace ctk
{
class PointToMeshDistance
{
public:
  PointToMeshDistance();
  ~PointToMeshDistance();
  PointToMeshDistance(const PointToMeshDistance&) = delete;
  PointToMeshDistance& operator=(const PointToMeshDistance&) = delete;

  /// Closest point of the mesh to a query, its triangle (an index into the triangles given to
  /// Build) and the distance.
  struct Result
  {
    double Distance = 0.0;
    Vec3 Closest = Vec3::Zero();
    Id Triangle = -1;
  };

  /// Builds the tree over numTriangles triangles of points (row-major #P by 3), triangles[3 t + a]
  /// being corner a of triangle t. Collinear and sliver triangles (area below 1e-12 of the
  /// longest edge squared) are left out: their closest point is not defined by a projection and,
  /// in a mesh, their edges belong to neighbours.
  /// Returns an empty string, or a message when an index is out of range, a coordinate is not
  /// finite or no triangle has a positive area.
  std::string Build(Id numPoints, const double* points, Id numTriangles, const Id* triangles);

  /// Closest point on the mesh. Build must have succeeded. Any finite query has a finite result
  /// (beyond 1e50 diagonals away, the closest point of a query 1e50 diagonals away in the same
  /// direction); a non-finite one gets Triangle -1 and a NaN distance. Queries only read the tree (it is
  /// fully built by Build), so any number of threads may query concurrently.
  Result Query(const Vec3& p) const;

  /// Number of triangles in the tree (non-degenerate ones).
  Id GetNumberOfTriangles() const;

private:
  struct Tree;
  // Checks indices and coordinates, and sets the tree's unit frame (centre and scale).
  static std::string CheckCornersAndFrame(
    Id numPoints, const double* points, Id numTriangles, const Id* triangles, Tree& tree);
  std::unique_ptr<Tree> Impl;
};

} // namespace ctk

#endif
