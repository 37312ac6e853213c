// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierTriangleTessellator.h"
#include "CTSplinesBezierCells.h"
#include "vtkSampledSurfaceSource.h"

#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSplineParameterProbe.h"

#include "vtkBezierTriangle.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkExecutive.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkSMPTools.h"
#include "vtkStringArray.h"
#include "vtkTypeInt32Array.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>

namespace
{

vtkSmartPointer<vtkUnstructuredGrid> MakeSpline(ctk::AnalyticSurface surface, int n)
{
  const ctk::ParameterMesh m = ctk::RegularGridMesh(n, ctk::GridDiagonal::Alternating);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputData(ctsplines_test::MakeSampledPolyData(m, surface));
  spline->SetConstructionToCTi();
  spline->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(spline->GetOutput());
  return out;
}

vtkSmartPointer<vtkPolyData> Tessellate(vtkDataSet* input, int level, bool split = true)
{
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputData(input);
  tessellator->SetSubdivisionLevel(level);
  tessellator->SetSplitSharpEdges(split);
  tessellator->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(tessellator->GetOutput());
  return out;
}

ctk::Vec3 Point(vtkDataSet* ds, vtkIdType i)
{
  ctk::Vec3 x;
  ds->GetPoint(i, x.data());
  return x;
}

ctk::Vec3 Tuple3(vtkDataArray* a, vtkIdType i)
{
  return ctk::Vec3(a->GetComponent(i, 0), a->GetComponent(i, 1), a->GetComponent(i, 2));
}

// VTK's own evaluation of cell c at parametric (r, s), rational weights included.
ctk::Vec3 VtkEvaluate(vtkUnstructuredGrid* grid, vtkIdType c, double r, double s)
{
  vtkBezierTriangle* cell = vtkBezierTriangle::SafeDownCast(grid->GetCell(c));
  EXPECT_NE(cell, nullptr);
  // VTK reads the active rational weights attribute only (set by the tests' grids).
  cell->SetRationalWeightsFromPointData(grid->GetPointData(), cell->GetNumberOfPoints());
  const double pcoords[3] = { r, s, 0.0 };
  double weights[ctk::MaxBezierPoints];
  int subId = 0;
  ctk::Vec3 x;
  cell->EvaluateLocation(subId, pcoords, x.data(), weights);
  return x;
}

// Parametric coordinates (r, s) of a domain point in cell c of a spline, from the corners' UV.
ctk::Vec2 CellParametric(vtkUnstructuredGrid* spline, vtkIdType c, const ctk::Vec2& uv)
{
  vtkDataArray* UV = spline->GetPointData()->GetArray("UV");
  vtkNew<vtkIdList> ids;
  spline->GetCellPoints(c, ids);
  ctk::Vec2 A[3];
  for (int a = 0; a < 3; ++a)
  {
    A[a] = ctk::Vec2(UV->GetComponent(ids->GetId(a), 0), UV->GetComponent(ids->GetId(a), 1));
  }
  const ctk::Vec3 t = ctk::Barycentric(A[0], A[1], A[2], uv);
  return ctk::Vec2(t[1], t[2]);
}

// Number of points of a conforming tessellation: unique corners and edges of the cells.
// Whether the point normals at the first `corners` corners of every triangle point to the side
// of its facet (triangles oriented as their cells, normals of their own side).
bool NormalsFollowFacets(vtkPolyData* pd, int corners)
{
  vtkDataArray* normals = pd->GetPointData()->GetNormals();
  for (vtkIdType t = 0; t < pd->GetNumberOfCells(); ++t)
  {
    const vtkIdType* pts;
    vtkIdType npts;
    pd->GetPolys()->GetCellAtId(t, npts, pts);
    const ctk::Vec3 facet =
      (Point(pd, pts[1]) - Point(pd, pts[0])).cross(Point(pd, pts[2]) - Point(pd, pts[0]));
    for (int a = 0; a < corners; ++a)
    {
      if (!(Tuple3(normals, pts[a]).dot(facet) > 0))
      {
        return false;
      }
    }
  }
  return true;
}

vtkIdType ExpectedPointCount(vtkUnstructuredGrid* grid, int L)
{
  std::set<vtkIdType> corners;
  std::set<std::pair<vtkIdType, vtkIdType>> edges;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType p = ids->GetId(a), q = ids->GetId((a + 1) % 3);
      corners.insert(p);
      edges.insert({ std::min(p, q), std::max(p, q) });
    }
  }
  const vtkIdType T = grid->GetNumberOfCells();
  return static_cast<vtkIdType>(corners.size()) +
    static_cast<vtkIdType>(edges.size()) * (L - 1) + T * (L - 1) * (L - 2) / 2;
}

// Smallest distance between two distinct output points (brute force).
double MinimumSeparation(vtkPolyData* pd)
{
  double best = std::numeric_limits<double>::infinity();
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    for (vtkIdType j = i + 1; j < pd->GetNumberOfPoints(); ++j)
    {
      best = std::min(best, (Point(pd, i) - Point(pd, j)).norm());
    }
  }
  return best;
}

// Edges used by exactly one output triangle.
vtkIdType BoundaryEdgeCount(vtkPolyData* pd)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> uses;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellPoints(c, ids);
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType p = ids->GetId(a), q = ids->GetId((a + 1) % 3);
      ++uses[{ std::min(p, q), std::max(p, q) }];
    }
  }
  vtkIdType boundary = 0;
  for (const auto& e : uses)
  {
    EXPECT_LE(e.second, 2);
    boundary += e.second == 1;
  }
  return boundary;
}

