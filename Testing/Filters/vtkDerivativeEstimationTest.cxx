// SPDX-License-Identifier: GPL-3.0-or-later
// The spline filter's DerivativeEstimation: without dFdu/dFdv the derivatives are estimated
// (LocalQuadratic: the spline of a quadratic surface is the one of its exact derivatives;
// MinimumEnergy: the same for a plane), given arrays are used as they are, None requires them,
// unused points are accepted and errors name the triangle.
#include "vtkCloughTocherSplineFilter.h"

#include "ErrorCapture.h"
#include "FilterTestUtilities.h"

#include "vtkFieldData.h"
#include "vtkMath.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

using namespace ctsplines_test;

namespace
{
using Filter = vtkCloughTocherSplineFilter;

/// Surface s on an n x n grid with moved interior vertices (no symmetric neighbourhoods),
/// without the derivative arrays named by drop ("dFdu", "dFdv", "both"; nullptr: both, "none").
vtkSmartPointer<vtkPolyData> Sampled(ctk::AnalyticSurface s, const char* drop = nullptr, int n = 6)
{
  ctk::ParameterMesh m = ctk::RegularGridMesh(n, ctk::GridDiagonal::Alternating);
  for (size_t k = 0; k < m.UV.size(); ++k)
  {
    ctk::Vec2& U = m.UV[k];
    if (U.x() > 0 && U.x() < 1 && U.y() > 0 && U.y() < 1)
    {
      U += (0.25 / n) * ctk::Vec2(std::sin(7.0 * k), std::cos(5.0 * k));
    }
  }
  vtkSmartPointer<vtkPolyData> pd = MakeSampledPolyData(m, s);
  for (const char* name : { "dFdu", "dFdv" })
  {
    if (!drop || std::string(drop) == name || std::string(drop) == "both")
    {
      pd->GetPointData()->RemoveArray(name);
    }
  }
  return pd;
}

struct Result
{
  int Ok = 0;
  std::string Errors;
  vtkSmartPointer<vtkUnstructuredGrid> Output;
};

Result Convert(vtkPolyData* input, int estimation, int construction = Filter::CTi)
{
  vtkNew<Filter> f;
  f->SetConstruction(construction);
  f->SetDerivativeEstimation(estimation);
  Result r;
  r.Errors = RunCapturingErrors(f, input, r.Ok);
  r.Output = f->GetOutput();
  return r;
}

std::string FieldString(vtkDataObject* data, const char* name)
{
  auto* a = vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfValues() == 1 ? a->GetValue(0) : "";
}

/// Largest distance between corresponding control points of two outputs of the same mesh.
double ControlPointDistance(vtkUnstructuredGrid* a, vtkUnstructuredGrid* b)
{
  EXPECT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  double d = 0.0;
  for (vtkIdType p = 0; p < std::min(a->GetNumberOfPoints(), b->GetNumberOfPoints()); ++p)
  {
    double x[3], y[3];
    a->GetPoint(p, x);
    b->GetPoint(p, y);
    d = std::max(d, std::sqrt(vtkMath::Distance2BetweenPoints(x, y)));
  }
  return d;
}

TEST(DerivativeEstimation, NoneRequiresTheArraysAndNamesTheMissingOne)
{
  const Result r = Convert(Sampled(ctk::AnalyticSurface::Quadratic, "dFdv"), Filter::NoEstimation);
  EXPECT_EQ(0, r.Ok);
  EXPECT_NE(r.Errors.find("point data array 'dFdv' (derivative d/dv) is missing"), std::string::npos)
    << r.Errors;
  EXPECT_NE(r.Errors.find("DerivativeEstimation"), std::string::npos) << r.Errors;
}

TEST(DerivativeEstimation, EstimatedSplinesMatchTheExactOnesWhereTheMethodIsExact)
{
  // LocalQuadratic is exact for quadratics, MinimumEnergy for planes: the splines are then those
  // of the exact derivatives, for a construction that reads neighbours (CTi) and a local one.
  const struct
  {
    int Method;
    ctk::AnalyticSurface Surface;
  } cases[] = { { Filter::LocalQuadratic, ctk::AnalyticSurface::Quadratic },
    { Filter::MinimumEnergy, ctk::AnalyticSurface::Plane } };
  for (const auto& c : cases)
  {
    for (int construction : { Filter::CTi, Filter::CTo })
    {
      const Result exact = Convert(Sampled(c.Surface, "none"), Filter::NoEstimation, construction);
      const Result estimated = Convert(Sampled(c.Surface), c.Method, construction);
      ASSERT_EQ(1, estimated.Ok) << estimated.Errors;
      EXPECT_LT(ControlPointDistance(exact.Output, estimated.Output), 1e-12)
        << Filter::GetDerivativeEstimationName(c.Method);
      EXPECT_EQ(Filter::GetDerivativeEstimationName(c.Method),
        FieldString(estimated.Output, "DerivativeEstimation"));
      EXPECT_EQ("None", FieldString(exact.Output, "DerivativeEstimation"));
    }
  }
}

TEST(DerivativeEstimation, FrankeSplinesConvergeToTheExactDerivativesSpline)
{
  // Control points differ by about (gradient error) x (edge length) / 3. Measured between
  // n = 12 and 24: orders 2.06 (LocalQuadratic) and 2.65 (MinimumEnergy), Franke's features
  // still pre-asymptotic there (kernel test: gradient orders 2 and 1 at the boundary later).
  for (int method : { Filter::LocalQuadratic, Filter::MinimumEnergy })
  {
    std::vector<double> d;
    for (int n : { 12, 24 })
    {
      const Result exact = Convert(Sampled(ctk::AnalyticSurface::Franke, "none", n), Filter::NoEstimation);
      const Result estimated = Convert(Sampled(ctk::AnalyticSurface::Franke, nullptr, n), method);
      ASSERT_EQ(1, estimated.Ok) << estimated.Errors;
      d.push_back(ControlPointDistance(exact.Output, estimated.Output));
    }
    std::printf("%s: control point distance n=12 %.3e, n=24 %.3e (order %.2f)\n",
      Filter::GetDerivativeEstimationName(method), d[0], d[1], std::log2(d[0] / d[1]));
    EXPECT_GT(std::log2(d[0] / d[1]), 1.5) << Filter::GetDerivativeEstimationName(method);
  }
}

TEST(DerivativeEstimation, GivenArraysAreUsedAsTheyAre)
{
  const Result none = Convert(Sampled(ctk::AnalyticSurface::Franke, "none"), Filter::NoEstimation);
  const Result given = Convert(Sampled(ctk::AnalyticSurface::Franke, "none"), Filter::LocalQuadratic);
  ASSERT_EQ(1, given.Ok) << given.Errors;
  EXPECT_EQ(0.0, ControlPointDistance(none.Output, given.Output));
  EXPECT_EQ("None", FieldString(given.Output, "DerivativeEstimation"));
  // One array missing: both are estimated (never a mix of given and estimated derivatives).
  const Result one = Convert(Sampled(ctk::AnalyticSurface::Franke, "dFdu"), Filter::LocalQuadratic);
  const Result both = Convert(Sampled(ctk::AnalyticSurface::Franke, "both"), Filter::LocalQuadratic);
  ASSERT_EQ(1, one.Ok) << one.Errors;
  EXPECT_EQ(0.0, ControlPointDistance(one.Output, both.Output));
}

TEST(DerivativeEstimation, UnusedPointsAreAcceptedAndErrorsNameTheTriangle)
{
  for (int method : { Filter::LocalQuadratic, Filter::MinimumEnergy })
  {
    // A point no triangle uses (read by no construction) is accepted, as with given arrays.
    vtkSmartPointer<vtkPolyData> pd = Sampled(ctk::AnalyticSurface::Franke);
    pd->GetPoints()->InsertNextPoint(0.5, 0.5, 0.0);
    const double uv[2] = { 0.5, 0.5 };
    pd->GetPointData()->GetArray("UV")->InsertNextTuple(uv);
    const Result stray = Convert(pd, method);
    EXPECT_EQ(1, stray.Ok) << stray.Errors;
    // A zero-area triangle on the boundary row (points 0, 1, 2 are collinear): the energy is
    // undefined there, and the construction's validation names it after the local estimate.
    const vtkIdType degenerate[3] = { 0, 1, 2 };
    pd->GetPolys()->InsertNextCell(3, degenerate);
    const Result r = Convert(pd, method);
    EXPECT_EQ(0, r.Ok);
    const std::string expected = method == Filter::MinimumEnergy
      ? "parameter triangle 72 is degenerate (zero area)"
      : "cell 72 (points 0, 1, 2) has zero area in (u, v)";
    EXPECT_NE(r.Errors.find(expected), std::string::npos) << r.Errors;
  }
}

TEST(DerivativeEstimation, PropertyGhostLevelsAndPrintSelf)
{
  vtkNew<Filter> f;
  EXPECT_EQ(Filter::NoEstimation, f->GetDerivativeEstimation());
  const int base = f->GetRequiredGhostLevels();
  f->SetDerivativeEstimationToMinimumEnergy();
  EXPECT_EQ(Filter::MinimumEnergy, f->GetDerivativeEstimation());
  f->SetDerivativeEstimation(7);
  EXPECT_EQ(Filter::MinimumEnergy, f->GetDerivativeEstimation()); // clamped
  f->SetDerivativeEstimationToLocalQuadratic();
  EXPECT_EQ(base + 4, f->GetRequiredGhostLevels());
  std::ostringstream os;
  f->PrintSelf(os, vtkIndent());
  EXPECT_NE(os.str().find("DerivativeEstimation: LocalQuadratic"), std::string::npos);
  EXPECT_STREQ("None", Filter::GetDerivativeEstimationName(Filter::NoEstimation));
  EXPECT_STREQ("Unknown", Filter::GetDerivativeEstimationName(3));
}

} // namespace
