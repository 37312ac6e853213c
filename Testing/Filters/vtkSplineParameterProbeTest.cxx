// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkSplineParameterProbe.h"

#include "CTSplinesArrayRanges.h"
#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"

#include "BezierTriangle.h"
#include "LocalityOrder.h"

#include "vtkCellType.h"
#include "vtkCharArray.h"
#include "vtkExecutive.h"
#include "vtkImageData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>
#include <string>

namespace
{

const ctk::ParameterMesh& Grid()
{
  static const ctk::ParameterMesh m = ctk::RegularGridMesh(4, ctk::GridDiagonal::Alternating);
  return m;
}

// The CTi spline of `surface` sampled on `mesh` mapped by A u + t.
vtkSmartPointer<vtkUnstructuredGrid> MakeSpline(const ctk::ParameterMesh& mesh,
  ctk::AnalyticSurface surface, const Eigen::Matrix2d& A = Eigen::Matrix2d::Identity(),
  const ctk::Vec2& t = ctk::Vec2::Zero())
{
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputData(ctsplines_test::MakeSampledPolyData(mesh, surface, A, t));
  spline->SetConstructionToCTi();
  spline->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(spline->GetOutput());
  return out;
}

vtkSmartPointer<vtkUnstructuredGrid> MakeSpline(ctk::AnalyticSurface surface,
  const Eigen::Matrix2d& A = Eigen::Matrix2d::Identity(), const ctk::Vec2& t = ctk::Vec2::Zero())
{
  return MakeSpline(Grid(), surface, A, t);
}

vtkSmartPointer<vtkPolyData> QueryPoints(const std::vector<ctk::Vec2>& uv)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const ctk::Vec2& p : uv)
  {
    points->InsertNextPoint(p.x(), p.y(), 0.7); // z is ignored
  }
  pd->SetPoints(points);
  return pd;
}

ctk::Vec3 Tuple3(vtkDataArray* a, vtkIdType i)
{
  return ctk::Vec3(a->GetComponent(i, 0), a->GetComponent(i, 1), a->GetComponent(i, 2));
}

ctk::Vec3 Point(vtkDataSet* ds, vtkIdType i)
{
  ctk::Vec3 x;
  ds->GetPoint(i, x.data());
  return x;
}

// Random points of [0, 1]^2, the grid's vertices and edge midpoints (shared edges and vertices).
std::vector<ctk::Vec2> DomainPoints(std::mt19937& rng, int nRandom)
{
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<ctk::Vec2> uv;
  for (int i = 0; i < nRandom; ++i)
  {
    uv.emplace_back(U(rng), U(rng));
  }
  const ctk::ParameterMesh& m = Grid();
  uv.insert(uv.end(), m.UV.begin(), m.UV.end());
  for (ctk::Id t = 0; t < m.NumberOfTriangles(); ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      uv.push_back(0.5 * (m.UV[m.Triangles[3 * t + l]] + m.UV[m.Triangles[3 * t + (l + 1) % 3]]));
    }
  }
  return uv;
}

vtkSmartPointer<vtkDataSet> Probe(vtkDataSet* input, vtkDataObject* source)
{
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(input);
  probe->SetSourceData(source);
  probe->Update();
  vtkSmartPointer<vtkDataSet> out;
  out.TakeReference(probe->GetOutput()->NewInstance());
  out->ShallowCopy(probe->GetOutput());
  return out;
}
} // namespace

TEST(vtkSplineParameterProbe, QuadraticIsReproducedExactly)
{
  // CTi has quadratic precision: the spline is the sampled quadratic.
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Quadratic);
  std::mt19937 rng(1);
  const std::vector<ctk::Vec2> uv = DomainPoints(rng, 300);
  vtkSmartPointer<vtkDataSet> out = Probe(QueryPoints(uv), spline);
  ASSERT_EQ(out->GetNumberOfPoints(), static_cast<vtkIdType>(uv.size()));
  vtkPointData* pd = out->GetPointData();
  vtkDataArray* du = pd->GetArray("dFdu");
  vtkDataArray* dv = pd->GetArray("dFdv");
  vtkDataArray* normals = pd->GetNormals();
  vtkDataArray* mask = pd->GetArray("vtkValidPointMask");
  vtkDataArray* macro = pd->GetArray("MacroTriangleId");
  ASSERT_TRUE(du && dv && normals && mask && macro);
  EXPECT_EQ(mask->GetDataType(), VTK_CHAR);
  const ctk::ParameterMesh& m = Grid();
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const ctk::SurfacePoint exact =
      ctk::EvaluateAnalyticSurface(ctk::AnalyticSurface::Quadratic, uv[i].x(), uv[i].y());
    ASSERT_EQ(mask->GetComponent(i, 0), 1) << "point " << i;
    EXPECT_LE((Point(out, i) - exact.F).norm(), 1e-12) << "point " << i;
    EXPECT_LE((Tuple3(du, i) - exact.Fu).norm(), 1e-10) << "point " << i;
    EXPECT_LE((Tuple3(dv, i) - exact.Fv).norm(), 1e-10) << "point " << i;
    const ctk::Vec3 N = Tuple3(normals, i);
    EXPECT_NEAR(N.norm(), 1.0, 1e-14);
    EXPECT_LE((N - exact.Fu.cross(exact.Fv).normalized()).norm(), 1e-10);
    // The macro-triangle reported contains the parameter point.
    const vtkIdType t = static_cast<vtkIdType>(macro->GetComponent(i, 0));
    ASSERT_GE(t, 0);
    ASSERT_LT(t, m.NumberOfTriangles());
    const ctk::Vec3 b = ctk::Barycentric(
      m.UV[m.Triangles[3 * t]], m.UV[m.Triangles[3 * t + 1]], m.UV[m.Triangles[3 * t + 2]], uv[i]);
    EXPECT_GE(b.minCoeff(), -1e-12);
  }
}