// One rational quartic cell (the sphere octant); with mirrored = true a second cell, the octant
// reflected in z = 0, shares the corners (1,0,0), (0,1,0) and the edge between them. The weights
// are the active rational weights attribute (what VTK's cells read) or only a named array.
vtkSmartPointer<vtkUnstructuredGrid> SphereOctants(bool mirrored, bool active = true)
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
  vtkIdType ids[15];
  for (int p = 0; p < 15; ++p)
  {
    ids[p] = points->InsertNextPoint(P[order[p]].data());
    weights->InsertNextValue(w[order[p]]);
  }
  grid->SetPoints(points);
  if (active)
  {
    grid->GetPointData()->SetRationalWeights(weights);
  }
  else
  {
    grid->GetPointData()->AddArray(weights);
  }
  grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 15, ids);
  if (mirrored)
  {
    // VTK points 0, 1 (corners) and 3, 4, 5 (edge 0->1) lie in z = 0: shared.
    vtkIdType mirror[15];
    for (int p = 0; p < 15; ++p)
    {
      if (p == 0 || p == 1 || (p >= 3 && p <= 5))
      {
        mirror[p] = ids[p];
        continue;
      }
      const ctk::Vec3 q = P[order[p]].cwiseProduct(ctk::Vec3(1, 1, -1));
      mirror[p] = points->InsertNextPoint(q.data());
      weights->InsertNextValue(w[order[p]]);
    }
    grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 15, mirror);
  }
  return grid;
}

// Barycentric coordinates of the corners of the level-L lattice's triangles in the order of the
// tessellator's output: rows k, then j; the up triangle (j, k), (j+1, k), (j, k+1), then the
// down one (j+1, k), (j+1, k+1), (j, k+1).
std::vector<std::array<ctk::Vec3, 3>> LatticeTriangles(int L)
{
  auto t = [L](int j, int k) {
    return ctk::Vec3(double(L - j - k) / L, double(j) / L, double(k) / L);
  };
  std::vector<std::array<ctk::Vec3, 3>> triangles;
  for (int k = 0; k < L; ++k)
  {
    for (int j = 0; j < L - k; ++j)
    {
      triangles.push_back({ t(j, k), t(j + 1, k), t(j, k + 1) });
      if (j + k + 2 <= L)
      {
        triangles.push_back({ t(j + 1, k), t(j + 1, k + 1), t(j, k + 1) });
      }
    }
  }
  return triangles;
}
} // namespace

TEST(vtkBezierTriangleTessellator, CubicSplineMatchesVtkEvaluation)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke, 3);
  const int L = 5;
  vtkSmartPointer<vtkPolyData> out = Tessellate(spline, L);
  ASSERT_EQ(out->GetNumberOfCells(), spline->GetNumberOfCells() * L * L);
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_DOUBLE);
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  vtkDataArray* cellIds = out->GetCellData()->GetArray("BezierCellId");
  ASSERT_NE(uv, nullptr);
  ASSERT_NE(cellIds, nullptr);
  vtkNew<vtkIdList> ids;
  for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
  {
    const vtkIdType c = static_cast<vtkIdType>(cellIds->GetComponent(t, 0));
    out->GetCellPoints(t, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 3);
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType p = ids->GetId(a);
      const ctk::Vec2 rs =
        CellParametric(spline, c, ctk::Vec2(uv->GetComponent(p, 0), uv->GetComponent(p, 1)));
      // Samples lie on the uniform lattice of the cell...
      EXPECT_NEAR(rs.x() * L, std::round(rs.x() * L), 1e-9);
      EXPECT_NEAR(rs.y() * L, std::round(rs.y() * L), 1e-9);
      // ...and are the cell's exact points there.
      const ctk::Vec3 x = VtkEvaluate(spline, c, rs.x(), rs.y());
      EXPECT_LE((x - Point(out, p)).norm(), 1e-12 * (1 + x.norm())) << "triangle " << t;
    }
  }
}

TEST(vtkBezierTriangleTessellator, ConformingPointCountsAndTopology)
{
  const int n = 3;
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::FarinCubic, n);
  for (int L : { 1, 2, 3, 5, 8 })
  {
    vtkSmartPointer<vtkPolyData> out = Tessellate(spline, L);
    EXPECT_EQ(out->GetNumberOfPoints(), ExpectedPointCount(spline, L)) << "L = " << L;
    EXPECT_EQ(out->GetNumberOfCells(), spline->GetNumberOfCells() * L * L);
    // Shared points are stored once: no two points coincide.
    EXPECT_GT(MinimumSeparation(out), 1e-12) << "L = " << L;
    // Watertight: only the 4n boundary macro-edges, each cut into L pieces, are open.
    EXPECT_EQ(BoundaryEdgeCount(out), 4 * n * L) << "L = " << L;
  }
}

