// SPDX-License-Identifier: GPL-3.0-or-later
// The cubic Clough-Tocher macro-element (spec section 2): where its 19 control points live in a
// spline's shared control-point array, the micro-triangle nets, and Steps 1 and 3 of the study
// (eq. 11-14), which are the C1 conditions of Rule A inside one macro-triangle.
//
// Names (study): V_i vertex, T_ij on macro-edge U_i U_j near U_i, I_i1 = (2 U_i + Z)/3,
// I_i2 = (U_i + 2 Z)/3, C_k centre of micro-triangle T_k, S = Z. Micro-triangle T_k is the one
// opposite U_k: T_k = (U_{k+1}, U_{k+2}, Z), so local macro-edge l = (U_l, U_{l+1}) carries T_{l+2}.
#ifndef CTSplines_Kernel_CubicMacroElement_h
#define CTSplines_Kernel_CubicMacroElement_h

#include "BezierTriangle.h"
#include "MeshTopology.h"

#include <array>

namespace ctk
{
/// Shared control-point numbering of a cubic CT spline: one point per mesh vertex (V), two per
/// macro-edge (T_ab near a then T_ba, for edge (a, b), a < b), ten per macro-triangle.
/// Total: #V + 2 #E + 10 #T.
struct CubicSplineLayout
{
  Id NumberOfVertices = 0;
  Id NumberOfEdges = 0;
  Id NumberOfTriangles = 0;

  /// Local slots of the ten triangle-owned points.
  static constexpr int I1(int i) { return i; }
  static constexpr int I2(int i) { return 3 + i; }
  static constexpr int C(int k) { return 6 + k; }
  static constexpr int S = 9;
  static constexpr int PointsPerTriangle = 10;

  Id NumberOfPoints() const
  {
    return NumberOfVertices + 2 * NumberOfEdges + PointsPerTriangle * NumberOfTriangles;
  }
  constexpr Id Vertex(Id v) const { return v; }
  /// The first of edge e's two T points, the one near its smaller vertex id; the other follows.
  Id EdgePoints(Id e) const { return NumberOfVertices + 2 * e; }
  /// T point of edge e near its vertex `near` (one of the edge's two vertices).
  Id EdgePoint(const MeshTopology& topo, Id e, Id near) const
  {
    return EdgePoints(e) + (topo.Edges[e][0] == near ? 0 : 1);
  }
  Id TrianglePoint(Id t, int slot) const
  {
    return NumberOfVertices + 2 * NumberOfEdges + PointsPerTriangle * t + slot;
  }
};

/// Point ids of one macro-triangle's 19 control points, by the study's names.
struct MacroElementIds
{
  std::array<Id, 3> V;
  std::array<std::array<Id, 3>, 3> T; // T[i][j], i != j (diagonal unused)
  std::array<Id, 3> I1, I2, C;
  Id S;
};

/// The 19 ids of macro-triangle t (vertices triangles[3t..3t+2]). Inline: out of line, its
/// callers' 16-byte loads of the returned ids waited on its 8-byte stores.
inline MacroElementIds GetMacroElementIds(
  const CubicSplineLayout& layout, const MeshTopology& topo, const Id* triangles, Id t)
{
  MacroElementIds ids;
  const Id* p = triangles + 3 * t;
  for (int i = 0; i < 3; ++i)
  {
    ids.V[i] = layout.Vertex(p[i]);
    ids.I1[i] = layout.TrianglePoint(t, CubicSplineLayout::I1(i));
    ids.I2[i] = layout.TrianglePoint(t, CubicSplineLayout::I2(i));
    ids.C[i] = layout.TrianglePoint(t, CubicSplineLayout::C(i));
    ids.T[i][i] = -1;
  }
  const std::array<Id, 3>& edges = topo.TriangleEdges[t];
  for (int l = 0; l < 3; ++l)
  {
    const int i = l, j = (l + 1) % 3;
    // layout.EdgePoint without reading topo.Edges (a cache miss per edge): edges are stored as
    // (smaller, larger) vertex id.
    const Id first = layout.EdgePoints(edges[l]);
    const Id nearI = p[i] < p[j] ? 0 : 1;
    ids.T[i][j] = first + nearI;
    ids.T[j][i] = first + (1 - nearI);
  }
  ids.S = layout.TrianglePoint(t, CubicSplineLayout::S);
  return ids;
}

/// The micro-triangle k (MicroTriangleNet's) on local edge l of its macro-triangle: the one
/// over (U_l, U_{l+1}, Z).
constexpr int MicroTriangleAtEdge(int l)
{
  return (l + 2) % 3;
}

/// Ids of the cubic net of micro-triangle k of a macro-element, in the kernel's canonical
/// order for the domain (U_{k+1}, U_{k+2}, Z). Inline: Step 3 reads a few entries of three nets.
inline std::array<Id, 10> MicroTriangleNet(const MacroElementIds& ids, int k)
{
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  // Canonical order (rows by the exponent of U_i, descending): exponents (i, j, z) =
  // 300 210 201 120 111 102 030 021 012 003.
  return { ids.V[i], ids.T[i][j], ids.I1[i], ids.T[j][i], ids.C[k], ids.I2[i], ids.V[j],
    ids.I1[j], ids.I2[j], ids.S };
}

/// Step 1, eq. (11): T_ij = f_i + ((u_j - u_i) f_u + (v_j - v_i) f_v) / 3 at vertex i.
inline Vec3 EdgeControlPoint(const Vec3& fi, const Vec3& fui, const Vec3& fvi, const Vec2& Ui,
  const Vec2& Uj)
{
  const Vec2 d = Uj - Ui;
  return fi + (d.x() * fui + d.y() * fvi) / 3.0;
}

/// The macro-patch net over (U0, U1, U2) in canonical order from the Step 1 points and a
/// central point Q.
std::array<Vec3, 10> MacroNet(const MacroElementIds& ids, const Vec3* points, const Vec3& Q);

/// Eq. (18): Q of the quadratic-precision macro-patch (Fa) from the boundary ordinates of a cubic
/// macro net (canonical order; its central point is not read).
Vec3 QuadraticPrecisionQ(const Vec3* macro);

/// Step 1, eq. (12): I_i1 = tau_i V_i + tau_j T_ij + tau_k T_ik.
void ComputeInnerRing1(const MacroElementIds& ids, const Vec3& tau, Vec3* points);

/// Step 3, eq. (13)-(14): I_i2 from I_i1 and the two C points beside it, then S.
void ComputeInnerRing2AndSplitPoint(const MacroElementIds& ids, const Vec3& tau, Vec3* points);

} // namespace ctk

#endif