// The locator is built once per spline: probing again with new queries reuses it, a modified
// source (or another UV array name) rebuilds it, and the results follow the new spline.
TEST(vtkSplineParameterProbe, SplineIsBuiltOncePerSource)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Quadratic);
  std::mt19937 rng(2);
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetSourceData(spline);
  probe->SetInputData(QueryPoints(DomainPoints(rng, 50)));
  probe->Update();
  EXPECT_EQ(probe->GetNumberOfSplineBuilds(), 1);
  const std::vector<ctk::Vec2> uv = DomainPoints(rng, 50);
  probe->SetInputData(QueryPoints(uv));
  probe->Update();
  EXPECT_EQ(probe->GetNumberOfSplineBuilds(), 1);
  const ctk::Vec3 before = Point(vtkDataSet::SafeDownCast(probe->GetOutput()), 0);

  // Move the spline up by 1: the probe must see it.
  vtkPoints* points = spline->GetPoints();
  for (vtkIdType p = 0; p < points->GetNumberOfPoints(); ++p)
  {
    double x[3];
    points->GetPoint(p, x);
    points->SetPoint(p, x[0], x[1], x[2] + 1.0);
  }
  points->Modified();
  probe->Modified();
  probe->Update();
  EXPECT_EQ(probe->GetNumberOfSplineBuilds(), 2);
  const ctk::Vec3 after = Point(vtkDataSet::SafeDownCast(probe->GetOutput()), 0);
  EXPECT_NEAR(after.z() - before.z(), 1.0, 1e-12);
  EXPECT_NEAR((after - before).head<2>().norm(), 0.0, 1e-12);

  probe->ReleaseSpline();
  probe->Modified();
  probe->Update();
  EXPECT_EQ(probe->GetNumberOfSplineBuilds(), 3);
}

// Every output array of two probes, bit for bit.
void ExpectSameBits(vtkDataSet* a, vtkDataSet* b)
{
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    ASSERT_EQ(Point(a, i), Point(b, i)) << "point " << i;
  }
  for (const char* name :
    { "dFdu", "dFdv", "Normals", "MacroTriangleId", "vtkValidPointMask" })
  {
    vtkDataArray* x = a->GetPointData()->GetArray(name);
    vtkDataArray* y = b->GetPointData()->GetArray(name);
    ASSERT_TRUE(x && y) << name;
    for (vtkIdType i = 0; i < x->GetNumberOfValues(); ++i)
    {
      ASSERT_EQ(x->GetComponent(i / x->GetNumberOfComponents(), i % x->GetNumberOfComponents()),
        y->GetComponent(i / y->GetNumberOfComponents(), i % y->GetNumberOfComponents()))
        << name << " value " << i;
    }
  }
}

// uv in a random order: point k is uv[perm[k]].
std::vector<ctk::Vec2> Shuffled(
  const std::vector<ctk::Vec2>& uv, std::mt19937& rng, std::vector<vtkIdType>& perm)
{
  perm.resize(uv.size());
  std::iota(perm.begin(), perm.end(), vtkIdType(0));
  std::shuffle(perm.begin(), perm.end(), rng);
  std::vector<ctk::Vec2> shuffled;
  for (vtkIdType i : perm)
  {
    shuffled.push_back(uv[i]);
  }
  return shuffled;
}

