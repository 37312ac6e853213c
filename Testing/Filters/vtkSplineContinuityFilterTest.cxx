// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineContinuityFilter.h"

#include "BezierTriangle.h"
#include "ErrorCapture.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using ctsplines_test::ErrorCapture;

vtkSmartPointer<vtkUnstructuredGrid> Spline(int surface, int construction, int resolution = 30)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurface(surface);
  source->SetDomainToRandomDelaunay();
  source->SetResolution(resolution);
  source->SetSeed(3);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  spline->SetConstruction(construction);
  spline->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(spline->GetOutput());
  return out;
}

vtkSmartPointer<vtkPolyData> Continuity(vtkDataSet* input, bool match = true)
{
  vtkNew<vtkSplineContinuityFilter> filter;
  filter->SetInputData(input);
  filter->SetMatchCoincidentEdges(match);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

double Summary(vtkPolyData* pd, const std::string& name)
{
  vtkDataArray* a = pd->GetFieldData()->GetArray(name.c_str());
  return a ? a->GetTuple1(0) : std::nan("");
}

double Diagonal(vtkDataSet* ds)
{
  return std::sqrt(ds->GetLength2());
}

// A copy of `grid` whose point `point` is duplicated for cell `cell` only, the copy moved by
// `delta`: the other cells keep the original.
vtkSmartPointer<vtkUnstructuredGrid> Detach(
  vtkUnstructuredGrid* grid, vtkIdType cell, vtkIdType point, const ctk::Vec3& delta)
{
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(grid);
  ctk::Vec3 x;
  grid->GetPoint(point, x.data());
  const ctk::Vec3 y = x + delta;
  const vtkIdType copy = out->GetPoints()->InsertNextPoint(y.data());
  vtkPointData* pd = out->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    pd->GetArray(a)->InsertNextTuple(point, grid->GetPointData()->GetArray(a));
  }
  vtkNew<vtkUnstructuredGrid> rebuilt;
  rebuilt->SetPoints(out->GetPoints());
  rebuilt->GetPointData()->ShallowCopy(pd);
  rebuilt->GetCellData()->ShallowCopy(out->GetCellData());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    out->GetCellPoints(c, ids);
    if (c == cell)
    {
      ids->SetId(ids->IsId(point), copy);
    }
    rebuilt->InsertNextCell(out->GetCellType(c), ids);
  }
  return rebuilt;
}

// The edge (line) whose Cells are (a, b).
vtkIdType EdgeOf(vtkPolyData* edges, vtkIdType a, vtkIdType b)
{
  vtkDataArray* cells = edges->GetCellData()->GetArray("Cells");
  for (vtkIdType e = 0; e < edges->GetNumberOfCells(); ++e)
  {
    if (cells->GetComponent(e, 0) == a && cells->GetComponent(e, 1) == b)
    {
      return e;
    }
  }
  return -1;
}

double Cell(vtkPolyData* pd, const char* name, vtkIdType e)
{
  return pd->GetCellData()->GetArray(name)->GetComponent(e, 0);
}
} // namespace

// Every construction gives a C0 and C1 spline (zero jumps on every interior edge, G1 angle 0)
// that is not C2.
TEST(vtkSplineContinuityFilter, ConstructionsAreC1)
{
  for (int construction = vtkCloughTocherSplineFilter::CTo;
       construction <= vtkCloughTocherSplineFilter::Quartic; ++construction)
  {
    const auto spline = Spline(vtkSampledSurfaceSource::Franke, construction);
    const auto edges = Continuity(spline);
    const double diag = Diagonal(spline);
    const std::string name = vtkCloughTocherSplineFilter::GetConstructionName(construction);
    const vtkIdType nMacro = spline->GetNumberOfCells() / 3;
    EXPECT_EQ(Summary(edges, "Micro_EdgeCount"), 3 * nMacro) << name;
    EXPECT_EQ(Summary(edges, "Interface_EdgeCount"), 0) << name;
    EXPECT_GT(Summary(edges, "Boundary_EdgeCount"), 0) << name;
    for (const char* kind : { "Macro", "Micro" })
    {
      const std::string k = kind;
      EXPECT_LT(Summary(edges, k + "_C0Gap_Max"), 1e-13 * diag) << name << " " << kind;
      EXPECT_LT(Summary(edges, k + "_C1Jump_Max"), 1e-13 * diag) << name << " " << kind;
      EXPECT_LT(Summary(edges, k + "_G1Angle_Max"), 1e-5) << name << " " << kind;
    }
    EXPECT_GT(Summary(edges, "Macro_C2Jump_Max"), 1e-6 * diag) << name;
    if (construction != vtkCloughTocherSplineFilter::Quartic)
    {
      EXPECT_GT(Summary(edges, "Macro_C2JumpEq7_Max"), 1e-6 * diag) << name;
    }
    std::printf("%-8s macro C2 max %.3e mean %.3e, eq7 max %.3e; micro C2 max %.3e\n",
      name.c_str(), Summary(edges, "Macro_C2Jump_Max"), Summary(edges, "Macro_C2Jump_Mean"),
      Summary(edges, "Macro_C2JumpEq7_Max"), Summary(edges, "Micro_C2Jump_Max"));
  }
}

