// SPDX-License-Identifier: GPL-3.0-or-later
#include "PointToMeshDistance.h"

#include "SplineDataValidation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

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

struct PointToMeshDistance::Tree
{
  // The primitives point into Triangles, so it must not change once the tree is built.
  std::vector<Triangle> Triangles;
  std::vector<Id> InputIds; // input triangle index of each kept triangle
  AABBTree AABB;
};

PointToMeshDistance::PointToMeshDistance() = default;
PointToMeshDistance::~PointToMeshDistance() = default;

std::string PointToMeshDistance::Build(
  Id numPoints, const double* points, Id numTriangles, const Id* triangles)
{
  this->Impl.reset();
  auto tree = std::make_unique<Tree>();
  tree->Triangles.reserve(static_cast<size_t>(std::max<Id>(numTriangles, 0)));
  for (Id t = 0; t < numTriangles; ++t)
  {
    Point corner[3];
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
      corner[a] = Point(x[0], x[1], x[2]);
    }
    if (CGAL::collinear(corner[0], corner[1], corner[2]))
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

PointToMeshDistance::Result PointToMeshDistance::Query(const Vec3& p) const
{
  Result r;
  if (!IsUsablePoint(p))
  {
    r.Distance = std::numeric_limits<double>::quiet_NaN();
    r.Closest.setConstant(r.Distance);
    return r;
  }
  const Point q(p.x(), p.y(), p.z());
  const auto hit = this->Impl->AABB.closest_point_and_primitive(q);
  r.Closest = Vec3(hit.first.x(), hit.first.y(), hit.first.z());
  r.Distance = (r.Closest - p).norm();
  r.Triangle = this->Impl->InputIds[static_cast<size_t>(hit.second - this->Impl->Triangles.cbegin())];
  return r;
}

Id PointToMeshDistance::GetNumberOfTriangles() const
{
  return this->Impl ? static_cast<Id>(this->Impl->Triangles.size()) : 0;
}

} // namespace ctk