// A spline large enough for the locality order (38,400 cells), probed at random points and at
// the mesh's vertices and edge midpoints (ties between cells): probing again with the spline
// reused gives the same bits, and queries in another order give the same result per query, also
// between queries processed as they come (grid rows) and sorted (the same points shuffled).
// (InPlaceAndCopiedSourcesKeepTheBits compares with the source's own order.)
TEST(vtkSplineParameterProbe, LocalityOrderKeepsTheBits)
{
  const ctk::ParameterMesh mesh = ctk::RegularGridMesh(80, ctk::GridDiagonal::Alternating);
  vtkNew<vtkCloughTocherSplineFilter> filter;
  filter->SetInputData(ctsplines_test::MakeSampledPolyData(mesh, ctk::AnalyticSurface::Franke));
  filter->SetConstructionToCTi();
  filter->Update();
  ASSERT_GE(filter->GetOutput()->GetNumberOfCells(), ctk::MinTrianglesForLocalityOrder);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<ctk::Vec2> uv;
  for (int i = 0; i < 40000; ++i)
  {
    uv.emplace_back(U(rng), U(rng));
  }
  for (ctk::Id t = 0; t < mesh.NumberOfTriangles(); t += 7)
  {
    for (int l = 0; l < 3; ++l)
    {
      const ctk::Vec2& a = mesh.UV[mesh.Triangles[3 * t + l]];
      uv.push_back(a);
      uv.push_back(0.5 * (a + mesh.UV[mesh.Triangles[3 * t + (l + 1) % 3]]));
    }
  }
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetSourceConnection(filter->GetOutputPort());
  probe->SetInputData(QueryPoints(uv));
  probe->Update();
  vtkSmartPointer<vtkDataSet> sourceOrder;
  sourceOrder.TakeReference(probe->GetOutput()->NewInstance());
  sourceOrder->DeepCopy(probe->GetOutput());
  probe->Modified();
  probe->Update();
  EXPECT_EQ(probe->GetNumberOfSplineBuilds(), 1);
  ExpectSameBits(sourceOrder, vtkDataSet::SafeDownCast(probe->GetOutput()));

  std::vector<vtkIdType> perm;
  probe->SetInputData(QueryPoints(Shuffled(uv, rng, perm)));
  probe->Update();
  vtkDataSet* out = vtkDataSet::SafeDownCast(probe->GetOutput());
  vtkPointData* a = sourceOrder->GetPointData();
  vtkPointData* b = out->GetPointData();
  for (size_t k = 0; k < perm.size(); ++k)
  {
    ASSERT_EQ(Point(out, k), Point(sourceOrder, perm[k])) << k;
    ASSERT_EQ(Tuple3(b->GetArray("dFdu"), k), Tuple3(a->GetArray("dFdu"), perm[k])) << k;
    ASSERT_EQ(Tuple3(b->GetArray("dFdv"), k), Tuple3(a->GetArray("dFdv"), perm[k])) << k;
    ASSERT_EQ(b->GetArray("MacroTriangleId")->GetComponent(k, 0),
      a->GetArray("MacroTriangleId")->GetComponent(perm[k], 0))
      << k;
  }

  // Rows of a grid come in a coherent order (neighbouring queries in neighbouring buckets: the
  // rows' step is well below the locator's ~1/200 bucket) and are processed as they come; the
  // same points shuffled are sorted first: the same bits.
  std::vector<ctk::Vec2> rows;
  for (int j = 0; j <= 60; ++j)
  {
    for (int i = 0; i <= 800; ++i)
    {
      rows.emplace_back(i / 800.0, j / 60.0);
    }
  }
  probe->SetInputData(QueryPoints(rows));
  probe->Update();
  vtkSmartPointer<vtkDataSet> inRows;
  inRows.TakeReference(probe->GetOutput()->NewInstance());
  inRows->DeepCopy(probe->GetOutput());
  std::vector<vtkIdType> rowPerm;
  probe->SetInputData(QueryPoints(Shuffled(rows, rng, rowPerm)));
  probe->Update();
  out = vtkDataSet::SafeDownCast(probe->GetOutput());
  for (size_t k = 0; k < rowPerm.size(); ++k)
  {
    ASSERT_EQ(Point(out, k), Point(inRows, rowPerm[k])) << k;
    for (const char* name : { "dFdu", "dFdv", "Normals" })
    {
      ASSERT_EQ(Tuple3(out->GetPointData()->GetArray(name), k),
        Tuple3(inRows->GetPointData()->GetArray(name), rowPerm[k]))
        << name << " " << k;
    }
    for (const char* name : { "MacroTriangleId", "vtkValidPointMask" })
    {
      ASSERT_EQ(out->GetPointData()->GetArray(name)->GetComponent(k, 0),
        inRows->GetPointData()->GetArray(name)->GetComponent(rowPerm[k], 0))
        << name << " " << k;
    }
  }
  EXPECT_EQ(probe->GetNumberOfSplineBuilds(), 1);
}

// Query k of a probe against a brute-force reference over the source's cells in their own
// order and VTK's point order: the cell whose smallest barycentric coordinate is largest (at
// least -1e-12), the lowest cell id among ties, evaluated with the kernel: the same bits.
void ExpectBruteForceBits(vtkUnstructuredGrid* spline, const std::vector<ctk::Vec2>& corners,
  vtkDataSet* out, const ctk::Vec2& X, vtkIdType k)
{
  vtkNew<vtkIdList> ids;
  vtkIdType best = -1;
  double bestMin = -1e-12;
  ctk::Vec3 bestBary;
  for (vtkIdType c = 0; c < spline->GetNumberOfCells(); ++c)
  {
    const ctk::Vec2* A = &corners[3 * c];
    const ctk::Vec3 b = ctk::Barycentric(A[0], A[1], A[2], X);
    if (b.minCoeff() > bestMin || (b.minCoeff() == bestMin && best < 0))
    {
      best = c, bestMin = b.minCoeff(), bestBary = b;
    }
  }
  const ctk::Vec2* bestCorners = &corners[3 * std::max<vtkIdType>(best, 0)];
  ASSERT_GE(best, 0) << "query " << k;
  spline->GetCellPoints(best, ids);
  const int n = ids->GetNumberOfIds() == 10 ? 3 : -1;
  ASSERT_EQ(n, 3);
  const std::vector<int> order = ctk::VtkBezierTriangleOrder(n);
  ctk::Vec3 P[ctk::MaxBezierPoints];
  for (int p = 0; p < ctk::BezierPointCount(n); ++p)
  {
    spline->GetPoint(ids->GetId(p), P[order[p]].data());
  }
  const ctk::ParametricJet jet = ctk::EvaluateOverDomain(
    n, P, nullptr, bestCorners[0], bestCorners[1], bestCorners[2], bestBary, 1);
  ASSERT_EQ(Point(out, k), jet.Value) << "query " << k;
  ASSERT_EQ(Tuple3(out->GetPointData()->GetArray("dFdu"), k), jet.Du) << "query " << k;
  ASSERT_EQ(Tuple3(out->GetPointData()->GetArray("dFdv"), k), jet.Dv) << "query " << k;
  ASSERT_EQ(out->GetPointData()->GetArray("MacroTriangleId")->GetComponent(k, 0),
    spline->GetCellData()->GetArray("MacroTriangleId")->GetComponent(best, 0))
    << "query " << k;
}

// Every query of `out` (at uv) against ExpectBruteForceBits over the cells of `spline`.
void ExpectBruteForceBits(vtkUnstructuredGrid* spline, const std::vector<ctk::Vec2>& uv, vtkDataSet* out)
{
  std::vector<ctk::Vec2> corners; // of every cell, in the source's order
  vtkDataArray* uvArray = spline->GetPointData()->GetArray("UV");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < spline->GetNumberOfCells(); ++c)
  {
    spline->GetCellPoints(c, ids);
    for (int a = 0; a < 3; ++a)
    {
      corners.emplace_back(uvArray->GetComponent(ids->GetId(a), 0), uvArray->GetComponent(ids->GetId(a), 1));
    }
  }
  for (size_t k = 0; k < uv.size(); ++k)
  {
    ExpectBruteForceBits(spline, corners, out, uv[k], static_cast<vtkIdType>(k));
    if (testing::Test::HasFatalFailure())
    {
      return;
    }
  }
}

