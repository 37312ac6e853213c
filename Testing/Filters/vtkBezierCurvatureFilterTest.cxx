// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierCurvatureFilter.h"

#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"

#include "vtkCellType.h"
#include "vtkCurvatures.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>

namespace
{
using ctsplines_test::ErrorCapture;

vtkSmartPointer<vtkUnstructuredGrid> Spline(vtkAlgorithm* source)
{
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  spline->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(spline->GetOutput());
  return out;
}

vtkSmartPointer<vtkPolyData> Curvature(vtkDataSet* input, int level, bool merge = false)
{
  vtkNew<vtkBezierCurvatureFilter> filter;
  filter->SetInputData(input);
  filter->SetSubdivisionLevel(level);
  filter->SetMergePoints(merge);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

double Value(vtkPolyData* pd, const char* name, vtkIdType i, int component = 0)
{
  return pd->GetPointData()->GetArray(name)->GetComponent(i, component);
}

// The single rational quartic patch of the sphere octant, with the spec's corner order.
vtkSmartPointer<vtkUnstructuredGrid> OctantCell()
{
  std::array<ctk::Vec3, 15> P;
  std::array<double, 15> w;
  ctk::SphereOctantNet(P, w);
  const std::vector<int> order = ctk::VtkBezierTriangleOrder(4);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("RationalWeights");
  std::vector<vtkIdType> ids;
  for (int p = 0; p < 15; ++p)
  {
    points->InsertNextPoint(P[order[p]].data());
    weights->InsertNextValue(w[order[p]]);
    ids.push_back(p);
  }
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(weights);
  grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 15, ids.data());
  return grid;
}

vtkSmartPointer<vtkSampledSurfaceSource> OctantSource(int level)
{
  auto source = vtkSmartPointer<vtkSampledSurfaceSource>::New();
  source->SetSurfaceToSphereOctant();
  source->SetDomainToEquilateralTriangle();
  source->SetResolution(level);
  return source;
}
} // namespace

// The spline of quadratic data reproduces z = q(x, y) exactly, so must its curvatures.
TEST(vtkBezierCurvatureFilter, ExactOnParaboloid)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToQuadratic();
  source->SetDomainToGrid();
  source->SetResolution(4);
  const auto surface = Curvature(Spline(source), 5);
  ASSERT_GT(surface->GetNumberOfPoints(), 0);
  double worstK = 0, worstH = 0, worstMaxMin = 0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    double x[3];
    surface->GetPoint(i, x);
    // z = 0.5 x^2 - 0.3 x y + 0.8 y^2 + 0.1 x
    const double zx = x[0] - 0.3 * x[1] + 0.1, zy = -0.3 * x[0] + 1.6 * x[1];
    const double zxx = 1.0, zxy = -0.3, zyy = 1.6, W2 = 1 + zx * zx + zy * zy;
    const double K = (zxx * zyy - zxy * zxy) / (W2 * W2);
    // Upward normal (-zx, -zy, 1)/W: the surface bends towards it, so H < 0 by our convention.
    double H = -((1 + zx * zx) * zyy - 2 * zx * zy * zxy + (1 + zy * zy) * zxx) /
      (2 * std::pow(W2, 1.5));
    if (Value(surface, "Normals", i, 2) < 0)
    {
      H = -H;
    }
    worstK = std::max(worstK, std::abs(Value(surface, "Gauss_Curvature", i) - K) / std::abs(K));
    worstH = std::max(worstH, std::abs(Value(surface, "Mean_Curvature", i) - H) / std::abs(H));
    const double kmax = Value(surface, "Maximum_Curvature", i);
    const double kmin = Value(surface, "Minimum_Curvature", i);
    worstMaxMin = std::max(
      { worstMaxMin, std::abs(kmax * kmin - K), std::abs(0.5 * (kmax + kmin) - H) });
    EXPECT_GE(kmax, kmin);
  }
  // Relative; the nets are evaluated relative to their first point (2.7e-12 before).
  EXPECT_LT(worstK, 1e-12);
  EXPECT_LT(worstH, 1e-12);
  EXPECT_LT(worstMaxMin, 1e-10);
  for (const char* name : { "UV", "Normals", "Maximum_Curvature_Direction",
         "Minimum_Curvature_Direction" })
  {
    EXPECT_NE(surface->GetPointData()->GetArray(name), nullptr) << name;
  }
  EXPECT_NE(surface->GetCellData()->GetArray("BezierCellId"), nullptr);
  EXPECT_NE(surface->GetCellData()->GetArray("MacroTriangleId"), nullptr);
  EXPECT_NE(surface->GetCellData()->GetArray("MicroTriangleId"), nullptr);
}

