// SPDX-License-Identifier: GPL-3.0-or-later
// Bernstein bases of one degree tabulated at fixed barycentric points: a tessellation evaluates
// every cell at the same lattice points, so the bases (and the index shifts of the derivatives)
// are computed once per pattern instead of once per point and cell. The results are the same
// doubles as EvaluateBezierTriangle's and PatchNormal's (same bases, same sums in the same order).
// Pure maths: no VTK.
#ifndef CTSplines_Kernel_BezierBasisTable_h
#define CTSplines_Kernel_BezierBasisTable_h

#include "BezierTriangle.h"

#include <vector>

namespace ctk
{
class BezierBasisTable
{
public:
  /// Degree n (1..MaxDegree) bases at the barycentric points `points`.
  BezierBasisTable(int n, const std::vector<Vec3>& points);
  int Degree() const { return this->N; }
  int NumberOfPoints() const { return static_cast<int>(this->Points.size()); }

  /// Position at point p of the net whose HomogeneousNet is H (EvaluateBezierTriangle's value).
  Vec3 Value(const Eigen::Vector4d* H, int p) const;
  /// PatchNormal at point p. HR: HomogeneousNet of R (a RelativeNet, for accuracy) with the
  /// net's weights w; at a singular tangent plane PatchNormal(R, w) takes the limit from inside.
  Vec3 Normal(const Eigen::Vector4d* HR, const Vec3* R, const double* w, int p) const;

private:
  int N = 0, Count = 0, CountLower = 0;
  std::vector<Vec3> Points;
  std::vector<double> Basis;      // Count degree-n Bernstein values per point
  std::vector<double> BasisLower; // CountLower degree-(n-1) values per point
  /// Per direction a: the canonical index of i + e_a for every degree-(n-1) multi-index i.
  std::vector<int> Shifted[3];
};

} // namespace ctk

#endif