TEST(vtkBezierTriangleTessellator, NormalsAreUnitAndOrthogonalToTangents)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke, 2);
  vtkSmartPointer<vtkPolyData> out = Tessellate(spline, 4);
  vtkDataArray* normals = out->GetPointData()->GetNormals();
  ASSERT_NE(normals, nullptr);
  ASSERT_STREQ(normals->GetName(), "Normals");
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  vtkDataArray* cellIds = out->GetCellData()->GetArray("BezierCellId");
  vtkNew<vtkIdList> ids;
  const double h = 1e-6;
  for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
  {
    const vtkIdType c = static_cast<vtkIdType>(cellIds->GetComponent(t, 0));
    out->GetCellPoints(t, ids);
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType p = ids->GetId(a);
      const ctk::Vec3 N = Tuple3(normals, p);
      EXPECT_NEAR(N.norm(), 1.0, 1e-14);
      const ctk::Vec2 rs =
        CellParametric(spline, c, ctk::Vec2(uv->GetComponent(p, 0), uv->GetComponent(p, 1)));
      // Central differences of the cell's polynomial (C1 spline: any cell at the point agrees).
      const ctk::Vec3 Tr =
        VtkEvaluate(spline, c, rs.x() + h, rs.y()) - VtkEvaluate(spline, c, rs.x() - h, rs.y());
      const ctk::Vec3 Ts =
        VtkEvaluate(spline, c, rs.x(), rs.y() + h) - VtkEvaluate(spline, c, rs.x(), rs.y() - h);
      EXPECT_LT(std::abs(N.dot(Tr)) / Tr.norm(), 1e-8);
      EXPECT_LT(std::abs(N.dot(Ts)) / Ts.norm(), 1e-8);
      // Oriented like the cell (its parameter triangles are counter-clockwise).
      EXPECT_GT(N.dot(Tr.cross(Ts)), 0.0);
    }
  }
}

TEST(vtkBezierTriangleTessellator, RationalQuarticSphereOctant)
{
  vtkSmartPointer<vtkUnstructuredGrid> octant = SphereOctants(false);
  const int L = 8;
  vtkSmartPointer<vtkPolyData> out = Tessellate(octant, L);
  ASSERT_EQ(out->GetNumberOfPoints(), (L + 1) * (L + 2) / 2);
  ASSERT_EQ(out->GetNumberOfCells(), L * L);
  vtkDataArray* normals = out->GetPointData()->GetNormals();
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
  {
    const ctk::Vec3 x = Point(out, p);
    EXPECT_NEAR(x.norm(), 1.0, 1e-12);
    EXPECT_GE(x.minCoeff(), -1e-12);
    // On the unit sphere the normal is the position (outward for this orientation).
    EXPECT_LE((Tuple3(normals, p) - x).norm(), 1e-12);
  }
  // Every lattice point evaluated by VTK is exactly one output point.
  std::vector<int> matched(out->GetNumberOfPoints(), 0);
  for (int k = 0; k <= L; ++k)
  {
    for (int j = 0; j <= L - k; ++j)
    {
      const ctk::Vec3 x = VtkEvaluate(octant, 0, double(j) / L, double(k) / L);
      int hits = 0;
      for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
      {
        if ((Point(out, p) - x).norm() <= 1e-12)
        {
          ++hits;
          ++matched[p];
        }
      }
      EXPECT_EQ(hits, 1) << "lattice point " << j << ", " << k;
    }
  }
  EXPECT_EQ(std::count(matched.begin(), matched.end(), 1), out->GetNumberOfPoints());
}

TEST(vtkBezierTriangleTessellator, RationalCellsSharingAnEdge)
{
  // Weights only by name here: the tessellator reads them all the same.
  vtkSmartPointer<vtkUnstructuredGrid> octants = SphereOctants(true, false);
  for (int L : { 1, 3, 6 })
  {
    vtkSmartPointer<vtkPolyData> out = Tessellate(octants, L, false);
    // 4 corners, 5 edges, 2 cells.
    EXPECT_EQ(out->GetNumberOfPoints(), 4 + 5 * (L - 1) + 2 * (L - 1) * (L - 2) / 2);
    EXPECT_EQ(out->GetNumberOfPoints(), ExpectedPointCount(octants, L));
    EXPECT_GT(MinimumSeparation(out), 1e-12);
    EXPECT_EQ(BoundaryEdgeCount(out), 4 * L);
    vtkDataArray* normals = out->GetPointData()->GetNormals();
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
    {
      const ctk::Vec3 x = Point(out, p);
      EXPECT_NEAR(x.norm(), 1.0, 1e-12);
      EXPECT_LE(Tuple3(normals, p).cross(x).norm(), 1e-12);
    }
    // The mirrored octant has the opposite orientation: its normals are -x, so with
    // SplitSharpEdges the L + 1 points of the shared edge are split, and every triangle's
    // corners carry the normal of its own side.
    vtkSmartPointer<vtkPolyData> split = Tessellate(octants, L);
    EXPECT_EQ(split->GetNumberOfPoints(), out->GetNumberOfPoints() + L + 1);
    EXPECT_TRUE(NormalsFollowFacets(split, 3));
    EXPECT_EQ(MinimumSeparation(split), 0.0); // the copies keep their coordinates
  }
}

TEST(vtkBezierTriangleTessellator, HigherOrderCellsAndArbitraryPointOrder)
{
  // Degree 1..7 cells built from random nets; compare with VTK at every output triangle corner.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int n = 1; n <= 7; ++n)
  {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkDoubleArray> weights;
    weights->SetName("RationalWeights");
    std::vector<vtkIdType> ids(ctk::BezierPointCount(n));
    for (vtkIdType& id : ids)
    {
      id = points->InsertNextPoint(U(rng), U(rng), U(rng));
      weights->InsertNextValue(1.5 + U(rng));
    }
    // Reversed storage: connectivity, not storage order, defines the net.
    std::reverse(ids.begin(), ids.end());
    grid->SetPoints(points);
    grid->GetPointData()->SetRationalWeights(weights);
    grid->InsertNextCell(VTK_BEZIER_TRIANGLE, static_cast<vtkIdType>(ids.size()), ids.data());
    const int L = 4;
    vtkSmartPointer<vtkPolyData> out = Tessellate(grid, L);
    ASSERT_EQ(out->GetNumberOfPoints(), (L + 1) * (L + 2) / 2) << "degree " << n;
    for (int k = 0; k <= L; ++k)
    {
      for (int j = 0; j <= L - k; ++j)
      {
        const ctk::Vec3 x = VtkEvaluate(grid, 0, double(j) / L, double(k) / L);
        double best = std::numeric_limits<double>::infinity();
        for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
        {
          best = std::min(best, (Point(out, p) - x).norm());
        }
        EXPECT_LE(best, 1e-12 * (1 + x.norm())) << "degree " << n;
      }
    }
  }
}