// The rational octant lies on the unit sphere: K = 1, H = 1 with its outward normal.
TEST(vtkBezierCurvatureFilter, ExactOnRationalSphereOctant)
{
  const auto surface = Curvature(OctantCell(), 12);
  double worst = 0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    ctk::Vec3 x, n, d1, d2;
    surface->GetPoint(i, x.data());
    for (int c = 0; c < 3; ++c)
    {
      n[c] = Value(surface, "Normals", i, c);
      d1[c] = Value(surface, "Maximum_Curvature_Direction", i, c);
      d2[c] = Value(surface, "Minimum_Curvature_Direction", i, c);
    }
    EXPECT_NEAR(x.norm(), 1.0, 1e-12);
    EXPECT_NEAR(n.dot(x), 1.0, 1e-10) << "normal not outward at point " << i;
    EXPECT_NEAR(d1.norm(), 1.0, 1e-12);
    EXPECT_NEAR(d1.dot(n), 0.0, 1e-10);
    EXPECT_NEAR(d2.dot(n), 0.0, 1e-10);
    worst = std::max({ worst, std::abs(Value(surface, "Gauss_Curvature", i) - 1),
      std::abs(Value(surface, "Mean_Curvature", i) - 1),
      std::abs(Value(surface, "Maximum_Curvature", i) - 1),
      std::abs(Value(surface, "Minimum_Curvature", i) - 1) });
  }
  EXPECT_LT(worst, 1e-10);
}

// The C1 spline of the octant: curvature converges to that of the unit sphere under refinement.
TEST(vtkBezierCurvatureFilter, SplineOfOctantConverges)
{
  double previousK = 1e300, previousH = 1e300;
  for (int level = 1; level <= 4; ++level)
  {
    const auto surface = Curvature(Spline(OctantSource(level)), 6);
    double errK = 0, errH = 0;
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    {
      errK = std::max(errK, std::abs(Value(surface, "Gauss_Curvature", i) - 1));
      errH = std::max(errH, std::abs(Value(surface, "Mean_Curvature", i) - 1));
    }
    std::printf("octant spline level %d: max |K - 1| = %.3e, max |H - 1| = %.3e\n", level, errK,
      errH);
    EXPECT_LT(errK, previousK) << "level " << level;
    EXPECT_LT(errH, previousH) << "level " << level;
    previousK = errK;
    previousH = errH;
  }
  EXPECT_LT(previousH, 0.5);
}