// The usual source (64-bit cells, double arrays) is read in place; 32-bit cells too; a source
// with a float array goes through the copying reader. All give the bits of a brute-force
// search in the source's own order, although the probe works in the locality order from the
// first call on (ties between cells at the mesh's vertices and edge midpoints included).
TEST(vtkSplineParameterProbe, InPlaceAndCopiedSourcesKeepTheBits)
{
  const ctk::ParameterMesh mesh = ctk::RegularGridMesh(80, ctk::GridDiagonal::Alternating);
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(mesh, ctk::AnalyticSurface::Franke);
  ASSERT_GE(spline->GetNumberOfCells(), ctk::MinTrianglesForLocalityOrder);
  ASSERT_FALSE(spline->GetCells()->IsStorage64Bit()); // the filter writes 32-bit ids
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<ctk::Vec2> uv;
  for (int i = 0; i < 600; ++i)
  {
    uv.emplace_back(U(rng), U(rng));
  }
  for (ctk::Id t = 0; t < mesh.NumberOfTriangles(); t += 97)
  {
    const ctk::Vec2& a = mesh.UV[mesh.Triangles[3 * t]];
    uv.push_back(a);
    uv.push_back(0.5 * (a + mesh.UV[mesh.Triangles[3 * t + 1]]));
  }
  vtkSmartPointer<vtkDataSet> reference = Probe(QueryPoints(uv), spline);
  ExpectBruteForceBits(spline, uv, reference);
  if (testing::Test::HasFatalFailure())
  {
    return;
  }

  // 64-bit cell storage: read in place as well.
  auto cells64 = vtkSmartPointer<vtkUnstructuredGrid>::New();
  cells64->DeepCopy(spline);
  vtkNew<vtkCellArray> wide;
  wide->DeepCopy(spline->GetCells());
  ASSERT_TRUE(wide->ConvertTo64BitStorage());
  cells64->SetCells(cells64->GetCellTypesArray(), wide);
  ASSERT_TRUE(cells64->GetCells()->IsStorage64Bit());
  ExpectSameBits(reference, Probe(QueryPoints(uv), cells64));

  // An unused point beyond the cells' box: the grid, laid over the points' box, is built again
  // over the cells' box. The same bits.
  auto extra = vtkSmartPointer<vtkUnstructuredGrid>::New();
  extra->DeepCopy(spline);
  extra->GetPoints()->InsertNextPoint(0.0, 0.0, 0.0);
  vtkPointData* extraPD = extra->GetPointData();
  for (int a = 0; a < extraPD->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = extraPD->GetArray(a);
    const double far[3] = { 5.0, -3.0, 0.0 };
    ASSERT_LE(array->GetNumberOfComponents(), 3);
    array->InsertNextTuple(far);
  }
  ASSERT_EQ(extraPD->GetArray("UV")->GetComponent(extra->GetNumberOfPoints() - 1, 0), 5.0);
  ExpectSameBits(reference, Probe(QueryPoints(uv), extra));

  // Rational weights of 1 as doubles (in place) and as floats (copied): the same bits.
  vtkSmartPointer<vtkDataSet> weighted[2];
  for (int copied = 0; copied < 2; ++copied)
  {
    auto rational = vtkSmartPointer<vtkUnstructuredGrid>::New();
    rational->ShallowCopy(spline);
    vtkSmartPointer<vtkDataArray> w = copied ? vtkSmartPointer<vtkDataArray>(vtkSmartPointer<vtkFloatArray>::New())
                                             : vtkSmartPointer<vtkDataArray>(vtkSmartPointer<vtkDoubleArray>::New());
    w->SetName("RationalWeights");
    w->SetNumberOfTuples(rational->GetNumberOfPoints());
    w->Fill(1.0);
    rational->GetPointData()->AddArray(w);
    weighted[copied] = Probe(QueryPoints(uv), rational);
  }
  ExpectSameBits(weighted[0], weighted[1]);
}

// A copy of `spline` whose cell j is cell order[j] of `spline` (its MacroTriangleId with it).
vtkSmartPointer<vtkUnstructuredGrid> ReorderCells(
  vtkUnstructuredGrid* spline, const std::vector<vtkIdType>& order)
{
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->SetPoints(spline->GetPoints());
  out->GetPointData()->ShallowCopy(spline->GetPointData());
  out->Allocate(static_cast<vtkIdType>(order.size()));
  vtkNew<vtkIdTypeArray> macro;
  macro->SetName("MacroTriangleId");
  vtkDataArray* in = spline->GetCellData()->GetArray("MacroTriangleId");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c : order)
  {
    spline->GetCellPoints(c, ids);
    out->InsertNextCell(spline->GetCellType(c), ids);
    macro->InsertNextValue(static_cast<vtkIdType>(in->GetComponent(c, 0)));
  }
  out->GetCellData()->AddArray(macro);
  return out;
}