TEST(vtkBezierTriangleTessellator, CellDataCarriedOver)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane, 2);
  const int L = 3;
  vtkSmartPointer<vtkPolyData> out = Tessellate(spline, L);
  vtkDataArray* source = out->GetCellData()->GetArray("BezierCellId");
  vtkDataArray* macro = out->GetCellData()->GetArray("MacroTriangleId");
  vtkDataArray* micro = out->GetCellData()->GetArray("MicroTriangleId");
  ASSERT_NE(source, nullptr);
  ASSERT_NE(macro, nullptr);
  ASSERT_NE(micro, nullptr);
  EXPECT_EQ(macro->GetDataType(), spline->GetCellData()->GetArray("MacroTriangleId")->GetDataType());
  std::vector<int> count(spline->GetNumberOfCells(), 0);
  for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
  {
    const vtkIdType c = static_cast<vtkIdType>(source->GetComponent(t, 0));
    ++count[c];
    EXPECT_EQ(macro->GetComponent(t, 0),
      spline->GetCellData()->GetArray("MacroTriangleId")->GetComponent(c, 0));
    EXPECT_EQ(micro->GetComponent(t, 0),
      spline->GetCellData()->GetArray("MicroTriangleId")->GetComponent(c, 0));
  }
  for (int c : count)
  {
    EXPECT_EQ(c, L * L);
  }
}

// Ids that fit in 32 bits are stored in 32 bits (offsets and connectivity are 40 % of the
// output's fresh memory), with the same triangles.
TEST(vtkBezierTriangleTessellator, CellArraysUse32BitStorageWhenIdsFit)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::FarinCubic, 3);
  vtkSmartPointer<vtkPolyData> out = Tessellate(spline, 4);
  vtkCellArray* polys = out->GetPolys();
  ASSERT_FALSE(polys->IsStorage64Bit());
  ASSERT_EQ(polys->GetNumberOfCells(), spline->GetNumberOfCells() * 16);
  vtkTypeInt32Array* offsets = polys->GetOffsetsArray32();
  vtkTypeInt32Array* connectivity = polys->GetConnectivityArray32();
  for (vtkIdType c = 0; c <= polys->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(offsets->GetValue(c), 3 * c);
  }
  for (vtkIdType k = 0; k < connectivity->GetNumberOfValues(); ++k)
  {
    ASSERT_GE(connectivity->GetValue(k), 0);
    ASSERT_LT(connectivity->GetValue(k), out->GetNumberOfPoints());
  }
  EXPECT_EQ(BoundaryEdgeCount(out), 4 * 3 * 4); // still watertight
}

TEST(vtkBezierTriangleTessellator, ResultIndependentOfThreadCount)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke, 6);
  const std::string backend = vtkSMPTools::GetBackend();
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  vtkSmartPointer<vtkPolyData> a = Tessellate(spline, 7);
  // STDThread is always compiled in (VTK >= 9.1); several threads even on one core.
  ASSERT_TRUE(vtkSMPTools::SetBackend("STDThread"));
  vtkSMPTools::Initialize(4);
  vtkSmartPointer<vtkPolyData> b = Tessellate(spline, 7);
  vtkSMPTools::SetBackend(backend.c_str());
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
  {
    ASSERT_EQ(Point(a, p), Point(b, p));
    ASSERT_EQ(Tuple3(a->GetPointData()->GetNormals(), p),
      Tuple3(b->GetPointData()->GetNormals(), p));
  }
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  vtkNew<vtkIdList> ia, ib;
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
  {
    a->GetCellPoints(c, ia);
    b->GetCellPoints(c, ib);
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(ia->GetId(k), ib->GetId(k));
    }
  }
}

// The batched fast path against the pointwise de Casteljau-style kernel evaluation, point by
// point at level 8: at each output point's owner (its lowest cell), positions and UV are the
// same doubles as EvaluateBezierTriangle's and the normals PatchNormal's to round-off.
void ExpectOwnersMatchPointwiseEvaluation(vtkUnstructuredGrid* grid, int L)
{
  vtkSmartPointer<vtkPolyData> out = Tessellate(grid, L, false);
  const std::vector<std::array<ctk::Vec3, 3>> lattice = LatticeTriangles(L);
  ASSERT_EQ(out->GetNumberOfCells(), grid->GetNumberOfCells() * L * L);
  vtkDataArray* normals = out->GetPointData()->GetNormals();
  vtkDataArray* uvOut = out->GetPointData()->GetArray("UV");
  vtkDataArray* uvIn = grid->GetPointData()->GetArray("UV");
  vtkDataArray* weights = grid->GetPointData()->GetRationalWeights();
  std::vector<char> seen(out->GetNumberOfPoints(), 0);
  vtkNew<vtkIdList> ids, tri;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    const int n =
      static_cast<int>(std::lround((std::sqrt(8.0 * ids->GetNumberOfIds() + 1) - 3) / 2));
    const std::vector<int> order = ctk::VtkBezierTriangleOrder(n);
    std::vector<ctk::Vec3> P(order.size()), R(order.size()), UV(order.size());
    std::vector<double> w(order.size(), 1.0);
    for (size_t p = 0; p < order.size(); ++p)
    {
      P[order[p]] = Point(grid, ids->GetId(p));
      w[order[p]] = weights ? weights->GetComponent(ids->GetId(p), 0) : 1.0;
      UV[order[p]] = uvIn ? ctk::Vec3(uvIn->GetComponent(ids->GetId(p), 0),
                              uvIn->GetComponent(ids->GetId(p), 1), 0.0)
                          : ctk::Vec3::Zero();
    }
    const double* wp = weights ? w.data() : nullptr;
    ctk::RelativeNet(n, P.data(), R.data());
    for (vtkIdType m = 0; m < L * L; ++m)
    {
      out->GetCellPoints(c * L * L + m, tri);
      for (int a = 0; a < 3; ++a)
      {
        const vtkIdType id = tri->GetId(a);
        if (seen[id]++)
        {
          continue; // owned by a lower cell
        }
        const ctk::Vec3& t = lattice[m][a];
        EXPECT_EQ(Point(out, id), ctk::EvaluateBezierTriangle(n, P.data(), wp, t).Value);
        EXPECT_LE((Tuple3(normals, id) - ctk::PatchNormal(n, R.data(), wp, t)).norm(), 1e-12)
          << "cell " << c << " point " << id;
        if (uvIn)
        {
          const ctk::Vec3 uv = ctk::EvaluateBezierTriangle(n, UV.data(), wp, t).Value;
          EXPECT_EQ(uvOut->GetComponent(id, 0), uv.x());
          EXPECT_EQ(uvOut->GetComponent(id, 1), uv.y());
        }
      }
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 0), 0);
}

