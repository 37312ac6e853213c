// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkApproximationErrorFilter.h"

#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"

#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkUnstructuredGrid.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
using ctsplines_test::ErrorCapture;

vtkSmartPointer<vtkUnstructuredGrid> MakeSpline(const ctk::ParameterMesh& mesh,
  ctk::AnalyticSurface surface, int construction = vtkCloughTocherSplineFilter::CTi)
{
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputData(ctsplines_test::MakeSampledPolyData(mesh, surface));
  spline->SetConstruction(construction);
  spline->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(spline->GetOutput());
  return out;
}

vtkSmartPointer<vtkPolyData> Tessellate(vtkDataSet* spline, int level)
{
  vtkNew<vtkBezierTriangleTessellator> t;
  t->SetInputData(spline);
  t->SetSubdivisionLevel(level);
  t->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(t->GetOutput());
  return out;
}

double Field(vtkPolyData* pd, const char* name)
{
  vtkDataArray* a = pd->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? a->GetTuple1(0) : std::nan("");
}

// Runs the filter; returns its output (a copy) or null when it failed.
vtkSmartPointer<vtkPolyData> RunFilter(vtkDataSet* spline, vtkPolyData* reference, int mode,
  int level = 4, int referenceLevel = 1, std::string* errors = nullptr)
{
  vtkNew<vtkApproximationErrorFilter> f;
  auto capture = ErrorCapture::Attach(f);
  f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, capture);
  f->SetInputData(spline);
  if (reference)
  {
    f->SetReferenceData(reference);
  }
  f->SetMode(mode);
  f->SetSubdivisionLevel(level);
  f->SetReferenceSampleLevel(referenceLevel);
  f->Update();
  if (errors)
  {
    *errors = capture->Message;
  }
  if (capture->Count > 0)
  {
    return nullptr;
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}

// Independent point-to-triangle distance: the interior projection when it falls inside, else the
// nearest of the three edges.
double SegmentDistance(const ctk::Vec3& p, const ctk::Vec3& a, const ctk::Vec3& b)
{
  const ctk::Vec3 d = b - a;
  const double s = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + s * d)).norm();
}

double TriangleDistance(const ctk::Vec3& p, const ctk::Vec3& a, const ctk::Vec3& b, const ctk::Vec3& c)
{
  double best = std::min({ SegmentDistance(p, a, b), SegmentDistance(p, b, c), SegmentDistance(p, c, a) });
  const ctk::Vec3 n = (b - a).cross(c - a);
  if (n.squaredNorm() > 0)
  {
    const ctk::Vec3 q = p - n * ((p - a).dot(n) / n.squaredNorm());
    if ((b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
      (a - c).cross(q - c).dot(n) >= 0)
    {
      best = std::min(best, (p - q).norm());
    }
  }
  return best;
}

ctk::Vec3 Point(vtkPolyData* pd, vtkIdType i)
{
  double x[3];
  pd->GetPoint(i, x);
  return ctk::Vec3(x[0], x[1], x[2]);
}

double BruteDistance(const ctk::Vec3& p, vtkPolyData* mesh)
{
  double best = std::numeric_limits<double>::infinity();
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    mesh->GetCellPoints(c, n, ids);
    best = std::min(best, TriangleDistance(p, Point(mesh, ids[0]), Point(mesh, ids[1]), Point(mesh, ids[2])));
  }
  return best;
}

vtkSmartPointer<vtkPolyData> Translated(vtkPolyData* pd, const ctk::Vec3& d)
{
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(pd);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const ctk::Vec3 p = Point(out, i) + d;
    out->GetPoints()->SetPoint(i, p.data());
  }
  return out;
}

const ctk::ParameterMesh& Grid()
{
  static const ctk::ParameterMesh m = ctk::RegularGridMesh(4, ctk::GridDiagonal::Alternating);
  return m;
}
} // namespace

TEST(vtkApproximationErrorFilter, ParametricZeroOnQuadraticData)
{
  // Every construction reproduces a quadratic; the reference samples it on another mesh.
  for (int c : { vtkCloughTocherSplineFilter::CTo, vtkCloughTocherSplineFilter::FO,
         vtkCloughTocherSplineFilter::Quartic })
  {
    auto spline = MakeSpline(Grid(), ctk::AnalyticSurface::Quadratic, c);
    auto reference = ctsplines_test::MakeSampledPolyData(
      ctk::RegularGridMesh(13, ctk::GridDiagonal::Backward), ctk::AnalyticSurface::Quadratic);
    auto out = RunFilter(spline, reference, vtkApproximationErrorFilter::Parametric);
    ASSERT_NE(out, nullptr);
    EXPECT_EQ(out->GetNumberOfPoints(), reference->GetNumberOfPoints());
    EXPECT_LT(Field(out, "MaxError"), 1e-12) << c;
    EXPECT_LT(Field(out, "RMSError"), 1e-12);
    EXPECT_EQ(Field(out, "NumberOfReferenceSamples"), reference->GetNumberOfPoints());
    EXPECT_GT(Field(out, "BoundingBoxDiagonal"), 1.4);
  }
}