// A spline in the spline filter's layout (cells 3 i .. 3 i + 2 of macro-triangle i), also in
// reverse cell order (whole triples still), is located by macro-triangles; with its cells
// shuffled or the first one moved to the end, or without MacroTriangleId, by cells. Every one
// gives the bits of a brute-force search in its own cell order, ties at vertices, split points
// and the midpoints of macro and micro edges included.
TEST(vtkSplineParameterProbe, MacroTriangleLocatorKeepsTheBits)
{
  const ctk::ParameterMesh mesh = ctk::RegularGridMesh(24, ctk::GridDiagonal::Alternating);
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(mesh, ctk::AnalyticSurface::Franke);
  const vtkIdType n = spline->GetNumberOfCells();
  ASSERT_EQ(n, 3 * mesh.NumberOfTriangles());
  std::mt19937 rng(29);
  std::vector<ctk::Vec2> uv = DomainPoints(rng, 300);
  vtkDataArray* uvArray = spline->GetPointData()->GetArray("UV");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < n; c += 7)
  {
    spline->GetCellPoints(c, ids);
    for (int a = 0; a < 3; ++a)
    {
      const ctk::Vec2 A(uvArray->GetComponent(ids->GetId(a), 0), uvArray->GetComponent(ids->GetId(a), 1));
      const ctk::Vec2 B(uvArray->GetComponent(ids->GetId((a + 1) % 3), 0),
        uvArray->GetComponent(ids->GetId((a + 1) % 3), 1));
      uv.push_back(A);
      uv.push_back(0.5 * (A + B));
    }
  }
  std::vector<vtkIdType> order(n);
  std::iota(order.begin(), order.end(), vtkIdType(0));
  std::vector<vtkIdType> reversed(order.rbegin(), order.rend()), shuffled = order,
                                                               rotated = order;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  std::rotate(rotated.begin(), rotated.begin() + 1, rotated.end());
  const std::pair<const std::vector<vtkIdType>*, int> cases[] = { { &order, 3 },
    { &reversed, 3 }, { &shuffled, 1 }, { &rotated, 1 } };
  for (const auto& [cellOrder, perEntry] : cases)
  {
    vtkSmartPointer<vtkUnstructuredGrid> source = ReorderCells(spline, *cellOrder);
    vtkNew<vtkSplineParameterProbe> probe;
    probe->SetSourceData(source);
    probe->SetInputData(QueryPoints(uv));
    probe->Update();
    EXPECT_EQ(probe->GetNumberOfCellsPerLocatorEntry(), perEntry);
    ExpectBruteForceBits(source, uv, vtkDataSet::SafeDownCast(probe->GetOutput()));
    if (testing::Test::HasFatalFailure())
    {
      return;
    }
  }
  auto noMacroIds = vtkSmartPointer<vtkUnstructuredGrid>::New();
  noMacroIds->ShallowCopy(spline);
  noMacroIds->GetCellData()->RemoveArray("MacroTriangleId");
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetSourceData(noMacroIds);
  probe->SetInputData(QueryPoints(uv));
  probe->Update();
  EXPECT_EQ(probe->GetNumberOfCellsPerLocatorEntry(), 1);
  vtkSmartPointer<vtkDataSet> grouped = Probe(QueryPoints(uv), spline);
  for (size_t k = 0; k < uv.size(); ++k)
  {
    ASSERT_EQ(Point(vtkDataSet::SafeDownCast(probe->GetOutput()), k), Point(grouped, k)) << k;
  }
}

// ComputeDerivatives off: the same positions, no derivative arrays.
TEST(vtkSplineParameterProbe, PositionsOnly)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke);
  std::mt19937 rng(3);
  vtkSmartPointer<vtkPolyData> queries = QueryPoints(DomainPoints(rng, 200));
  vtkSmartPointer<vtkDataSet> full = Probe(queries, spline);
  vtkNew<vtkSplineParameterProbe> probe;
  probe->ComputeDerivativesOff();
  probe->SetSourceData(spline);
  probe->SetInputData(queries);
  probe->Update();
  vtkDataSet* out = vtkDataSet::SafeDownCast(probe->GetOutput());
  ASSERT_EQ(out->GetNumberOfPoints(), full->GetNumberOfPoints());
  EXPECT_EQ(out->GetPointData()->GetArray("dFdu"), nullptr);
  EXPECT_EQ(out->GetPointData()->GetNormals(), nullptr);
  ASSERT_NE(out->GetPointData()->GetArray("vtkValidPointMask"), nullptr);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    EXPECT_EQ(Point(out, i), Point(full, i)) << "point " << i; // the same arithmetic
  }
}

TEST(vtkSplineParameterProbe, AffinelyReparametrisedQuadratic)
{
  // CTi is invariant: probing at A U + t gives the surface point of U, derivatives J A^-1.
  Eigen::Matrix2d A;
  A << 1.7, -0.4, 0.3, 0.6;
  const ctk::Vec2 shift(-2.0, 5.0);
  vtkSmartPointer<vtkUnstructuredGrid> spline =
    MakeSpline(ctk::AnalyticSurface::Quadratic, A, shift);
  std::mt19937 rng(2);
  std::vector<ctk::Vec2> uv = DomainPoints(rng, 200), mapped;
  for (const ctk::Vec2& p : uv)
  {
    mapped.push_back(A * p + shift);
  }
  vtkSmartPointer<vtkDataSet> out = Probe(QueryPoints(mapped), spline);
  vtkPointData* pd = out->GetPointData();
  const Eigen::Matrix2d Ainv = A.inverse();
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const ctk::SurfacePoint exact =
      ctk::EvaluateAnalyticSurface(ctk::AnalyticSurface::Quadratic, uv[i].x(), uv[i].y());
    Eigen::Matrix<double, 3, 2> J;
    J << exact.Fu, exact.Fv;
    const Eigen::Matrix<double, 3, 2> Jp = J * Ainv;
    ASSERT_EQ(pd->GetArray("vtkValidPointMask")->GetComponent(i, 0), 1);
    EXPECT_LE((Point(out, i) - exact.F).norm(), 1e-12);
    EXPECT_LE((Tuple3(pd->GetArray("dFdu"), i) - Jp.col(0)).norm(), 1e-10);
    EXPECT_LE((Tuple3(pd->GetArray("dFdv"), i) - Jp.col(1)).norm(), 1e-10);
  }
}