TEST(vtkBezierTriangleTessellator, FastPathMatchesPointwiseEvaluation)
{
  ExpectOwnersMatchPointwiseEvaluation(MakeSpline(ctk::AnalyticSurface::Franke, 6), 8);
  ExpectOwnersMatchPointwiseEvaluation(SphereOctants(true), 8);
  ExpectOwnersMatchPointwiseEvaluation(SphereOctants(true), 3);
}

TEST(vtkBezierTriangleTessellator, EmptyInputGivesEmptyOutput)
{
  vtkNew<vtkUnstructuredGrid> empty;
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(tessellator);
  tessellator->SetInputData(empty);
  EXPECT_EQ(tessellator->GetExecutive()->Update(), 1);
  EXPECT_TRUE(errors->Message.empty()) << errors->Message;
  EXPECT_EQ(tessellator->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(tessellator->GetOutput()->GetNumberOfCells(), 0);
}

TEST(vtkBezierTriangleTessellator, RejectsOtherCellTypes)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Plane, 1);
  const vtkIdType bad = spline->GetNumberOfCells();
  const vtkIdType tri[3] = { 0, 1, 2 };
  spline->InsertNextCell(VTK_TRIANGLE, 3, tri);
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(tessellator);
  tessellator->SetInputData(spline);
  EXPECT_EQ(tessellator->GetExecutive()->Update(), 0);
  EXPECT_NE(errors->Message.find("cell " + std::to_string(bad) + " is a vtkTriangle"),
    std::string::npos)
    << errors->Message;
}

TEST(vtkBezierTriangleTessellator, RejectsBadPointCounts)
{
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  for (int p = 0; p < 7; ++p)
  {
    points->InsertNextPoint(p, p * p, 0);
  }
  grid->SetPoints(points);
  const vtkIdType ids[7] = { 0, 1, 2, 3, 4, 5, 6 };
  grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 6, ids);
  grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 7, ids);
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(tessellator);
  tessellator->SetInputData(grid);
  EXPECT_EQ(tessellator->GetExecutive()->Update(), 0);
  EXPECT_NE(errors->Message.find("cell 1 has 7 points"), std::string::npos) << errors->Message;
}

TEST(vtkBezierTriangleTessellator, RejectsBadRationalWeights)
{
  vtkSmartPointer<vtkUnstructuredGrid> octant = SphereOctants(false);
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("RationalWeights");
  weights->SetNumberOfComponents(2);
  weights->SetNumberOfTuples(octant->GetNumberOfPoints());
  weights->Fill(1.0);
  octant->GetPointData()->AddArray(weights);
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(tessellator);
  tessellator->SetInputData(octant);
  EXPECT_EQ(tessellator->GetExecutive()->Update(), 0);
  EXPECT_NE(errors->Message.find("'RationalWeights' has 2 components"), std::string::npos)
    << errors->Message;
}

TEST(vtkBezierTriangleTessellator, PrintSelfAndDefaults)
{
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  EXPECT_EQ(tessellator->GetSubdivisionLevel(), 8);
  EXPECT_STREQ(tessellator->GetUVArrayName(), "UV");
  tessellator->SetSubdivisionLevel(0);
  EXPECT_EQ(tessellator->GetSubdivisionLevel(), 1);
  std::ostringstream os;
  tessellator->Print(os);
  EXPECT_NE(os.str().find("SubdivisionLevel: 1"), std::string::npos);
}

namespace
{
// Adds a point data array equal to the control points' coordinates: interpolated with the
// cells' own (rational) basis it must give the output points themselves.
void AddPositionArray(vtkDataSet* grid)
{
  vtkNew<vtkDoubleArray> position;
  position->SetName("Position");
  position->SetNumberOfComponents(3);
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    position->InsertNextTuple(grid->GetPoint(p));
  }
  grid->GetPointData()->AddArray(position);
}