TEST(vtkApproximationErrorFilter, MeshDistanceZeroOnQuadraticData)
{
  // Two constructions of quadratic data are the same polynomial pieces, so the tessellation of
  // one lies on the other (and vice versa).
  auto a = MakeSpline(Grid(), ctk::AnalyticSurface::Quadratic, vtkCloughTocherSplineFilter::CTo);
  auto b = MakeSpline(Grid(), ctk::AnalyticSurface::Quadratic, vtkCloughTocherSplineFilter::Ka);
  auto out = RunFilter(a, Tessellate(b, 4), vtkApproximationErrorFilter::MeshDistance, 4, 3);
  ASSERT_NE(out, nullptr);
  EXPECT_LT(Field(out, "MaxError"), 1e-12);
  EXPECT_LT(Field(out, "HausdorffReferenceToSpline"), 1e-12);
  vtkDataArray* error = out->GetPointData()->GetArray("Error");
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->GetNumberOfTuples(), out->GetNumberOfPoints());
}

TEST(vtkApproximationErrorFilter, MeshDistanceMatchesBruteForce)
{
  auto spline = MakeSpline(ctk::RegularGridMesh(2, ctk::GridDiagonal::Forward), ctk::AnalyticSurface::Franke);
  // Reference: a coarse, differently triangulated, perturbed sampling of the same surface.
  auto reference = ctsplines_test::MakeSampledPolyData(
    ctk::RegularGridMesh(5, ctk::GridDiagonal::Backward), ctk::AnalyticSurface::Franke);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-0.05, 0.05);
  for (vtkIdType i = 0; i < reference->GetNumberOfPoints(); ++i)
  {
    const ctk::Vec3 p = Point(reference, i) + ctk::Vec3(U(rng), U(rng), U(rng));
    reference->GetPoints()->SetPoint(i, p.data());
  }
  const int level = 3, referenceLevel = 3;
  auto out = RunFilter(spline, reference, vtkApproximationErrorFilter::MeshDistance, level, referenceLevel);
  ASSERT_NE(out, nullptr);
  vtkDataArray* error = out->GetPointData()->GetArray("Error");
  ASSERT_NE(error, nullptr);
  double maxS = 0, sum2 = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const double d = BruteDistance(Point(out, i), reference);
    EXPECT_NEAR(error->GetTuple1(i), d, 1e-12) << i;
    maxS = std::max(maxS, d);
    sum2 += d * d;
  }
  // Reference samples: vertices and the points (i, j, k)/3 of every triangle.
  double maxR = 0;
  for (vtkIdType c = 0; c < reference->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    reference->GetCellPoints(c, n, ids);
    for (int i = 0; i <= referenceLevel; ++i)
    {
      for (int j = 0; i + j <= referenceLevel; ++j)
      {
        const int k = referenceLevel - i - j;
        const ctk::Vec3 p = (i * Point(reference, ids[0]) + j * Point(reference, ids[1]) +
                              k * Point(reference, ids[2])) /
          referenceLevel;
        maxR = std::max(maxR, BruteDistance(p, out));
      }
    }
  }
  EXPECT_NEAR(Field(out, "HausdorffSplineToReference"), maxS, 1e-12);
  EXPECT_NEAR(Field(out, "HausdorffReferenceToSpline"), maxR, 1e-12);
  EXPECT_NEAR(Field(out, "MaxError"), std::max(maxS, maxR), 1e-12);
  EXPECT_NEAR(Field(out, "RMSError"), std::sqrt(sum2 / out->GetNumberOfPoints()), 1e-12);
  const double diag = Field(out, "BoundingBoxDiagonal");
  double b[6];
  reference->GetBounds(b);
  EXPECT_NEAR(diag, std::sqrt(std::pow(b[1] - b[0], 2) + std::pow(b[3] - b[2], 2) + std::pow(b[5] - b[4], 2)), 1e-14);
  EXPECT_NEAR(Field(out, "RelativeMaxError"), Field(out, "MaxError") / diag, 1e-15);
  EXPECT_NEAR(Field(out, "RelativeRMSError"), Field(out, "RMSError") / diag, 1e-15);
  EXPECT_NEAR(Field(out, "RelativeHausdorffSplineToReference"), maxS / diag, 1e-12);
  EXPECT_NEAR(Field(out, "RelativeHausdorffReferenceToSpline"), maxR / diag, 1e-12);
  EXPECT_GT(maxS, 1e-3); // not a trivial case
}

