// SPDX-License-Identifier: GPL-3.0-or-later
// The retained large blocks (vtkCloughTocherSplineFilter::SetRetainedMemoryLimit,
// ctk::MapLargeBlock): the spline's arrays, freed with its output, are retained, and every
// construction, and the tessellator and probe after it, give the same bits when those blocks
// come back filled with 0xff bytes (CTSPLINES_POISON_RETAINED_BLOCKS) as when every array is a
// fresh mapping of zeros: no code reads a large array before writing it.
#include "LargeArrays.h" // for CTSPLINES_MAP_LARGE_ARRAYS
#include "OutputBits.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"
#include "vtkSplineParameterProbe.h"

#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace
{
// A random Delaunay domain of about 1.2e5 triangles: the spline's points and several working
// arrays are above the 4 MiB of a mapped block.
vtkSmartPointer<vtkPolyData> Mesh(int surface)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetDomainToRandomDelaunay();
  source->SetResolution(60000);
  source->SetSurface(surface);
  source->Update();
  vtkSmartPointer<vtkPolyData> mesh = source->GetOutput();
  return mesh;
}

// 1e5 random queries in [-0.05, 1.05]^2.
vtkSmartPointer<vtkPolyData> Queries()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uv(-0.05, 1.05);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(100000);
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    const double u = uv(rng);
    points->SetPoint(i, u, uv(rng), 0.0);
  }
  auto queries = vtkSmartPointer<vtkPolyData>::New();
  queries->SetPoints(points);
  return queries;
}

// The outputs of a spline of `construction` and, for CTi and the quartic construction, its
// tessellation at level 2 and a probe of it (they depend on the degree only): each filter new,
// so that every large array is asked for anew.
std::vector<vtkSmartPointer<vtkDataObject>> Outputs(
  vtkPolyData* mesh, vtkPolyData* queries, int construction)
{
  std::vector<vtkSmartPointer<vtkDataObject>> out;
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputData(mesh);
  spline->SetConstruction(construction);
  spline->Update();
  out.emplace_back(spline->GetOutput());
  if (construction != vtkCloughTocherSplineFilter::CTi &&
    construction != vtkCloughTocherSplineFilter::Quartic)
  {
    return out;
  }
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputData(spline->GetOutput());
  tessellator->SetSubdivisionLevel(2);
  tessellator->Update();
  out.emplace_back(tessellator->GetOutput());
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(queries);
  probe->SetSourceData(spline->GetOutput());
  probe->SetComputeDerivatives(true);
  probe->Update();
  out.emplace_back(probe->GetOutput());
  return out;
}

struct Limit
{
  vtkTypeUInt64 Saved = vtkCloughTocherSplineFilter::GetRetainedMemoryLimit();
  ~Limit()
  {
    unsetenv("CTSPLINES_POISON_RETAINED_BLOCKS");
    vtkCloughTocherSplineFilter::ReleaseRetainedMemory();
    vtkCloughTocherSplineFilter::SetRetainedMemoryLimit(this->Saved);
  }
};

TEST(RetainedMemory, PoisonedBlocksGiveTheBitsOfFreshOnes)
{
#if !CTSPLINES_MAP_LARGE_ARRAYS
  GTEST_SKIP() << "nothing is retained in this build (ASan)";
#endif
  const Limit restore;
  const auto mesh = Mesh(vtkSampledSurfaceSource::Franke);
  const auto queries = Queries();
  for (int c = 0; c < vtkCloughTocherSplineFilter::GetNumberOfConstructions(); ++c)
  {
    const std::string name = vtkCloughTocherSplineFilter::GetConstructionName(c);
    vtkCloughTocherSplineFilter::SetRetainedMemoryLimit(0); // every block a fresh mapping
    const auto fresh = Outputs(mesh, queries, c);
    ASSERT_EQ(vtkCloughTocherSplineFilter::GetRetainedMemory(), 0u) << name;
    // The points of a first run are retained full of 0xff bytes, then taken by a second run.
    vtkCloughTocherSplineFilter::SetRetainedMemoryLimit(vtkTypeUInt64(8) << 30);
    ASSERT_EQ(setenv("CTSPLINES_POISON_RETAINED_BLOCKS", "1", 1), 0);
    Outputs(mesh, queries, c);
    EXPECT_GT(vtkCloughTocherSplineFilter::GetRetainedMemory(), vtkTypeUInt64(8) << 20) << name;
    const auto reused = Outputs(mesh, queries, c);
    unsetenv("CTSPLINES_POISON_RETAINED_BLOCKS");
    const char* what[] = { "spline", "tessellation", "probe" };
    ASSERT_EQ(fresh.size(), reused.size()) << name;
    for (size_t k = 0; k < fresh.size(); ++k)
    {
      EXPECT_EQ(ctsplines_test::OutputDifference(fresh[k], reused[k]), "")
        << name << " " << what[k];
    }
    vtkCloughTocherSplineFilter::ReleaseRetainedMemory();
  }
}

// The tessellator's output arrays (ctsplines::AllocateTuples) are retained blocks: freed with the
// output, they are retained; one that a caller keeps and grows goes through VTK's reallocation,
// which frees the old block through the module's free function, and keeps its values.
TEST(RetainedMemory, OutputArraysAreRetainedWhenFreedOrGrown)
{
#if !CTSPLINES_MAP_LARGE_ARRAYS
  GTEST_SKIP() << "nothing is retained in this build (ASan)";
#endif
  const Limit restore;
  vtkCloughTocherSplineFilter::ReleaseRetainedMemory();
  vtkCloughTocherSplineFilter::SetRetainedMemoryLimit(vtkTypeUInt64(4) << 30);
  vtkSmartPointer<vtkDoubleArray> normals;
  vtkTypeUInt64 pointBytes = 0;
  {
    vtkNew<vtkCloughTocherSplineFilter> spline;
    spline->SetInputData(Mesh(vtkSampledSurfaceSource::Franke));
    vtkNew<vtkBezierTriangleTessellator> tessellator;
    tessellator->SetInputConnection(spline->GetOutputPort());
    tessellator->SetSubdivisionLevel(3);
    tessellator->Update();
    vtkPolyData* out = tessellator->GetOutput();
    normals = vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("Normals"));
    ASSERT_NE(normals, nullptr);
    pointBytes = 8 * out->GetPoints()->GetData()->GetNumberOfValues();
    ASSERT_GT(pointBytes, vtkTypeUInt64(8) << 20);
  }
  // The spline's and the tessellation's arrays but the normals: at least the points.
  const vtkTypeUInt64 retained = vtkCloughTocherSplineFilter::GetRetainedMemory();
  EXPECT_GE(retained, pointBytes);
  const vtkIdType n = normals->GetNumberOfTuples();
  double first[3], last[3];
  normals->GetTypedTuple(0, first);
  normals->GetTypedTuple(n - 1, last);
  normals->InsertNextTuple3(1.0, 2.0, 3.0); // VTK reallocates and frees the old block
  ASSERT_EQ(normals->GetNumberOfTuples(), n + 1);
  double again[3];
  normals->GetTypedTuple(0, again);
  EXPECT_EQ(first[0], again[0]);
  EXPECT_EQ(first[2], again[2]);
  normals->GetTypedTuple(n - 1, again);
  EXPECT_EQ(last[1], again[1]);
  EXPECT_EQ(normals->GetComponent(n, 2), 3.0);
  EXPECT_GE(vtkCloughTocherSplineFilter::GetRetainedMemory(), retained + 24 * n - (2 << 20));
  normals = nullptr;
}
} // namespace
