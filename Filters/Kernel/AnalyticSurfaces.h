// SPDX-License-Identifier: GPL-3.0-or-later
// Analytic test surfaces of the papers with exact first derivatives, and the parameter-domain
// triangulations used to sample them (regular N x N grid, refined equilateral triangle).
#ifndef CTSplines_Kernel_AnalyticSurfaces_h
#define CTSplines_Kernel_AnalyticSurfaces_h

#include "BezierTriangle.h"
#include "MeshTopology.h"

#include <vector>

namespace ctk
{
enum class AnalyticSurface
{
  Plane = 0,        // z = 0.3 + 0.5 x - 0.2 y
  Quadratic = 1,    // z = 0.5 x^2 - 0.3 x y + 0.8 y^2 + 0.1 x
  FarinCubic = 2,   // study eq. (26)
  Franke = 3,       // study eq. (27)
  SineWave = 4,     // z = 0.25 sin(2 pi x)
  SphereOctant = 5  // rational quartic Bezier triangle (Farin, Piper, Worsey 1987)
};

const char* ToString(AnalyticSurface s);

/// Position and first derivatives of a surface at parameter (u, v).
struct SurfacePoint
{
  Vec3 F, Fu, Fv;
};

/// Functional surfaces are (u, v, z(u, v)); the sphere octant is parametrised over
/// SphereOctantDomain() (and extends smoothly, off the sphere, outside it).
SurfacePoint EvaluateAnalyticSurface(AnalyticSurface s, double u, double v);

/// The equilateral parameter triangle of the sphere octant: (0,0), (1,0), (1/2, sqrt(3)/2),
/// mapped to (1,0,0), (0,1,0), (0,0,1).
std::array<Vec2, 3> SphereOctantDomain();

/// The octant's rational quartic net in canonical order (15 points) and its weights.
void SphereOctantNet(std::array<Vec3, 15>& points, std::array<double, 15>& weights);

/// A triangulated parameter domain: #V by 2 parameter values, #T by 3 vertex ids.
struct ParameterMesh
{
  std::vector<Vec2> UV;
  std::vector<Id> Triangles;
  Id NumberOfTriangles() const { return static_cast<Id>(Triangles.size() / 3); }
};

enum class GridDiagonal
{
  Forward = 0,    // splits each cell along (0,0)-(1,1)
  Backward = 1,   // along (1,0)-(0,1)
  Alternating = 2 // checkerboard of both
};

/// Regular grid of n x n cells on [x0, x1] x [y0, y1], two triangles per cell.
ParameterMesh RegularGridMesh(int n, GridDiagonal diagonal, double x0 = 0.0, double x1 = 1.0,
  double y0 = 0.0, double y1 = 1.0);

/// The triangle (A0, A1, A2) refined `level` times by midpoint subdivision: 4^level triangles.
ParameterMesh RefinedTriangleMesh(const Vec2& A0, const Vec2& A1, const Vec2& A2, int level);

} // namespace ctk

#endif
