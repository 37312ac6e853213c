// SPDX-License-Identifier: GPL-3.0-or-later
// Every array the module's filters read is checked for its tuple count (issue 13: short arrays
// were read past their end: segfaults, non-finite points without an error, or pieces that kept
// the wrong cells). One test per filter family; each asserts that RequestData fails with a
// message naming the array and its size, and that nothing is read out of bounds (run under
// ASan by the sanitizer job). Also duplicate triangles, folds and huge values through the
// spline filter.
#include "vtkBezierCurvatureFilter.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSplineContinuityFilter.h"
#include "vtkSplineParameterProbe.h"

#include "ErrorCapture.h"
#include "FilterTestUtilities.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ctsplines_test;

namespace
{
vtkSmartPointer<vtkPolyData> Franke(int n = 3)
{
  return MakeSampledPolyData(
    ctk::RegularGridMesh(n, ctk::GridDiagonal::Alternating), ctk::AnalyticSurface::Franke);
}

// Runs `algorithm` on `input`; expects failure and returns the error text.
std::string Failure(vtkAlgorithm* algorithm, vtkDataObject* input)
{
  int result = 1;
  const std::string message = RunCapturingErrors(algorithm, input, result);
  EXPECT_EQ(result, 0) << message;
  return message;
}

std::string SplineFailure(vtkPolyData* input, int construction = vtkCloughTocherSplineFilter::CTi,
  const char* curves = "")
{
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetConstruction(construction);
  f->SetBoundaryCurvePointsArrayName(curves);
  return Failure(f, input);
}

// One tuple fewer than the data set has points (cells).
void Shorten(vtkDataArray* a)
{
  a->SetNumberOfTuples(a->GetNumberOfTuples() - 1);
}

vtkSmartPointer<vtkUnstructuredGrid> Spline(vtkPolyData* input)
{
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(input);
  f->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}

void ExpectNames(const std::string& message, const std::string& what)
{
  EXPECT_NE(message.find(what), std::string::npos) << message;
  EXPECT_NE(message.find("tuples for"), std::string::npos) << message;
}
} // namespace

TEST(InputArraySize, SplineFilterPointAndCellArrays)
{
  for (const char* name : { "UV", "dFdu", "dFdv" })
  {
    vtkSmartPointer<vtkPolyData> input = Franke();
    Shorten(input->GetPointData()->GetArray(name));
    ExpectNames(SplineFailure(input), std::string("point data array '") + name + "'");
  }
  vtkSmartPointer<vtkPolyData> input = Franke();
  Shorten(input->GetCellData()->GetArray("EdgeGradients"));
  ExpectNames(SplineFailure(input, vtkCloughTocherSplineFilter::MGo), "'EdgeGradients'");

  input = Franke();
  vtkNew<vtkDoubleArray> curves;
  curves->SetName("Curves");
  curves->SetNumberOfComponents(18);
  curves->SetNumberOfTuples(input->GetNumberOfCells() - 2);
  curves->Fill(std::nan(""));
  input->GetCellData()->AddArray(curves);
  ExpectNames(SplineFailure(input, vtkCloughTocherSplineFilter::CTi, "Curves"), "'Curves'");
}

TEST(InputArraySize, SplineFilterGlobalIdsAndGhosts)
{
  vtkSmartPointer<vtkPolyData> input = Franke();
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("GlobalCellIds");
  ids->SetNumberOfTuples(input->GetNumberOfCells() / 2);
  ids->Fill(0);
  input->GetCellData()->SetGlobalIds(ids);
  ExpectNames(SplineFailure(input), "global ids 'GlobalCellIds'");

  // A global id that is not an integer (a double array with NaN) used to be cast as it was.
  input = Franke();
  vtkNew<vtkDoubleArray> nanIds;
  nanIds->SetName("Ids");
  nanIds->SetNumberOfTuples(input->GetNumberOfCells());
  nanIds->Fill(3.0);
  nanIds->SetValue(5, std::nan(""));
  input->GetCellData()->SetGlobalIds(nanIds);
  const std::string message = SplineFailure(input);
  EXPECT_NE(message.find("at cell 5"), std::string::npos) << message;

  input = Franke();
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfTuples(3);
  ghosts->Fill(0);
  input->GetCellData()->AddArray(ghosts);
  ExpectNames(SplineFailure(input), "'vtkGhostType'");
}

