// SPDX-License-Identifier: GPL-3.0-or-later
#include "BezierBasisTable.h"

#include <cassert>

namespace ctk
{
BezierBasisTable::BezierBasisTable(int n, const std::vector<Vec3>& points)
  : N(n)
  , Count(BezierPointCount(n))
  , CountLower(BezierPointCount(n - 1))
  , Points(points)
{
  assert(n >= 1 && n <= MaxDegree);
  this->Basis.resize(this->Points.size() * this->Count);
  this->BasisLower.resize(this->Points.size() * this->CountLower);
  for (size_t p = 0; p < this->Points.size(); ++p)
  {
    Bernstein(n, this->Points[p], this->Basis.data() + p * this->Count);
    Bernstein(n - 1, this->Points[p], this->BasisLower.data() + p * this->CountLower);
  }
  for (int a = 0; a < 3; ++a)
  {
    this->Shifted[a].reserve(this->CountLower);
    for (int r = 0; r <= n - 1; ++r)
    {
      for (int k = 0; k <= r; ++k)
      {
        const int i = n - 1 - r, j = r - k;
        this->Shifted[a].push_back(BezierIndex(n, i + (a == 0), j + (a == 1)));
      }
    }
  }
}

Vec3 BezierBasisTable::Value(const Eigen::Vector4d* H, int p) const
{
  const double* B = this->Basis.data() + static_cast<size_t>(p) * this->Count;
  Eigen::Vector4d h = Eigen::Vector4d::Zero();
  for (int i = 0; i < this->Count; ++i)
  {
    h += B[i] * H[i];
  }
  return h.head<3>() / h[3];
}

Vec3 BezierBasisTable::Normal(const Eigen::Vector4d* HR, const Vec3* R, const double* w, int p) const
{
  const double* B = this->Basis.data() + static_cast<size_t>(p) * this->Count;
  const double* BL = this->BasisLower.data() + static_cast<size_t>(p) * this->CountLower;
  Eigen::Vector4d h = Eigen::Vector4d::Zero();
  for (int i = 0; i < this->Count; ++i)
  {
    h += B[i] * HR[i];
  }
  const double W = h[3];
  const Vec3 value = h.head<3>() / W;
  Vec3 DT[3];
  for (int a = 0; a < 3; ++a)
  {
    Eigen::Vector4d s = Eigen::Vector4d::Zero();
    const int* shifted = this->Shifted[a].data();
    for (int i = 0; i < this->CountLower; ++i)
    {
      s += BL[i] * HR[shifted[i]];
    }
    const Eigen::Vector4d hd = this->N * s;
    DT[a] = (hd.head<3>() - value * hd[3]) / W;
  }
  const Vec3 dr = DT[1] - DT[0], ds = DT[2] - DT[0];
  if (IsSingularTangentPlane(dr, ds))
  {
    return PatchNormal(this->N, R, w, this->Points[p]);
  }
  const Vec3 normal = dr.cross(ds);
  const double length = normal.norm();
  return length > 0 ? Vec3(normal / length) : normal;
}

} // namespace ctk
