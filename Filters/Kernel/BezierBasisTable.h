// SPDX-License-Identifier: GPL-3.0-or-later
// Bernstein bases of one degree tabulated at fixed barycentric points: a tessellation evaluates
// every cell at the same lattice points, so the bases and the derivative coefficients are
// computed once per pattern instead of once per point and cell. Evaluation is batched: a run of
// consecutive table points at a time, stored point-minor (structure of arrays), so that the sums
// over the control points vectorise over the points. Positions are EvaluateBezierTriangle's
// doubles, normals PatchNormal's to round-off (their sums are grouped differently). Pure maths:
// no VTK.
#ifndef CTSplines_Kernel_BezierBasisTable_h
#define CTSplines_Kernel_BezierBasisTable_h

#include "BezierTriangle.h"

#include <vector>

namespace ctk
{
/// A net's ordinates as scalar arrays, one per coordinate, for the batched evaluation:
/// homogeneous (w P and w) when rational, and the RelativeNet R = P - P[0] (for accurate
/// derivatives far from the origin).
struct ScalarNet
{
  int N = 0;
  const double* Weights = nullptr; // nullptr: polynomial
  double X[3][MaxBezierPoints];    // w P
  double RX[3][MaxBezierPoints];   // w R
  Vec3 R[MaxBezierPoints];         // R itself (singular tangent planes)
  /// Loads the degree-n net P with weights w (nullptr: polynomial; w must outlive the net).
  void Load(int n, const Vec3* P, const double* w);
};

class BezierBasisTable
{
public:
  /// Largest number of points of one batched call.
  static constexpr int Block = 64;
  using BlockArray = double[Block];

  /// Degree n (1..MaxDegree) bases at the barycentric points `points`.
  BezierBasisTable(int n, const std::vector<Vec3>& points);
  int Degree() const { return this->N; }
  int NumberOfPoints() const { return this->NP; }
  const Vec3& Point(int p) const { return this->Points[p]; }

  /// out[q] = sum_i B_i(t_{begin+q}) f[i], q < end - begin <= Block, for `components` ordinate
  /// arrays f[k] (one scalar per control point, canonical order, MaxBezierPoints apart) into
  /// out[k].
  void Combine(const double* f, int components, int begin, int end, BlockArray* out) const;

  /// Positions x[k][q] and unit normals normal[k][q] at points begin + q (end - begin <= Block)
  /// of the net, and the denominators W[q] = sum_i B_i w_i (w_i = 1 when polynomial) that
  /// data ordinates are divided by. x and W may be nullptr (normals only). The positions are
  /// EvaluateBezierTriangle's doubles (same sums in the same order); the normal is
  /// (x_r x x_s)/|x_r x x_s|, x_r = dx/dt1 - dx/dt0 and x_s = dx/dt2 - dx/dt0, PatchNormal's to
  /// round-off, or PatchNormal's limit from inside where the tangent plane is singular.
  void Evaluate(const ScalarNet& net, int begin, int end, BlockArray* x, BlockArray* normal,
    double* W) const;

private:
  // Sums of the coefficient table `table` (Count rows of NP) with the ordinates f.
  void Sum(const std::vector<double>& table, const double* f, int components, int begin,
    int end, BlockArray* out) const;

  int N = 0, Count = 0, NP = 0;
  std::vector<Vec3> Points;
  std::vector<double> Basis;      // B_i(t_p) at i * NP + p
  std::vector<double> DerivR;     // coefficients of x_r, same layout
  std::vector<double> DerivS;     // coefficients of x_s
  std::vector<double> BasisSum;   // sum_i B_i(t_p), summed as EvaluateBezierTriangle does
};

} // namespace ctk

#endif
