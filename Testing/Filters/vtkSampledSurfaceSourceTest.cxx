// SPDX-License-Identifier: GPL-3.0-or-later
// vtkSampledSurfaceSource: exact derivatives (checked against finite differences of the positions,
// not against the formulas), edge gradients, affine reparameterisation through the spline filter,
// the sphere octant, reproducible random meshes and parameter validation.
#include "AnalyticSurfaces.h"
#include "ErrorCapture.h"
#include "MeshTopology.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <vector>

namespace
{
using ctk::Vec2;
using ctk::Vec3;

/// A mesh read back from the source's output arrays.
struct Sampled
{
  std::vector<Vec3> F, Fu, Fv;
  std::vector<Vec2> UV;
  std::vector<ctk::Id> Tri;
  std::vector<double> EG; // 18 per triangle
  ctk::Id NumberOfTriangles() const { return static_cast<ctk::Id>(Tri.size() / 3); }
};

Sampled Read(vtkPolyData* pd)
{
  Sampled s;
  vtkDataArray* uv = pd->GetPointData()->GetArray("UV");
  vtkDataArray* du = pd->GetPointData()->GetArray("dFdu");
  vtkDataArray* dv = pd->GetPointData()->GetArray("dFdv");
  vtkDataArray* eg = pd->GetCellData()->GetArray("EdgeGradients");
  EXPECT_NE(uv, nullptr);
  EXPECT_NE(du, nullptr);
  EXPECT_NE(dv, nullptr);
  EXPECT_NE(eg, nullptr);
  if (!uv || !du || !dv || !eg)
  {
    return s;
  }
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    Vec3 p;
    pd->GetPoint(i, p.data());
    s.F.push_back(p);
    s.UV.emplace_back(uv->GetComponent(i, 0), uv->GetComponent(i, 1));
    s.Fu.emplace_back(du->GetComponent(i, 0), du->GetComponent(i, 1), du->GetComponent(i, 2));
    s.Fv.emplace_back(dv->GetComponent(i, 0), dv->GetComponent(i, 1), dv->GetComponent(i, 2));
  }
  vtkCellArray* polys = pd->GetPolys();
  vtkIdType n;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    EXPECT_EQ(n, 3);
    s.Tri.insert(s.Tri.end(), ids, ids + 3);
  }
  EXPECT_EQ(eg->GetNumberOfComponents(), 18);
  EXPECT_EQ(eg->GetNumberOfTuples(), pd->GetNumberOfPolys());
  for (vtkIdType c = 0; c < eg->GetNumberOfTuples(); ++c)
  {
    for (int k = 0; k < 18; ++k)
    {
      s.EG.push_back(eg->GetComponent(c, k));
    }
  }
  return s;
}

struct Config
{
  int Surface = vtkSampledSurfaceSource::Franke;
  int Domain = vtkSampledSurfaceSource::Grid;
  int Resolution = 8;
  unsigned Seed = 1;
  Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  Vec2 T = Vec2::Zero();
};

vtkSmartPointer<vtkSampledSurfaceSource> MakeSource(const Config& c)
{
  auto src = vtkSmartPointer<vtkSampledSurfaceSource>::New();
  src->SetSurface(c.Surface);
  src->SetDomain(c.Domain);
  src->SetResolution(c.Resolution);
  src->SetSeed(c.Seed);
  src->SetAffineMatrix(c.A(0, 0), c.A(0, 1), c.A(1, 0), c.A(1, 1));
  src->SetAffineTranslation(c.T.x(), c.T.y());
  return src;
}

Sampled Sample(const Config& c)
{
  auto src = MakeSource(c);
  src->Update();
  return Read(src->GetOutput());
}

/// A shear-and-stretch map with a reflection-free, far-from-identity matrix.
const Eigen::Matrix2d kA = (Eigen::Matrix2d() << 2.0, 0.7, -0.3, 1.5).finished();
const Vec2 kT(0.4, -1.2);