TEST(vtkSplineParameterProbe, PointsOutsideTheDomainAreMasked)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke);
  const std::vector<ctk::Vec2> uv = { ctk::Vec2(-0.1, 0.5), ctk::Vec2(0.5, 1.0 + 1e-9),
    ctk::Vec2(2.0, 2.0), ctk::Vec2(1e30, -1e30), ctk::Vec2(0.5, 0.5), ctk::Vec2(1.0, 1.0) };
  vtkSmartPointer<vtkDataSet> out = Probe(QueryPoints(uv), spline);
  vtkPointData* pd = out->GetPointData();
  for (vtkIdType i = 0; i < 4; ++i)
  {
    EXPECT_EQ(pd->GetArray("vtkValidPointMask")->GetComponent(i, 0), 0) << i;
    EXPECT_EQ(Point(out, i), ctk::Vec3(uv[i].x(), uv[i].y(), 0.0));
    EXPECT_EQ(Tuple3(pd->GetArray("dFdu"), i), ctk::Vec3::Zero());
    EXPECT_EQ(Tuple3(pd->GetArray("dFdv"), i), ctk::Vec3::Zero());
    EXPECT_EQ(Tuple3(pd->GetArray("Normals"), i), ctk::Vec3::Zero());
    EXPECT_EQ(pd->GetArray("MacroTriangleId")->GetComponent(i, 0), -1);
  }
  for (vtkIdType i = 4; i < 6; ++i)
  {
    EXPECT_EQ(pd->GetArray("vtkValidPointMask")->GetComponent(i, 0), 1) << i;
    EXPECT_NEAR(Tuple3(pd->GetArray("Normals"), i).norm(), 1.0, 1e-14) << i;
  }
}

TEST(vtkSplineParameterProbe, AgreesWithTheTessellator)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke);
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputData(spline);
  tessellator->SetSubdivisionLevel(6);
  tessellator->Update();
  vtkPolyData* tess = tessellator->GetOutput();
  vtkDataArray* uvArray = tess->GetPointData()->GetArray("UV");
  ASSERT_NE(uvArray, nullptr);
  std::vector<ctk::Vec2> uv;
  for (vtkIdType p = 0; p < tess->GetNumberOfPoints(); ++p)
  {
    uv.emplace_back(uvArray->GetComponent(p, 0), uvArray->GetComponent(p, 1));
  }
  vtkSmartPointer<vtkDataSet> out = Probe(QueryPoints(uv), spline);
  vtkPointData* pd = out->GetPointData();
  for (vtkIdType p = 0; p < tess->GetNumberOfPoints(); ++p)
  {
    ASSERT_EQ(pd->GetArray("vtkValidPointMask")->GetComponent(p, 0), 1) << p;
    const ctk::Vec3 x = Point(tess, p);
    EXPECT_LE((Point(out, p) - x).norm(), 1e-12 * (1 + x.norm())) << p;
    // Counter-clockwise parameter triangles: both normals have the same orientation.
    EXPECT_GT(Tuple3(pd->GetNormals(), p).dot(Tuple3(tess->GetPointData()->GetNormals(), p)),
      1 - 1e-12)
      << p;
  }
}

TEST(vtkSplineParameterProbe, RationalSphereOctant)
{
  // One rational quartic cell over the octant's equilateral domain: UV = domain points.
  std::array<ctk::Vec3, 15> P;
  std::array<double, 15> w;
  ctk::SphereOctantNet(P, w);
  const std::array<ctk::Vec2, 3> D = ctk::SphereOctantDomain();
  const std::vector<std::array<int, 3>> exponents = ctk::BezierExponents(4);
  const std::vector<int> order = ctk::VtkBezierTriangleOrder(4);
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> weights, uvArray;
  weights->SetName("RationalWeights");
  uvArray->SetName("UV");
  uvArray->SetNumberOfComponents(2);
  vtkIdType ids[15];
  for (int p = 0; p < 15; ++p)
  {
    const int q = order[p];
    ids[p] = points->InsertNextPoint(P[q].data());
    weights->InsertNextValue(w[q]);
    const ctk::Vec2 U =
      (exponents[q][0] * D[0] + exponents[q][1] * D[1] + exponents[q][2] * D[2]) / 4.0;
    uvArray->InsertNextTuple(U.data());
  }
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(weights);
  grid->GetPointData()->AddArray(uvArray);
  grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 15, ids);

  std::mt19937 rng(4);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<ctk::Vec2> uv = { D[0], D[1], D[2], 0.5 * (D[0] + D[2]) };
  for (int i = 0; i < 200; ++i)
  {
    ctk::Vec3 t(U(rng), U(rng), U(rng));
    t /= t.sum();
    uv.push_back(t[0] * D[0] + t[1] * D[1] + t[2] * D[2]);
  }
  vtkSmartPointer<vtkDataSet> out = Probe(QueryPoints(uv), grid);
  vtkPointData* pd = out->GetPointData();
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const ctk::SurfacePoint exact =
      ctk::EvaluateAnalyticSurface(ctk::AnalyticSurface::SphereOctant, uv[i].x(), uv[i].y());
    ASSERT_EQ(pd->GetArray("vtkValidPointMask")->GetComponent(i, 0), 1);
    const ctk::Vec3 x = Point(out, i);
    EXPECT_NEAR(x.norm(), 1.0, 1e-12);
    EXPECT_LE((x - exact.F).norm(), 1e-12);
    EXPECT_LE((Tuple3(pd->GetArray("dFdu"), i) - exact.Fu).norm(), 1e-10);
    EXPECT_LE((Tuple3(pd->GetArray("dFdv"), i) - exact.Fv).norm(), 1e-10);
    // Tangents of a sphere are orthogonal to the position.
    EXPECT_LE(std::abs(Tuple3(pd->GetArray("dFdu"), i).dot(x)), 1e-12);
    EXPECT_LE((Tuple3(pd->GetNormals(), i) - x).norm(), 1e-12);
  }
}

