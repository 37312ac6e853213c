// SPDX-License-Identifier: GPL-3.0-or-later
// The spline filter through VTK: output layout (shared points, cell types, arrays), agreement with
// VTK's own Bézier evaluation, precision and C1 of the output grid, and every bad-input case.
#include "vtkCloughTocherSplineFilter.h"

#include "CTSplinesInput.h"
#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "CubicMacroElement.h"
#include "LocalityOrder.h"
#include "MeshTopology.h"
#include "RuleA.h"

#include "vtkAppendFilter.h"
#include "vtkBezierTriangle.h"
#include "vtkCellData.h"
#include "vtkCellTypes.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkDataSetAttributes.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>

using namespace ctsplines_test;

namespace
{
vtkSmartPointer<vtkUnstructuredGrid> Convert(vtkPolyData* input, int construction,
  int splitPoint = vtkCloughTocherSplineFilter::Bary,
  int boundary = vtkCloughTocherSplineFilter::Midpoint)
{
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(input);
  f->SetConstruction(construction);
  f->SetSplitPoint(splitPoint);
  f->SetBoundaryMode(boundary);
  f->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

// Runs the filter (setup: further settings) expecting failure; returns the error text.
std::string ExpectFailure(vtkPolyData* input, int construction = vtkCloughTocherSplineFilter::CTi,
  int boundary = vtkCloughTocherSplineFilter::Midpoint,
  const std::function<void(vtkCloughTocherSplineFilter*)>& setup = nullptr)
{
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(input);
  f->SetConstruction(construction);
  f->SetBoundaryMode(boundary);
  if (setup)
  {
    setup(f);
  }
  auto capture = ErrorCapture::Attach(f);
  auto pipelineCapture = ErrorCapture::Attach(f->GetExecutive());
  f->Update();
  EXPECT_GE(capture->Count, 1);
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0);
  return capture->Message;
}

vtkSmartPointer<vtkPolyData> Franke(int n = 4)
{
  return MakeSampledPolyData(
    ctk::RegularGridMesh(n, ctk::GridDiagonal::Alternating), ctk::AnalyticSurface::Franke);
}

// Evaluates cell c of the output with VTK's vtkBezierTriangle at parametric (r, s).
ctk::Vec3 VtkEvaluate(vtkUnstructuredGrid* grid, vtkIdType c, double r, double s)
{
  vtkNew<vtkGenericCell> cell;
  grid->GetCell(c, cell);
  int subId = 0;
  double pcoords[3] = { r, s, 0.0 }, x[3], weights[64];
  cell->EvaluateLocation(subId, pcoords, x, weights);
  return ctk::Vec3(x[0], x[1], x[2]);
}

/// Largest C0 and C1 jumps (Rule A) over the edges shared by two cells of a Bézier-triangle grid
/// (edges found by corner ids); withinMacroTriangles keeps only edges whose cells have the same
/// MacroTriangleId (the micro-edges). Returns the number of edges measured.
int MaxJumpsAcrossCellEdges(vtkUnstructuredGrid* out, int degree, bool withinMacroTriangles, double worst[2])
{
  const int count = ctk::BezierPointCount(degree);
  EXPECT_EQ(out->GetCellSize(0), count);
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  vtkDataArray* macro = out->GetCellData()->GetArray("MacroTriangleId");
  const std::vector<int> order = ctk::VtkBezierTriangleOrder(degree);
  auto net = [&](vtkIdType c, ctk::Vec3* P, ctk::Vec2* A, vtkIdType* corners) {
    vtkNew<vtkIdList> ids;
    out->GetCellPoints(c, ids);
    for (int a = 0; a < count; ++a)
    {
      double x[3];
      out->GetPoint(ids->GetId(a), x);
      P[order[a]] = ctk::Vec3(x[0], x[1], x[2]);
    }
    for (int i = 0; i < 3; ++i)
    {
      corners[i] = ids->GetId(i);
      A[i] = ctk::Vec2(uv->GetComponent(corners[i], 0), uv->GetComponent(corners[i], 1));
    }
  };
  std::map<std::pair<vtkIdType, vtkIdType>, std::vector<vtkIdType>> edgeCells;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    ctk::Vec3 P[ctk::MaxBezierPoints];
    ctk::Vec2 A[3];
    vtkIdType corners[3];
    net(c, P, A, corners);
    for (int l = 0; l < 3; ++l)
    {
      const vtkIdType a = corners[l], b = corners[(l + 1) % 3];
      edgeCells[{ std::min(a, b), std::max(a, b) }].push_back(c);
    }
  }
  int measured = 0;
  worst[0] = worst[1] = 0;
  for (const auto& [edge, cells] : edgeCells)
  {
    EXPECT_LE(cells.size(), 2u);
    if (cells.size() != 2 ||
      (withinMacroTriangles && macro->GetTuple1(cells[0]) != macro->GetTuple1(cells[1])))
    {
      continue;
    }
    ++measured;
    ctk::Vec3 PA[ctk::MaxBezierPoints], PB[ctk::MaxBezierPoints];
    ctk::Vec2 A[3], B[3];
    vtkIdType ca[3], cb[3];
    net(cells[0], PA, A, ca);
    net(cells[1], PB, B, cb);
    double j[2];
    ctk::RuleAJumps(degree, PA, A, PB, B, 1, j);
    worst[0] = std::max(worst[0], j[0]);
    worst[1] = std::max(worst[1], j[1]);
  }
  return measured;
}
} // namespace

TEST(vtkCloughTocherSplineFilter, OutputLayoutAndArrays)
{
  const int n = 3;
  vtkSmartPointer<vtkPolyData> input = Franke(n);
  vtkSmartPointer<vtkUnstructuredGrid> out = Convert(input, vtkCloughTocherSplineFilter::CTi);
  const vtkIdType nV = (n + 1) * (n + 1), nE = 3 * n * n + 2 * n, nT = 2 * n * n;
  EXPECT_EQ(out->GetNumberOfPoints(), nV + 2 * nE + 10 * nT);
  EXPECT_EQ(out->GetNumberOfCells(), 3 * nT);
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_DOUBLE);
  // 32-bit offsets and connectivity (the ids fit), read by VTK's cell API like 64-bit ones.
  EXPECT_FALSE(out->GetCells()->IsStorage64Bit());
  EXPECT_EQ(out->GetCells()->GetOffsetsArray32()->GetValue(out->GetNumberOfCells()),
    10 * out->GetNumberOfCells());
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(out->GetCellType(c), VTK_BEZIER_TRIANGLE);
    ASSERT_EQ(out->GetCellSize(c), 10);
  }
  // Every control point is used; shared ones (vertices, macro-edge points, inner points) by
  // several cells.
  std::vector<int> uses(out->GetNumberOfPoints(), 0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    out->GetCellPoints(c, ids);
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
    {
      ++uses[ids->GetId(a)];
    }
  }
  for (int u : uses)
  {
    ASSERT_GE(u, 1);
  }
  ASSERT_NE(out->GetPointData()->GetArray("UV"), nullptr);
  EXPECT_EQ(out->GetPointData()->GetArray("UV")->GetNumberOfComponents(), 2);
  auto* macro = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("MacroTriangleId"));
  ASSERT_NE(macro, nullptr);
  ASSERT_NE(out->GetCellData()->GetArray("MicroTriangleId"), nullptr);
  EXPECT_EQ(macro->GetValue(3 * 5 + 2), 5);
  auto* name = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("Construction"));
  ASSERT_NE(name, nullptr);
  EXPECT_EQ(name->GetValue(0), "CTi");
  EXPECT_EQ(vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("SplitPoint"))
              ->GetValue(0),
    "Bary");
}

