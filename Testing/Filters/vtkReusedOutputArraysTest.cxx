// SPDX-License-Identifier: GPL-3.0-or-later
// ReuseOutputArrays (CTSplinesRecycledArrays.h): an execution that writes into the previous
// output's arrays gives the bits a new filter gives, VTK's caches see new values, and an array
// that anything else still holds is never written.
#include "CTSplinesRecycledArrays.h"
#include "ErrorCapture.h"
#include "OutputBits.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"
#include "vtkSplineParameterProbe.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWeakPointer.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

namespace
{
// A grid of 2 x 150^2 triangles: every large output array is above RecycledArrays' 1 MiB.
vtkSmartPointer<vtkSampledSurfaceSource> Source(int surface)
{
  auto source = vtkSmartPointer<vtkSampledSurfaceSource>::New();
  source->SetDomainToGrid();
  source->SetResolution(150);
  source->SetSurface(surface);
  return source;
}

// The same values, type and shape, compared as bytes.
void ExpectSameArray(vtkDataArray* a, vtkDataArray* b, const std::string& what)
{
  ASSERT_NE(a, nullptr) << what;
  ASSERT_NE(b, nullptr) << what;
  ASSERT_EQ(ctsplines_test::ArrayDifference(a, b), "") << what;
  // Ranges as VTK serves them (stored by the filter or computed): those of the new values.
  for (int c = -1; c < a->GetNumberOfComponents(); ++c)
  {
    double ra[2], rb[2];
    a->GetRange(ra, c);
    b->GetRange(rb, c);
    EXPECT_EQ(ra[0], rb[0]) << what << " component " << c;
    EXPECT_EQ(ra[1], rb[1]) << what << " component " << c;
  }
}

void ExpectSameCells(vtkCellArray* a, vtkCellArray* b, const std::string& what)
{
  ASSERT_NE(a, nullptr) << what;
  ASSERT_NE(b, nullptr) << what;
  EXPECT_EQ(ctsplines_test::CellsDifference(a, b), "") << what;
}

void ExpectSameData(vtkDataSetAttributes* a, vtkDataSetAttributes* b, const std::string& what)
{
  ASSERT_EQ(a->GetNumberOfArrays(), b->GetNumberOfArrays()) << what;
  for (int i = 0; i < a->GetNumberOfArrays(); ++i)
  {
    const char* name = a->GetArrayName(i);
    ASSERT_NE(name, nullptr) << what;
    ExpectSameArray(a->GetArray(i), b->GetArray(name), what + " " + name);
  }
}

void ExpectSameSpline(vtkUnstructuredGrid* a, vtkUnstructuredGrid* b)
{
  ExpectSameArray(a->GetPoints()->GetData(), b->GetPoints()->GetData(), "points");
  ExpectSameCells(a->GetCells(), b->GetCells(), "cells");
  ExpectSameArray(a->GetCellTypesArray(), b->GetCellTypesArray(), "cell types");
  ExpectSameData(a->GetPointData(), b->GetPointData(), "point data");
  ExpectSameData(a->GetCellData(), b->GetCellData(), "cell data");
}

void ExpectSameTessellation(vtkPolyData* a, vtkPolyData* b)
{
  ExpectSameArray(a->GetPoints()->GetData(), b->GetPoints()->GetData(), "points");
  ExpectSameCells(a->GetPolys(), b->GetPolys(), "triangles");
  ExpectSameData(a->GetPointData(), b->GetPointData(), "point data");
  ExpectSameData(a->GetCellData(), b->GetCellData(), "cell data");
}

// The spline of `surface` from a filter that allocates its output.
vtkSmartPointer<vtkUnstructuredGrid> FreshSpline(int surface, int construction)
{
  vtkNew<vtkCloughTocherSplineFilter> filter;
  filter->SetReuseOutputArrays(false);
  filter->SetConstruction(construction);
  filter->SetInputConnection(Source(surface)->GetOutputPort());
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

vtkTypeUInt64 Bytes(vtkDataArray* a)
{
  return static_cast<vtkTypeUInt64>(a->GetNumberOfValues()) * a->GetDataTypeSize();
}

// n random (u, v, 0) queries in [-0.05, 1.05]^2 (some outside the grid's [0, 1]^2), with a
// point data array "Payload" of 3 x n doubles for the probe to pass through.
vtkSmartPointer<vtkPolyData> Queries(vtkIdType n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uv(-0.05, 1.05);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkDoubleArray> payload;
  payload->SetName("Payload");
  payload->SetNumberOfComponents(3);
  payload->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double u = uv(rng), v = uv(rng);
    points->SetPoint(i, u, v, 0.0);
    payload->SetTuple3(i, v, u, double(i));
  }
  auto queries = vtkSmartPointer<vtkPolyData>::New();
  queries->SetPoints(points);
  queries->GetPointData()->AddArray(payload);
  return queries;
}

// The probe's output on these queries from a probe that allocates its output.
vtkSmartPointer<vtkPolyData> FreshProbe(vtkDataSet* spline, vtkPolyData* queries)
{
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetReuseOutputArrays(false);
  probe->SetSourceData(spline);
  probe->SetInputData(queries);
  probe->Update();
  EXPECT_EQ(probe->GetReusedOutputBytes(), 0u);
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(probe->GetOutput());
  return out;
}

void ExpectSameProbe(vtkDataSet* output, vtkPolyData* b)
{
  vtkPolyData* a = vtkPolyData::SafeDownCast(output);
  ASSERT_NE(a, nullptr);
  ExpectSameArray(a->GetPoints()->GetData(), b->GetPoints()->GetData(), "points");
  ExpectSameData(a->GetPointData(), b->GetPointData(), "point data");
}

// 50,000 queries: their points, derivatives and normals are each above RecycledArrays' 1 MiB
// (the 400 KB of macro-triangle ids and the 50 KB mask are not kept).
constexpr vtkIdType ProbePoints = 50000;
constexpr vtkTypeUInt64 ProbeKeptBytes = ProbePoints * 4 * 3 * sizeof(double);
} // namespace