// Two flat cubic cells folded by `angle` degrees about their common edge on the y axis: cell 0
// in the plane z = 0, cell 1 rotated about the y axis.
vtkSmartPointer<vtkUnstructuredGrid> Fold(double angle)
{
  const std::vector<int> order = ctk::VtkBezierTriangleOrder(3);
  const auto exponents = ctk::BezierExponents(3);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  grid->SetPoints(points);
  const double a = vtkMath::RadiansFromDegrees(angle);
  const ctk::Vec3 apex[2] = { ctk::Vec3(1, 0.5, 0), ctk::Vec3(-std::cos(a), 0.5, std::sin(a)) };
  std::map<std::array<int, 3>, vtkIdType> shared; // edge points on the y axis, by exponent
  for (int c = 0; c < 2; ++c)
  {
    // Corners (0, 0, 0), (0, 1, 0) on the axis, then the apex; corner order flipped for cell 1
    // so that both cells' normals point to the same side of the fold.
    const ctk::Vec3 corner[3] = { ctk::Vec3(0, c == 0 ? 0 : 1, 0), ctk::Vec3(0, c == 0 ? 1 : 0, 0), apex[c] };
    std::vector<vtkIdType> ids(10);
    for (int p = 0; p < 10; ++p)
    {
      const std::array<int, 3>& e = exponents[order[p]];
      const ctk::Vec3 x = (e[0] * corner[0] + e[1] * corner[1] + e[2] * corner[2]) / 3.0;
      if (e[2] == 0)
      {
        const std::array<int, 3> key = c == 0 ? e : std::array<int, 3>{ e[1], e[0], 0 };
        auto it = shared.find(key);
        ids[p] = it != shared.end() ? it->second : (shared[key] = points->InsertNextPoint(x.data()));
      }
      else
      {
        ids[p] = points->InsertNextPoint(x.data());
      }
    }
    grid->InsertNextCell(VTK_BEZIER_TRIANGLE, 10, ids.data());
  }
  return grid;
}
} // namespace

TEST(vtkBezierTriangleTessellator, PointAndCellDataAreCarried)
{
  for (bool rational : { false, true })
  {
    vtkSmartPointer<vtkUnstructuredGrid> grid =
      rational ? SphereOctants(true) : MakeSpline(ctk::AnalyticSurface::Franke, 3);
    AddPositionArray(grid);
    vtkNew<vtkIntArray> pointLabel, cellLabel;
    pointLabel->SetName("PointLabel");
    pointLabel->SetNumberOfTuples(grid->GetNumberOfPoints());
    pointLabel->Fill(3);
    grid->GetPointData()->AddArray(pointLabel);
    cellLabel->SetName("CellLabel");
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      cellLabel->InsertNextValue(static_cast<int>(7 * c + 1));
    }
    grid->GetCellData()->SetScalars(cellLabel);
    vtkNew<vtkStringArray> names;
    names->SetName("CellName");
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      names->InsertNextValue("cell " + std::to_string(c));
    }
    grid->GetCellData()->AddArray(names);
    vtkSmartPointer<vtkPolyData> out = Tessellate(grid, 5);
    vtkDataArray* position = out->GetPointData()->GetArray("Position");
    ASSERT_NE(position, nullptr);
    double worst = 0;
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
    {
      worst = std::max(worst, (Tuple3(position, p) - Point(out, p)).norm());
    }
    EXPECT_LT(worst, 1e-14) << (rational ? "rational" : "polynomial");
    // Integer point data has no meaning between control points: not carried.
    EXPECT_EQ(out->GetPointData()->GetArray("PointLabel"), nullptr);
    vtkDataArray* label = out->GetCellData()->GetScalars();
    ASSERT_NE(label, nullptr);
    EXPECT_STREQ(label->GetName(), "CellLabel");
    vtkDataArray* source = out->GetCellData()->GetArray("BezierCellId");
    auto* outNames = vtkStringArray::SafeDownCast(out->GetCellData()->GetAbstractArray("CellName"));
    ASSERT_NE(outNames, nullptr);
    for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
    {
      ASSERT_EQ(label->GetComponent(t, 0), 7 * source->GetComponent(t, 0) + 1);
      ASSERT_EQ(outNames->GetValue(t), "cell " + std::to_string(static_cast<vtkIdType>(source->GetComponent(t, 0))));
    }
    if (!rational)
    {
      EXPECT_NE(out->GetCellData()->GetArray("MacroTriangleId"), nullptr);
      EXPECT_NE(out->GetPointData()->GetArray("UV"), nullptr);
    }
  }
}

