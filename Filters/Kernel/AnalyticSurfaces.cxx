// SPDX-License-Identifier: GPL-3.0-or-later
#include "AnalyticSurfaces.h"

#include <algorithm>
#include <cmath>

namespace ctk
{
const char* ToString(AnalyticSurface s)
{
  switch (s)
  {
    case AnalyticSurface::Plane:
      return "Plane";
    case AnalyticSurface::Quadratic:
      return "Quadratic";
    case AnalyticSurface::FarinCubic:
      return "FarinCubic";
    case AnalyticSurface::Franke:
      return "Franke";
    case AnalyticSurface::SineWave:
      return "SineWave";
    case AnalyticSurface::SphereOctant:
      return "SphereOctant";
  }
  return "Unknown";
}

std::array<Vec2, 3> SphereOctantDomain()
{
  return { Vec2(0.0, 0.0), Vec2(1.0, 0.0), Vec2(0.5, std::sqrt(3.0) / 2.0) };
}

void SphereOctantNet(std::array<Vec3, 15>& points, std::array<double, 15>& weights)
{
  const double s2 = std::sqrt(2.0), s3 = std::sqrt(3.0);
  const double a0 = 1.0 - 1.0 / s3;
  const double a1 = (3.0 + s3) / 6.0;
  const double a2 = 1.0 - (5.0 - s2) * (7.0 - s3) / 46.0;
  const double w400 = 4.0 * s3 * (s3 - 1.0), w310 = 3.0 * s2, w220 = 4.0;
  const double w211 = s2 * (3.0 + 2.0 * s2 - s3) / s3;
  const std::vector<std::array<int, 3>> exps = BezierExponents(4);
  for (size_t idx = 0; idx < exps.size(); ++idx)
  {
    const std::array<int, 3>& e = exps[idx];
    const int emax = std::max({ e[0], e[1], e[2] });
    Vec3 p = Vec3::Zero();
    double w = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      // Corner a is the unit vector along axis a; the pattern of exponents fixes the value.
      switch (emax)
      {
        case 4:
          p[a] = e[a] == 4 ? 1.0 : 0.0;
          w = w400;
          break;
        case 3:
          p[a] = e[a] == 3 ? 1.0 : (e[a] == 1 ? a0 : 0.0);
          w = w310;
          break;
        default:
          if (e[0] == 2 && e[1] == 2 || e[1] == 2 && e[2] == 2 || e[0] == 2 && e[2] == 2)
          {
            p[a] = e[a] == 2 ? a1 : 0.0;
            w = w220;
          }
          else
          {
            p[a] = e[a] == 2 ? 1.0 : a2;
            w = w211;
          }
      }
    }
    points[idx] = p;
    weights[idx] = w;
  }
}