// A construction with cubic precision (KaG: Ka with exact mid-edge gradients on the boundary)
// reproduces Farin's cubic: then it is C2 everywhere, and both C2 measures vanish.
TEST(vtkSplineContinuityFilter, CubicPrecisionGivesC2)
{
  const auto spline = Spline(vtkSampledSurfaceSource::FarinCubic, vtkCloughTocherSplineFilter::KaG);
  const auto edges = Continuity(spline);
  const double diag = Diagonal(spline);
  for (const char* kind : { "Macro", "Micro" })
  {
    EXPECT_LT(Summary(edges, std::string(kind) + "_C2Jump_Max"), 1e-11 * diag) << kind;
  }
  EXPECT_LT(Summary(edges, "Macro_C2JumpEq7_Max"), 1e-11 * diag);
}

// Hand-broken grids: the reported jump is the displacement.
TEST(vtkSplineContinuityFilter, ReportsKnownDefects)
{
  const auto spline = Spline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::CTi, 12);
  const auto clean = Continuity(spline);
  const vtkIdType nCells = spline->GetNumberOfCells();
  const ctk::Vec3 delta(3e-3, -4e-3, 1.2e-2); // |delta| = 0.013

  // C1: move the centre (1,1,1) of the last cell; it lies in row 1 of all three edges.
  const vtkIdType last = nCells - 1;
  vtkNew<vtkIdList> ids;
  spline->GetCellPoints(last, ids);
  const vtkIdType centre = ids->GetId(9);
  auto moved = Detach(spline, last, centre, delta);
  const auto c1 = Continuity(moved);
  vtkDataArray* cells = c1->GetCellData()->GetArray("Cells");
  int checked = 0;
  for (vtkIdType e = 0; e < c1->GetNumberOfCells(); ++e)
  {
    if (cells->GetComponent(e, 1) == last)
    {
      EXPECT_NEAR(Cell(c1, "C1Jump", e), delta.norm(), 1e-13) << "edge " << e;
      EXPECT_LT(Cell(c1, "C0Gap", e), 1e-14);
      EXPECT_GT(Cell(c1, "G1Angle", e), 1e-3);
      ++checked;
    }
  }
  EXPECT_GE(checked, 2); // the last cell has the higher id at its micro-edges (and macro-edge)
  // Nothing else changed.
  for (vtkIdType e = 0; e < c1->GetNumberOfCells(); ++e)
  {
    if (cells->GetComponent(e, 0) != last && cells->GetComponent(e, 1) != last)
    {
      EXPECT_EQ(Cell(c1, "C1Jump", e), Cell(clean, "C1Jump", e));
    }
  }

  // C0: give the highest-id cell at a macro-edge its own, moved copy of an edge point.
  const auto kinds = clean->GetCellData()->GetArray("EdgeKind");
  vtkIdType edge = -1;
  for (vtkIdType e = 0; e < clean->GetNumberOfCells() && edge < 0; ++e)
  {
    edge = kinds->GetComponent(e, 0) == vtkSplineContinuityFilter::Macro ? e : -1;
  }
  ASSERT_GE(edge, 0);
  const vtkIdType A = static_cast<vtkIdType>(clean->GetCellData()->GetArray("Cells")->GetComponent(edge, 0));
  const vtkIdType B = static_cast<vtkIdType>(clean->GetCellData()->GetArray("Cells")->GetComponent(edge, 1));
  vtkNew<vtkIdList> idsA, idsB;
  spline->GetCellPoints(A, idsA);
  spline->GetCellPoints(B, idsB);
  vtkIdType shared = -1; // an edge inner point (VTK points 3..8) of both cells
  for (int p = 3; p < 9 && shared < 0; ++p)
  {
    shared = idsA->IsId(idsB->GetId(p)) >= 0 ? idsB->GetId(p) : -1;
  }
  ASSERT_GE(shared, 0);
  const auto gap = Continuity(Detach(spline, B, shared, delta));
  const vtkIdType e = EdgeOf(gap, A, B);
  ASSERT_GE(e, 0);
  EXPECT_NEAR(Cell(gap, "C0Gap", e), delta.norm(), 1e-13);
  EXPECT_NEAR(Cell(gap, "C1Jump", e), Cell(clean, "C1Jump", edge), 1e-13);
}