TEST(vtkCloughTocherSplineFilter, PointOrderAgreesWithVtkBezierEvaluation)
{
  // The cell's points, read as VTK's Bézier ordinates, must give the kernel's micro-patch:
  // the corner UVs map the cell's parametric (r, s) to the domain, and the spline reproduces
  // quadratic data exactly, so VTK's evaluation must land on the exact surface.
  vtkSmartPointer<vtkPolyData> input = MakeSampledPolyData(
    ctk::RegularGridMesh(3, ctk::GridDiagonal::Forward), ctk::AnalyticSurface::Quadratic);
  for (int construction : { vtkCloughTocherSplineFilter::CTo, vtkCloughTocherSplineFilter::CTi,
         vtkCloughTocherSplineFilter::MGo, vtkCloughTocherSplineFilter::MGi,
         vtkCloughTocherSplineFilter::Fa, vtkCloughTocherSplineFilter::Ka,
         vtkCloughTocherSplineFilter::KaG, vtkCloughTocherSplineFilter::Kashyap,
         vtkCloughTocherSplineFilter::Quartic })
  {
    vtkSmartPointer<vtkUnstructuredGrid> out =
      Convert(input, construction, vtkCloughTocherSplineFilter::Inc3);
    vtkDataArray* uv = out->GetPointData()->GetArray("UV");
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    vtkNew<vtkIdList> ids;
    double worst = 0.0;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      out->GetCellPoints(c, ids);
      ctk::Vec2 A[3];
      for (int i = 0; i < 3; ++i)
      {
        A[i] = ctk::Vec2(uv->GetComponent(ids->GetId(i), 0), uv->GetComponent(ids->GetId(i), 1));
      }
      for (int k = 0; k < 5; ++k)
      {
        double r = U(rng), s = U(rng);
        if (r + s > 1.0)
        {
          r = 1.0 - r;
          s = 1.0 - s;
        }
        const ctk::Vec2 X = (1.0 - r - s) * A[0] + r * A[1] + s * A[2];
        const ctk::Vec3 exact =
          ctk::EvaluateAnalyticSurface(ctk::AnalyticSurface::Quadratic, X.x(), X.y()).F;
        worst = std::max(worst, (VtkEvaluate(out, c, r, s) - exact).norm());
      }
    }
    EXPECT_LT(worst, 1e-13) << vtkCloughTocherSplineFilter::GetConstructionName(construction);
  }
}

TEST(vtkCloughTocherSplineFilter, OutputIsC1AcrossEveryCellEdge)
{
  // Rule A on the output grid itself: every pair of cells sharing an edge (two corner ids).
  vtkSmartPointer<vtkPolyData> input = MakeSampledPolyData(
    ctk::RefinedTriangleMesh(ctk::Vec2(0, 0), ctk::Vec2(1, 0), ctk::Vec2(0.3, 0.8), 2),
    ctk::AnalyticSurface::SineWave);
  for (int construction : { vtkCloughTocherSplineFilter::MGi, vtkCloughTocherSplineFilter::Kashyap,
         vtkCloughTocherSplineFilter::Quartic })
  {
    vtkNew<vtkCloughTocherSplineFilter> f;
    f->SetInputData(input);
    f->SetConstruction(construction);
    f->SetSplitPointToInc2();
    f->SetBoundaryModeToGradientToSplitPoint();
    f->SetIterations(2);
    f->Update();
    const int degree = construction == vtkCloughTocherSplineFilter::Quartic ? 4 : 3;
    double worst[2];
    const int interior = MaxJumpsAcrossCellEdges(f->GetOutput(), degree, false, worst);
    const char* name = vtkCloughTocherSplineFilter::GetConstructionName(construction);
    EXPECT_GT(interior, 40) << name;
    EXPECT_LT(worst[0], 1e-14) << name;
    EXPECT_LT(worst[1], 1e-12) << name;
  }
}

TEST(vtkCloughTocherSplineFilter, QuarticOutputLayout)
{
  const int n = 3;
  vtkSmartPointer<vtkPolyData> input = Franke(n);
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(input);
  f->SetConstructionToQuartic();
  f->SetIterations(3);
  f->Update();
  vtkUnstructuredGrid* out = f->GetOutput();
  const vtkIdType nV = (n + 1) * (n + 1), nE = 3 * n * n + 2 * n, nT = 2 * n * n;
  EXPECT_EQ(out->GetNumberOfPoints(), nV + 3 * nE + 19 * nT);
  EXPECT_EQ(out->GetNumberOfCells(), 3 * nT);
  EXPECT_EQ(out->GetCellSize(0), 15);
  EXPECT_EQ(out->GetCellType(0), VTK_BEZIER_TRIANGLE);
  EXPECT_EQ(vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("Construction"))
              ->GetValue(0),
    "Quartic");
}

TEST(vtkCloughTocherSplineFilter, FallsBackToActiveTextureCoordinates)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  vtkDataArray* uv = input->GetPointData()->GetArray("UV");
  uv->SetName("tcoords");
  input->GetPointData()->SetTCoords(uv);
  vtkSmartPointer<vtkUnstructuredGrid> out = Convert(input, vtkCloughTocherSplineFilter::CTo);
  EXPECT_EQ(out->GetNumberOfCells(), 3 * 8);
}

TEST(vtkCloughTocherSplineFilter, SettableArrayNames)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  input->GetPointData()->GetArray("dFdu")->SetName("Su");
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(input);
  f->SetDuArrayName("Su");
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 3 * 8);
}

// --- Bad input: each case names the problem and the offending element. -------------------------

TEST(vtkCloughTocherSplineFilter, RejectsEmptyInput)
{
  vtkNew<vtkPolyData> empty;
  EXPECT_NE(ExpectFailure(empty).find("empty input"), std::string::npos);
}

TEST(vtkCloughTocherSplineFilter, RejectsNonTriangleCells)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  vtkIdType quad[4] = { 0, 1, 4, 3 };
  input->GetPolys()->InsertNextCell(4, quad);
  input->GetCellData()->Initialize();
  const std::string msg = ExpectFailure(input);
  EXPECT_NE(msg.find("cell 8 is a polygon with 4 points"), std::string::npos) << msg;

  vtkSmartPointer<vtkPolyData> withLine = Franke(2);
  vtkNew<vtkCellArray> lines;
  vtkIdType line[2] = { 0, 1 };
  lines->InsertNextCell(2, line);
  withLine->SetLines(lines);
  EXPECT_NE(ExpectFailure(withLine).find("line cell"), std::string::npos);
}

TEST(vtkCloughTocherSplineFilter, RejectsMissingAndWrongSizedArrays)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  input->GetPointData()->RemoveArray("dFdv");
  std::string msg = ExpectFailure(input);
  EXPECT_NE(msg.find("'dFdv'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;

  input = Franke(2);
  input->GetPointData()->RemoveArray("UV");
  msg = ExpectFailure(input);
  EXPECT_NE(msg.find("no parameter coordinates"), std::string::npos) << msg;

  input = Franke(2);
  vtkNew<vtkDoubleArray> uv3;
  uv3->SetName("UV");
  uv3->SetNumberOfComponents(3);
  uv3->SetNumberOfTuples(input->GetNumberOfPoints());
  uv3->Fill(0.0);
  input->GetPointData()->AddArray(uv3);
  msg = ExpectFailure(input);
  EXPECT_NE(msg.find("has 3 components, expected 2"), std::string::npos) << msg;

  // Mid-edge gradients: needed by MGi, wrong size.
  input = Franke(2);
  input->GetCellData()->RemoveArray("EdgeGradients");
  msg = ExpectFailure(input, vtkCloughTocherSplineFilter::MGi);
  EXPECT_NE(msg.find("'EdgeGradients'"), std::string::npos) << msg;
  vtkNew<vtkDoubleArray> eg;
  eg->SetName("EdgeGradients");
  eg->SetNumberOfComponents(6);
  eg->SetNumberOfTuples(input->GetNumberOfCells());
  eg->Fill(0.0);
  input->GetCellData()->AddArray(eg);
  msg = ExpectFailure(input, vtkCloughTocherSplineFilter::CTi,
    vtkCloughTocherSplineFilter::GradientToSplitPoint);
  EXPECT_NE(msg.find("has 6 components, expected 18"), std::string::npos) << msg;
}

TEST(vtkCloughTocherSplineFilter, RejectsNonFiniteValues)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  input->GetPointData()->GetArray("dFdu")->SetComponent(4, 2, std::nan(""));
  std::string msg = ExpectFailure(input);
  EXPECT_NE(msg.find("non-finite value"), std::string::npos) << msg;
  EXPECT_NE(msg.find("point 4"), std::string::npos) << msg;

  input = Franke(2);
  double p[3] = { 0.0, std::numeric_limits<double>::infinity(), 0.0 };
  input->GetPoints()->SetPoint(7, p);
  msg = ExpectFailure(input);
  EXPECT_NE(msg.find("point 7"), std::string::npos) << msg;

  input = Franke(2);
  input->GetCellData()->GetArray("EdgeGradients")->SetComponent(3, 11, std::nan(""));
  msg = ExpectFailure(input, vtkCloughTocherSplineFilter::MGo);
  EXPECT_NE(msg.find("the mid-edge gradients of triangle 3 include nan"), std::string::npos)
    << msg;

  // Gradients of another type are copied, and checked on the way.
  input = Franke(2);
  vtkNew<vtkFloatArray> single;
  single->DeepCopy(input->GetCellData()->GetArray("EdgeGradients"));
  single->SetComponent(5, 2, std::numeric_limits<float>::infinity());
  input->GetCellData()->AddArray(single); // replaces the array of the same name
  msg = ExpectFailure(input, vtkCloughTocherSplineFilter::MGo);
  EXPECT_NE(msg.find("cell data array 'EdgeGradients'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cell 5"), std::string::npos) << msg;
}