SurfacePoint EvaluateAnalyticSurface(AnalyticSurface s, double x, double y)
{
  SurfacePoint r;
  double z = 0.0, zx = 0.0, zy = 0.0;
  switch (s)
  {
    case AnalyticSurface::Plane:
      z = 0.3 + 0.5 * x - 0.2 * y;
      zx = 0.5;
      zy = -0.2;
      break;
    case AnalyticSurface::Quadratic:
      z = 0.5 * x * x - 0.3 * x * y + 0.8 * y * y + 0.1 * x;
      zx = x - 0.3 * y + 0.1;
      zy = -0.3 * x + 1.6 * y;
      break;
    case AnalyticSurface::FarinCubic:
    {
      const double a = x - 0.3, b = y - 0.3;
      z = a * a * a + x * b * b - 0.1 * x;
      zx = 3.0 * a * a + b * b - 0.1;
      zy = 2.0 * x * b;
      break;
    }
    case AnalyticSurface::Franke:
    {
      const double X = 9.0 * x, Y = 9.0 * y;
      const double e1 = 0.75 * std::exp(-0.25 * (X - 2) * (X - 2) - 0.25 * (Y - 2) * (Y - 2));
      const double e2 = 0.75 * std::exp(-(X + 1) * (X + 1) / 49.0 - (Y + 1) / 10.0);
      const double e3 = 0.5 * std::exp(-0.25 * (X - 7) * (X - 7) - 0.25 * (Y - 3) * (Y - 3));
      const double e4 = 0.2 * std::exp(-(X - 4) * (X - 4) - (Y - 7) * (Y - 7));
      z = e1 + e2 + e3 - e4;
      // d/dx = 9 d/dX.
      zx = 9.0 * (e1 * (-0.5 * (X - 2)) + e2 * (-2.0 * (X + 1) / 49.0) + e3 * (-0.5 * (X - 7)) -
                   e4 * (-2.0 * (X - 4)));
      zy = 9.0 * (e1 * (-0.5 * (Y - 2)) + e2 * (-0.1) + e3 * (-0.5 * (Y - 3)) -
                   e4 * (-2.0 * (Y - 7)));
      break;
    }
    case AnalyticSurface::SineWave:
      z = 0.25 * std::sin(2.0 * M_PI * x);
      zx = 0.5 * M_PI * std::cos(2.0 * M_PI * x);
      zy = 0.0;
      break;
    case AnalyticSurface::SphereOctant:
    {
      std::array<Vec3, 15> P;
      std::array<double, 15> w;
      SphereOctantNet(P, w);
      const std::array<Vec2, 3> A = SphereOctantDomain();
      const Vec3 t = Barycentric(A[0], A[1], A[2], Vec2(x, y));
      const ParametricJet j = EvaluateOverDomain(4, P.data(), w.data(), A[0], A[1], A[2], t, 1);
      r.F = j.Value;
      r.Fu = j.Du;
      r.Fv = j.Dv;
      return r;
    }
  }
  r.F = Vec3(x, y, z);
  r.Fu = Vec3(1.0, 0.0, zx);
  r.Fv = Vec3(0.0, 1.0, zy);
  return r;
}

ParameterMesh RegularGridMesh(int n, GridDiagonal diagonal, double x0, double x1, double y0, double y1)
{
  ParameterMesh m;
  m.UV.reserve((n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      m.UV.emplace_back(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n);
    }
  }
  m.Triangles.reserve(6 * n * n);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const Id a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      const bool forward = diagonal == GridDiagonal::Forward ||
        (diagonal == GridDiagonal::Alternating && (i + j) % 2 == 0);
      const Id tris[2][3] = { { a, b, d }, { a, d, c } };
      const Id trisB[2][3] = { { a, b, c }, { b, d, c } };
      for (int s = 0; s < 2; ++s)
      {
        for (int l = 0; l < 3; ++l)
        {
          m.Triangles.push_back(forward ? tris[s][l] : trisB[s][l]);
        }
      }
    }
  }
  return m;
}

ParameterMesh RefinedTriangleMesh(const Vec2& A0, const Vec2& A1, const Vec2& A2, int level)
{
  // Lattice points (i, j) with i + j <= n, n = 2^level, at A0 + (i (A1 - A0) + j (A2 - A0)) / n.
  const int n = 1 << level;
  ParameterMesh m;
  auto id = [n](int i, int j) { return static_cast<Id>(j * (n + 1) - j * (j - 1) / 2 + i); };
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i + j <= n; ++i)
    {
      m.UV.push_back(A0 + (double(i) * (A1 - A0) + double(j) * (A2 - A0)) / n);
    }
  }
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i + j < n; ++i)
    {
      m.Triangles.insert(m.Triangles.end(), { id(i, j), id(i + 1, j), id(i, j + 1) });
      if (i + j + 1 < n)
      {
        m.Triangles.insert(m.Triangles.end(), { id(i + 1, j), id(i + 1, j + 1), id(i, j + 1) });
      }
    }
  }
  return m;
}

} // namespace ctk