TEST(vtkBezierTriangleTessellator, CreasesAreSplitWithExactNormals)
{
  const int L = 4;
  for (double angle : { 90.0, 45.0, 20.0 })
  {
    vtkSmartPointer<vtkUnstructuredGrid> fold = Fold(angle);
    AddPositionArray(fold);
    vtkSmartPointer<vtkPolyData> merged = Tessellate(fold, L, false);
    vtkSmartPointer<vtkPolyData> split = Tessellate(fold, L);
    // 4 corners, 5 edges, 2 cells; the L + 1 points of the fold are doubled above 30 degrees.
    const vtkIdType conforming = 4 + 5 * (L - 1) + 2 * (L - 1) * (L - 2) / 2;
    EXPECT_EQ(merged->GetNumberOfPoints(), conforming);
    const bool crease = angle > 30;
    EXPECT_EQ(split->GetNumberOfPoints(), conforming + (crease ? L + 1 : 0)) << angle;
    EXPECT_EQ(split->GetNumberOfCells(), merged->GetNumberOfCells());
    // Every point carries the exact normal of its own cell's plane where split.
    vtkDataArray* normals = split->GetPointData()->GetNormals();
    vtkDataArray* source = split->GetCellData()->GetArray("BezierCellId");
    const double a = vtkMath::RadiansFromDegrees(angle);
    const ctk::Vec3 planeNormal[2] = { ctk::Vec3(0, 0, -1), ctk::Vec3(-std::sin(a), 0, -std::cos(a)) };
    for (vtkIdType t = 0; t < split->GetNumberOfCells(); ++t)
    {
      const vtkIdType* pts;
      vtkIdType npts;
      split->GetPolys()->GetCellAtId(t, npts, pts);
      const int c = static_cast<int>(source->GetComponent(t, 0));
      for (int k = 0; k < 3; ++k)
      {
        const ctk::Vec3 n = Tuple3(normals, pts[k]);
        if (crease || c == 0)
        {
          EXPECT_LT((n - planeNormal[c]).norm(), 1e-14) << angle << " cell " << c;
        }
      }
    }
    // The copies keep their coordinates bit for bit, and carry the point data.
    EXPECT_GT(MinimumSeparation(merged), 1e-6);
    EXPECT_EQ(MinimumSeparation(split), crease ? 0.0 : MinimumSeparation(merged));
    vtkDataArray* position = split->GetPointData()->GetArray("Position");
    for (vtkIdType p = 0; p < split->GetNumberOfPoints(); ++p)
    {
      EXPECT_LT((Tuple3(position, p) - Point(split, p)).norm(), 1e-15);
    }
  }
  // A feature angle above the fold keeps the points shared.
  vtkNew<vtkBezierTriangleTessellator> wide;
  wide->SetInputData(Fold(90));
  wide->SetSubdivisionLevel(L);
  wide->SetFeatureAngle(100);
  wide->Update();
  EXPECT_EQ(wide->GetOutput()->GetNumberOfPoints(), 4 + 5 * (L - 1) + 2 * (L - 1) * (L - 2) / 2);
}

namespace
{
vtkSmartPointer<vtkPolyData> Adaptive(vtkDataSet* input, int maxLevel, double chordal,
  double angular, bool split = false)
{
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputData(input);
  tessellator->SetSubdivisionLevel(maxLevel);
  tessellator->SetChordalTolerance(chordal);
  tessellator->SetAngularTolerance(angular);
  tessellator->SetSplitSharpEdges(split);
  tessellator->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(tessellator->GetOutput());
  return out;
}

// Number of triangles at every edge (by point ids): 1 on the boundary, 2 inside when conforming.
std::map<std::pair<vtkIdType, vtkIdType>, int> EdgeUse(vtkPolyData* pd)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> use;
  for (vtkIdType t = 0; t < pd->GetNumberOfCells(); ++t)
  {
    const vtkIdType* pts;
    vtkIdType npts;
    pd->GetPolys()->GetCellAtId(t, npts, pts);
    for (int a = 0; a < 3; ++a)
    {
      ++use[std::minmax(pts[a], pts[(a + 1) % 3])];
    }
  }
  return use;
}

// Distance of each triangle's centroid from the spline at the centroid's (u, v).
std::vector<double> CentroidDeviation(vtkPolyData* pd, vtkDataSet* spline)
{
  vtkNew<vtkPolyData> queries;
  vtkNew<vtkPoints> points;
  vtkDataArray* uv = pd->GetPointData()->GetArray("UV");
  std::vector<ctk::Vec3> centroids;
  for (vtkIdType t = 0; t < pd->GetNumberOfCells(); ++t)
  {
    const vtkIdType* pts;
    vtkIdType npts;
    pd->GetPolys()->GetCellAtId(t, npts, pts);
    ctk::Vec3 x = ctk::Vec3::Zero();
    double u = 0, v = 0;
    for (int a = 0; a < 3; ++a)
    {
      x += Point(pd, pts[a]) / 3.0;
      u += uv->GetComponent(pts[a], 0) / 3.0;
      v += uv->GetComponent(pts[a], 1) / 3.0;
    }
    centroids.push_back(x);
    points->InsertNextPoint(u, v, 0.0);
  }
  queries->SetPoints(points);
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(queries);
  probe->SetSourceData(spline);
  probe->Update();
  vtkDataSet* on = probe->GetOutput();
  std::vector<double> d;
  for (vtkIdType t = 0; t < pd->GetNumberOfCells(); ++t)
  {
    d.push_back((Point(on, t) - centroids[t]).norm());
  }
  return d;
}
} // namespace

TEST(vtkBezierTriangleTessellator, AdaptiveIsConformingAndWithinTheChordalTolerance)
{
  vtkSmartPointer<vtkUnstructuredGrid> spline = MakeSpline(ctk::AnalyticSurface::Franke, 6);
  const double diagonal = spline->GetLength();
  vtkSmartPointer<vtkPolyData> uniform = Tessellate(spline, 32, false);
  for (double relative : { 1e-3, 1e-4 })
  {
    vtkSmartPointer<vtkPolyData> out = Adaptive(spline, 32, relative, 0.0);
    // Conforming: every edge has one (boundary) or two triangles, and the boundary is the
    // uniform tessellation's (6 cells of 4 grid edges per side).
    int boundary = 0;
    for (const auto& [edge, count] : EdgeUse(out))
    {
      ASSERT_LE(count, 2);
      boundary += count == 1;
    }
    EXPECT_GT(boundary, 0);
    EXPECT_LT(out->GetNumberOfCells(), uniform->GetNumberOfCells());
    const std::vector<double> d = CentroidDeviation(out, spline);
    const double worst = *std::max_element(d.begin(), d.end());
    // Checked at edge midpoints; centroids of the same triangles deviate a little more.
    EXPECT_LT(worst, 1.5 * relative * diagonal) << relative;
    // Every cell's triangles are oriented as the cell: all normals of a triangle's corners
    // agree with its facet.
    EXPECT_TRUE(NormalsFollowFacets(out, 1));
    std::cout << "chordal " << relative << ": " << out->GetNumberOfCells()
              << " triangles, centroid deviation " << worst / diagonal << " (uniform 32: "
              << uniform->GetNumberOfCells() << ")\n";
  }
  // The tighter tolerance needs more triangles.
  EXPECT_LT(Adaptive(spline, 32, 1e-3, 0)->GetNumberOfCells(),
    Adaptive(spline, 32, 1e-4, 0)->GetNumberOfCells());
}