// A new surface on the same grid, then a quartic construction (other sizes, not reused) and
// back: each execution equals a new filter's output, bit for bit, ranges included. The cubic
// constructions reuse the control and domain points.
TEST(ReusedOutputArrays, SplineRewritesItsArraysWithTheBitsOfANewFilter)
{
  auto source = Source(vtkSampledSurfaceSource::Franke);
  vtkNew<vtkCloughTocherSplineFilter> filter;
  ASSERT_TRUE(filter->GetReuseOutputArrays()); // the default
  filter->SetInputConnection(source->GetOutputPort());
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  const vtkTypeUInt64 pointBytes = Bytes(filter->GetOutput()->GetPoints()->GetData()) +
    Bytes(filter->GetOutput()->GetPointData()->GetArray("UV"));
  double before[2];
  filter->GetOutput()->GetPoints()->GetData()->GetRange(before, 2); // cached in the array

  source->SetSurface(vtkSampledSurfaceSource::SineWave);
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), pointBytes);
  ExpectSameSpline(filter->GetOutput(),
    FreshSpline(vtkSampledSurfaceSource::SineWave, vtkCloughTocherSplineFilter::CTi));
  double after[2];
  filter->GetOutput()->GetPoints()->GetData()->GetRange(after, 2);
  EXPECT_NE(before[1], after[1]); // not the first surface's cached range

  // Other sizes: nothing to reuse, the old arrays are released.
  filter->SetConstruction(vtkCloughTocherSplineFilter::Quartic);
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  ExpectSameSpline(filter->GetOutput(),
    FreshSpline(vtkSampledSurfaceSource::SineWave, vtkCloughTocherSplineFilter::Quartic));
  filter->Modified();
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  ExpectSameSpline(filter->GetOutput(),
    FreshSpline(vtkSampledSurfaceSource::SineWave, vtkCloughTocherSplineFilter::Quartic));
  filter->SetConstruction(vtkCloughTocherSplineFilter::CTo);
  filter->Update();
  filter->SetSplitPoint(vtkCloughTocherSplineFilter::Inc3);
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), pointBytes);
  vtkNew<vtkCloughTocherSplineFilter> fresh;
  fresh->SetReuseOutputArrays(false);
  fresh->SetConstruction(vtkCloughTocherSplineFilter::CTo);
  fresh->SetSplitPoint(vtkCloughTocherSplineFilter::Inc3);
  fresh->SetInputConnection(Source(vtkSampledSurfaceSource::SineWave)->GetOutputPort());
  fresh->Update();
  ExpectSameSpline(filter->GetOutput(), fresh->GetOutput());
}