// The mid-edge gradients are checked where a construction reads them: every edge's for MGo, the
// boundary edges' for KaG, whose spline does not depend on the others (the same bits with a NaN
// there). The message names the input cell, after the locality renumbering too.
TEST(vtkCloughTocherSplineFilter, ChecksTheMidEdgeGradientsItReads)
{
  const vtkSmartPointer<vtkPolyData> clean = Franke(3);
  std::map<std::pair<vtkIdType, vtkIdType>, int> edgeUses;
  auto edgeOf = [&](vtkIdType c, int l) {
    vtkIdType n = 0;
    const vtkIdType* p = nullptr;
    clean->GetCellPoints(c, n, p);
    const vtkIdType a = p[l], b = p[(l + 1) % 3];
    return std::make_pair(std::min(a, b), std::max(a, b));
  };
  for (vtkIdType c = 0; c < clean->GetNumberOfCells(); ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      ++edgeUses[edgeOf(c, l)];
    }
  }
  const vtkSmartPointer<vtkUnstructuredGrid> reference =
    Convert(clean, vtkCloughTocherSplineFilter::KaG);
  int boundary = 0, interior = 0;
  for (vtkIdType c = 0; c < clean->GetNumberOfCells(); ++c)
  {
    for (int l = 0; l < 3; ++l)
    {
      vtkNew<vtkPolyData> input;
      input->DeepCopy(clean);
      input->GetCellData()->GetArray("EdgeGradients")->SetComponent(c, 6 * l + 4, std::nan(""));
      const std::string cell = "the mid-edge gradients of triangle " + std::to_string(c) + " ";
      std::string msg = ExpectFailure(input, vtkCloughTocherSplineFilter::MGo);
      EXPECT_NE(msg.find(cell), std::string::npos) << msg;
      if (edgeUses[edgeOf(c, l)] == 1)
      {
        ++boundary;
        msg = ExpectFailure(input, vtkCloughTocherSplineFilter::KaG);
        EXPECT_NE(msg.find(cell), std::string::npos) << msg;
        // The Bézier extraction's degrees of freedom are these values: never a NaN among them.
        msg = ExpectFailure(input, vtkCloughTocherSplineFilter::KaG,
          vtkCloughTocherSplineFilter::Midpoint,
          [](vtkCloughTocherSplineFilter* f) { f->ComputeBezierExtractionOn(); });
        EXPECT_NE(msg.find(cell), std::string::npos) << msg;
        continue;
      }
      ++interior;
      const vtkSmartPointer<vtkUnstructuredGrid> out =
        Convert(input, vtkCloughTocherSplineFilter::KaG);
      ASSERT_EQ(out->GetNumberOfPoints(), reference->GetNumberOfPoints());
      for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
      {
        double p[3], q[3];
        out->GetPoint(i, p);
        reference->GetPoint(i, q);
        ASSERT_TRUE(p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) << "cell " << c << " edge " << l;
      }
    }
  }
  EXPECT_EQ(boundary, 12); // a 3 x 3 grid's boundary
  EXPECT_GT(interior, 12);

  // Above ctk::MinTrianglesForLocalityOrder the kernel's triangle ids are not the cells'.
  const vtkSmartPointer<vtkPolyData> large = Franke(130);
  ASSERT_GE(large->GetNumberOfCells(), ctk::MinTrianglesForLocalityOrder);
  large->GetCellData()->GetArray("EdgeGradients")->SetComponent(20001, 7, -std::nan(""));
  const std::string msg = ExpectFailure(large, vtkCloughTocherSplineFilter::MGo);
  EXPECT_NE(msg.find("the mid-edge gradients of triangle 20001 "), std::string::npos) << msg;
}

TEST(vtkCloughTocherSplineFilter, RejectsZeroAreaParameterTriangles)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  // Point 4 (the centre) moved onto the line through points 0 and 8 makes cell 0 flat in (u, v)
  // for the forward/alternating diagonal of cell (0, 0): triangle (0, 1, 4) -> move 1 onto 0-4.
  vtkDataArray* uv = input->GetPointData()->GetArray("UV");
  uv->SetComponent(1, 0, 0.25);
  uv->SetComponent(1, 1, 0.25);
  const std::string msg = ExpectFailure(input);
  EXPECT_NE(msg.find("degenerate parameter triangle: cell 0"), std::string::npos) << msg;
}

TEST(vtkCloughTocherSplineFilter, RejectsNonManifoldEdges)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  // A third triangle on the interior edge (0, 4), with a new point off the mesh.
  double p[3] = { 0.25, -0.5, 0.0 };
  const vtkIdType extra = input->GetPoints()->InsertNextPoint(p);
  for (const char* name : { "UV", "dFdu", "dFdv" })
  {
    vtkDataArray* a = input->GetPointData()->GetArray(name);
    std::vector<double> t(a->GetNumberOfComponents(), 0.0);
    t[0] = name[0] == 'U' ? 0.25 : 1.0;
    if (name[0] == 'U')
    {
      t[1] = -0.5;
    }
    a->InsertNextTuple(t.data());
  }
  vtkIdType tri[3] = { 0, 4, extra };
  input->GetPolys()->InsertNextCell(3, tri);
  input->GetCellData()->Initialize();
  const std::string msg = ExpectFailure(input);
  EXPECT_NE(msg.find("non-manifold edge (0, 4)"), std::string::npos) << msg;
}

TEST(vtkCloughTocherSplineFilter, RejectsRepeatedVertices)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  vtkIdType tri[3] = { 2, 2, 5 };
  input->GetPolys()->InsertNextCell(3, tri);
  input->GetCellData()->Initialize();
  const std::string msg = ExpectFailure(input);
  EXPECT_NE(msg.find("repeats a vertex"), std::string::npos) << msg;
}

TEST(vtkCloughTocherSplineFilter, KaGNeedsEdgeGradients)
{
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  input->GetCellData()->RemoveArray("EdgeGradients");
  const std::string msg = ExpectFailure(input, vtkCloughTocherSplineFilter::KaG);
  EXPECT_NE(msg.find("needed by KaG"), std::string::npos) << msg;
  // Ka itself needs none.
  EXPECT_EQ(Convert(input, vtkCloughTocherSplineFilter::Ka)->GetNumberOfCells(), 24);
}

TEST(vtkCloughTocherSplineFilter, BezierExtractionReproducesTheControlPoints)
{
  vtkSmartPointer<vtkPolyData> input = Franke(3);
  for (int construction : { vtkCloughTocherSplineFilter::CTi, vtkCloughTocherSplineFilter::KaG,
         vtkCloughTocherSplineFilter::MGi })
  {
    vtkNew<vtkCloughTocherSplineFilter> f;
    f->SetInputData(input);
    f->SetConstruction(construction);
    f->SetBoundaryModeToGradientToSplitPoint();
    f->ComputeBezierExtractionOn();
    f->Update();
    vtkUnstructuredGrid* out = f->GetOutput();
    vtkDataArray* dofIds = out->GetCellData()->GetArray("GlobalDofIds");
    vtkDataArray* ops = out->GetCellData()->GetArray("BezierExtraction");
    vtkDataArray* dofs = out->GetFieldData()->GetArray("DegreesOfFreedom");
    ASSERT_NE(dofIds, nullptr);
    ASSERT_NE(ops, nullptr);
    ASSERT_NE(dofs, nullptr);
    const int M = dofIds->GetNumberOfComponents();
    ASSERT_EQ(ops->GetNumberOfComponents(), 10 * M);
    double worst = 0.0;
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      out->GetCellPoints(c, ids);
      for (int row = 0; row < 10; ++row)
      {
        ctk::Vec3 p = ctk::Vec3::Zero();
        for (int j = 0; j < M; ++j)
        {
          const vtkIdType d = static_cast<vtkIdType>(dofIds->GetComponent(c, j));
          if (d >= 0)
          {
            p += ops->GetComponent(c, row * M + j) *
              ctk::Vec3(dofs->GetComponent(d, 0), dofs->GetComponent(d, 1), dofs->GetComponent(d, 2));
          }
        }
        double x[3];
        out->GetPoint(ids->GetId(row), x);
        worst = std::max(worst, (p - ctk::Vec3(x[0], x[1], x[2])).norm());
      }
    }
    EXPECT_LT(worst, 1e-13) << vtkCloughTocherSplineFilter::GetConstructionName(construction);
  }
  vtkNew<vtkCloughTocherSplineFilter> iterated;
  iterated->SetInputData(input);
  iterated->SetIterations(2);
  iterated->ComputeBezierExtractionOn();
  auto capture = ErrorCapture::Attach(iterated);
  auto pipelineCapture = ErrorCapture::Attach(iterated->GetExecutive());
  iterated->Update();
  EXPECT_NE(capture->Message.find("iterations"), std::string::npos) << capture->Message;
}

