// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierBasisTable.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace ctk
{
void ScalarNet::Load(int n, const Vec3* P, const double* w)
{
  this->N = n;
  this->Weights = w;
  RelativeNet(n, P, this->R);
  for (int i = 0; i < BezierPointCount(n); ++i)
  {
    const double wi = w ? w[i] : 1.0;
    for (int k = 0; k < 3; ++k)
    {
      this->X[k][i] = wi * P[i][k];
      this->RX[k][i] = wi * this->R[i][k];
    }
  }
}

BezierBasisTable::BezierBasisTable(int n, const std::vector<Vec3>& points)
  : N(n)
  , Count(BezierPointCount(n))
  , NP(static_cast<int>(points.size()))
  , Points(points)
{
  assert(n >= 1 && n <= MaxDegree);
  const size_t size = static_cast<size_t>(this->Count) * this->NP;
  this->Basis.resize(size);
  this->DerivR.resize(size);
  this->DerivS.resize(size);
  this->BasisSum.assign(this->NP, 0.0);
  const std::vector<std::array<int, 3>> e = BezierExponents(n);
  double B[MaxBezierPoints], BL[MaxBezierPoints];
  for (int p = 0; p < this->NP; ++p)
  {
    Bernstein(n, this->Points[p], B);
    Bernstein(n - 1, this->Points[p], BL);
    for (int i = 0; i < this->Count; ++i)
    {
      // d B_i / dt_a = n B^{n-1}_{i - e_a} (zero when exponent a of i is zero).
      const auto lower = [&](int a) {
        return e[i][a] == 0 ? 0.0
                            : n * BL[BezierIndex(n - 1, e[i][0] - (a == 0), e[i][1] - (a == 1))];
      };
      const size_t at = static_cast<size_t>(i) * this->NP + p;
      this->Basis[at] = B[i];
      this->BasisSum[p] += B[i];
      this->DerivR[at] = lower(1) - lower(0);
      this->DerivS[at] = lower(2) - lower(0);
    }
  }
}

namespace
{
// Sum with K ordinate arrays, four points at a time held in registers over all control points
// (no store and reload per term). Every point's sum runs over i in order from zero: the same
// doubles as a pointwise sum. The points are explicit vectors (GCC and Clang vector extensions):
// left to itself GCC vectorised over i instead and spilled the accumulators.
template <int K>
void SumPoints(const double* table, size_t stride, int count, const double* f, int m,
  BezierBasisTable::BlockArray* out)
{
  constexpr int lanes = 4;
  int q = 0;
#if defined(__GNUC__)
  // Pairs: SSE2's width (GCC keeps wider generic vectors in memory when AVX is off); loaded and
  // stored unaligned in place (copies into arrays kept the accumulators in memory).
  typedef double Pair __attribute__((vector_size(2 * sizeof(double)), aligned(8), may_alias));
  for (; q + lanes <= m; q += lanes)
  {
    Pair acc[K][2];
    const Pair* b = reinterpret_cast<const Pair*>(table + q);
    for (int k = 0; k < K; ++k)
    {
      acc[k][0] = 0.0 + b[0] * f[k * MaxBezierPoints];
      acc[k][1] = 0.0 + b[1] * f[k * MaxBezierPoints];
    }
    for (int i = 1; i < count; ++i)
    {
      b = reinterpret_cast<const Pair*>(table + i * stride + q);
      const Pair b0 = b[0], b1 = b[1];
      for (int k = 0; k < K; ++k)
      {
        const double fi = f[k * MaxBezierPoints + i];
        acc[k][0] += b0 * fi;
        acc[k][1] += b1 * fi;
      }
    }
    for (int k = 0; k < K; ++k)
    {
      Pair* to = reinterpret_cast<Pair*>(out[k] + q);
      to[0] = acc[k][0];
      to[1] = acc[k][1];
    }
  }
#endif
  for (; q < m; ++q)
  {
    for (int k = 0; k < K; ++k)
    {
      double sum = 0.0 + table[q] * f[k * MaxBezierPoints];
      for (int i = 1; i < count; ++i)
      {
        sum += table[i * stride + q] * f[k * MaxBezierPoints + i];
      }
      out[k][q] = sum;
    }
  }
}
} // namespace

void BezierBasisTable::Sum(const std::vector<double>& table, const double* f, int components,
  int begin, int end, BlockArray* out) const
{
  assert(end - begin <= Block && begin >= 0 && end <= this->NP);
  const double* t = table.data() + begin;
  const size_t stride = static_cast<size_t>(this->NP);
  for (int k = 0; k < components; k += 3)
  {
    const double* fk = f + k * MaxBezierPoints;
    switch (std::min(3, components - k))
    {
      case 1:
        SumPoints<1>(t, stride, this->Count, fk, end - begin, out + k);
        break;
      case 2:
        SumPoints<2>(t, stride, this->Count, fk, end - begin, out + k);
        break;
      default:
        SumPoints<3>(t, stride, this->Count, fk, end - begin, out + k);
    }
  }
}

void BezierBasisTable::Combine(
  const double* f, int components, int begin, int end, BlockArray* out) const
{
  this->Sum(this->Basis, f, components, begin, end, out);
}

void BezierBasisTable::Evaluate(
  const ScalarNet& net, int begin, int end, BlockArray* x, BlockArray* normal, double* W) const
{
  assert(net.N == this->N);
  const int m = end - begin;
  const bool rational = net.Weights != nullptr;
  // The denominators, as EvaluateBezierTriangle's: sum B_i w_i, or sum B_i when polynomial.
  double w[Block];
  if (rational)
  {
    this->Sum(this->Basis, net.Weights, 1, begin, end, &w);
  }
  else
  {
    std::copy_n(this->BasisSum.data() + begin, m, w);
  }
  if (W)
  {
    std::copy_n(w, m, W);
  }
  if (x)
  {
    // The same sums in the same order as EvaluateBezierTriangle: the same doubles.
    this->Sum(this->Basis, net.X[0], 3, begin, end, x);
    for (int k = 0; k < 3; ++k)
    {
      for (int q = 0; q < m; ++q)
      {
        x[k][q] /= w[q];
      }
    }
  }
  BlockArray dr[3], ds[3];
  this->Sum(this->DerivR, net.RX[0], 3, begin, end, dr);
  this->Sum(this->DerivS, net.RX[0], 3, begin, end, ds);
  if (rational)
  {
    // x_r = (g_r - v g_r^w) / W with v = sum B w R / W the relative position; the common
    // factor 1/W is left out: the normal is normalised and the singularity test scale-free.
    BlockArray v[3], gw[2];
    this->Sum(this->Basis, net.RX[0], 3, begin, end, v);
    this->Sum(this->DerivR, net.Weights, 1, begin, end, &gw[0]);
    this->Sum(this->DerivS, net.Weights, 1, begin, end, &gw[1]);
    for (int k = 0; k < 3; ++k)
    {
      for (int q = 0; q < m; ++q)
      {
        const double value = v[k][q] / w[q];
        dr[k][q] -= value * gw[0][q];
        ds[k][q] -= value * gw[1][q];
      }
    }
  }
  bool singular[Block];
  for (int q = 0; q < m; ++q)
  {
    const double nx = dr[1][q] * ds[2][q] - dr[2][q] * ds[1][q];
    const double ny = dr[2][q] * ds[0][q] - dr[0][q] * ds[2][q];
    const double nz = dr[0][q] * ds[1][q] - dr[1][q] * ds[0][q];
    const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
    const double scale = dr[0][q] * dr[0][q] + dr[1][q] * dr[1][q] + dr[2][q] * dr[2][q] +
      ds[0][q] * ds[0][q] + ds[1][q] * ds[1][q] + ds[2][q] * ds[2][q];
    singular[q] = !(length > 1e-12 * scale); // IsSingularTangentPlane
    const double divisor = length > 0 ? length : 1.0; // PatchNormal's division
    normal[0][q] = nx / divisor;
    normal[1][q] = ny / divisor;
    normal[2][q] = nz / divisor;
  }
  for (int q = 0; q < m; ++q)
  {
    if (singular[q])
    {
      const Vec3 limit = PatchNormal(this->N, net.R, net.Weights, this->Points[begin + q]);
      for (int k = 0; k < 3; ++k)
      {
        normal[k][q] = limit[k];
      }
    }
  }
}

} // namespace ctk
