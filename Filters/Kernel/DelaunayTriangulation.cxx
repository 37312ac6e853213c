// SPDX-License-Identifier: GPL-3.0-or-later
#include "DelaunayTriangulation.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <utility>

namespace ctk
{
std::vector<Id> DelaunayTriangulation(const std::vector<double>& xy)
{
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<Id, K>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb>;
  using DT = CGAL::Delaunay_triangulation_2<K, Tds>;
  const std::size_t n = xy.size() / 2;
  std::vector<std::pair<K::Point_2, Id>> points(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    points[i] = { K::Point_2(xy[2 * i], xy[2 * i + 1]), static_cast<Id>(i) };
  }
  DT dt;
  dt.insert(points.begin(), points.end()); // spatially sorted; the info keeps the indices
  std::vector<Id> triangles;
  if (dt.dimension() < 2)
  {
    return triangles;
  }
  triangles.reserve(3 * dt.number_of_faces());
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
  {
    for (int l = 0; l < 3; ++l)
    {
      triangles.push_back(f->vertex(l)->info());
    }
  }
  return triangles;
}
} // namespace ctk