namespace
{
// The output keeps only the control points its cells use.
void ExpectEveryPointUsed(vtkUnstructuredGrid* out)
{
  std::vector<char> used(out->GetNumberOfPoints(), 0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType k = 0; k < out->GetNumberOfCells(); ++k)
  {
    out->GetCellPoints(k, ids);
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
    {
      used[ids->GetId(a)] = 1;
    }
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), out->GetNumberOfPoints());
}

// A piece's cells keep the Bézier extraction that the same piece without ghost flags gives them.
void ExpectGhostsKeepTheExtraction(vtkPolyData* part, int construction)
{
  vtkNew<vtkPolyData> unflagged;
  unflagged->ShallowCopy(part);
  unflagged->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  vtkNew<vtkCloughTocherSplineFilter> flagged, all;
  flagged->SetInputData(part);
  all->SetInputData(unflagged);
  for (vtkCloughTocherSplineFilter* f : { flagged.Get(), all.Get() })
  {
    f->SetConstruction(construction);
    f->ComputeBezierExtractionOn();
    f->Update();
  }
  vtkCellData* got = flagged->GetOutput()->GetCellData();
  vtkCellData* want = all->GetOutput()->GetCellData();
  ASSERT_LT(got->GetNumberOfTuples(), want->GetNumberOfTuples());
  for (const char* name : { "GlobalDofIds", "BezierExtraction" })
  {
    vtkDataArray* g = got->GetArray(name);
    vtkDataArray* w = want->GetArray(name);
    ASSERT_TRUE(g && w) << name;
    for (vtkIdType c = 0; c < g->GetNumberOfTuples(); ++c)
    {
      const vtkIdType s = 3 * static_cast<vtkIdType>(got->GetArray("MacroTriangleId")->GetTuple1(c)) +
        static_cast<vtkIdType>(got->GetArray("MicroTriangleId")->GetTuple1(c));
      for (int j = 0; j < g->GetNumberOfComponents(); ++j)
      {
        ASSERT_EQ(g->GetComponent(c, j), w->GetComponent(s, j)) << name << " cell " << c;
      }
    }
  }
}
} // namespace

TEST(vtkCloughTocherSplineFilter, PiecesWithGhostCellsReproduceTheSerialSpline)
{
  // A distributed run, emulated: each piece is its own triangles plus the ghost levels the
  // filter asks for (flagged in vtkGhostType); the pieces' outputs must be the serial spline.
  vtkSmartPointer<vtkPolyData> input = MakeSampledPolyData(
    ctk::RegularGridMesh(8, ctk::GridDiagonal::Alternating), ctk::AnalyticSurface::Franke);
  const vtkIdType nT = input->GetNumberOfCells();
  vtkNew<vtkIdTypeArray> gids;
  gids->SetName("GlobalCellIds");
  for (vtkIdType t = 0; t < nT; ++t)
  {
    gids->InsertNextValue(1000 + t);
  }
  input->GetCellData()->SetGlobalIds(gids);
  // Cells sharing a point are neighbours (VTK's ghost levels).
  input->BuildLinks();
  auto ring = [&](std::vector<char>& in) {
    std::vector<char> grown = in;
    vtkNew<vtkIdList> pts, cells;
    for (vtkIdType t = 0; t < nT; ++t)
    {
      if (!in[t])
      {
        continue;
      }
      input->GetCellPoints(t, pts);
      for (vtkIdType a = 0; a < pts->GetNumberOfIds(); ++a)
      {
        input->GetPointCells(pts->GetId(a), cells);
        for (vtkIdType b = 0; b < cells->GetNumberOfIds(); ++b)
        {
          grown[cells->GetId(b)] = 1;
        }
      }
    }
    in.swap(grown);
  };
  struct Case
  {
    int Construction, Iterations;
  };
  for (const Case c : { Case{ vtkCloughTocherSplineFilter::CTo, 0 },
         Case{ vtkCloughTocherSplineFilter::CTi, 0 }, Case{ vtkCloughTocherSplineFilter::Ka, 2 },
         Case{ vtkCloughTocherSplineFilter::KaG, 0 }, Case{ vtkCloughTocherSplineFilter::Kashyap, 2 },
         Case{ vtkCloughTocherSplineFilter::Quartic, 2 } })
  {
    vtkNew<vtkCloughTocherSplineFilter> serial;
    serial->SetInputData(input);
    serial->SetConstruction(c.Construction);
    serial->SetIterations(c.Iterations);
    serial->Update();
    vtkUnstructuredGrid* whole = serial->GetOutput();
    const int perCell = whole->GetCellSize(0);
    vtkDataArray* wholeGid = whole->GetCellData()->GetArray("MacroTriangleGlobalId");
    ASSERT_NE(wholeGid, nullptr);
    std::map<std::pair<vtkIdType, int>, vtkIdType> serialCell;
    vtkDataArray* wholeMicro = whole->GetCellData()->GetArray("MicroTriangleId");
    for (vtkIdType k = 0; k < whole->GetNumberOfCells(); ++k)
    {
      serialCell[{ static_cast<vtkIdType>(wholeGid->GetTuple1(k)), static_cast<int>(wholeMicro->GetTuple1(k)) }] = k;
    }
    const int levels = serial->GetRequiredGhostLevels();
    vtkIdType covered = 0;
    double worst = 0.0;
    for (int piece = 0; piece < 3; ++piece)
    {
      std::vector<char> own(nT, 0), with(nT, 0);
      for (vtkIdType t = 0; t < nT; ++t)
      {
        double b[6];
        input->GetCellBounds(t, b);
        own[t] = with[t] = static_cast<int>(3.0 * (b[0] + b[1]) / 2.0) == piece;
      }
      for (int l = 0; l < levels; ++l)
      {
        ring(with);
      }
      vtkNew<vtkPolyData> part;
      part->SetPoints(input->GetPoints());
      part->GetPointData()->ShallowCopy(input->GetPointData());
      vtkNew<vtkCellArray> polys;
      part->GetCellData()->CopyAllocate(input->GetCellData());
      vtkNew<vtkUnsignedCharArray> ghost;
      ghost->SetName(vtkDataSetAttributes::GhostArrayName());
      vtkNew<vtkIdList> pts;
      for (vtkIdType t = 0; t < nT; ++t)
      {
        if (with[t])
        {
          input->GetCellPoints(t, pts);
          part->GetCellData()->CopyData(input->GetCellData(), t, polys->GetNumberOfCells());
          polys->InsertNextCell(pts);
          ghost->InsertNextValue(own[t] ? 0 : vtkDataSetAttributes::DUPLICATECELL);
        }
      }
      part->SetPolys(polys);
      part->GetCellData()->AddArray(ghost);
      // CopyData leaves global ids out by default: give the part its own.
      vtkNew<vtkIdTypeArray> partIds;
      partIds->SetName("GlobalCellIds");
      for (vtkIdType t = 0; t < nT; ++t)
      {
        if (with[t])
        {
          partIds->InsertNextValue(gids->GetValue(t));
        }
      }
      part->GetCellData()->SetGlobalIds(partIds);
      vtkNew<vtkCloughTocherSplineFilter> f;
      f->SetInputData(part);
      f->SetConstruction(c.Construction);
      f->SetIterations(c.Iterations);
      f->Update();
      vtkUnstructuredGrid* out = f->GetOutput();
      EXPECT_EQ(out->GetNumberOfCells(), 3 * std::count(own.begin(), own.end(), 1));
      // Ghost triangles are dropped with the control points only they use (CTo needs none).
      ASSERT_EQ(levels == 0, with == own);
      if (levels > 0)
      {
        ExpectEveryPointUsed(out);
      }
      if (levels > 0 &&
        vtkCloughTocherSplineFilter::GetConstructionHasBezierExtraction(c.Construction))
      {
        ExpectGhostsKeepTheExtraction(part, c.Construction);
      }
      covered += out->GetNumberOfCells();
      vtkDataArray* gid = out->GetCellData()->GetArray("MacroTriangleGlobalId");
      vtkDataArray* micro = out->GetCellData()->GetArray("MicroTriangleId");
      ASSERT_NE(gid, nullptr);
      vtkNew<vtkIdList> a, b;
      for (vtkIdType k = 0; k < out->GetNumberOfCells(); ++k)
      {
        const vtkIdType s = serialCell.at({ static_cast<vtkIdType>(gid->GetTuple1(k)), static_cast<int>(micro->GetTuple1(k)) });
        out->GetCellPoints(k, a);
        whole->GetCellPoints(s, b);
        for (int p = 0; p < perCell; ++p)
        {
          double x[3], y[3];
          out->GetPoint(a->GetId(p), x);
          whole->GetPoint(b->GetId(p), y);
          worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(x, y)));
        }
      }
    }
    EXPECT_EQ(covered, whole->GetNumberOfCells());
    EXPECT_LT(worst, 1e-12) << vtkCloughTocherSplineFilter::GetConstructionName(c.Construction);
  }
}