/// Largest trapezoid-rule residual |F1 - F0 - (J0 + J1) dU / 2| and midpoint-rule residual
/// |F1 - F0 - J_mid dU| (J_mid from EdgeGradients) over all local edges. Both are O(h^3) exactly
/// when J is the derivative of the positions with respect to the output UV.
std::pair<double, double> EdgeResiduals(const Sampled& s)
{
  double trap = 0.0, mid = 0.0;
  for (ctk::Id t = 0; t < s.NumberOfTriangles(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      const ctk::Id a = s.Tri[3 * t + l], b = s.Tri[3 * t + (l + 1) % 3];
      const Vec2 d = s.UV[b] - s.UV[a];
      const Vec3 dF = s.F[b] - s.F[a];
      const Vec3 jt = 0.5 * ((s.Fu[a] + s.Fu[b]) * d.x() + (s.Fv[a] + s.Fv[b]) * d.y());
      const double* g = &s.EG[18 * t + 6 * l];
      const Vec3 jm = Vec3(g[0], g[1], g[2]) * d.x() + Vec3(g[3], g[4], g[5]) * d.y();
      trap = std::max(trap, (dF - jt).norm());
      mid = std::max(mid, (dF - jm).norm());
    }
  }
  return { trap, mid };
}

double MaxAbs(vtkDataArray* a)
{
  double m = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    m = std::max(m, std::abs(a->GetComponent(i / a->GetNumberOfComponents(),
                      static_cast<int>(i % a->GetNumberOfComponents()))));
  }
  return m;
}

/// Max |difference| of two arrays of identical shape, relative to the first's max |value|.
double RelativeDifference(vtkDataArray* a, vtkDataArray* b)
{
  EXPECT_EQ(a->GetNumberOfTuples(), b->GetNumberOfTuples());
  EXPECT_EQ(a->GetNumberOfComponents(), b->GetNumberOfComponents());
  double d = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
    {
      d = std::max(d, std::abs(a->GetComponent(i, c) - b->GetComponent(i, c)));
    }
  }
  return d / MaxAbs(a);
}
} // namespace

TEST(SampledSurfaceSource, DefaultsAndOutputLayout)
{
  vtkNew<vtkSampledSurfaceSource> src;
  EXPECT_EQ(src->GetSurface(), vtkSampledSurfaceSource::Franke);
  EXPECT_EQ(src->GetDomain(), vtkSampledSurfaceSource::RandomDelaunay);
  EXPECT_EQ(src->GetNumberOfInputPorts(), 0);
  const double* A = src->GetAffineMatrix();
  EXPECT_EQ(A[0], 1.0);
  EXPECT_EQ(A[1], 0.0);
  EXPECT_EQ(A[2], 0.0);
  EXPECT_EQ(A[3], 1.0);
  src->Update();
  vtkPolyData* out = src->GetOutput();
  ASSERT_GT(out->GetNumberOfPolys(), 0);
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_DOUBLE);
  EXPECT_EQ(out->GetPointData()->GetTCoords(), out->GetPointData()->GetArray("UV"));
  EXPECT_EQ(out->GetPointData()->GetArray("UV")->GetNumberOfComponents(), 2);
  EXPECT_EQ(out->GetPointData()->GetArray("dFdu")->GetNumberOfComponents(), 3);
  EXPECT_EQ(out->GetPointData()->GetArray("dFdv")->GetNumberOfComponents(), 3);
  auto* surface = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("Surface"));
  ASSERT_NE(surface, nullptr);
  EXPECT_EQ(surface->GetValue(0), "Franke");
  std::ostringstream os;
  src->Print(os);
  EXPECT_NE(os.str().find("Domain: RandomDelaunay"), std::string::npos);
  EXPECT_NE(os.str().find("Seed: 1"), std::string::npos);
}

TEST(SampledSurfaceSource, MeshSizes)
{
  Config c;
  c.Domain = vtkSampledSurfaceSource::Grid;
  c.Resolution = 7;
  Sampled g = Sample(c);
  EXPECT_EQ(g.F.size(), 64u);
  EXPECT_EQ(g.NumberOfTriangles(), 2 * 49);
  c.Domain = vtkSampledSurfaceSource::EquilateralTriangle;
  c.Resolution = 3;
  Sampled e = Sample(c);
  EXPECT_EQ(e.NumberOfTriangles(), 64);
  EXPECT_EQ(e.F.size(), 45u); // (2^3 + 1)(2^3 + 2)/2
  for (int diag : { 0, 1, 2 })
  {
    auto src = MakeSource(Config());
    src->SetGridDiagonal(diag);
    src->Update();
    EXPECT_EQ(src->GetOutput()->GetNumberOfPolys(), 128);
  }
}