TEST(vtkApproximationErrorFilter, SwappingSplinesSwapsTheOneSidedDistances)
{
  // With vertex samples only and the same subdivision level, the spline samples of one run are
  // the reference samples of the other.
  auto a = MakeSpline(Grid(), ctk::AnalyticSurface::Franke, vtkCloughTocherSplineFilter::CTo);
  auto b = MakeSpline(Grid(), ctk::AnalyticSurface::Franke, vtkCloughTocherSplineFilter::FO);
  const int level = 5;
  auto ab = RunFilter(a, Tessellate(b, level), vtkApproximationErrorFilter::MeshDistance, level);
  auto ba = RunFilter(b, Tessellate(a, level), vtkApproximationErrorFilter::MeshDistance, level);
  ASSERT_NE(ab, nullptr);
  ASSERT_NE(ba, nullptr);
  EXPECT_GT(Field(ab, "MaxError"), 1e-4);
  EXPECT_NEAR(Field(ab, "HausdorffSplineToReference"), Field(ba, "HausdorffReferenceToSpline"), 1e-15);
  EXPECT_NEAR(Field(ab, "HausdorffReferenceToSpline"), Field(ba, "HausdorffSplineToReference"), 1e-15);
  EXPECT_NEAR(Field(ab, "MaxError"), Field(ba, "MaxError"), 1e-15);
}

TEST(vtkApproximationErrorFilter, KnownOffsetAlongThePlaneNormal)
{
  // Plane z = 0.3 + 0.5 x - 0.2 y: every sample of a copy moved by d along the normal is at
  // distance d from the spline (which reproduces the plane), both ways and parametrically.
  const double d = 0.0375;
  const ctk::Vec3 n = ctk::Vec3(-0.5, 0.2, 1.0).normalized();
  auto spline = MakeSpline(Grid(), ctk::AnalyticSurface::Plane);
  auto moved = Translated(Tessellate(spline, 3), d * n);
  auto mesh = RunFilter(spline, moved, vtkApproximationErrorFilter::MeshDistance, 6, 2);
  ASSERT_NE(mesh, nullptr);
  EXPECT_NEAR(Field(mesh, "HausdorffSplineToReference"), d, 1e-12);
  EXPECT_NEAR(Field(mesh, "HausdorffReferenceToSpline"), d, 1e-12);
  EXPECT_NEAR(Field(mesh, "RMSError"), d, 1e-12);
  vtkDataArray* error = mesh->GetPointData()->GetArray("Error");
  double lo = 1e300, hi = 0;
  for (vtkIdType i = 0; i < error->GetNumberOfTuples(); ++i)
  {
    lo = std::min(lo, error->GetTuple1(i));
    hi = std::max(hi, error->GetTuple1(i));
  }
  EXPECT_NEAR(lo, d, 1e-12);
  EXPECT_NEAR(hi, d, 1e-12);

  auto sampled = Translated(ctsplines_test::MakeSampledPolyData(
                              ctk::RegularGridMesh(9, ctk::GridDiagonal::Forward), ctk::AnalyticSurface::Plane),
    d * n);
  auto param = RunFilter(spline, sampled, vtkApproximationErrorFilter::Parametric);
  ASSERT_NE(param, nullptr);
  EXPECT_NEAR(Field(param, "MaxError"), d, 1e-12);
  EXPECT_NEAR(Field(param, "RMSError"), d, 1e-12);
}

TEST(vtkApproximationErrorFilter, ParametricSkipsPointsOutsideTheDomain)
{
  auto spline = MakeSpline(Grid(), ctk::AnalyticSurface::Quadratic);
  // Parameters on [0, 2]^2: three quarters of the points fall outside [0, 1]^2.
  auto reference = ctsplines_test::MakeSampledPolyData(
    ctk::RegularGridMesh(8, ctk::GridDiagonal::Forward, 0.0, 2.0, 0.0, 2.0), ctk::AnalyticSurface::Quadratic);
  auto out = RunFilter(spline, reference, vtkApproximationErrorFilter::Parametric);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(Field(out, "NumberOfReferenceSamples"), 25.0); // the 5 x 5 points in [0, 1]^2
  EXPECT_LT(Field(out, "MaxError"), 1e-12);
}