// A caller that holds the old output, one of its arrays, or a view of an array's storage
// (vtkAOSDataArrayTemplate::ShallowCopy, as vtkArrayRename makes) keeps its values: those arrays
// are not written, the new output gets new ones.
TEST(ReusedOutputArrays, ArraysHeldElsewhereAreNeverWritten)
{
  auto source = Source(vtkSampledSurfaceSource::Franke);
  vtkNew<vtkCloughTocherSplineFilter> filter;
  filter->SetInputConnection(source->GetOutputPort());
  filter->Update();
  vtkSmartPointer<vtkDataArray> heldUV = filter->GetOutput()->GetPointData()->GetArray("UV");
  const vtkTypeUInt64 pointBytes = Bytes(filter->GetOutput()->GetPoints()->GetData());
  auto snapshot = vtkSmartPointer<vtkUnstructuredGrid>::New();
  snapshot->DeepCopy(filter->GetOutput());

  source->SetSurface(vtkSampledSurfaceSource::SineWave);
  filter->Update();
  ExpectSameArray(heldUV, snapshot->GetPointData()->GetArray("UV"), "held UV");
  EXPECT_NE(filter->GetOutput()->GetPointData()->GetArray("UV"), heldUV.Get());
  EXPECT_EQ(filter->GetReusedOutputBytes(), pointBytes); // the points were free
  ExpectSameSpline(filter->GetOutput(),
    FreshSpline(vtkSampledSurfaceSource::SineWave, vtkCloughTocherSplineFilter::CTi));

  // Views: other array objects on the same storage.
  heldUV = nullptr;
  auto pointsView = vtkSmartPointer<vtkDoubleArray>::New();
  pointsView->ShallowCopy(filter->GetOutput()->GetPoints()->GetData());
  auto uvView = vtkSmartPointer<vtkDoubleArray>::New();
  uvView->ShallowCopy(filter->GetOutput()->GetPointData()->GetArray("UV"));
  snapshot->DeepCopy(filter->GetOutput());
  source->SetSurface(vtkSampledSurfaceSource::Franke);
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  ExpectSameArray(pointsView, snapshot->GetPoints()->GetData(), "points view");
  ExpectSameArray(uvView, snapshot->GetPointData()->GetArray("UV"), "UV view");
  ExpectSameSpline(filter->GetOutput(),
    FreshSpline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::CTi));

  // A shallow copy of the whole output holds every array.
  pointsView = nullptr;
  uvView = nullptr;
  auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
  copy->ShallowCopy(filter->GetOutput());
  snapshot->DeepCopy(filter->GetOutput());
  source->SetSurface(vtkSampledSurfaceSource::SineWave);
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  ExpectSameSpline(copy, snapshot);
}

// Off, with the pipeline releasing the output's data, or after a failed execution, the filter
// keeps nothing of an output.
TEST(ReusedOutputArrays, NothingIsKeptWhenOffReleasedOrFailed)
{
  auto source = Source(vtkSampledSurfaceSource::Franke);
  vtkNew<vtkCloughTocherSplineFilter> filter;
  filter->SetInputConnection(source->GetOutputPort());
  filter->SetReuseOutputArrays(false);
  filter->Update();
  filter->Modified();
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);

  filter->SetReuseOutputArrays(true);
  auto* executive = vtkStreamingDemandDrivenPipeline::SafeDownCast(filter->GetExecutive());
  executive->SetReleaseDataFlag(0, 1);
  filter->Update();
  filter->Modified();
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  executive->SetReleaseDataFlag(0, 0);

  filter->Modified();
  filter->Update();
  filter->Modified();
  filter->Update();
  EXPECT_GT(filter->GetReusedOutputBytes(), 0u);
  // Derivatives missing: the execution fails, after which nothing is kept.
  filter->SetDuArrayName("NoSuchArray");
  auto errors = ctsplines_test::ErrorCapture::AttachToAlgorithm(filter);
  EXPECT_EQ(filter->GetExecutive()->Update(), 0);
  EXPECT_NE(errors->Message.find("NoSuchArray"), std::string::npos) << errors->Message;
  filter->SetDuArrayName("dFdu");
  filter->Update();
  EXPECT_EQ(filter->GetReusedOutputBytes(), 0u);
  ExpectSameSpline(filter->GetOutput(),
    FreshSpline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::CTi));
}

