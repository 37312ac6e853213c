// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkReflectionLinesFilter.h"

#include "ErrorCapture.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>

namespace
{
using ctsplines_test::ErrorCapture;
using V = Eigen::Vector3d;

// Points of the plane x0 + a e1 + b e2 (random a, b) with the constant normal e1 x e2.
vtkSmartPointer<vtkPolyData> PlanePoints(const V& x0, const V& e1, const V& e2, int n = 200)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  const V normal = e1.cross(e2).normalized();
  vtkNew<vtkCellArray> verts;
  for (int i = 0; i < n; ++i)
  {
    const V x = x0 + coord(rng) * e1 + coord(rng) * e2;
    const vtkIdType id = points->InsertNextPoint(x.data());
    normals->InsertNextTuple(normal.data());
    verts->InsertNextCell(1, &id);
  }
  pd->SetPoints(points);
  pd->SetVerts(verts);
  pd->GetPointData()->AddArray(normals);
  return pd;
}

vtkSmartPointer<vtkPolyData> Reflect(vtkPolyData* input, const V& eye, const V& origin,
  const V& planeNormal, const V& direction, double spacing = 0.25)
{
  vtkNew<vtkReflectionLinesFilter> filter;
  filter->SetInputData(input);
  filter->SetEyePosition(eye.data());
  filter->SetLightPlaneOrigin(origin.data());
  filter->SetLightPlaneNormal(planeNormal.data());
  filter->SetLightLineDirection(direction.data());
  filter->SetSpacing(spacing);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

double Value(vtkPolyData* pd, const char* name, vtkIdType i)
{
  return pd->GetPointData()->GetArray(name)->GetComponent(i, 0);
}
} // namespace

// A plane mirrors the light lines by a central projection: with the light plane parallel to the
// surface, that is a homothety and the parameter is an affine function of position.
TEST(vtkReflectionLinesFilter, ParallelPlaneGivesAffineParameter)
{
  const V e1(1, 0.2, 0), e2(0, 1, 0.1);
  const auto plane = PlanePoints(V(0.1, -0.2, 0.3), e1, e2);
  const V normal = e1.cross(e2).normalized();
  const auto out =
    Reflect(plane, V(0.3, 0.5, 4.0), V(0.1, -0.2, 0.3) + 3 * normal, normal, V(1, 1, 0));
  const vtkIdType n = out->GetNumberOfPoints();
  Eigen::MatrixXd M(n, 4);
  Eigen::VectorXd p(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    out->GetPoint(i, x);
    M.row(i) << x[0], x[1], x[2], 1.0;
    p[i] = Value(out, "ReflectionLineParameter", i);
    EXPECT_NEAR(Value(out, "ReflectionLines", i), std::cos(2 * M_PI * p[i] / 0.25), 1e-12);
  }
  const Eigen::VectorXd fit = M.colPivHouseholderQr().solve(p);
  EXPECT_LT((M * fit - p).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(p.maxCoeff() - p.minCoeff(), 0.5); // several stripes
}

// Any plane: the reflection lines are still straight (the parameter is a ratio of affine
// functions of position, a projective map), but no longer parallel.
TEST(vtkReflectionLinesFilter, PlaneGivesStraightLines)
{
  const V e1(1, 0, 0.3), e2(0, 1, -0.2), x0(0, 0, 0);
  const auto plane = PlanePoints(x0, e1, e2);
  const auto out = Reflect(plane, V(0.5, -3, 3), V(0, 0, 4), V(0.2, 0.1, 1), V(1, 0.3, 0));
  // p (c . (a, b) + 1) = q . (a, b) + d: linear in (q, d, c) over the plane's coordinates.
  const vtkIdType n = out->GetNumberOfPoints();
  Eigen::MatrixXd M(n, 5);
  Eigen::VectorXd p(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    V x;
    out->GetPoint(i, x.data());
    const double a = x.x(), b = x.y(); // the plane is a graph over (x, y)
    p[i] = Value(out, "ReflectionLineParameter", i);
    M.row(i) << a, b, 1.0, -p[i] * a, -p[i] * b;
  }
  const Eigen::VectorXd fit = M.colPivHouseholderQr().solve(p);
  EXPECT_LT((M * fit - p).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT(std::abs(fit[3]) + std::abs(fit[4]), 1e-3); // genuinely projective
}

// Moving the whole scene rigidly changes nothing; moving the light plane's origin along the
// lines changes nothing; across the lines by Spacing shifts the parameter and keeps the stripes.
TEST(vtkReflectionLinesFilter, Invariance)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToFranke();
  source->SetResolution(6);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkBezierTriangleTessellator> tess;
  tess->SetInputConnection(spline->GetOutputPort());
  tess->SetSubdivisionLevel(4);
  tess->Update();
  vtkPolyData* surface = tess->GetOutput();
  const V eye(0.5, -2.5, 3.0), origin(0, 0, 2), planeNormal(0.1, 0.2, 1), dir(1, 0, 0);
  const auto ref = Reflect(surface, eye, origin, planeNormal, dir);

  const Eigen::Matrix3d R =
    Eigen::AngleAxisd(0.7, V(1, 2, 3).normalized()).toRotationMatrix();
  const V t(3, -1, 2);
  vtkNew<vtkPolyData> moved;
  moved->DeepCopy(surface);
  vtkDataArray* normals = moved->GetPointData()->GetArray("Normals");
  for (vtkIdType i = 0; i < moved->GetNumberOfPoints(); ++i)
  {
    V x, n;
    moved->GetPoint(i, x.data());
    normals->GetTuple(i, n.data());
    const V y = R * x + t, m = R * n;
    moved->GetPoints()->SetPoint(i, y.data());
    normals->SetTuple(i, m.data());
  }
  const auto rigid = Reflect(moved, R * eye + t, R * origin + t, R * planeNormal, R * dir);
  const V m = planeNormal.normalized().cross(dir).normalized();
  const V inPlane = m.cross(planeNormal.normalized()); // the lines' direction in the plane
  const auto along = Reflect(surface, eye, origin + 0.37 * inPlane, planeNormal, dir);
  const auto across = Reflect(surface, eye, origin + 0.25 * m, planeNormal, dir);
  double worst = 0;
  vtkIdType missed = 0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    const double p = Value(ref, "ReflectionLineParameter", i);
    const double s = Value(ref, "ReflectionLines", i);
    // Points whose reflected ray misses the plane are NaN in every variant.
    ASSERT_EQ(std::isnan(p), std::isnan(Value(rigid, "ReflectionLineParameter", i)));
    ASSERT_EQ(std::isnan(p), std::isnan(Value(across, "ReflectionLineParameter", i)));
    if (std::isnan(p))
    {
      ++missed;
      continue;
    }
    worst = std::max({ worst, std::abs(Value(rigid, "ReflectionLineParameter", i) - p),
      std::abs(Value(along, "ReflectionLineParameter", i) - p),
      std::abs(Value(across, "ReflectionLineParameter", i) - (p - 0.25)),
      std::abs(Value(across, "ReflectionLines", i) - s) });
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(surface->GetNumberOfPoints() - missed, 100); // enough points see a light line
}

// A mirror facing away from the light plane reflects no light line.
TEST(vtkReflectionLinesFilter, RaysAwayFromThePlaneSeeNothing)
{
  const auto plane = PlanePoints(V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), 20);
  const auto out = Reflect(plane, V(0, 0, 5), V(0, 0, -3), V(0, 0, 1), V(1, 0, 0));
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    EXPECT_TRUE(std::isnan(Value(out, "ReflectionLineParameter", i)));
    EXPECT_TRUE(std::isnan(Value(out, "ReflectionLines", i)));
  }
}