TEST(vtkApproximationErrorFilter, BadInputIsReported)
{
  auto spline = MakeSpline(Grid(), ctk::AnalyticSurface::Quadratic);
  auto reference = ctsplines_test::MakeSampledPolyData(Grid(), ctk::AnalyticSurface::Quadratic);
  std::string errors;

  EXPECT_EQ(RunFilter(spline, nullptr, vtkApproximationErrorFilter::MeshDistance, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("no reference"), std::string::npos) << errors;

  vtkNew<vtkPolyData> empty;
  EXPECT_EQ(RunFilter(spline, empty, vtkApproximationErrorFilter::Parametric, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("no points"), std::string::npos) << errors;

  // A reference without UV in Parametric mode.
  auto noUV = vtkSmartPointer<vtkPolyData>::New();
  noUV->DeepCopy(reference);
  noUV->GetPointData()->RemoveArray("UV");
  EXPECT_EQ(RunFilter(spline, noUV, vtkApproximationErrorFilter::Parametric, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("'UV'"), std::string::npos) << errors;

  // Non-finite reference point.
  auto nan = vtkSmartPointer<vtkPolyData>::New();
  nan->DeepCopy(reference);
  nan->GetPoints()->SetPoint(3, std::nan(""), 0, 0);
  EXPECT_EQ(RunFilter(spline, nan, vtkApproximationErrorFilter::MeshDistance, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("point 3"), std::string::npos) << errors;

  // Lines are not a triangle mesh.
  auto lines = vtkSmartPointer<vtkPolyData>::New();
  lines->SetPoints(reference->GetPoints());
  vtkNew<vtkCellArray> cells;
  const vtkIdType line[2] = { 0, 1 };
  cells->InsertNextCell(2, line);
  lines->SetLines(cells);
  EXPECT_EQ(RunFilter(spline, lines, vtkApproximationErrorFilter::MeshDistance, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("line"), std::string::npos) << errors;

  // Reference triangles without area.
  auto flat = vtkSmartPointer<vtkPolyData>::New();
  flat->DeepCopy(reference);
  for (vtkIdType i = 0; i < flat->GetNumberOfPoints(); ++i)
  {
    flat->GetPoints()->SetPoint(i, 0.5, 0.5, 0.5);
  }
  EXPECT_EQ(RunFilter(spline, flat, vtkApproximationErrorFilter::MeshDistance, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("positive area"), std::string::npos) << errors;

  // A spline input that is not made of Bézier triangles (the sampled mesh itself).
  EXPECT_EQ(RunFilter(reference, reference, vtkApproximationErrorFilter::MeshDistance, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("tessellating"), std::string::npos) << errors;
  EXPECT_EQ(RunFilter(reference, reference, vtkApproximationErrorFilter::Parametric, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("evaluating"), std::string::npos) << errors;

  // An empty spline.
  vtkNew<vtkUnstructuredGrid> none;
  EXPECT_EQ(RunFilter(none, reference, vtkApproximationErrorFilter::MeshDistance, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("no cells"), std::string::npos) << errors;

  // No reference parameter inside the spline's domain.
  auto outside = vtkSmartPointer<vtkPolyData>::New();
  outside->DeepCopy(reference);
  vtkDataArray* uv = outside->GetPointData()->GetArray("UV");
  for (vtkIdType i = 0; i < uv->GetNumberOfTuples(); ++i)
  {
    uv->SetTuple2(i, 5.0 + uv->GetComponent(i, 0), 5.0);
  }
  EXPECT_EQ(RunFilter(spline, outside, vtkApproximationErrorFilter::Parametric, 4, 1, &errors), nullptr);
  EXPECT_NE(errors.find("none of the reference"), std::string::npos) << errors;
}

TEST(vtkApproximationErrorFilter, PrintSelfAndParameters)
{
  vtkNew<vtkApproximationErrorFilter> f;
  EXPECT_EQ(f->GetMode(), vtkApproximationErrorFilter::MeshDistance);
  f->SetModeToParametric();
  f->SetSubdivisionLevel(0);
  EXPECT_EQ(f->GetSubdivisionLevel(), 1);
  f->SetReferenceUVArrayName("T");
  std::ostringstream os;
  f->PrintSelf(os, vtkIndent());
  EXPECT_NE(os.str().find("Mode: Parametric"), std::string::npos);
  EXPECT_NE(os.str().find("ReferenceUVArrayName: T"), std::string::npos);
  EXPECT_EQ(f->GetReference(), nullptr);
}
