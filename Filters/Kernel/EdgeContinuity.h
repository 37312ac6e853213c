// SPDX-License-Identifier: GPL-3.0-or-later
// Continuity of two polynomial Bézier triangles A and B across an edge they share: the C0 gap,
// C1 and C2 jumps of Rule A (ctk::RuleAJumps, after mapping B's parameter triangle onto A's along
// the edge and elevating the lower degree), the largest angle between the unit normals along the
// edge (G1) and, for cubics, the study's eq. (7) C2 measure. Pure maths: no VTK.
#ifndef CTSplines_Kernel_EdgeContinuity_h
#define CTSplines_Kernel_EdgeContinuity_h

#include "BezierTriangle.h"

#include <array>
#include <limits>
#include <string>

namespace ctk
{
/// One side of a shared edge: a polynomial net over its parameter triangle.
struct EdgePatch
{
  /// Degree 1..MaxDegree.
  int Degree = 0;
  /// BezierPointCount(Degree) control points in canonical order.
  const Vec3* Points = nullptr;
  /// Parameters (u, v) of the corners 0, 1, 2.
  std::array<Vec2, 3> Domain{ Vec2::Zero(), Vec2::Zero(), Vec2::Zero() };
  /// Local corners (0..2) of the shared edge. EdgeCorners[i] of A and of B are the same point of
  /// the surface (its parameters may differ between the sides, see MapDomainOntoEdge).
  std::array<int, 2> EdgeCorners{ 0, 1 };
};

struct EdgeContinuityOptions
{
  /// Number of points inside the edge where the normals are compared (at least 1).
  int G1Samples = 5;
  /// Compute C2JumpEq7 (only defined when the common degree is 3).
  bool Eq7 = true;
};

struct EdgeContinuity
{
  /// Rule A jumps of rows 0, 1, 2: the largest distance between an ordinate of B within r rows
  /// of the edge and A's polynomial, extended by blossoming, at the same domain point (0 for
  /// rows beyond the common degree).
  double C0Gap = 0, C1Jump = 0, C2Jump = 0;
  /// Largest angle in degrees between the unit normals (x_r x x_s of each side's own
  /// parametrisation, so 180 where orientations disagree) at G1Samples points inside the edge.
  double G1Angle = 0;
  /// Eq. (7) of the study: with A over (U0, U1, U2) and B over (U1, U0, U3), the largest of
  /// |b_A(Ui, U2, U3) - b_B(Ui, U2, U3)|, i = 0, 1 (b the blossoms, in A's parameters). NaN
  /// unless options.Eq7 and the common degree is 3.
  double C2JumpEq7 = std::numeric_limits<double>::quiet_NaN();
  /// Empty when measured; otherwise what is wrong with the input (the measures are not set).
  std::string Error;
};

/// The measures above for the edge shared by A and B. Checks the degrees, the edge corners and
/// that both parameter triangles have nonzero area (relative 1e-13 of their longest squared
/// edge); an Error names the side otherwise. Allocation-free unless it reports an error.
EdgeContinuity MeasureEdgeContinuity(
  const EdgePatch& A, const EdgePatch& B, const EdgeContinuityOptions& options = {});

/// B's parameter triangle DB expressed in A's parameters: unchanged when the edge corners have
/// the same (u, v) on both sides (within 1e-9 of the edge length), else moved by the similarity
/// (with a reflection if needed) that maps B's copy of the edge (DB[pb], DB[qb]) onto A's
/// (DA[pa], DA[qa]) and puts B's third corner on the side of the edge opposite A's.
void MapDomainOntoEdge(const Vec2* DA, int pa, int qa, Vec2* DB, int pb, int qb);

} // namespace ctk

#endif