// The tessellator: a new spline of the same sizes, then another level (other sizes), each equal
// to a new tessellator's output; the cell data copied from the spline is reused too.
TEST(ReusedOutputArrays, TessellatorRewritesItsArraysWithTheBitsOfANewFilter)
{
  auto source = Source(vtkSampledSurfaceSource::Franke);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputConnection(spline->GetOutputPort());
  tessellator->SetSubdivisionLevel(3);
  tessellator->Update();
  EXPECT_EQ(tessellator->GetReusedOutputBytes(), 0u);
  auto fresh = [&]() {
    vtkNew<vtkBezierTriangleTessellator> other;
    other->SetReuseOutputArrays(false);
    other->SetInputData(spline->GetOutput());
    other->SetSubdivisionLevel(tessellator->GetSubdivisionLevel());
    other->Update();
    auto out = vtkSmartPointer<vtkPolyData>::New();
    out->ShallowCopy(other->GetOutput());
    return out;
  };

  source->SetSurface(vtkSampledSurfaceSource::SineWave);
  tessellator->Update();
  vtkPolyData* out = tessellator->GetOutput();
  ExpectSameTessellation(out, fresh());
  // A view of the normals' storage and a renamed view of the cell data keep their values.
  auto normalsView = vtkSmartPointer<vtkDoubleArray>::New();
  normalsView->ShallowCopy(out->GetPointData()->GetArray("Normals"));
  vtkSmartPointer<vtkDataArray> macroView =
    vtkSmartPointer<vtkDataArray>::Take(out->GetCellData()->GetArray("MacroTriangleId")->NewInstance());
  macroView->ShallowCopy(out->GetCellData()->GetArray("MacroTriangleId"));
  macroView->SetName("Renamed");
  auto snapshot = vtkSmartPointer<vtkPolyData>::New();
  snapshot->DeepCopy(out);
  source->SetSurface(vtkSampledSurfaceSource::Franke);
  tessellator->Update();
  out = tessellator->GetOutput();
  ExpectSameArray(normalsView, snapshot->GetPointData()->GetArray("Normals"), "normals view");
  ExpectSameArray(macroView, snapshot->GetCellData()->GetArray("MacroTriangleId"), "renamed view");
  ExpectSameTessellation(out, fresh());
  const vtkTypeUInt64 viewed = Bytes(normalsView) + Bytes(macroView);
  normalsView = nullptr;
  macroView = nullptr;
  EXPECT_GT(tessellator->GetReusedOutputBytes(), 0u);

  source->SetSurface(vtkSampledSurfaceSource::SineWave);
  tessellator->Update();
  const vtkTypeUInt64 all = Bytes(out->GetPoints()->GetData()) +
    Bytes(out->GetPointData()->GetArray("Normals")) + Bytes(out->GetPointData()->GetArray("UV")) +
    Bytes(out->GetPolys()->GetOffsetsArray()) + Bytes(out->GetPolys()->GetConnectivityArray()) +
    Bytes(out->GetCellData()->GetArray("BezierCellId")) +
    Bytes(out->GetCellData()->GetArray("MacroTriangleId"));
  EXPECT_GE(tessellator->GetReusedOutputBytes(), all);
  EXPECT_GT(all, viewed);
  ExpectSameTessellation(out, fresh());

  tessellator->SetSubdivisionLevel(4);
  tessellator->Update();
  EXPECT_EQ(tessellator->GetReusedOutputBytes(), 0u);
  ExpectSameTessellation(tessellator->GetOutput(), fresh());
}