TEST(vtkSplineParameterProbe, OutputTypeFollowsTheInput)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane);
  // A point set keeps its type and cells; its own arrays are passed.
  vtkSmartPointer<vtkPolyData> sampled =
    ctsplines_test::MakeSampledPolyData(ctk::RegularGridMesh(3, ctk::GridDiagonal::Forward),
      ctk::AnalyticSurface::Plane);
  vtkNew<vtkPoints> flat;
  for (vtkIdType i = 0; i < sampled->GetNumberOfPoints(); ++i)
  {
    const double* uv = sampled->GetPointData()->GetArray("UV")->GetTuple2(i);
    flat->InsertNextPoint(uv[0], uv[1], 0.0);
  }
  sampled->SetPoints(flat);
  vtkSmartPointer<vtkDataSet> out = Probe(sampled, spline);
  ASSERT_TRUE(out->IsA("vtkPolyData"));
  EXPECT_EQ(out->GetNumberOfCells(), sampled->GetNumberOfCells());
  EXPECT_NE(out->GetPointData()->GetArray("UV"), nullptr);
  EXPECT_NE(out->GetCellData()->GetArray("EdgeGradients"), nullptr);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const ctk::Vec3 x = Point(out, i);
    EXPECT_NEAR(x.z(), 0.3 + 0.5 * x.x() - 0.2 * x.y(), 1e-13);
  }

  vtkNew<vtkUnstructuredGrid> ugrid;
  ugrid->SetPoints(flat);
  vtkSmartPointer<vtkDataSet> outGrid = Probe(ugrid, spline);
  EXPECT_TRUE(outGrid->IsA("vtkUnstructuredGrid"));
  EXPECT_EQ(outGrid->GetNumberOfPoints(), flat->GetNumberOfPoints());

  // Image data is not a point set: a vtkPolyData of the points.
  vtkNew<vtkImageData> image;
  image->SetDimensions(5, 4, 1);
  image->SetSpacing(0.25, 1.0 / 3.0, 1.0);
  vtkSmartPointer<vtkDataSet> outImage = Probe(image, spline);
  ASSERT_TRUE(outImage->IsA("vtkPolyData"));
  EXPECT_EQ(outImage->GetNumberOfPoints(), 20);
  EXPECT_EQ(outImage->GetNumberOfCells(), 0);
  vtkDataArray* mask = outImage->GetPointData()->GetArray("vtkValidPointMask");
  for (vtkIdType i = 0; i < 20; ++i)
  {
    EXPECT_EQ(mask->GetComponent(i, 0), 1);
    double uv[3];
    image->GetPoint(i, uv);
    EXPECT_NEAR(Point(outImage, i).z(), 0.3 + 0.5 * uv[0] - 0.2 * uv[1], 1e-13);
  }
}

TEST(vtkSplineParameterProbe, EmptySourceMasksEverything)
{
  vtkNew<vtkUnstructuredGrid> empty;
  vtkNew<vtkPoints> points;
  empty->SetPoints(points);
  vtkNew<vtkDoubleArray> uv;
  uv->SetName("UV");
  uv->SetNumberOfComponents(2);
  empty->GetPointData()->AddArray(uv);
  vtkNew<vtkSplineParameterProbe> probe;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(probe);
  probe->SetInputData(QueryPoints({ ctk::Vec2(0.5, 0.5) }));
  probe->SetSourceData(empty);
  EXPECT_EQ(probe->GetExecutive()->Update(), 1);
  EXPECT_TRUE(errors->Message.empty()) << errors->Message;
  EXPECT_EQ(probe->GetOutput()->GetPointData()->GetArray("vtkValidPointMask")->GetComponent(0, 0), 0);
}

namespace
{
// Runs the probe on a bad source (or none) and returns the error messages; RequestData must fail.
std::string FailingProbe(vtkDataObject* source)
{
  vtkNew<vtkSplineParameterProbe> probe;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(probe);
  probe->SetInputData(QueryPoints({ ctk::Vec2(0.5, 0.5), ctk::Vec2(0.1, 0.2) }));
  if (source)
  {
    probe->SetSourceData(source);
  }
  EXPECT_EQ(probe->GetExecutive()->Update(), 0);
  return errors->Message;
}
} // namespace