// Two faces with separate points (and a face id) along a coincident seam: the seam is an
// interface, still C1 when both faces carry the same (or a similar) parametrisation.
TEST(vtkSplineContinuityFilter, MatchesCoincidentEdgesOfSeparateFaces)
{
  const auto spline = Spline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::FO, 20);
  const vtkIdType nCells = spline->GetNumberOfCells();
  const auto clean = Continuity(spline);
  // Face 1: the second half of the macro-triangles, with its own copies of all its points and
  // its parameters moved by a similarity (rotation, scale, translation).
  vtkDataArray* macro = spline->GetCellData()->GetArray("MacroTriangleId");
  const double half = 0.5 * (nCells / 3);
  vtkNew<vtkUnstructuredGrid> split;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->DeepCopy(spline->GetPoints());
  vtkNew<vtkDoubleArray> uv;
  uv->DeepCopy(spline->GetPointData()->GetArray("UV"));
  vtkNew<vtkIdTypeArray> face;
  face->SetName("FaceId");
  std::vector<vtkIdType> copyOf(spline->GetNumberOfPoints(), -1);
  const double cs = 1.7 * std::cos(0.4), sn = 1.7 * std::sin(0.4);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    spline->GetCellPoints(c, ids);
    const bool second = macro->GetTuple1(c) >= half;
    face->InsertNextValue(second ? 1 : 0);
    if (second)
    {
      for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
      {
        vtkIdType& copy = copyOf[ids->GetId(i)];
        if (copy < 0)
        {
          copy = points->InsertNextPoint(spline->GetPoint(ids->GetId(i)));
          const double* u = spline->GetPointData()->GetArray("UV")->GetTuple2(ids->GetId(i));
          const double mapped[2] = { cs * u[0] - sn * u[1] + 2.0, sn * u[0] + cs * u[1] - 1.0 };
          uv->InsertNextTuple(mapped);
        }
        ids->SetId(i, copy);
      }
    }
    split->InsertNextCell(VTK_BEZIER_TRIANGLE, ids);
  }
  split->SetPoints(points);
  split->GetPointData()->AddArray(uv);
  split->GetCellData()->AddArray(macro);
  split->GetCellData()->AddArray(face);

  const auto matched = Continuity(split, true);
  const double diag = Diagonal(spline);
  const double interfaces = Summary(matched, "Interface_EdgeCount");
  EXPECT_GT(interfaces, 0);
  EXPECT_EQ(Summary(matched, "Boundary_EdgeCount"), Summary(clean, "Boundary_EdgeCount"));
  EXPECT_EQ(Summary(matched, "Macro_EdgeCount") + interfaces, Summary(clean, "Macro_EdgeCount"));
  EXPECT_LT(Summary(matched, "Interface_C0Gap_Max"), 1e-13 * diag);
  EXPECT_LT(Summary(matched, "Interface_C1Jump_Max"), 1e-12 * diag);
  EXPECT_LT(Summary(matched, "Interface_G1Angle_Max"), 1e-5);

  const auto unmatched = Continuity(split, false);
  EXPECT_EQ(Summary(unmatched, "Interface_EdgeCount"), 0);
  EXPECT_EQ(Summary(unmatched, "Boundary_EdgeCount"),
    Summary(clean, "Boundary_EdgeCount") + 2 * interfaces);
}

TEST(vtkSplineContinuityFilter, ThreadCountDoesNotChangeResults)
{
  const auto spline = Spline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::Ka, 60);
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(1);
  const auto one = Continuity(spline);
  vtkSMPTools::Initialize(4);
  const auto four = Continuity(spline);
  for (const char* name : { "C0Gap", "C1Jump", "C2Jump", "G1Angle", "C2JumpEq7" })
  {
    vtkDataArray* a = one->GetCellData()->GetArray(name);
    vtkDataArray* b = four->GetCellData()->GetArray(name);
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    {
      const double x = a->GetTuple1(i), y = b->GetTuple1(i);
      ASSERT_TRUE(x == y || (std::isnan(x) && std::isnan(y))) << name << " " << i;
    }
  }
}

namespace
{
std::string RunFilter(vtkDataObject* input, int& result)
{
  vtkNew<vtkSplineContinuityFilter> filter;
  return ctsplines_test::RunCapturingErrors(filter, input, result);
}
} // namespace

TEST(vtkSplineContinuityFilter, RejectsBadInput)
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

  auto spline = Spline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::CTi, 10);
  spline->GetPointData()->RemoveArray("UV");
  m = RunFilter(spline, result);
  EXPECT_EQ(result, 0);
  EXPECT_NE(m.find("no point data array 'UV'"), std::string::npos) << m;
}

TEST(vtkSplineContinuityFilter, PrintSelf)
{
  vtkNew<vtkSplineContinuityFilter> filter;
  EXPECT_TRUE(filter->GetMatchCoincidentEdges());
  EXPECT_EQ(filter->GetTolerance(), 1e-6);
  EXPECT_STREQ(filter->GetFaceIdArrayName(), "FaceId");
  std::ostringstream os;
  filter->SetFaceIdArrayName("Patch");
  filter->Print(os);
  EXPECT_NE(os.str().find("FaceIdArrayName: Patch"), std::string::npos);
  EXPECT_STREQ(vtkSplineContinuityFilter::GetEdgeKindName(3), "Interface");
}