// The kept corners and edges (SharedCellTopology) serve only cells with the same corners: the
// same spline with its cells in reverse order, the same counts everywhere, is numbered anew;
// another level on the same cells is not. Nothing is kept with the property off.
TEST(ReusedOutputArrays, TessellatorNumbersCellsWithOtherCornersAnew)
{
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(Source(vtkSampledSurfaceSource::Franke)->GetOutputPort());
  spline->Update();
  vtkUnstructuredGrid* forward = spline->GetOutput();
  vtkNew<vtkUnstructuredGrid> reversed;
  reversed->SetPoints(forward->GetPoints());
  reversed->GetPointData()->ShallowCopy(forward->GetPointData());
  const vtkIdType n = forward->GetNumberOfCells();
  reversed->Allocate(n);
  reversed->GetCellData()->CopyAllocate(forward->GetCellData(), n);
  for (vtkIdType k = n - 1; k >= 0; --k)
  {
    vtkIdType count = 0;
    const vtkIdType* ids = nullptr;
    forward->GetCellPoints(k, count, ids);
    const vtkIdType id = reversed->InsertNextCell(forward->GetCellType(k), count, ids);
    reversed->GetCellData()->CopyData(forward->GetCellData(), k, id);
  }
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  struct Run
  {
    vtkDataSet* Input;
    int Level;
    vtkTypeUInt64 Builds; // after the run
  };
  for (const Run& run : { Run{ forward, 3, 1 }, Run{ reversed, 3, 2 }, Run{ reversed, 4, 2 },
         Run{ forward, 4, 3 } })
  {
    tessellator->SetInputData(run.Input);
    tessellator->SetSubdivisionLevel(run.Level);
    tessellator->Update();
    EXPECT_EQ(tessellator->GetNumberOfTopologyBuilds(), run.Builds);
    vtkNew<vtkBezierTriangleTessellator> fresh;
    fresh->SetReuseOutputArrays(false);
    fresh->SetInputData(run.Input);
    fresh->SetSubdivisionLevel(run.Level);
    fresh->Update();
    ExpectSameTessellation(tessellator->GetOutput(), fresh->GetOutput());
  }
  tessellator->SetReuseOutputArrays(false);
  tessellator->SetSubdivisionLevel(3);
  tessellator->Update();
  EXPECT_EQ(tessellator->GetNumberOfTopologyBuilds(), 4u);
  tessellator->Modified();
  tessellator->Update();
  EXPECT_EQ(tessellator->GetNumberOfTopologyBuilds(), 5u);
}

// RecycledArrays itself: a kept array comes back only to a request of its class and sizes, only
// while nothing else holds it, and as a new array would be: no name, no cached ranges, a newer
// MTime (an unnamed array's ranges would otherwise be served stale).
TEST(ReusedOutputArrays, RecycledArraysGiveBackArraysAsNew)
{
  const vtkIdType n = 200000; // 1.6 MB of doubles
  // An output with a large array (ranges cached) and a small one, kept by `recycled`, then
  // released as the pipeline's PrepareForNewData does. Returns the large array's storage.
  auto keepOutput = [n](ctsplines::RecycledArrays& recycled, vtkDataArray** large) {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    auto values = vtkSmartPointer<vtkDoubleArray>::New();
    values->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      values->SetValue(i, static_cast<double>(i));
    }
    double range[2];
    values->GetRange(range); // cached in its information
    grid->GetPointData()->AddArray(values);
    auto small = vtkSmartPointer<vtkDoubleArray>::New(); // below MinimumBytes: not kept
    small->SetNumberOfTuples(10);
    grid->GetPointData()->AddArray(small);
    recycled.End(grid, true);
    *large = values;
    return grid;
  };
  ctsplines::RecycledArrays recycled;
  vtkDataArray* kept = nullptr;

  // Still held by the output when the next execution begins: released, not given back.
  auto grid = keepOutput(recycled, &kept);
  recycled.Begin(true, {});
  EXPECT_NE(recycled.New<vtkDoubleArray>(1, n).Get(), kept);
  EXPECT_EQ(recycled.GetReusedBytes(), 0u);

  // A view of its storage (another array object) holds it too.
  grid = keepOutput(recycled, &kept);
  auto view = vtkSmartPointer<vtkDoubleArray>::New();
  view->ShallowCopy(kept);
  grid->Initialize();
  recycled.Begin(true, {});
  EXPECT_NE(recycled.New<vtkDoubleArray>(1, n)->GetVoidPointer(0), view->GetVoidPointer(0));
  EXPECT_EQ(recycled.GetReusedBytes(), 0u);
  EXPECT_EQ(view->GetValue(n - 1), n - 1.0);

  // Free: given back to a request of its class and size only, once, as a new array.
  grid = keepOutput(recycled, &kept);
  const vtkMTimeType before = kept->GetMTime();
  grid->Initialize();
  recycled.Begin(true, {});
  EXPECT_EQ(recycled.New<vtkDoubleArray>(1, n + 1)->GetNumberOfTuples(), n + 1); // other size
  EXPECT_EQ(recycled.New<vtkFloatArray>(1, n)->GetNumberOfTuples(), n);          // other class
  EXPECT_EQ(recycled.GetReusedBytes(), 0u);
  vtkSmartPointer<vtkDoubleArray> a = recycled.New<vtkDoubleArray>(1, n);
  ASSERT_EQ(a.Get(), kept);
  EXPECT_EQ(recycled.GetReusedBytes(), static_cast<size_t>(n) * sizeof(double));
  EXPECT_GT(a->GetMTime(), before);
  EXPECT_FALSE(a->GetInformation()->Has(vtkDataArray::PER_COMPONENT()));
  for (vtkIdType i = 0; i < n; ++i)
  {
    a->SetValue(i, -static_cast<double>(i));
  }
  double range[2];
  a->GetRange(range); // the new values', not the cached ones
  EXPECT_EQ(range[0], 1.0 - n);
  EXPECT_EQ(range[1], 0.0);
  EXPECT_NE(recycled.New<vtkDoubleArray>(1, n).Get(), a.Get());
}