TEST(vtkBezierTriangleTessellator, AdaptiveAngularTolerance)
{
  vtkSmartPointer<vtkUnstructuredGrid> octants = SphereOctants(false);
  for (double degrees : { 10.0, 3.0 })
  {
    vtkSmartPointer<vtkPolyData> out = Adaptive(octants, 64, 0.0, degrees);
    vtkDataArray* normals = out->GetPointData()->GetNormals();
    double worst = 0;
    for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
    {
      const vtkIdType* pts;
      vtkIdType npts;
      out->GetPolys()->GetCellAtId(t, npts, pts);
      for (int a = 0; a < 3; ++a)
      {
        const double c = Tuple3(normals, pts[a]).dot(Tuple3(normals, pts[(a + 1) % 3]));
        worst = std::max(worst, vtkMath::DegreesFromRadians(std::acos(std::min(1.0, c))));
      }
    }
    EXPECT_LE(worst, degrees + 1e-9);
    // A sphere octant spans 90 degrees: at least 90 / degrees segments per edge.
    const vtkIdType atLeast = static_cast<vtkIdType>(std::pow(90.0 / degrees, 2));
    EXPECT_GE(out->GetNumberOfCells(), atLeast);
  }
}

// The shared corners and edges as defined: corners in order of first use (slot 3 c + a), edges
// by lower corner then slot, each owned by its first cell; on 1 and 3 threads, on a random
// Delaunay spline. A kept topology is recognised by the same corners only.
TEST(vtkBezierTriangleTessellator, SharedCornersAndEdgesFollowTheirDefinition)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetDomainToRandomDelaunay();
  source->SetResolution(4000);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  spline->Update();
  ctsplines::BezierCells cells;
  ASSERT_EQ(ctsplines::GatherBezierCells(spline->GetOutput(), cells), "");
  const vtkIdType nSlots = 3 * cells.NumberOfCells();
  // The reference: one pass in slot order.
  std::map<vtkIdType, vtkIdType> cornerOf;
  std::vector<vtkIdType> corner(nSlots);
  std::vector<bool> ownsCorner(nSlots);
  for (vtkIdType s = 0; s < nSlots; ++s)
  {
    const vtkIdType p = cells.CellIds(s / 3)[s % 3];
    ownsCorner[s] = cornerOf.emplace(p, static_cast<vtkIdType>(cornerOf.size())).second;
    corner[s] = cornerOf[p];
  }
  std::vector<std::array<vtkIdType, 3>> byLower; // lower corner, upper corner, slot
  for (vtkIdType s = 0; s < nSlots; ++s)
  {
    const vtkIdType a = corner[s], b = corner[3 * (s / 3) + (s % 3 + 1) % 3];
    byLower.push_back({ std::min(a, b), std::max(a, b), s });
  }
  std::sort(byLower.begin(), byLower.end(),
    [](const auto& x, const auto& y) { return x[0] != y[0] ? x[0] < y[0] : x[2] < y[2]; });
  std::map<std::pair<vtkIdType, vtkIdType>, vtkIdType> edgeOf;
  std::vector<vtkIdType> edge(nSlots);
  std::vector<bool> ownsEdge(nSlots);
  for (const auto& item : byLower)
  {
    ownsEdge[item[2]] =
      edgeOf.emplace(std::make_pair(item[0], item[1]), static_cast<vtkIdType>(edgeOf.size()))
        .second;
    edge[item[2]] = edgeOf[{ item[0], item[1] }];
  }
  for (const char* threads : { "1", "3" })
  {
    setenv("CTSPLINES_NUM_THREADS", threads, 1);
    const ctsplines::SharedCellTopology numbering(cells);
    EXPECT_TRUE(numbering.SameCorners(cells)) << threads;
    // Another corner in the last cell, then one cell fewer.
    ctsplines::BezierCells changed = cells;
    std::swap(changed.Ids[changed.Offsets[changed.NumberOfCells() - 1]],
      changed.Ids[changed.Offsets[changed.NumberOfCells() - 1] + 1]);
    EXPECT_FALSE(numbering.SameCorners(changed)) << threads;
    changed = cells;
    changed.Degree.pop_back();
    changed.Offsets.pop_back();
    EXPECT_FALSE(numbering.SameCorners(changed)) << threads;
    unsetenv("CTSPLINES_NUM_THREADS");
    ASSERT_EQ(numbering.NumberOfCorners(), static_cast<vtkIdType>(cornerOf.size())) << threads;
    ASSERT_EQ(numbering.NumberOfEdges(), static_cast<vtkIdType>(edgeOf.size())) << threads;
    for (vtkIdType s = 0; s < nSlots; ++s)
    {
      const vtkIdType c = s / 3;
      const int a = static_cast<int>(s % 3);
      ASSERT_EQ(numbering.CornerId(c, a), corner[s]) << threads << " slot " << s;
      ASSERT_EQ(numbering.OwnsCorner(c, a), ownsCorner[s]) << threads << " slot " << s;
      ASSERT_EQ(numbering.EdgeId(c, a), edge[s]) << threads << " slot " << s;
      ASSERT_EQ(numbering.OwnsEdge(c, a), ownsEdge[s]) << threads << " slot " << s;
    }
  }
}