TEST(vtkCloughTocherSplineFilter, AcceptsUnstructuredGridsOfTriangles)
{
  vtkSmartPointer<vtkPolyData> input = Franke(3);
  vtkNew<vtkAppendFilter> toGrid;
  toGrid->AddInputData(input);
  toGrid->Update();
  vtkSmartPointer<vtkUnstructuredGrid> fromPoly = Convert(input, vtkCloughTocherSplineFilter::Ka);
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(toGrid->GetOutput());
  f->SetConstructionToKa();
  f->Update();
  vtkUnstructuredGrid* fromGrid = f->GetOutput();
  ASSERT_EQ(fromGrid->GetNumberOfPoints(), fromPoly->GetNumberOfPoints());
  for (vtkIdType p = 0; p < fromGrid->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    fromGrid->GetPoint(p, a);
    fromPoly->GetPoint(p, b);
    ASSERT_EQ(vtkMath::Distance2BetweenPoints(a, b), 0.0);
  }
  // Other cell types are named.
  vtkNew<vtkUnstructuredGrid> mixed;
  mixed->DeepCopy(toGrid->GetOutput());
  const vtkIdType quad[4] = { 0, 1, 5, 4 };
  mixed->InsertNextCell(VTK_QUAD, 4, quad);
  mixed->GetCellData()->Initialize();
  vtkNew<vtkCloughTocherSplineFilter> g;
  g->SetInputData(mixed);
  auto capture = ErrorCapture::Attach(g);
  auto pipelineCapture = ErrorCapture::Attach(g->GetExecutive());
  g->Update();
  EXPECT_NE(capture->Message.find("cell 18 is a vtkQuad"), std::string::npos) << capture->Message;
}

namespace
{
/// Boundary-curve array for `input`: per boundary local edge, curve(t, l) gives the six values
/// (near p_l, near p_{l+1}); interior edges NaN.
template <typename Curve>
vtkSmartPointer<vtkDoubleArray> BoundaryCurves(vtkPolyData* input, const ctk::MeshTopology& topo, Curve curve)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName("Curves");
  a->SetNumberOfComponents(18);
  a->SetNumberOfTuples(input->GetNumberOfCells());
  a->Fill(std::nan(""));
  for (vtkIdType t = 0; t < input->GetNumberOfCells(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      if (topo.Neighbor(t, l) < 0)
      {
        double c[6];
        curve(t, l, c);
        for (int i = 0; i < 6; ++i)
        {
          a->SetComponent(t, 6 * l + i, c[i]);
        }
      }
    }
  }
  return a;
}

std::vector<ctk::Id> Triangles(vtkPolyData* input)
{
  std::vector<ctk::Id> tri;
  for (vtkIdType t = 0; t < input->GetNumberOfCells(); ++t)
  {
    for (int i = 0; i < 3; ++i)
    {
      tri.push_back(input->GetCell(t)->GetPointId(i));
    }
  }
  return tri;
}
} // namespace

TEST(vtkCloughTocherSplineFilter, BoundaryCurvePointsAreFollowed)
{
  vtkSmartPointer<vtkPolyData> input = MakeSampledPolyData(
    ctk::RefinedTriangleMesh(ctk::Vec2(0, 0), ctk::Vec2(1, 0), ctk::Vec2(0.3, 0.8), 2),
    ctk::AnalyticSurface::SineWave);
  const std::vector<ctk::Id> tri = Triangles(input);
  ctk::MeshTopology topo;
  ASSERT_TRUE(ctk::BuildMeshTopology(input->GetNumberOfPoints(), input->GetNumberOfCells(), tri.data(), topo).Ok);
  const ctk::Id nV = input->GetNumberOfPoints();
  auto row = [&](const char* name, ctk::Id v) {
    vtkDataArray* a = input->GetPointData()->GetArray(name);
    return ctk::Vec3(a->GetComponent(v, 0), a->GetComponent(v, 1), a->GetComponent(v, 2));
  };
  auto uvOf = [&](ctk::Id v) {
    vtkDataArray* a = input->GetPointData()->GetArray("UV");
    return ctk::Vec2(a->GetComponent(v, 0), a->GetComponent(v, 1));
  };
  auto position = [&](ctk::Id v) {
    double x[3];
    input->GetPoint(v, x);
    return ctk::Vec3(x[0], x[1], x[2]);
  };
  // Eq. (11) from the vertex data: prescribing it changes nothing, bit for bit.
  auto eq11 = [&](vtkIdType t, int l, double* c) {
    const ctk::Id a = tri[3 * t + l], b = tri[3 * t + (l + 1) % 3];
    const ctk::Vec3 ta = ctk::EdgeControlPoint(position(a), row("dFdu", a), row("dFdv", a), uvOf(a), uvOf(b));
    const ctk::Vec3 tb = ctk::EdgeControlPoint(position(b), row("dFdu", b), row("dFdv", b), uvOf(b), uvOf(a));
    std::copy_n(ta.data(), 3, c);
    std::copy_n(tb.data(), 3, c + 3);
  };
  // Another curve: eq. (11) moved off the surface by a smooth field.
  auto moved = [&](vtkIdType t, int l, double* c) {
    eq11(t, l, c);
    for (int i = 0; i < 6; ++i)
    {
      c[i] += 0.01 * std::sin(3 * c[i % 3] + i);
    }
  };
  for (int construction = vtkCloughTocherSplineFilter::CTo; construction <= vtkCloughTocherSplineFilter::KaG;
       ++construction)
  {
    const char* name = vtkCloughTocherSplineFilter::GetConstructionName(construction);
    auto run = [&](vtkDataArray* curves) {
      vtkNew<vtkPolyData> copy;
      copy->DeepCopy(input);
      if (curves)
      {
        copy->GetCellData()->AddArray(curves);
      }
      vtkNew<vtkCloughTocherSplineFilter> f;
      f->SetInputData(copy);
      f->SetConstruction(construction);
      f->SetBoundaryModeToGradientToSplitPoint();
      f->SetBoundaryCurvePointsArrayName(curves ? "Curves" : "");
      f->Update();
      auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
      out->ShallowCopy(f->GetOutput());
      return out;
    };
    vtkSmartPointer<vtkUnstructuredGrid> plain = run(nullptr);
    vtkSmartPointer<vtkUnstructuredGrid> same = run(BoundaryCurves(input, topo, eq11));
    vtkSmartPointer<vtkUnstructuredGrid> other = run(BoundaryCurves(input, topo, moved));
    ASSERT_EQ(plain->GetNumberOfPoints(), same->GetNumberOfPoints()) << name;
    ASSERT_EQ(plain->GetNumberOfPoints(), other->GetNumberOfPoints()) << name;
    for (vtkIdType p = 0; p < plain->GetNumberOfPoints(); ++p)
    {
      double x[3], y[3];
      plain->GetPoint(p, x);
      same->GetPoint(p, y);
      ASSERT_TRUE(std::equal(x, x + 3, y)) << name << ": point " << p;
    }
    // The boundary macro-edge points of the output (kernel layout) are the prescribed doubles.
    vtkSmartPointer<vtkDoubleArray> curves = BoundaryCurves(input, topo, moved);
    int boundaryEdges = 0;
    for (ctk::Id e = 0; e < static_cast<ctk::Id>(topo.Edges.size()); ++e)
    {
      if (!topo.IsBoundaryEdge(e))
      {
        continue;
      }
      ++boundaryEdges;
      const ctk::Id t = topo.EdgeTriangles[e][0];
      const int l = topo.EdgeLocalIndex[e][0];
      for (int s = 0; s < 2; ++s)
      {
        const ctk::Id a = topo.Edges[e][s];
        const int offset = a == tri[3 * t + l] ? 0 : 3;
        double x[3];
        other->GetPoint(nV + 2 * e + s, x);
        for (int i = 0; i < 3; ++i)
        {
          EXPECT_EQ(x[i], curves->GetComponent(t, 6 * l + offset + i)) << name << ": edge " << e;
        }
      }
    }
    EXPECT_GT(boundaryEdges, 8);
    // Every macro-patch stays C1 inside (its micro-edges).
    double worst[2];
    EXPECT_GT(MaxJumpsAcrossCellEdges(other, 3, true, worst), 40) << name;
    EXPECT_LT(worst[0], 1e-14) << name;
    EXPECT_LT(worst[1], 1e-12) << name;
  }
}