// The spline filter's output carries ranges stored from values all finite (FiniteRanges): the
// probe takes them for its check of the points, (u, v) and weights instead of a pass over them,
// but only while the array is unmodified: a NaN set and marked modified is found and named.
TEST(vtkSplineParameterProbe, StoredRangesServeUntilTheSourceIsModified)
{
  for (const std::string what : { "points", "UV" })
  {
    vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke);
    auto* array = vtkDoubleArray::FastDownCast(what == "UV"
        ? spline->GetPointData()->GetArray("UV")
        : spline->GetPoints()->GetData());
    ASSERT_NE(array, nullptr);
    double range[6];
    ASSERT_TRUE(ctsplines::FiniteRanges(array, range)) << what;
    vtkSmartPointer<vtkDataSet> good = Probe(QueryPoints({ ctk::Vec2(0.5, 0.5) }), spline);
    ASSERT_NE(good, nullptr) << what;
    array->GetPointer(0)[7] = std::nan(""); // point 3 (UV) or 2 (points)
    array->Modified();
    EXPECT_FALSE(ctsplines::FiniteRanges(array, range)) << what;
    const std::string m = FailingProbe(spline);
    EXPECT_NE(m.find(what == "UV" ? "'UV' has a non-finite value (nan) at point 3"
                                  : "point 2 has the coordinates"),
      std::string::npos)
      << what << ": " << m;
  }
  // The stored ranges are taken instead of the values: a coordinate changed without Modified()
  // (which VTK's own range cache needs too) is not read; marked modified, it is.
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke);
  auto* points = vtkDoubleArray::FastDownCast(spline->GetPoints()->GetData());
  ASSERT_NE(points, nullptr);
  points->GetPointer(0)[7] = 1e200; // point 2, above the usable magnitude
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(QueryPoints({ ctk::Vec2(0.5, 0.5) }));
  probe->SetSourceData(spline);
  EXPECT_EQ(probe->GetExecutive()->Update(), 1) << "the points were read, not their ranges";
  points->Modified();
  const std::string m = FailingProbe(spline);
  EXPECT_NE(m.find("point 2 has the coordinates"), std::string::npos) << m;
}

// Rational weights with stored ranges: finite ones are not all usable, the lowest must be
// positive; a zero weight in an array with stored ranges is found and named.
TEST(vtkSplineParameterProbe, StoredRangesOfWeightsMustBePositive)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke);
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("RationalWeights");
  weights->SetNumberOfTuples(spline->GetNumberOfPoints());
  weights->Fill(1.0);
  spline->GetPointData()->SetRationalWeights(weights);
  ASSERT_TRUE(ctsplines::CacheRanges(weights));
  ASSERT_NE(Probe(QueryPoints({ ctk::Vec2(0.5, 0.5) }), spline), nullptr);
  weights->SetValue(3, 0.0);
  weights->Modified();
  ASSERT_TRUE(ctsplines::CacheRanges(weights));
  double range[2];
  ASSERT_TRUE(ctsplines::FiniteRanges(weights, range));
  EXPECT_EQ(range[0], 0.0);
  const std::string m = FailingProbe(spline);
  EXPECT_NE(m.find("point 3"), std::string::npos) << m;
}

TEST(vtkSplineParameterProbe, MissingSource)
{
  const std::string m = FailingProbe(nullptr);
  EXPECT_NE(m.find("no spline source"), std::string::npos) << m;
}

TEST(vtkSplineParameterProbe, SourceWithoutUV)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane);
  spline->GetPointData()->RemoveArray("UV");
  const std::string m = FailingProbe(spline);
  EXPECT_NE(m.find("no point data array 'UV'"), std::string::npos) << m;

  // A custom name is looked up instead.
  vtkSmartPointer<vtkUnstructuredGrid> good = MakeSpline(ctk::AnalyticSurface::Plane);
  vtkNew<vtkSplineParameterProbe> probe;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(probe);
  probe->SetUVArrayName("Params");
  probe->SetInputData(QueryPoints({ ctk::Vec2(0.5, 0.5) }));
  probe->SetSourceData(good);
  EXPECT_EQ(probe->GetExecutive()->Update(), 0);
  EXPECT_NE(errors->Message.find("'Params'"), std::string::npos) << errors->Message;
}

TEST(vtkSplineParameterProbe, UVWithWrongComponentCount)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane);
  vtkNew<vtkDoubleArray> uv3;
  uv3->SetName("UV");
  uv3->SetNumberOfComponents(3);
  uv3->SetNumberOfTuples(spline->GetNumberOfPoints());
  uv3->Fill(0.0);
  spline->GetPointData()->AddArray(uv3);
  const std::string m = FailingProbe(spline);
  EXPECT_NE(m.find("'UV' has 3 components, expected 2"), std::string::npos) << m;
}

TEST(vtkSplineParameterProbe, NonBezierSourceCell)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane);
  const vtkIdType bad = spline->GetNumberOfCells();
  const vtkIdType quad[4] = { 0, 1, 2, 3 };
  spline->InsertNextCell(VTK_QUAD, 4, quad);
  const std::string m = FailingProbe(spline);
  EXPECT_NE(m.find("source cell " + std::to_string(bad) + " is a vtkQuad"), std::string::npos)
    << m;
}

TEST(vtkSplineParameterProbe, DegenerateParameterTriangle)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane);
  vtkNew<vtkIdList> ids;
  spline->GetCellPoints(0, ids);
  vtkDataArray* uv = spline->GetPointData()->GetArray("UV");
  uv->SetTuple(ids->GetId(1), uv->GetTuple(ids->GetId(0)));
  const std::string m = FailingProbe(spline);
  EXPECT_NE(m.find("degenerate parameter triangle: source cell 0"), std::string::npos) << m;
}

TEST(vtkSplineParameterProbe, PrintSelfAndDefaults)
{
  vtkNew<vtkSplineParameterProbe> probe;
  EXPECT_STREQ(probe->GetUVArrayName(), "UV");
  EXPECT_EQ(probe->GetSource(), nullptr);
  std::ostringstream os;
  probe->Print(os);
  EXPECT_NE(os.str().find("UVArrayName: UV"), std::string::npos);
  EXPECT_NE(os.str().find("ReuseOutputArrays: 1"), std::string::npos);
  EXPECT_TRUE(probe->GetReuseOutputArrays());
  EXPECT_EQ(probe->GetReusedOutputBytes(), 0u);
  EXPECT_EQ(probe->GetNumberOfCellsPerLocatorEntry(), 0);
}
