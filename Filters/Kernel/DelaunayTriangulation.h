// SPDX-License-Identifier: GPL-3.0-or-later
// The Delaunay triangulation of points in the plane (CGAL's, exact predicates), for the sampled
// test surfaces and the benchmarks' random meshes. Its header does not expose CGAL.
#ifndef CTSplines_Kernel_DelaunayTriangulation_h
#define CTSplines_Kernel_DelaunayTriangulation_h

#include "ParallelFor.h" // Id

#include <vector>

namespace ctk
{
/// The Delaunay triangulation of the n points xy (#n by 2, finite): #T by 3 point indices, every
/// triangle counter-clockwise, in the triangulation's iteration order (the same for the same
/// points). Points are inserted in a spatial sort (O(n log n) expected; vtkDelaunay2D's
/// insertion in the given order took 32 s for 1e5 random points and 517 s for 5e5). An exact
/// duplicate of an earlier point is used by no triangle; empty below 3 points not all on a line.
/// CGAL's exceptions (std::bad_alloc included) reach the caller.
std::vector<Id> DelaunayTriangulation(const std::vector<double>& xy);
} // namespace ctk

#endif