// vtkCurvatures' discrete estimates on a fine tessellation approach the exact values.
TEST(vtkBezierCurvatureFilter, AgreesWithDiscreteCurvaturesInTheLimit)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToQuadratic();
  source->SetDomainToGrid();
  source->SetResolution(3);
  const auto spline = Spline(source);
  double previousH = 1e300, previousK = 1e300;
  for (int level : { 4, 8, 16 })
  {
    const auto surface = Curvature(spline, level, true);
    const vtkIdType n = surface->GetNumberOfPoints();
    std::vector<double> exactH(n), exactK(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      exactH[i] = Value(surface, "Mean_Curvature", i);
      exactK[i] = Value(surface, "Gauss_Curvature", i);
    }
    vtkNew<vtkCurvatures> discrete;
    discrete->SetInputData(surface);
    discrete->SetCurvatureTypeToMean();
    discrete->Update();
    vtkNew<vtkCurvatures> discreteK;
    discreteK->SetInputData(surface);
    discreteK->SetCurvatureTypeToGaussian();
    discreteK->Update();
    vtkDataArray* h = discrete->GetOutput()->GetPointData()->GetArray("Mean_Curvature");
    vtkDataArray* k = discreteK->GetOutput()->GetPointData()->GetArray("Gauss_Curvature");
    double sumH = 0, sumK = 0;
    int count = 0;
    for (vtkIdType i = 0; i < n; ++i)
    {
      double x[3];
      surface->GetPoint(i, x);
      // Away from the boundary, where the discrete estimates are not defined.
      if (x[0] < 0.2 || x[0] > 0.8 || x[1] < 0.2 || x[1] > 0.8)
      {
        continue;
      }
      sumH += std::abs(h->GetTuple1(i) - exactH[i]);
      sumK += std::abs(k->GetTuple1(i) - exactK[i]);
      ++count;
    }
    ASSERT_GT(count, 0);
    const double meanH = sumH / count, meanK = sumK / count;
    std::printf("level %2d: mean |H_vtk - H| = %.3e, mean |K_vtk - K| = %.3e (%d points)\n",
      level, meanH, meanK, count);
    EXPECT_LT(meanH, previousH);
    EXPECT_LT(meanK, previousK);
    previousH = meanH;
    previousK = meanK;
  }
  EXPECT_LT(previousH, 0.05);
  EXPECT_LT(previousK, 0.05);
}

// MergePoints reproduces the tessellator's conforming numbering; the default keeps cells apart.
TEST(vtkBezierCurvatureFilter, MergePointsMatchesTessellator)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToFranke();
  source->SetDomainToRandomDelaunay();
  source->SetResolution(20);
  const auto spline = Spline(source);
  const int L = 5;
  vtkNew<vtkBezierTriangleTessellator> tess;
  tess->SetInputData(spline);
  tess->SetSubdivisionLevel(L);
  tess->Update();
  vtkPolyData* reference = tess->GetOutput();
  const auto merged = Curvature(spline, L, true);
  ASSERT_EQ(merged->GetNumberOfPoints(), reference->GetNumberOfPoints());
  ASSERT_EQ(merged->GetNumberOfCells(), reference->GetNumberOfCells());
  for (vtkIdType i = 0; i < merged->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    merged->GetPoint(i, a);
    reference->GetPoint(i, b);
    for (int c = 0; c < 3; ++c)
    {
      ASSERT_EQ(a[c], b[c]) << "point " << i;
      ASSERT_NEAR(Value(merged, "Normals", i, c), Value(reference, "Normals", i, c), 1e-14);
    }
  }
  const auto separate = Curvature(spline, L, false);
  EXPECT_EQ(separate->GetNumberOfPoints(), spline->GetNumberOfCells() * (L + 1) * (L + 2) / 2);
  EXPECT_EQ(separate->GetNumberOfCells(), spline->GetNumberOfCells() * L * L);

  // A C1 spline has curvature jumps across edges: points at the same place differ in K.
  double jump = 0;
  std::map<std::array<long long, 3>, vtkIdType> seen;
  for (vtkIdType i = 0; i < separate->GetNumberOfPoints(); ++i)
  {
    double x[3];
    separate->GetPoint(i, x);
    const std::array<long long, 3> key{ std::llround(x[0] * 1e8), std::llround(x[1] * 1e8),
      std::llround(x[2] * 1e8) };
    const auto found = seen.emplace(key, i);
    if (!found.second)
    {
      const vtkIdType j = found.first->second;
      jump = std::max(jump,
        std::abs(Value(separate, "Mean_Curvature", i) - Value(separate, "Mean_Curvature", j)));
    }
  }
  EXPECT_GT(jump, 1e-6);
}