TEST(vtkCloughTocherSplineFilter, RejectsBadBoundaryCurvePoints)
{
  auto failure = [](vtkPolyData* input, int construction, bool extraction) {
    vtkNew<vtkCloughTocherSplineFilter> f;
    f->SetInputData(input);
    f->SetConstruction(construction);
    f->SetBoundaryCurvePointsArrayName("Curves");
    f->SetComputeBezierExtraction(extraction);
    auto capture = ErrorCapture::Attach(f);
    auto pipelineCapture = ErrorCapture::Attach(f->GetExecutive());
    f->Update();
    EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0);
    return capture->Message;
  };
  vtkSmartPointer<vtkPolyData> input = Franke(2);
  std::string msg = failure(input, vtkCloughTocherSplineFilter::CTi, false);
  EXPECT_NE(msg.find("'Curves' (boundary curve points) is missing"), std::string::npos) << msg;

  vtkNew<vtkDoubleArray> curves;
  curves->SetName("Curves");
  curves->SetNumberOfComponents(6);
  curves->SetNumberOfTuples(input->GetNumberOfCells());
  curves->Fill(0.0);
  input->GetCellData()->AddArray(curves);
  msg = failure(input, vtkCloughTocherSplineFilter::CTi, false);
  EXPECT_NE(msg.find("has 6 components, expected 18"), std::string::npos) << msg;

  curves->SetNumberOfComponents(18);
  curves->SetNumberOfTuples(input->GetNumberOfCells());
  curves->Fill(std::nan(""));
  curves->SetComponent(3, 7, 0.5); // one value of local edge 1 given, five NaN
  msg = failure(input, vtkCloughTocherSplineFilter::CTi, false);
  EXPECT_NE(msg.find("partly NaN group (components 6 to 11) at cell 3"), std::string::npos) << msg;

  curves->SetComponent(3, 7, std::numeric_limits<double>::infinity());
  msg = failure(input, vtkCloughTocherSplineFilter::CTi, false);
  EXPECT_NE(msg.find("non-finite value (inf) at cell 3"), std::string::npos) << msg;

  curves->Fill(std::nan(""));
  msg = failure(input, vtkCloughTocherSplineFilter::Kashyap, false);
  EXPECT_NE(msg.find("does not take prescribed boundary curves"), std::string::npos) << msg;
  msg = failure(input, vtkCloughTocherSplineFilter::CTi, true);
  EXPECT_NE(msg.find("Bezier extraction"), std::string::npos) << msg;
}

namespace
{
// Franke on a grid of 2 n^2 triangles, its inner points moved at random (by up to 0.15 of the
// spacing: no exact dyadic values, so that a changed order of operations shows in the bits), its
// points and triangles numbered at random (no locality order left, as qhull numbers a Delaunay
// mesh).
vtkSmartPointer<vtkPolyData> ShuffledFranke(int n, unsigned seed)
{
  ctk::ParameterMesh grid = ctk::RegularGridMesh(n, ctk::GridDiagonal::Alternating);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15 / n, 0.15 / n);
  for (ctk::Vec2& U : grid.UV)
  {
    for (int c = 0; c < 2; ++c)
    {
      U[c] += U[c] > 0 && U[c] < 1 ? jitter(rng) : 0.0;
    }
  }
  std::vector<ctk::Id> vertex(grid.UV.size()), triangle(grid.NumberOfTriangles());
  std::iota(vertex.begin(), vertex.end(), ctk::Id(0));
  std::iota(triangle.begin(), triangle.end(), ctk::Id(0));
  std::shuffle(vertex.begin(), vertex.end(), rng);
  std::shuffle(triangle.begin(), triangle.end(), rng);
  ctk::ParameterMesh m = grid;
  for (size_t v = 0; v < grid.UV.size(); ++v)
  {
    m.UV[vertex[v]] = grid.UV[v];
  }
  for (ctk::Id t = 0; t < grid.NumberOfTriangles(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      m.Triangles[3 * triangle[t] + l] = vertex[grid.Triangles[3 * t + l]];
    }
  }
  return MakeSampledPolyData(m, ctk::AnalyticSurface::Franke);
}

vtkSmartPointer<vtkUnstructuredGrid> ConvertInOrder(vtkPolyData* input, int construction,
  int order, const std::function<void(vtkCloughTocherSplineFilter*)>& setup = nullptr)
{
  vtkNew<vtkCloughTocherSplineFilter> f;
  f->SetInputData(input);
  f->SetConstruction(construction);
  f->SetOutputOrder(order);
  if (setup)
  {
    setup(f);
  }
  f->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

// The number of cells of `got` whose control points or domain points differ, bit for bit, from
// those of the cell of `want` with the same MacroTriangleId and MicroTriangleId.
vtkIdType CellsDifferingBitwise(vtkUnstructuredGrid* got, vtkUnstructuredGrid* want)
{
  auto macroOf = [](vtkUnstructuredGrid* g, vtkIdType c) {
    return 3 * static_cast<vtkIdType>(g->GetCellData()->GetArray("MacroTriangleId")->GetTuple1(c)) +
      static_cast<vtkIdType>(g->GetCellData()->GetArray("MicroTriangleId")->GetTuple1(c));
  };
  std::map<vtkIdType, vtkIdType> wantCell;
  for (vtkIdType c = 0; c < want->GetNumberOfCells(); ++c)
  {
    wantCell[macroOf(want, c)] = c;
  }
  vtkDataArray* uvGot = got->GetPointData()->GetArray("UV");
  vtkDataArray* uvWant = want->GetPointData()->GetArray("UV");
  vtkIdType differing = 0;
  vtkNew<vtkIdList> a, b;
  for (vtkIdType c = 0; c < got->GetNumberOfCells(); ++c)
  {
    const auto it = wantCell.find(macroOf(got, c));
    if (it == wantCell.end())
    {
      ++differing;
      continue;
    }
    got->GetCellPoints(c, a);
    want->GetCellPoints(it->second, b);
    bool same = a->GetNumberOfIds() == b->GetNumberOfIds();
    for (vtkIdType i = 0; same && i < a->GetNumberOfIds(); ++i)
    {
      double x[3], y[3], u[2], w[2];
      got->GetPoint(a->GetId(i), x);
      want->GetPoint(b->GetId(i), y);
      uvGot->GetTuple(a->GetId(i), u);
      uvWant->GetTuple(b->GetId(i), w);
      same = std::memcmp(x, y, sizeof(x)) == 0 && std::memcmp(u, w, sizeof(u)) == 0;
    }
    differing += same ? 0 : 1;
  }
  return differing;
}
} // namespace