TEST(vtkReflectionLinesFilter, Isophotes)
{
  const V e1(1, 0, 1), e2(0, 1, 0);
  const auto plane = PlanePoints(V(0, 0, 0), e1, e2, 10);
  vtkNew<vtkReflectionLinesFilter> filter;
  filter->SetInputData(plane);
  filter->SetLightDirection(0, 0, 2);
  filter->SetIsophoteSpacing(30);
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    EXPECT_NEAR(Value(out, "IsophoteAngle", i), 45.0, 1e-12); // normal (-1, 0, 1)/sqrt(2)
    EXPECT_NEAR(Value(out, "Isophotes", i), std::cos(2 * M_PI * 45.0 / 30.0), 1e-12);
  }
  EXPECT_STREQ(out->GetPointData()->GetScalars()->GetName(), "ReflectionLines");
}


TEST(vtkReflectionLinesFilter, RejectsBadInput)
{
  int result = 1;
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkReflectionLinesFilter> f1;
  std::string m = ctsplines_test::RunCapturingErrors(f1, empty, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("empty input"), std::string::npos) << m;

  auto plane = PlanePoints(V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), 5);
  plane->GetPointData()->RemoveArray("Normals");
  vtkNew<vtkReflectionLinesFilter> f2;
  m = ctsplines_test::RunCapturingErrors(f2, plane, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("no point normals"), std::string::npos) << m;

  auto good = PlanePoints(V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), 5);
  vtkNew<vtkReflectionLinesFilter> f3;
  f3->SetLightLineDirection(0, 0, 3);
  m = ctsplines_test::RunCapturingErrors(f3, good, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("parallel to LightPlaneNormal"), std::string::npos) << m;

  vtkNew<vtkReflectionLinesFilter> f4;
  f4->SetEyePosition(0, std::nan(""), 1);
  m = ctsplines_test::RunCapturingErrors(f4, good, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("EyePosition is"), std::string::npos) << m;
  vtkNew<vtkReflectionLinesFilter> f5;
  f5->SetLightPlaneOrigin(1e300, 0, 0);
  m = ctsplines_test::RunCapturingErrors(f5, good, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("LightPlaneOrigin is"), std::string::npos) << m;
}

TEST(vtkReflectionLinesFilter, PrintSelf)
{
  vtkNew<vtkReflectionLinesFilter> filter;
  EXPECT_EQ(filter->GetSpacing(), 1.0);
  EXPECT_STREQ(filter->GetNormalsArrayName(), "Normals");
  filter->SetSpacing(0.5);
  std::ostringstream os;
  filter->Print(os);
  EXPECT_NE(os.str().find("Spacing: 0.5"), std::string::npos);
  EXPECT_NE(os.str().find("EyePosition: (0, 0, 10)"), std::string::npos);
}