// Derivatives and edge gradients against finite differences of the positions along every mesh
// edge, with a non-trivial affine map: the residuals must be third order in h (ratio 8 per
// halving), which fails if UV, dFdu/dFdv or EdgeGradients are transformed inconsistently.
TEST(SampledSurfaceSource, DerivativesMatchFiniteDifferencesAlongEdges)
{
  struct Case
  {
    int Surface, Domain, Level;
  };
  const Case cases[] = { { vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::Grid, 32 },
    { vtkSampledSurfaceSource::FarinCubic, vtkSampledSurfaceSource::Grid, 4 },
    { vtkSampledSurfaceSource::SineWave, vtkSampledSurfaceSource::EquilateralTriangle, 3 },
    { vtkSampledSurfaceSource::SphereOctant, vtkSampledSurfaceSource::EquilateralTriangle, 3 } };
  for (const Case& k : cases)
  {
    SCOPED_TRACE(vtkSampledSurfaceSource::GetSurfaceName(k.Surface));
    Config c;
    c.Surface = k.Surface;
    c.Domain = k.Domain;
    c.A = kA;
    c.T = kT;
    c.Resolution = k.Level;
    const auto coarse = EdgeResiduals(Sample(c));
    c.Resolution = k.Domain == vtkSampledSurfaceSource::Grid ? 2 * k.Level : k.Level + 1;
    const auto fine = EdgeResiduals(Sample(c));
    EXPECT_GT(coarse.first / fine.first, 6.0) << coarse.first << " -> " << fine.first;
    EXPECT_GT(coarse.second / fine.second, 6.0) << coarse.second << " -> " << fine.second;
    EXPECT_LT(fine.first, 1e-2);
  }
  // Both rules are exact for quadratics along a line.
  for (int s : { vtkSampledSurfaceSource::Plane, vtkSampledSurfaceSource::Quadratic })
  {
    Config c;
    c.Surface = s;
    c.Domain = vtkSampledSurfaceSource::RandomDelaunay;
    c.Resolution = 50;
    c.A = kA;
    c.T = kT;
    const auto r = EdgeResiduals(Sample(c));
    EXPECT_LT(r.first, 1e-14);
    EXPECT_LT(r.second, 1e-14);
  }
}

TEST(SampledSurfaceSource, EdgeGradientsAreTheSurfaceGradientAtMidpoints)
{
  for (int s : { vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::SphereOctant })
  {
    Config c;
    c.Surface = s;
    c.Domain = vtkSampledSurfaceSource::RandomDelaunay;
    c.Resolution = 100;
    c.A = kA;
    c.T = kT;
    const Sampled m = Sample(c);
    ASSERT_GT(m.NumberOfTriangles(), 100);
    const Eigen::Matrix2d Ainv = kA.inverse();
    double err = 0.0;
    for (ctk::Id t = 0; t < m.NumberOfTriangles(); ++t)
    {
      for (int l = 0; l < 3; ++l)
      {
        const Vec2 mid =
          0.5 * (m.UV[m.Tri[3 * t + l]] + m.UV[m.Tri[3 * t + (l + 1) % 3]]);
        const Vec2 U = Ainv * (mid - kT);
        const ctk::SurfacePoint p =
          ctk::EvaluateAnalyticSurface(static_cast<ctk::AnalyticSurface>(s), U.x(), U.y());
        Eigen::Matrix<double, 3, 2> J;
        J << p.Fu, p.Fv;
        const Eigen::Matrix<double, 3, 2> Jp = J * Ainv;
        const double* g = &m.EG[18 * t + 6 * l];
        err = std::max(err, (Jp.col(0) - Vec3(g[0], g[1], g[2])).norm() / Jp.norm());
        err = std::max(err, (Jp.col(1) - Vec3(g[3], g[4], g[5])).norm() / Jp.norm());
      }
    }
    EXPECT_LT(err, 1e-13);
  }
}

