// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSampledSurfaceSource.h"

#include "AnalyticSurfaces.h"
#include "DelaunayTriangulation.h"
#include "CTSplinesArrayRanges.h"
#include "CTSplinesSMP.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStringArray.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSampledSurfaceSource);

namespace
{
constexpr int MaxGridResolution = 4096;
constexpr int MaxTriangleLevel = 12;
constexpr int MaxRandomPoints = 10000000;

/// splitmix64 (Steele, Lea, Flood 2014): fixed integer arithmetic, hence identical sequences on
/// every platform, unlike std::uniform_real_distribution.
class SplitMix64
{
public:
  explicit SplitMix64(std::uint64_t seed)
    : State(seed)
  {
  }
  std::uint64_t Next()
  {
    std::uint64_t z = (this->State += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1): the top 53 bits scaled exactly.
  double Uniform() { return static_cast<double>(this->Next() >> 11) * 0x1.0p-53; }

private:
  std::uint64_t State;
};

/// Corners, evenly spaced boundary points and `count` seeded random interior points of the
/// convex polygon `corners`, triangulated by ctk::DelaunayTriangulation. Unused points (exact
/// duplicates) and zero-area triangles are removed; triangles are oriented counter-clockwise.
std::string RandomDelaunayMesh(const std::vector<ctk::Vec2>& corners, int count,
  std::uint64_t seed, ctk::ParameterMesh& mesh)
{
  const int nc = static_cast<int>(corners.size());
  // Boundary spacing about that of the interior points (sqrt(count) per unit length).
  const int segments = std::max(1, static_cast<int>(std::lround(std::sqrt(double(count)))));
  std::vector<ctk::Vec2> uv;
  for (int c = 0; c < nc; ++c)
  {
    const ctk::Vec2& a = corners[c];
    const ctk::Vec2& b = corners[(c + 1) % nc];
    for (int s = 0; s < segments; ++s)
    {
      uv.push_back(a + (b - a) * (double(s) / segments));
    }
  }
  // Interior points stay a quarter of the boundary spacing inside, so that no sliver forms
  // against the boundary: sample the polygon shrunk towards its centroid.
  ctk::Vec2 centroid = ctk::Vec2::Zero();
  for (const ctk::Vec2& c : corners)
  {
    centroid += c / nc;
  }
  double inradius = std::numeric_limits<double>::max(); // distance from centroid to the edges
  for (int c = 0; c < nc; ++c)
  {
    const ctk::Vec2 e = corners[(c + 1) % nc] - corners[c];
    inradius = std::min(inradius,
      std::abs(ctk::SignedArea2(corners[c], corners[(c + 1) % nc], centroid)) / e.norm());
  }
  double minEdge = std::numeric_limits<double>::max();
  for (int c = 0; c < nc; ++c)
  {
    minEdge = std::min(minEdge, (corners[(c + 1) % nc] - corners[c]).norm());
  }
  const double shrink = 1.0 - 0.25 * minEdge / segments / inradius;
  std::vector<double> areas(nc);
  double total = 0.0;
  for (int k = 0; k < nc; ++k)
  {
    areas[k] = std::abs(ctk::SignedArea2(centroid, corners[k], corners[(k + 1) % nc]));
    total += areas[k];
  }
  SplitMix64 rng(seed);
  for (int i = 0; i < count; ++i)
  {
    // Uniform in the fan triangle (centroid, corner c, corner c + 1), chosen by area.
    double r = rng.Uniform() * total;
    int c = 0;
    while (c < nc - 1 && r >= areas[c])
    {
      r -= areas[c++];
    }
    double s = rng.Uniform(), t = rng.Uniform();
    if (s + t > 1.0)
    {
      s = 1.0 - s;
      t = 1.0 - t;
    }
    const ctk::Vec2 p = centroid + s * (corners[c] - centroid) +
      t * (corners[(c + 1) % nc] - centroid);
    uv.push_back(centroid + shrink * (p - centroid));
  }

  std::vector<double> xy(2 * uv.size());
  for (size_t i = 0; i < uv.size(); ++i)
  {
    xy[2 * i] = uv[i].x();
    xy[2 * i + 1] = uv[i].y();
  }
  std::vector<ctk::Id> triangles;
  try
  {
    triangles = ctk::DelaunayTriangulation(xy);
  }
  catch (const std::exception& e)
  {
    return std::string("the Delaunay triangulation of ") + std::to_string(uv.size()) +
      " points failed: " + e.what();
  }
  if (triangles.empty())
  {
    return "the Delaunay triangulation has no triangles";
  }

  double domainArea2 = 0.0;
  for (int k = 1; k + 1 < nc; ++k)
  {
    domainArea2 += std::abs(ctk::SignedArea2(corners[0], corners[k], corners[k + 1]));
  }
  std::vector<ctk::Id> newId(uv.size(), -1);
  mesh.UV.clear();
  mesh.Triangles.clear();
  for (size_t k = 0; k < triangles.size(); k += 3)
  {
    ctk::Id t[3] = { triangles[k], triangles[k + 1], triangles[k + 2] };
    const double a2 = ctk::SignedArea2(uv[t[0]], uv[t[1]], uv[t[2]]);
    if (std::abs(a2) <= 1e-12 * domainArea2)
    {
      continue;
    }
    if (a2 < 0.0)
    {
      std::swap(t[1], t[2]);
    }
    for (ctk::Id v : t)
    {
      if (newId[v] < 0)
      {
        newId[v] = static_cast<ctk::Id>(mesh.UV.size());
        mesh.UV.push_back(uv[v]);
      }
      mesh.Triangles.push_back(newId[v]);
    }
  }
  return std::string();
}

void AddFieldString(vtkFieldData* fd, const char* name, const char* value)
{
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}
} // namespace

vtkSampledSurfaceSource::vtkSampledSurfaceSource()
{
  this->SetNumberOfInputPorts(0);
}

vtkSampledSurfaceSource::~vtkSampledSurfaceSource() = default;

const char* vtkSampledSurfaceSource::GetSurfaceName(int surface)
{
  return ctk::ToString(static_cast<ctk::AnalyticSurface>(surface));
}

const char* vtkSampledSurfaceSource::GetDomainName(int domain)
{
  switch (domain)
  {
    case Grid:
      return "Grid";
    case EquilateralTriangle:
      return "EquilateralTriangle";
    case RandomDelaunay:
      return "RandomDelaunay";
  }
  return "Unknown";
}

namespace
{
// The parameter mesh of the source's Domain and Resolution; an error message or "".
std::string MakeParameterMesh(vtkSampledSurfaceSource* self, ctk::ParameterMesh& mesh)
{
  const std::array<ctk::Vec2, 3> tri = ctk::SphereOctantDomain();
  const int res = self->GetResolution();
  switch (self->GetDomain())
  {
    case vtkSampledSurfaceSource::Grid:
      mesh = ctk::RegularGridMesh(res, static_cast<ctk::GridDiagonal>(self->GetGridDiagonal()));
      return {};
    case vtkSampledSurfaceSource::EquilateralTriangle:
      mesh = ctk::RefinedTriangleMesh(tri[0], tri[1], tri[2], res);
      return {};
    default:
    {
      const std::vector<ctk::Vec2> corners = self->GetSurface() == vtkSampledSurfaceSource::SphereOctant
        ? std::vector<ctk::Vec2>(tri.begin(), tri.end())
        : std::vector<ctk::Vec2>{ { 0.0, 0.0 }, { 1.0, 0.0 }, { 1.0, 1.0 }, { 0.0, 1.0 } };
      return RandomDelaunayMesh(corners, res, self->GetSeed(), mesh);
    }
  }
}
} // namespace

int vtkSampledSurfaceSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!output)
  {
    vtkErrorMacro(<< "missing output data object");
    return 0;
  }

  // 1. Parameters.
  const auto surface = static_cast<ctk::AnalyticSurface>(this->Surface);
  const int res = this->Resolution;
  if (this->Domain == Grid && this->Surface == SphereOctant)
  {
    vtkErrorMacro(<< "the SphereOctant surface is parametrised over the equilateral triangle "
                     "only: use the EquilateralTriangle or RandomDelaunay domain, not Grid");
    return 0;
  }
  const struct
  {
    int Lo, Hi;
    const char* Meaning;
  } range[3] = { { 1, MaxGridResolution, "cells per side" },
    { 0, MaxTriangleLevel, "refinement level (4^level triangles)" },
    { 0, MaxRandomPoints, "number of random interior points" } };
  const auto& rr = range[this->Domain];
  if (res < rr.Lo || res > rr.Hi)
  {
    vtkErrorMacro(<< "Resolution " << res << " out of range for the " << GetDomainName(this->Domain)
                  << " domain: it is the " << rr.Meaning << ", in [" << rr.Lo << ", " << rr.Hi
                  << "]");
    return 0;
  }
  Eigen::Matrix2d A;
  A << this->AffineMatrix[0], this->AffineMatrix[1], this->AffineMatrix[2], this->AffineMatrix[3];
  const ctk::Vec2 shift(this->AffineTranslation[0], this->AffineTranslation[1]);
  const double scale = A.cwiseAbs().maxCoeff();
  if (!A.allFinite() || !shift.allFinite() || !(std::abs(A.determinant()) > 1e-12 * scale * scale))
  {
    vtkErrorMacro(<< "AffineMatrix (" << A(0, 0) << ", " << A(0, 1) << ", " << A(1, 0) << ", "
                  << A(1, 1) << ") with translation (" << shift.x() << ", " << shift.y()
                  << ") is singular or not finite");
    return 0;
  }
  const Eigen::Matrix2d Ainv = A.inverse();

  // 2. The parameter mesh, from the kernel's generators or Delaunay.
  ctk::ParameterMesh mesh;
  const std::string error = MakeParameterMesh(this, mesh);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  this->UpdateProgress(0.3);

  // 3. Sample. Every value is computed independently, so the result does not depend on the SMP
  // backend or thread count.
  const vtkIdType nV = static_cast<vtkIdType>(mesh.UV.size());
  const vtkIdType nT = static_cast<vtkIdType>(mesh.NumberOfTriangles());
  // Chain rule for U = A^{-1} (U' - t): dF/dU' = J A^{-1}.
  auto jacobian = [&](const ctk::SurfacePoint& p, double* fu, double* fv) {
    for (int c = 0; c < 3; ++c)
    {
      fu[c] = p.Fu[c] * Ainv(0, 0) + p.Fv[c] * Ainv(1, 0);
      fv[c] = p.Fu[c] * Ainv(0, 1) + p.Fv[c] * Ainv(1, 1);
    }
  };
  vtkNew<vtkDoubleArray> xyz, uv, du, dv, eg;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(nV);
  uv->SetName("UV");
  uv->SetNumberOfComponents(2);
  uv->SetNumberOfTuples(nV);
  du->SetName("dFdu");
  du->SetNumberOfComponents(3);
  du->SetNumberOfTuples(nV);
  dv->SetName("dFdv");
  dv->SetNumberOfComponents(3);
  dv->SetNumberOfTuples(nV);
  eg->SetName("EdgeGradients");
  eg->SetNumberOfComponents(18);
  eg->SetNumberOfTuples(nT);
  double* px = xyz->GetPointer(0);
  double* puv = uv->GetPointer(0);
  double* pdu = du->GetPointer(0);
  double* pdv = dv->GetPointer(0);
  double* peg = eg->GetPointer(0);
  ctsplines::ParallelFor(0, nV, ctsplines::GrainForEvaluations, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const ctk::Vec2& U = mesh.UV[i];
      const ctk::SurfacePoint p = ctk::EvaluateAnalyticSurface(surface, U.x(), U.y());
      const ctk::Vec2 Up = A * U + shift;
      for (int c = 0; c < 3; ++c)
      {
        px[3 * i + c] = p.F[c];
      }
      puv[2 * i] = Up.x();
      puv[2 * i + 1] = Up.y();
      jacobian(p, pdu + 3 * i, pdv + 3 * i);
    }
  });
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nT + 1);
  connectivity->SetNumberOfTuples(3 * nT);
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  ctsplines::ParallelFor(0, nT, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType t = b; t < e; ++t)
    {
      off[t] = 3 * t;
      for (int l = 0; l < 3; ++l)
      {
        const ctk::Id p0 = mesh.Triangles[3 * t + l], p1 = mesh.Triangles[3 * t + (l + 1) % 3];
        conn[3 * t + l] = p0;
        // The affine map keeps midpoints, so the original midpoint corresponds to the output's.
        const ctk::Vec2 mid = 0.5 * (mesh.UV[p0] + mesh.UV[p1]);
        const ctk::SurfacePoint p = ctk::EvaluateAnalyticSurface(surface, mid.x(), mid.y());
        jacobian(p, peg + 18 * t + 6 * l, peg + 18 * t + 6 * l + 3);
      }
    }
  });
  off[nT] = 3 * nT;
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);

  vtkNew<vtkPoints> points;
  points->SetData(xyz);
  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetPointData()->AddArray(uv);
  output->GetPointData()->SetTCoords(uv);
  output->GetPointData()->AddArray(du);
  output->GetPointData()->AddArray(dv);
  output->GetCellData()->AddArray(eg);
  AddFieldString(output->GetFieldData(), "Surface", GetSurfaceName(this->Surface));
  AddFieldString(output->GetFieldData(), "Domain", GetDomainName(this->Domain));
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSampledSurfaceSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Surface: " << GetSurfaceName(this->Surface) << "\n";
  os << indent << "Domain: " << GetDomainName(this->Domain) << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "GridDiagonal: "
     << (this->GridDiagonal == Forward ? "Forward"
                                       : (this->GridDiagonal == Backward ? "Backward" : "Alternating"))
     << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "AffineMatrix: (" << this->AffineMatrix[0] << ", " << this->AffineMatrix[1]
     << "; " << this->AffineMatrix[2] << ", " << this->AffineMatrix[3] << ")\n";
  os << indent << "AffineTranslation: (" << this->AffineTranslation[0] << ", "
     << this->AffineTranslation[1] << ")\n";
}