TEST(InputArraySize, SplineFilterMeshDefects)
{
  // A triangle and its reversed copy, alone: both would pass as a closed two-triangle surface.
  vtkSmartPointer<vtkPolyData> input = Franke(1);
  vtkIdType reversed[3] = { 0, 3, 1 };
  vtkIdType first[3];
  {
    const vtkIdType* pts;
    vtkIdType n;
    input->GetPolys()->GetCellAtId(0, n, pts);
    std::copy(pts, pts + 3, first);
  }
  vtkNew<vtkCellArray> pair;
  pair->InsertNextCell(3, first);
  reversed[0] = first[0];
  reversed[1] = first[2];
  reversed[2] = first[1];
  pair->InsertNextCell(3, reversed);
  input->SetPolys(pair);
  input->GetCellData()->Initialize();
  std::string message = SplineFailure(input);
  EXPECT_NE(message.find("duplicate triangles 0 and 1"), std::string::npos) << message;

  // Point 4 (the grid's centre at n = 2) moved across the boundary edge x = 1 folds the domain.
  input = Franke(2);
  input->GetPointData()->GetArray("UV")->SetTuple2(4, 1.3, 0.7);
  message = SplineFailure(input);
  EXPECT_NE(message.find("folded parameterisation"), std::string::npos) << message;

  input = Franke();
  input->GetPointData()->GetArray("dFdv")->SetComponent(2, 1, 1e250);
  message = SplineFailure(input);
  EXPECT_NE(message.find("value too large (1e+250) at point 2"), std::string::npos) << message;
}

TEST(InputArraySize, BezierGridFiltersCheckIdArrays)
{
  for (const char* name : { "MacroTriangleId", "MicroTriangleId" })
  {
    vtkSmartPointer<vtkUnstructuredGrid> spline = Spline(Franke());
    ASSERT_GT(spline->GetNumberOfCells(), 0);
    Shorten(spline->GetCellData()->GetArray(name));
    const std::string what = std::string("cell data array '") + name + "'";
    vtkNew<vtkBezierTriangleTessellator> tessellator;
    ExpectNames(Failure(tessellator, spline), what);
    vtkNew<vtkBezierCurvatureFilter> curvature;
    ExpectNames(Failure(curvature, spline), what);
    vtkNew<vtkSplineContinuityFilter> continuity;
    ExpectNames(Failure(continuity, spline), what);
  }
}

TEST(InputArraySize, ProbeChecksTheSourcesArrays)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = Spline(Franke());
  vtkSmartPointer<vtkPolyData> queries = Franke(2);
  {
    vtkSmartPointer<vtkUnstructuredGrid> source = vtkSmartPointer<vtkUnstructuredGrid>::New();
    source->DeepCopy(spline);
    Shorten(source->GetCellData()->GetArray("MacroTriangleId"));
    vtkNew<vtkSplineParameterProbe> probe;
    probe->SetSourceData(source);
    ExpectNames(Failure(probe, queries), "'MacroTriangleId'");
  }
  {
    // Ids that are not integers came out as up to +-7e18.
    vtkSmartPointer<vtkUnstructuredGrid> source = vtkSmartPointer<vtkUnstructuredGrid>::New();
    source->DeepCopy(spline);
    vtkNew<vtkDoubleArray> ids;
    ids->SetName("MacroTriangleId");
    ids->SetNumberOfTuples(source->GetNumberOfCells());
    ids->Fill(1.0);
    ids->SetValue(7, 1e300);
    source->GetCellData()->RemoveArray("MacroTriangleId");
    source->GetCellData()->AddArray(ids);
    vtkNew<vtkSplineParameterProbe> probe;
    probe->SetSourceData(source);
    const std::string message = Failure(probe, queries);
    EXPECT_NE(message.find("at cell 7"), std::string::npos) << message;
  }
  {
    vtkSmartPointer<vtkUnstructuredGrid> source = vtkSmartPointer<vtkUnstructuredGrid>::New();
    source->DeepCopy(spline);
    Shorten(source->GetPointData()->GetArray("UV"));
    vtkNew<vtkSplineParameterProbe> probe;
    probe->SetSourceData(source);
    ExpectNames(Failure(probe, queries), "'UV'");
  }
}

TEST(InputArraySize, BezierGridValuesAreChecked)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = Spline(Franke());
  const auto failure = [](vtkUnstructuredGrid* grid) {
    vtkNew<vtkBezierTriangleTessellator> tessellator;
    return Failure(tessellator, grid);
  };
  vtkNew<vtkUnstructuredGrid> grid;
  grid->DeepCopy(spline);
  grid->GetPoints()->SetPoint(5, 0.0, std::nan(""), 0.0);
  std::string message = failure(grid);
  EXPECT_NE(message.find("point 5 has the coordinates"), std::string::npos) << message;

  grid->DeepCopy(spline);
  grid->GetPoints()->SetPoint(6, 1e200, 0.0, 0.0);
  message = failure(grid);
  EXPECT_NE(message.find("point 6"), std::string::npos) << message;

  // Zero or negative rational weights make the rational patch undefined (division by zero).
  for (double w : { 0.0, -1.0 })
  {
    grid->DeepCopy(spline);
    vtkNew<vtkDoubleArray> weights;
    weights->SetName("RationalWeights");
    weights->SetNumberOfTuples(grid->GetNumberOfPoints());
    weights->Fill(1.0);
    weights->SetValue(3, w);
    grid->GetPointData()->SetRationalWeights(weights);
    message = failure(grid);
    EXPECT_NE(message.find("rational weight of point 3"), std::string::npos) << message;
  }
}