TEST(vtkCloughTocherSplineFilter, LocalityOutputOrderKeepsEveryTrianglesBits)
{
  // Issue #12: a large mesh is built and output in the Morton order of its triangles, cells
  // carrying their input triangle in MacroTriangleId; InputOrder keeps cells 3t + k.
  vtkSmartPointer<vtkPolyData> input = ShuffledFranke(128, 3u);
  const vtkIdType nT = input->GetNumberOfCells();
  ASSERT_GE(nT, ctk::MinTrianglesForLocalityOrder);
  std::vector<ctk::Id> triangles;
  std::vector<double> uv(2 * input->GetNumberOfPoints());
  ASSERT_TRUE(ctsplines::ExtractTriangles(input, triangles).empty());
  for (vtkIdType p = 0; p < input->GetNumberOfPoints(); ++p)
  {
    input->GetPointData()->GetArray("UV")->GetTuple(p, &uv[2 * p]);
  }
  const std::vector<ctk::Id> order =
    ctk::TriangleLocalityOrder(input->GetNumberOfPoints(), nT, triangles.data(), uv.data());
  ASSERT_EQ(static_cast<vtkIdType>(order.size()), nT);

  using F = vtkCloughTocherSplineFilter;
  auto estimate = [](F* f) { f->SetDerivativeEstimationToLocalQuadratic(); };
  vtkNew<vtkPolyData> underived;
  underived->DeepCopy(input);
  underived->GetPointData()->RemoveArray("dFdu");
  underived->GetPointData()->RemoveArray("dFdv");
  // Mid-edge gradients as floats are copied, doubles read in place: both through a row map.
  vtkNew<vtkPolyData> floatGradients;
  floatGradients->DeepCopy(input);
  vtkNew<vtkFloatArray> egFloat;
  egFloat->DeepCopy(input->GetCellData()->GetArray("EdgeGradients"));
  egFloat->SetName("EdgeGradients");
  floatGradients->GetCellData()->AddArray(egFloat);
  struct Case
  {
    int Construction;
    vtkPolyData* Input;
    std::function<void(F*)> Setup;
  };
  for (const Case& c : { Case{ F::CTi, input, nullptr }, Case{ F::KaG, input, nullptr },
         Case{ F::Kashyap, input, [](F* f) { f->SetIterations(1); } },
         Case{ F::Quartic, input, nullptr }, Case{ F::CTo, underived, estimate },
         Case{ F::MGo, input, nullptr }, Case{ F::MGo, floatGradients, nullptr },
         Case{ F::KaG, underived, estimate } })
  {
    const std::string name = F::GetConstructionName(c.Construction);
    auto inputOrder = ConvertInOrder(c.Input, c.Construction, F::InputOrder, c.Setup);
    auto local = ConvertInOrder(c.Input, c.Construction, F::LocalityOrder, c.Setup);
    ASSERT_EQ(inputOrder->GetNumberOfCells(), 3 * nT) << name;
    ASSERT_EQ(local->GetNumberOfCells(), 3 * nT) << name;
    ASSERT_EQ(local->GetNumberOfPoints(), inputOrder->GetNumberOfPoints()) << name;
    vtkDataArray* macroIn = inputOrder->GetCellData()->GetArray("MacroTriangleId");
    vtkDataArray* macro = local->GetCellData()->GetArray("MacroTriangleId");
    vtkDataArray* micro = local->GetCellData()->GetArray("MicroTriangleId");
    vtkIdType misplaced = 0;
    for (vtkIdType cell = 0; cell < 3 * nT; ++cell)
    {
      misplaced += macroIn->GetTuple1(cell) != static_cast<double>(cell / 3) ||
        macro->GetTuple1(cell) != static_cast<double>(order[cell / 3]) ||
        micro->GetTuple1(cell) != static_cast<double>(cell % 3);
    }
    EXPECT_EQ(misplaced, 0) << name;
    EXPECT_EQ(CellsDifferingBitwise(local, inputOrder), 0) << name;
    // The first control points are the vertices, by first use in that order.
    vtkDataArray* uvOut = local->GetPointData()->GetArray("UV");
    std::vector<char> seen(input->GetNumberOfPoints(), 0);
    vtkIdType next = 0, wrong = 0;
    for (const ctk::Id t : order)
    {
      for (int l = 0; l < 3; ++l)
      {
        const ctk::Id v = triangles[3 * t + l];
        if (!seen[v])
        {
          seen[v] = 1;
          wrong += uvOut->GetComponent(next, 0) != uv[2 * v] ||
            uvOut->GetComponent(next, 1) != uv[2 * v + 1];
          ++next;
        }
      }
    }
    EXPECT_EQ(wrong, 0) << name;
  }
}