TEST(vtkBezierCurvatureFilter, ThreadCountDoesNotChangeResults)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToFranke();
  source->SetDomainToRandomDelaunay();
  source->SetResolution(40);
  const auto spline = Spline(source);
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(1);
  const auto one = Curvature(spline, 6, true);
  vtkSMPTools::Initialize(4);
  const auto four = Curvature(spline, 6, true);
  for (const char* name : { "Gauss_Curvature", "Mean_Curvature", "Maximum_Curvature_Direction" })
  {
    vtkDataArray* a = one->GetPointData()->GetArray(name);
    vtkDataArray* b = four->GetPointData()->GetArray(name);
    ASSERT_EQ(a->GetNumberOfValues(), b->GetNumberOfValues());
    for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
    {
      ASSERT_EQ(a->GetVariantValue(i).ToDouble(), b->GetVariantValue(i).ToDouble()) << name;
    }
  }
}

namespace
{
std::string RunFilter(vtkDataObject* input, int& result)
{
  vtkNew<vtkBezierCurvatureFilter> filter;
  return ctsplines_test::RunCapturingErrors(filter, input, result);
}
} // namespace

TEST(vtkBezierCurvatureFilter, RejectsBadInput)
{
  int result = 1;
  vtkNew<vtkUnstructuredGrid> empty;
  std::string m = RunFilter(empty, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("empty input"), std::string::npos) << m;

  vtkNew<vtkSampledSurfaceSource> source;
  source->SetResolution(3);
  source->Update();
  m = RunFilter(source->GetOutput(), result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("cell 0 is a vtkTriangle"), std::string::npos) << m;

  auto octant = OctantCell();
  vtkNew<vtkDoubleArray> bad;
  bad->SetName("RationalWeights");
  bad->SetNumberOfComponents(2);
  bad->SetNumberOfTuples(15);
  bad->Fill(1.0);
  octant->GetPointData()->RemoveArray("RationalWeights");
  octant->GetPointData()->AddArray(bad);
  m = RunFilter(octant, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("'RationalWeights' has 2 components"), std::string::npos) << m;
}

TEST(vtkBezierCurvatureFilter, PrintSelf)
{
  vtkNew<vtkBezierCurvatureFilter> filter;
  EXPECT_EQ(filter->GetSubdivisionLevel(), 8);
  EXPECT_FALSE(filter->GetMergePoints());
  EXPECT_STREQ(filter->GetUVArrayName(), "UV");
  std::ostringstream os;
  filter->MergePointsOn();
  filter->Print(os);
  EXPECT_NE(os.str().find("MergePoints: on"), std::string::npos);
}

// The robust range spans the central 98 % of each curvature array, and vertex spikes of the
// Franke spline lie outside it.
TEST(vtkBezierCurvatureFilter, RobustColourRange)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToFranke();
  source->SetDomainToRandomDelaunay();
  source->SetResolution(300);
  const auto surface = Curvature(Spline(source), 6);
  for (const char* name : { "Gauss_Curvature", "Mean_Curvature", "Maximum_Curvature",
         "Minimum_Curvature" })
  {
    vtkDataArray* range =
      surface->GetFieldData()->GetArray((std::string(name) + "_RobustRange").c_str());
    ASSERT_NE(range, nullptr) << name;
    ASSERT_EQ(range->GetNumberOfComponents(), 2);
    const double lo = range->GetComponent(0, 0), hi = range->GetComponent(0, 1);
    vtkDataArray* a = surface->GetPointData()->GetArray(name);
    double full[2];
    a->GetRange(full);
    EXPECT_LT(lo, hi);
    EXPECT_GE(lo, full[0]);
    EXPECT_LE(hi, full[1]);
    vtkIdType inside = 0;
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    {
      inside += a->GetComponent(i, 0) >= lo && a->GetComponent(i, 0) <= hi;
    }
    const double fraction = double(inside) / a->GetNumberOfTuples();
    EXPECT_GE(fraction, 0.979) << name;
    EXPECT_LE(fraction, 0.99) << name; // some spikes are left out
  }
}