// The study: CTi (and MGi) are invariant to affine reparameterisation, CTo (and MGo) are not.
// The control-point layout depends only on the mesh, so the nets compare one to one.
TEST(SampledSurfaceSource, AffineReparameterisationThroughTheSplineFilter)
{
  Config c;
  c.Domain = vtkSampledSurfaceSource::RandomDelaunay;
  c.Resolution = 200;
  auto original = MakeSource(c);
  c.A = kA;
  c.T = kT;
  auto mapped = MakeSource(c);
  original->Update();
  mapped->Update();
  // Positions unchanged, UV mapped.
  EXPECT_EQ(RelativeDifference(original->GetOutput()->GetPoints()->GetData(),
              mapped->GetOutput()->GetPoints()->GetData()),
    0.0);

  auto spline = [](vtkSampledSurfaceSource* src, int construction) {
    auto f = vtkSmartPointer<vtkCloughTocherSplineFilter>::New();
    f->SetInputConnection(src->GetOutputPort());
    f->SetConstruction(construction);
    f->SetSplitPointToBary();
    f->SetBoundaryModeToMidpoint();
    f->Update();
    return vtkSmartPointer<vtkUnstructuredGrid>(f->GetOutput());
  };
  for (int k : { vtkCloughTocherSplineFilter::CTi, vtkCloughTocherSplineFilter::MGi,
         vtkCloughTocherSplineFilter::CTo, vtkCloughTocherSplineFilter::MGo })
  {
    SCOPED_TRACE(vtkCloughTocherSplineFilter::GetConstructionName(k));
    auto a = spline(original, k);
    auto b = spline(mapped, k);
    ASSERT_GT(a->GetNumberOfPoints(), 0);
    ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
    // Domain points correspond through the map.
    vtkDataArray* uva = a->GetPointData()->GetArray("UV");
    vtkDataArray* uvb = b->GetPointData()->GetArray("UV");
    double uvErr = 0.0;
    for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
    {
      const Vec2 U(uva->GetComponent(i, 0), uva->GetComponent(i, 1));
      const Vec2 V(uvb->GetComponent(i, 0), uvb->GetComponent(i, 1));
      uvErr = std::max(uvErr, (kA * U + kT - V).norm());
    }
    EXPECT_LT(uvErr, 1e-12);
    const double d = RelativeDifference(a->GetPoints()->GetData(), b->GetPoints()->GetData());
    if (k == vtkCloughTocherSplineFilter::CTi || k == vtkCloughTocherSplineFilter::MGi)
    {
      EXPECT_LT(d, 1e-12);
    }
    else
    {
      EXPECT_GT(d, 1e-4);
    }
  }
}

TEST(SampledSurfaceSource, SphereOctantPointsOnTheUnitSphere)
{
  for (int domain :
    { vtkSampledSurfaceSource::EquilateralTriangle, vtkSampledSurfaceSource::RandomDelaunay })
  {
    Config c;
    c.Surface = vtkSampledSurfaceSource::SphereOctant;
    c.Domain = domain;
    c.Resolution = domain == vtkSampledSurfaceSource::EquilateralTriangle ? 4 : 300;
    c.A = kA;
    c.T = kT;
    const Sampled m = Sample(c);
    ASSERT_GT(m.F.size(), 100u);
    double radius = 0.0, tangent = 0.0, minCoord = 0.0;
    for (size_t i = 0; i < m.F.size(); ++i)
    {
      radius = std::max(radius, std::abs(m.F[i].norm() - 1.0));
      // The derivative of |F|^2 = 1 vanishes: both derivatives are tangent to the sphere.
      tangent = std::max({ tangent, std::abs(m.F[i].dot(m.Fu[i])), std::abs(m.F[i].dot(m.Fv[i])) });
      minCoord = std::min(minCoord, m.F[i].minCoeff());
    }
    EXPECT_LT(radius, 1e-14);
    EXPECT_LT(tangent, 1e-13);
    EXPECT_GT(minCoord, -1e-15); // inside the positive octant
  }
}

TEST(SampledSurfaceSource, RandomMeshesAreReproducible)
{
  Config c;
  c.Domain = vtkSampledSurfaceSource::RandomDelaunay;
  c.Resolution = 500;
  c.Seed = 42;
  const Sampled a = Sample(c);
  const Sampled b = Sample(c);
  ASSERT_EQ(a.UV.size(), b.UV.size());
  EXPECT_EQ(a.Tri, b.Tri);
  EXPECT_EQ(a.EG, b.EG);
  for (size_t i = 0; i < a.UV.size(); ++i)
  {
    ASSERT_EQ(a.UV[i], b.UV[i]);
    ASSERT_EQ(a.F[i], b.F[i]);
  }
  c.Seed = 43;
  const Sampled d = Sample(c);
  std::set<std::pair<double, double>> pa, pd;
  for (const Vec2& u : a.UV)
  {
    pa.insert({ u.x(), u.y() });
  }
  for (const Vec2& u : d.UV)
  {
    pd.insert({ u.x(), u.y() });
  }
  std::vector<std::pair<double, double>> common;
  std::set_intersection(pa.begin(), pa.end(), pd.begin(), pd.end(), std::back_inserter(common));
  // Only the deterministic boundary points are shared.
  EXPECT_LT(common.size(), 200u);
  EXPECT_GT(pa.size() - common.size(), 450u);
}

