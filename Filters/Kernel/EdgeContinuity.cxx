// SPDX-License-Identifier: GPL-3.0-or-later
#include "EdgeContinuity.h"

#include "RuleA.h"

#include <algorithm>
#include <cmath>
#include <complex>

namespace ctk
{
namespace
{
// What is wrong with one side (named in the message), or empty; builds no string when valid.
std::string CheckSide(const EdgePatch& side, const char* name)
{
  auto prefix = [name]() { return std::string("side ") + name + ": "; };
  if (side.Degree < 1 || side.Degree > MaxDegree)
  {
    return prefix() + "degree " + std::to_string(side.Degree) + " is not in 1.." +
      std::to_string(MaxDegree);
  }
  if (!side.Points)
  {
    return prefix() + "no control points";
  }
  const int p = side.EdgeCorners[0], q = side.EdgeCorners[1];
  if (p < 0 || p > 2 || q < 0 || q > 2 || p == q)
  {
    return prefix() + "edge corners (" + std::to_string(p) + ", " + std::to_string(q) +
      ") are not two distinct corners 0..2";
  }
  const std::array<Vec2, 3>& D = side.Domain;
  const double longest = std::max(
    { (D[1] - D[0]).squaredNorm(), (D[2] - D[1]).squaredNorm(), (D[0] - D[2]).squaredNorm() });
  // Also false for NaN: the barycentric coordinates of Rule A divide by this area.
  if (!(std::abs(SignedArea2(D[0], D[1], D[2])) > 1e-13 * longest))
  {
    return prefix() + "the parameter triangle has zero area in (u, v)";
  }
  return std::string();
}

void ElevateTo(int from, int to, Vec3* P)
{
  Vec3 tmp[MaxBezierPoints];
  for (int n = from; n < to; ++n)
  {
    ElevateDegree(n, P, tmp);
    std::copy_n(tmp, BezierPointCount(n + 1), P);
  }
}

// Largest angle (radians) between the two sides' unit normals at `samples` points inside the
// edge (pa, qa) of A, which is (pb, qb) of B.
double LargestNormalAngle(
  int n, const Vec3* PA, int pa, int qa, const Vec3* PB, int pb, int qb, int samples)
{
  Vec3 RA[MaxBezierPoints], RB[MaxBezierPoints];
  RelativeNet(n, PA, RA);
  RelativeNet(n, PB, RB);
  double angle = 0;
  for (int k = 1; k <= samples; ++k)
  {
    const double s = double(k) / (samples + 1);
    Vec3 tA = Vec3::Zero(), tB = Vec3::Zero();
    tA[pa] = 1 - s, tA[qa] = s;
    tB[pb] = 1 - s, tB[qb] = s;
    const double cosine = PatchNormal(n, RA, nullptr, tA).dot(PatchNormal(n, RB, nullptr, tB));
    angle = std::max(angle, std::acos(std::max(-1.0, std::min(1.0, cosine))));
  }
  return angle;
}

// Eq. (7): both sides' blossoms at (Ui, U2, U3), Ui the edge corners, U2 and U3 the apexes (all
// in A's parameters).
double Eq7Jump(const Vec3* PA, const Vec2* DA, int pa, int qa, const Vec3* PB, const Vec2* DB,
  int apexB)
{
  const int apexA = 3 - pa - qa;
  double eq7 = 0;
  for (int i : { pa, qa })
  {
    const Vec2 U[3] = { DA[i], DA[apexA], DB[apexB] };
    Vec3 argsA[3], argsB[3];
    for (int a = 0; a < 3; ++a)
    {
      argsA[a] = Barycentric(DA[0], DA[1], DA[2], U[a]);
      argsB[a] = Barycentric(DB[0], DB[1], DB[2], U[a]);
    }
    eq7 = std::max(eq7, (Blossom(3, PA, argsA) - Blossom(3, PB, argsB)).norm());
  }
  return eq7;
}
} // namespace

void MapDomainOntoEdge(const Vec2* DA, int pa, int qa, Vec2* DB, int pb, int qb)
{
  const Vec2 Ap = DA[pa], Aq = DA[qa], Bp = DB[pb], Bq = DB[qb];
  const double scale = (Aq - Ap).norm();
  if ((Bp - Ap).norm() <= 1e-9 * scale && (Bq - Aq).norm() <= 1e-9 * scale)
  {
    return;
  }
  // Similarities of the plane as complex maps z -> a + c (z - b) or a + c conj(z - b).
  using C = std::complex<double>;
  auto z = [](const Vec2& v) { return C(v.x(), v.y()); };
  const C ap = z(Ap), bp = z(Bp);
  const C direct = (z(Aq) - ap) / (z(Bq) - bp), mirror = (z(Aq) - ap) / std::conj(z(Bq) - bp);
  const int apexA = 3 - pa - qa, apexB = 3 - pb - qb;
  const C apex = ap + direct * (z(DB[apexB]) - bp);
  const bool reflect =
    Cross2(Aq - Ap, DA[apexA] - Ap) * Cross2(Aq - Ap, Vec2(apex.real(), apex.imag()) - Ap) > 0;
  for (int i = 0; i < 3; ++i)
  {
    const C d = reflect ? ap + mirror * std::conj(z(DB[i]) - bp) : ap + direct * (z(DB[i]) - bp);
    DB[i] = Vec2(d.real(), d.imag());
  }
}

EdgeContinuity MeasureEdgeContinuity(
  const EdgePatch& A, const EdgePatch& B, const EdgeContinuityOptions& options)
{
  EdgeContinuity m;
  m.Error = CheckSide(A, "A");
  if (m.Error.empty())
  {
    m.Error = CheckSide(B, "B");
  }
  if (m.Error.empty() && options.G1Samples < 1)
  {
    m.Error = "G1Samples is " + std::to_string(options.G1Samples) + "; at least 1 is needed";
  }
  if (!m.Error.empty())
  {
    return m;
  }
  const int pa = A.EdgeCorners[0], qa = A.EdgeCorners[1];
  const int pb = B.EdgeCorners[0], qb = B.EdgeCorners[1];
  const Vec2 DA[3] = { A.Domain[0], A.Domain[1], A.Domain[2] };
  Vec2 DB[3] = { B.Domain[0], B.Domain[1], B.Domain[2] };
  MapDomainOntoEdge(DA, pa, qa, DB, pb, qb);

  // Rule A compares nets of one degree: elevate the lower one.
  const int n = std::max(A.Degree, B.Degree);
  Vec3 PA[MaxBezierPoints], PB[MaxBezierPoints];
  std::copy_n(A.Points, BezierPointCount(A.Degree), PA);
  std::copy_n(B.Points, BezierPointCount(B.Degree), PB);
  ElevateTo(A.Degree, n, PA);
  ElevateTo(B.Degree, n, PB);

  double jumps[3] = { 0, 0, 0 };
  RuleAJumps(n, PA, DA, PB, DB, std::min(n, 2), jumps);
  m.C0Gap = jumps[0];
  m.C1Jump = jumps[1];
  m.C2Jump = jumps[2];
  m.G1Angle = LargestNormalAngle(n, PA, pa, qa, PB, pb, qb, options.G1Samples) * 180.0 / M_PI;
  if (options.Eq7 && n == 3)
  {
    m.C2JumpEq7 = Eq7Jump(PA, DA, pa, qa, PB, DB, 3 - pb - qb);
  }
  return m;
}

} // namespace ctk