TEST(vtkCloughTocherSplineFilter, LocalityOutputOrderKeepsGhostsAndGlobalIds)
{
  // A distributed piece in the locality order: ghost triangles dropped, global ids passed on.
  vtkSmartPointer<vtkPolyData> input = ShuffledFranke(128, 4u);
  const vtkIdType nT = input->GetNumberOfCells();
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  vtkNew<vtkIdTypeArray> globalIds;
  globalIds->SetName("GlobalIds");
  vtkNew<vtkIdList> ids;
  vtkIdType owned = 0;
  for (vtkIdType t = 0; t < nT; ++t)
  {
    input->GetCellPoints(t, ids);
    double u = 0;
    for (int l = 0; l < 3; ++l)
    {
      u += input->GetPointData()->GetArray("UV")->GetComponent(ids->GetId(l), 0) / 3;
    }
    ghosts->InsertNextValue(u > 0.7 ? vtkDataSetAttributes::DUPLICATECELL : 0);
    owned += u > 0.7 ? 0 : 1;
    globalIds->InsertNextValue(7 * t + 1);
  }
  input->GetCellData()->AddArray(ghosts);
  input->GetCellData()->SetGlobalIds(globalIds);
  using F = vtkCloughTocherSplineFilter;
  auto inputOrder = ConvertInOrder(input, F::CTi, F::InputOrder);
  auto local = ConvertInOrder(input, F::CTi, F::LocalityOrder);
  ASSERT_EQ(local->GetNumberOfCells(), 3 * owned);
  ASSERT_EQ(local->GetNumberOfPoints(), inputOrder->GetNumberOfPoints());
  EXPECT_EQ(CellsDifferingBitwise(local, inputOrder), 0);
  vtkDataArray* macro = local->GetCellData()->GetArray("MacroTriangleId");
  vtkDataArray* global = local->GetCellData()->GetArray("MacroTriangleGlobalId");
  ASSERT_TRUE(global);
  vtkIdType wrong = 0, unordered = 0;
  for (vtkIdType c = 0; c < local->GetNumberOfCells(); ++c)
  {
    const vtkIdType t = static_cast<vtkIdType>(macro->GetTuple1(c));
    wrong += ghosts->GetValue(t) != 0 || global->GetTuple1(c) != static_cast<double>(7 * t + 1);
    unordered += c > 0 && macro->GetTuple1(c) < macro->GetTuple1(c - 1);
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(unordered, 0); // not the input's order
}

// Makes cell flat in (u, v): its third point moves to the midpoint of the other two (on a grid of
// dyadic (u, v) exactly).
void FlattenCell(vtkPolyData* input, vtkIdType cell)
{
  vtkNew<vtkIdList> ids;
  input->GetCellPoints(cell, ids);
  vtkDataArray* uv = input->GetPointData()->GetArray("UV");
  for (int c = 0; c < 2; ++c)
  {
    uv->SetComponent(ids->GetId(2), c,
      0.5 * (uv->GetComponent(ids->GetId(0), c) + uv->GetComponent(ids->GetId(1), c)));
  }
}

// The error text of the filter on input in both output orders, from the kernel's message on
// (VTK's prefix names the object's address), which must contain `expected`.
std::array<std::string, 2> ErrorsInBothOrders(vtkPolyData* input, const std::string& expected)
{
  std::array<std::string, 2> messages;
  for (int order : { vtkCloughTocherSplineFilter::InputOrder, vtkCloughTocherSplineFilter::LocalityOrder })
  {
    const std::string msg = ExpectFailure(input, vtkCloughTocherSplineFilter::CTi,
      vtkCloughTocherSplineFilter::Midpoint,
      [order](vtkCloughTocherSplineFilter* f) { f->SetOutputOrder(order); });
    const size_t at = msg.find(expected);
    EXPECT_NE(at, std::string::npos) << "order " << order << ": " << msg;
    messages[order] = msg.substr(std::min(at, msg.size()));
  }
  return messages;
}

TEST(vtkCloughTocherSplineFilter, LocalityOutputOrderNamesInputIdsInErrors)
{
  // A flat parameter triangle (found by the kernel, after the renumbering) is named by its
  // input id: the same message as in the input's order.
  vtkSmartPointer<vtkPolyData> input = ShuffledFranke(128, 5u);
  FlattenCell(input, 777);
  const std::array<std::string, 2> messages =
    ErrorsInBothOrders(input, "degenerate parameter triangle: cell 777 (");
  EXPECT_EQ(messages[1], messages[0]);
}

namespace
{
// A copy of input whose ghost triangles (DUPLICATECELL where u > 0.7) carry global ids, with
// (repeat set) a ghost copy of the first ghost and of the first owned triangle right after each,
// as D3 sends: the cells after them are shifted.
vtkSmartPointer<vtkPolyData> PieceWithGhosts(vtkPolyData* input, bool repeat)
{
  auto piece = vtkSmartPointer<vtkPolyData>::New();
  piece->SetPoints(input->GetPoints());
  piece->GetPointData()->ShallowCopy(input->GetPointData());
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  vtkNew<vtkIdTypeArray> globalIds;
  globalIds->SetName("GlobalIds");
  vtkDataArray* uv = input->GetPointData()->GetArray("UV");
  vtkDataArray* gradients = input->GetCellData()->GetArray("EdgeGradients");
  vtkNew<vtkDoubleArray> pieceGradients;
  pieceGradients->SetName("EdgeGradients");
  pieceGradients->SetNumberOfComponents(18);
  bool ghostRepeated = false, ownedRepeated = false;
  vtkNew<vtkIdList> ids;
  for (vtkIdType t = 0; t < input->GetNumberOfCells(); ++t)
  {
    input->GetCellPoints(t, ids);
    double u = 0;
    for (int l = 0; l < 3; ++l)
    {
      u += uv->GetComponent(ids->GetId(l), 0) / 3;
    }
    const bool ghost = u > 0.7;
    bool& repeated = ghost ? ghostRepeated : ownedRepeated;
    for (int copy = 0; copy < (repeat && !repeated ? 2 : 1); ++copy)
    {
      polys->InsertNextCell(ids);
      ghosts->InsertNextValue(ghost || copy ? vtkDataSetAttributes::DUPLICATECELL : 0);
      globalIds->InsertNextValue(7 * t + 1);
      pieceGradients->InsertNextTuple(gradients->GetTuple(t));
    }
    repeated = true;
  }
  piece->SetPolys(polys);
  piece->GetCellData()->AddArray(ghosts);
  piece->GetCellData()->SetGlobalIds(globalIds);
  piece->GetCellData()->AddArray(pieceGradients);
  return piece;
}
} // namespace

TEST(vtkCloughTocherSplineFilter, RepeatedGhostTrianglesAreDropped)
{
  // ParaView 5.11's D3 sends a few ghost cells twice (each of their edges then has three
  // triangles): the piece's spline is the one without the repeats, in both output orders and
  // with the Bézier extraction.
  vtkSmartPointer<vtkPolyData> input = ShuffledFranke(128, 6u);
  vtkSmartPointer<vtkPolyData> plain = PieceWithGhosts(input, false);
  vtkSmartPointer<vtkPolyData> repeated = PieceWithGhosts(input, true);
  ASSERT_EQ(repeated->GetNumberOfCells(), plain->GetNumberOfCells() + 2);
  using F = vtkCloughTocherSplineFilter;
  const std::function<void(F*)> extraction = [](F* f) { f->ComputeBezierExtractionOn(); };
  // MGo reads every triangle's mid-edge gradients, in place through a row map that must skip
  // the dropped rows.
  for (const int construction : { F::CTi, F::MGo })
  for (const int order : { F::InputOrder, F::LocalityOrder })
  {
    const auto setup = order == F::InputOrder && construction == F::CTi ? extraction : nullptr;
    auto want = ConvertInOrder(plain, construction, order, setup);
    auto got = ConvertInOrder(repeated, construction, order, setup);
    ASSERT_GT(want->GetNumberOfCells(), 0);
    ASSERT_EQ(got->GetNumberOfCells(), want->GetNumberOfCells()) << "order " << order;
    ASSERT_EQ(got->GetNumberOfPoints(), want->GetNumberOfPoints());
    // Same cells in the same order: the same global ids, points and extraction rows, bit for bit.
    std::vector<std::string> names = { "MacroTriangleGlobalId", "MicroTriangleId" };
    if (setup)
    {
      names.insert(names.end(), { "GlobalDofIds", "BezierExtraction" });
    }
    for (const std::string& name : names)
    {
      vtkDataArray* g = got->GetCellData()->GetArray(name.c_str());
      vtkDataArray* w = want->GetCellData()->GetArray(name.c_str());
      ASSERT_TRUE(g && w) << name;
      vtkIdType differing = 0;
      for (vtkIdType c = 0; c < g->GetNumberOfTuples(); ++c)
      {
        for (int j = 0; j < g->GetNumberOfComponents(); ++j)
        {
          differing += g->GetComponent(c, j) != w->GetComponent(c, j);
        }
      }
      EXPECT_EQ(differing, 0) << name << ", order " << order;
    }
    vtkIdType differing = 0;
    for (vtkIdType p = 0; p < got->GetNumberOfPoints(); ++p)
    {
      double x[3], y[3];
      got->GetPoint(p, x);
      want->GetPoint(p, y);
      differing += x[0] != y[0] || x[1] != y[1] || x[2] != y[2];
    }
    EXPECT_EQ(differing, 0) << "order " << order;
  }
}

namespace
{
// The last cell of piece that is no ghost: past the repeated ghosts of PieceWithGhosts (the
// first ghost and owned triangles come early in a grid's numbering), so that the kernel, which
// drops the two repeats, numbers it two lower.
vtkIdType LastOwnedCell(vtkPolyData* piece)
{
  vtkDataArray* ghosts = piece->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  vtkIdType last = piece->GetNumberOfCells() - 1;
  while (last >= 0 && ghosts->GetTuple1(last) != 0)
  {
    --last;
  }
  return last;
}
} // namespace

TEST(vtkCloughTocherSplineFilter, ErrorsAfterDroppedGhostsNameInputCells)
{
  // Errors found after the repeated ghosts are dropped name the input's cell, not the kernel's
  // triangle (two lower): a validation error, a topology error and an estimation error.
  using F = vtkCloughTocherSplineFilter;
  auto piece = [] { return PieceWithGhosts(Franke(4), true); };
  vtkSmartPointer<vtkPolyData> flat = piece();
  const vtkIdType cell = LastOwnedCell(flat);
  ASSERT_EQ(flat->GetNumberOfCells(), 34);
  ASSERT_EQ(cell, 31); // the kernel's triangle 29
  FlattenCell(flat, cell);
  std::string msg = ExpectFailure(flat);
  EXPECT_NE(msg.find("degenerate parameter triangle: cell 31 ("), std::string::npos) << msg;

  // The same cell, met by the minimum-energy estimation before the validation.
  flat->GetPointData()->RemoveArray("dFdu");
  flat->GetPointData()->RemoveArray("dFdv");
  msg = ExpectFailure(flat, F::CTi, F::Midpoint, [](F* f) { f->SetDerivativeEstimationToMinimumEnergy(); });
  EXPECT_NE(msg.find("parameter triangle 31 is degenerate"), std::string::npos) << msg;

  // A triangle that repeats a vertex, added last (cell 34, the kernel's 32), and an owned and a
  // ghost one whose point is out of range (the search for repeats, which reads the points of
  // both, leaves them to the topology's check).
  const vtkIdType repeatsVertex[3] = { 2, 2, 5 }, outOfRange[3] = { 2, 5, 1000000 };
  for (const int c : { 0, 1, 2 })
  {
    vtkSmartPointer<vtkPolyData> bad = piece();
    bad->GetPolys()->InsertNextCell(3, c == 0 ? repeatsVertex : outOfRange);
    vtkCellData* cd = bad->GetCellData();
    vtkUnsignedCharArray::SafeDownCast(cd->GetArray(vtkDataSetAttributes::GhostArrayName()))
      ->InsertNextValue(c == 2 ? vtkDataSetAttributes::DUPLICATECELL : 0);
    vtkIdTypeArray::SafeDownCast(cd->GetGlobalIds())->InsertNextValue(1000);
    msg = ExpectFailure(bad);
    const char* expected = c == 0 ? "triangle 34 repeats a vertex (2, 2, 5)"
                                  : "triangle 34 references point 1000000 outside [0, 25)";
    EXPECT_NE(msg.find(expected), std::string::npos) << "case " << c << ": " << msg;
  }

  // A fold: the same cell's third point moved just across its first edge. The two cells named
  // both have the edge named.
  vtkSmartPointer<vtkPolyData> folded = piece();
  vtkNew<vtkIdList> ids;
  folded->GetCellPoints(cell, ids);
  vtkDataArray* uv = folded->GetPointData()->GetArray("UV");
  for (int c = 0; c < 2; ++c)
  {
    const double mid = 0.5 * (uv->GetComponent(ids->GetId(0), c) + uv->GetComponent(ids->GetId(1), c));
    uv->SetComponent(ids->GetId(2), c, mid + 0.1 * (mid - uv->GetComponent(ids->GetId(2), c)));
  }
  msg = ExpectFailure(folded);
  long long named[2] = { -1, -1 }, edge[2] = { -1, -1 };
  const size_t at = msg.find("folded parameterisation: ");
  ASSERT_NE(at, std::string::npos) << msg;
  ASSERT_EQ(std::sscanf(msg.c_str() + at,
              "folded parameterisation: triangles %lld and %lld lie on the same side of their "
              "shared edge (%lld, %lld)",
              &named[0], &named[1], &edge[0], &edge[1]), 4) << msg;
  EXPECT_TRUE(named[0] == cell || named[1] == cell) << msg;
  for (const long long c : named)
  {
    ASSERT_TRUE(c >= 0 && c < folded->GetNumberOfCells()) << msg;
    folded->GetCellPoints(c, ids);
    EXPECT_TRUE(ids->IsId(edge[0]) >= 0 && ids->IsId(edge[1]) >= 0) << "cell " << c << ": " << msg;
  }
}

TEST(vtkCloughTocherSplineFilter, LocalityOrderErrorsAfterDroppedGhostsNameInputCells)
{
  // A large piece (built in the locality order) with repeated ghosts before a flat triangle: the
  // message names its input cell, in both output orders alike.
  vtkSmartPointer<vtkPolyData> piece = PieceWithGhosts(ShuffledFranke(128, 7u), true);
  ASSERT_GE(piece->GetNumberOfCells(), ctk::MinTrianglesForLocalityOrder);
  const vtkIdType cell = LastOwnedCell(piece);
  FlattenCell(piece, cell);
  const std::array<std::string, 2> messages = ErrorsInBothOrders(
    piece, "degenerate parameter triangle: cell " + std::to_string(cell) + " (");
  EXPECT_EQ(messages[1], messages[0]);
}