// Delaunay meshes: no zero-area triangles, consistently oriented, every point used, a manifold
// that covers the domain exactly (areas sum to the domain's).
TEST(SampledSurfaceSource, DelaunayMeshesAreValid)
{
  for (int s : { vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::SphereOctant })
  {
    for (int n : { 0, 1, 2, 10, 1000 })
    {
      for (unsigned seed : { 1u, 7u, 12345u })
      {
        SCOPED_TRACE(testing::Message() << vtkSampledSurfaceSource::GetSurfaceName(s) << " n=" << n
                                        << " seed=" << seed);
        Config c;
        c.Surface = s;
        c.Domain = vtkSampledSurfaceSource::RandomDelaunay;
        c.Resolution = n;
        c.Seed = seed;
        const Sampled m = Sample(c);
        const double domainArea = s == vtkSampledSurfaceSource::SphereOctant ? std::sqrt(3.0) / 4 : 1.0;
        double minArea = 1e300, total = 0.0;
        std::vector<int> used(m.UV.size(), 0);
        for (ctk::Id t = 0; t < m.NumberOfTriangles(); ++t)
        {
          const double a =
            0.5 * ctk::SignedArea2(m.UV[m.Tri[3 * t]], m.UV[m.Tri[3 * t + 1]], m.UV[m.Tri[3 * t + 2]]);
          minArea = std::min(minArea, a);
          total += a;
          for (int l = 0; l < 3; ++l)
          {
            used[m.Tri[3 * t + l]] = 1;
          }
        }
        EXPECT_GT(minArea, 1e-9 * domainArea);
        EXPECT_NEAR(total, domainArea, 1e-12);
        EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
        ctk::MeshTopology topo;
        const ctk::TopologyStatus st = ctk::BuildMeshTopology(static_cast<ctk::Id>(m.UV.size()),
          m.NumberOfTriangles(), m.Tri.data(), topo);
        ASSERT_TRUE(st.Ok) << st.Message;
        // Euler characteristic of a disc.
        EXPECT_EQ(static_cast<ctk::Id>(m.UV.size()) - static_cast<ctk::Id>(topo.Edges.size()) +
            m.NumberOfTriangles(),
          1);
      }
    }
  }
}

TEST(SampledSurfaceSource, BadParametersAreReported)
{
  struct Case
  {
    const char* Name;
    int Surface, Domain, Resolution;
    double A[4];
    const char* Expect;
  };
  const Case cases[] = {
    { "sphere on grid", vtkSampledSurfaceSource::SphereOctant, vtkSampledSurfaceSource::Grid, 4,
      { 1, 0, 0, 1 }, "SphereOctant" },
    { "grid resolution 0", vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::Grid, 0,
      { 1, 0, 0, 1 }, "Resolution 0" },
    { "grid too fine", vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::Grid, 5000,
      { 1, 0, 0, 1 }, "Resolution 5000" },
    { "level too high", vtkSampledSurfaceSource::Franke,
      vtkSampledSurfaceSource::EquilateralTriangle, 13, { 1, 0, 0, 1 }, "refinement level" },
    { "negative count", vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::RandomDelaunay,
      -1, { 1, 0, 0, 1 }, "random interior points" },
    { "singular matrix", vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::Grid, 4,
      { 1, 2, 2, 4 }, "singular" },
    { "NaN matrix", vtkSampledSurfaceSource::Franke, vtkSampledSurfaceSource::Grid, 4,
      { 1, 0, std::nan(""), 1 }, "singular or not finite" },
  };
  for (const Case& k : cases)
  {
    SCOPED_TRACE(k.Name);
    vtkNew<vtkSampledSurfaceSource> src;
    auto errors = ctsplines_test::ErrorCapture::Attach(src);
    auto pipelineErrors = ctsplines_test::ErrorCapture::Attach(src->GetExecutive());
    src->SetSurface(k.Surface);
    src->SetDomain(k.Domain);
    src->SetResolution(k.Resolution);
    src->SetAffineMatrix(k.A[0], k.A[1], k.A[2], k.A[3]);
    src->Update();
    EXPECT_EQ(errors->Count, 1);
    EXPECT_NE(errors->Message.find(k.Expect), std::string::npos) << errors->Message;
    EXPECT_EQ(src->GetOutput()->GetNumberOfPoints(), 0);
    // Fixing the parameters recovers.
    src->SetSurfaceToFranke();
    src->SetDomainToGrid();
    src->SetResolution(3);
    src->SetAffineMatrix(1, 0, 0, 1);
    src->Update();
    EXPECT_EQ(errors->Count, 1);
    EXPECT_EQ(src->GetOutput()->GetNumberOfPolys(), 18);
  }
}