// The probe: other queries of the same count reuse its points, derivatives, normals and ids,
// with the bits of a new probe; the input's arrays that it passes through are the input's and
// are never kept (nor written); an array the caller holds is never written; another count, or
// positions only, allocate anew.
TEST(ReusedOutputArrays, ProbeRewritesItsArraysWithTheBitsOfANewProbe)
{
  auto spline = FreshSpline(vtkSampledSurfaceSource::Franke, vtkCloughTocherSplineFilter::CTi);
  vtkNew<vtkSplineParameterProbe> probe;
  ASSERT_TRUE(probe->GetReuseOutputArrays()); // the default
  probe->SetSourceData(spline);
  vtkWeakPointer<vtkDataArray> payload;
  {
    auto first = Queries(ProbePoints, 1);
    payload = first->GetPointData()->GetArray("Payload");
    probe->SetInputData(first);
    probe->Update();
    EXPECT_EQ(probe->GetReusedOutputBytes(), 0u);
    ASSERT_EQ(probe->GetOutput()->GetPointData()->GetArray("Payload"), payload.Get());
  }
  // The first queries are gone; their payload lives in the output until the next execution.
  // (Kept with the output, it would be taken for the first new array of its size, the points.)
  auto second = Queries(ProbePoints, 2);
  probe->SetInputData(second);
  probe->Update();
  EXPECT_EQ(payload.Get(), nullptr) << "the input's passed array was kept";
  EXPECT_EQ(probe->GetReusedOutputBytes(), ProbeKeptBytes);
  ExpectSameProbe(probe->GetOutput(), FreshProbe(spline, second));

  // The caller holds the derivative array: it keeps its values, the rest is reused.
  vtkSmartPointer<vtkDataArray> heldDu = probe->GetOutput()->GetPointData()->GetArray("dFdu");
  auto snapshot = vtkSmartPointer<vtkPolyData>::New();
  snapshot->DeepCopy(vtkPolyData::SafeDownCast(probe->GetOutput()));
  auto third = Queries(ProbePoints, 3);
  probe->SetInputData(third);
  probe->Update();
  ExpectSameArray(heldDu, snapshot->GetPointData()->GetArray("dFdu"), "held dFdu");
  EXPECT_NE(probe->GetOutput()->GetPointData()->GetArray("dFdu"), heldDu.Get());
  EXPECT_EQ(probe->GetReusedOutputBytes(), ProbeKeptBytes - Bytes(heldDu));
  ExpectSameProbe(probe->GetOutput(), FreshProbe(spline, third));

  // Another count of queries, then positions only: new arrays, as a new probe's.
  auto fewer = Queries(ProbePoints - 1, 4);
  probe->SetInputData(fewer);
  probe->Update();
  EXPECT_EQ(probe->GetReusedOutputBytes(), 0u);
  ExpectSameProbe(probe->GetOutput(), FreshProbe(spline, fewer));
  probe->SetComputeDerivatives(false);
  probe->Update();
  EXPECT_EQ(probe->GetReusedOutputBytes(), 0u);
  EXPECT_EQ(probe->GetOutput()->GetPointData()->GetArray("dFdu"), nullptr);

  // Off: nothing is kept, for the same count either.
  probe->SetComputeDerivatives(true);
  probe->SetInputData(third);
  probe->Update();
  probe->Modified();
  probe->Update();
  ASSERT_EQ(probe->GetReusedOutputBytes(), ProbeKeptBytes); // on, as a control
  probe->SetReuseOutputArrays(false);
  probe->Update();
  probe->Modified();
  probe->Update();
  EXPECT_EQ(probe->GetReusedOutputBytes(), 0u);
  ExpectSameProbe(probe->GetOutput(), FreshProbe(spline, third));
}
