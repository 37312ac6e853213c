// SPDX-License-Identifier: GPL-3.0-or-later
#include "PointToMeshDistance.h"

#include "SplineDataValidation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace ctk
{
namespace
{
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using AABBTree = CGAL::AABB_tree<Traits>;
}

// CGAL's constructions (squared distances, projections) see the mesh centred on its box and
// scaled to a unit diagonal, with components below 1e-200 flushed to 0: denormal coordinates
// otherwise gave NaN squared radii inside CGAL's queries (a precondition abort), and large ones
// overflowed their squares.
struct PointToMeshDistance::Tree
{
  // The primitives point into Triangles, so it must not change once the tree is built.
  std::vector<Triangle> Triangles;
  std::vector<Id> InputIds; // input triangle index of each kept triangle
  AABBTree AABB;
  Vec3 Center = Vec3::Zero();
  double Scale = 1.0;

  Point ToUnit(const Vec3& x) const
  {
    Vec3 u = (x - this->Center) * this->Scale;
    for (int c = 0; c < 3; ++c)
    {
      u[c] = std::abs(u[c]) < 1e-200 ? 0.0 : u[c];
    }
    return Point(u.x(), u.y(), u.z());
  }
  Vec3 FromUnit(const Point& p) const
  {
    return Vec3(p.x(), p.y(), p.z()) / this->Scale + this->Center;
  }
};

/// Meshes smaller than this are rejected: queries up to MaxInputMagnitude away, scaled to the
/// mesh's unit diagonal, must keep finite squares.
constexpr double MinMeshDiagonal = 1e-50;

PointToMeshDistance::PointToMeshDistance() = default;
PointToMeshDistance::~PointToMeshDistance() = default;

std::string PointToMeshDistance::Build(
  Id numPoints, const double* points, Id numTriangles, const Id* triangles)
{
  this->Impl.reset();
  auto tree = std::make_unique<Tree>();
  tree->Triangles.reserve(static_cast<size_t>(std::max<Id>(numTriangles, 0)));
  std::string error = CheckCornersAndFrame(numPoints, points, numTriangles, triangles, *tree);
  if (!error.empty())
  {
    return error;
  }
  for (Id t = 0; t < numTriangles; ++t)
  {
    Point corner[3];
    for (int a = 0; a < 3; ++a)
    {
      const double* x = points + 3 * triangles[3 * t + a];
      corner[a] = tree->ToUnit(Vec3(x[0], x[1], x[2]));
    }
    // Collinear and nearly collinear (slivers flatter than 1e-12) triangles are left out: CGAL's
    // projection onto their plane divides by their area (NaN squared radii inside its queries);
    // their points lie within 1e-12 of their longest edge, which belongs to their neighbours.
    const Vec3 a(corner[0].x(), corner[0].y(), corner[0].z());
    const Vec3 e1 = Vec3(corner[1].x(), corner[1].y(), corner[1].z()) - a;
    const Vec3 e2 = Vec3(corner[2].x(), corner[2].y(), corner[2].z()) - a;
    const double longest2 = std::max({ e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm() });
    if (!(e1.cross(e2).norm() > 1e-12 * longest2) || CGAL::collinear(corner[0], corner[1], corner[2]))
    {
      continue;
    }
    tree->Triangles.emplace_back(corner[0], corner[1], corner[2]);
    tree->InputIds.push_back(t);
  }
  if (tree->Triangles.empty())
  {
    return "the mesh has no triangle of positive area";
  }
  tree->AABB.insert(tree->Triangles.cbegin(), tree->Triangles.cend());
  tree->AABB.build();
  // Builds the internal search tree now: CGAL otherwise builds it lazily on the first query,
  // which concurrent queries must not race for.
  tree->AABB.accelerate_distance_queries();
  this->Impl = std::move(tree);
  return std::string();
}

std::string PointToMeshDistance::CheckCornersAndFrame(
  Id numPoints, const double* points, Id numTriangles, const Id* triangles, Tree& tree)
{
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (Id t = 0; t < numTriangles; ++t)
  {
    for (int a = 0; a < 3; ++a)
    {
      const Id v = triangles[3 * t + a];
      if (v < 0 || v >= numPoints)
      {
        std::ostringstream msg;
        msg << "triangle " << t << " refers to point " << v << ", not in [0, " << numPoints << ")";
        return msg.str();
      }
      const double* x = points + 3 * v;
      // Squared distances of coordinates beyond MaxInputMagnitude would overflow in CGAL.
      if (!IsUsablePoint(Vec3(x[0], x[1], x[2])))
      {
        std::ostringstream msg;
        msg << "point " << v << " has a coordinate that is non-finite or too large ("
            << x[0] << ", " << x[1] << ", " << x[2] << "; magnitudes must stay below "
            << MaxInputMagnitude << ")";
        return msg.str();
      }
      lo = lo.cwiseMin(Vec3(x[0], x[1], x[2]));
      hi = hi.cwiseMax(Vec3(x[0], x[1], x[2]));
    }
  }
  const double diagonal = numTriangles > 0 ? (hi - lo).norm() : 0.0;
  if (!(diagonal >= MinMeshDiagonal))
  {
    return diagonal > 0 ? "the mesh is too small (bounding-box diagonal below 1e-50)"
                        : "the mesh has no triangle of positive area";
  }
  tree.Center = 0.5 * (lo + hi);
  tree.Scale = 1.0 / diagonal;
  return std::string();
}

PointToMeshDistance::Result PointToMeshDistance::Query(const Vec3& p) const
{
  Result r;
  if (!p.allFinite())
  {
    r.Distance = std::numeric_limits<double>::quiet_NaN();
    r.Closest.setConstant(r.Distance);
    return r;
  }
  // A query farther than 1e50 diagonals is moved to 1e50 diagonals in the same direction, so
  // that CGAL's squared distances stay finite; the distance differs by less than 1e-50 of it.
  // Differences are scaled by their largest component, so no intermediate overflows.
  const Tree& tree = *this->Impl;
  const Vec3 u = p - tree.Center;
  const double m = u.cwiseAbs().maxCoeff();
  const Vec3 q = m * tree.Scale > 1e50 ? Vec3(tree.Center + (u / m).normalized() * (1e50 / tree.Scale)) : p;
  const auto hit = tree.AABB.closest_point_and_primitive(tree.ToUnit(q));
  r.Closest = tree.FromUnit(hit.first);
  const Vec3 w = p - r.Closest;
  const double wm = w.cwiseAbs().maxCoeff();
  r.Distance = wm > 0 ? std::min(wm * (w / wm).norm(), std::numeric_limits<double>::max()) : 0.0;
  r.Triangle = this->Impl->InputIds[static_cast<size_t>(hit.second - this->Impl->Triangles.cbegin())];
  return r;
}

Id PointToMeshDistance::GetNumberOfTriangles() const
{
  return this->Impl ? static_cast<Id>(this->Impl->Triangles.size()) : 0;
}

} // namespace ctk
