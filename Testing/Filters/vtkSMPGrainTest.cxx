// SPDX-License-Identifier: GPL-3.0-or-later
// The module's parallel loops (CTSplinesSMP.h; VTK 9.2's STDThread backend would start threads
// on every vtkSMPTools::For call it splits): small filter calls start no thread, large ones run
// on the module's pool, which starts threads only when its size changes, and results are
// bit-identical to the Sequential backend for any thread count. Threads are counted by
// interposing pthread_create in this executable.
#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "CTSplinesSMP.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSplineParameterProbe.h"

#include "vtkCellData.h"
#include "vtkIdList.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <dlfcn.h>
#include <pthread.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <cstdlib>
#include <numeric>
#include <random>
#include <string>
#include <thread>

namespace
{
std::atomic<long> ThreadsCreated{ 0 };
}

// Every thread of the process (std::thread included) starts here; libc's does the work.
extern "C" int pthread_create(
  pthread_t* thread, const pthread_attr_t* attr, void* (*start)(void*), void* arg)
{
  using Create = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);
  static const Create next = reinterpret_cast<Create>(dlsym(RTLD_NEXT, "pthread_create"));
  ThreadsCreated.fetch_add(1);
  return next(thread, attr, start, arg);
}

namespace
{
struct Outputs
{
  vtkSmartPointer<vtkDataSet> Spline, Tessellation, Probe;
  long SplineThreads, TessellationThreads, ProbeThreads; // threads started by each filter
};

// The module's thread count (CTSPLINES_NUM_THREADS); 0 unsets it: the module follows VTK.
void SetModuleThreads(int threads)
{
  if (threads > 0)
  {
    setenv("CTSPLINES_NUM_THREADS", std::to_string(threads).c_str(), 1);
  }
  else
  {
    unsetenv("CTSPLINES_NUM_THREADS");
  }
}

vtkSmartPointer<vtkPolyData> QueryPoints(vtkIdType n)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double u = U(rng);
    points->InsertNextPoint(u, U(rng), 0.0);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  return pd;
}

template <typename T>
vtkSmartPointer<vtkDataSet> Copy(T* output)
{
  vtkSmartPointer<vtkDataSet> copy = vtkSmartPointer<vtkDataSet>::Take(output->NewInstance());
  copy->DeepCopy(output);
  return copy;
}

// Spline filter, tessellator (level 4) and probe on a gridCells x gridCells grid (two
// triangles per cell) of Franke's function, under the active backend, each filter with the
// module's thread count of threads[k] (see SetModuleThreads).
Outputs RunFilters(int gridCells, vtkIdType queries, const std::array<int, 3>& threads)
{
  const ctk::ParameterMesh mesh = ctk::RegularGridMesh(gridCells, ctk::GridDiagonal::Alternating);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputData(ctsplines_test::MakeSampledPolyData(mesh, ctk::AnalyticSurface::Franke));
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputConnection(spline->GetOutputPort());
  tessellator->SetSubdivisionLevel(4);
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(QueryPoints(queries));
  probe->SetSourceConnection(spline->GetOutputPort());
  auto update = [](vtkAlgorithm* filter, int n) {
    SetModuleThreads(n);
    const long before = ThreadsCreated.load();
    filter->Update();
    return ThreadsCreated.load() - before;
  };
  const long splineThreads = update(spline, threads[0]);
  const long tessellationThreads = update(tessellator, threads[1]);
  const long probeThreads = update(probe, threads[2]);
  return { Copy(spline->GetOutput()), Copy(tessellator->GetOutput()), Copy(probe->GetOutput()),
    splineThreads, tessellationThreads, probeThreads };
}

void ExpectSameArrays(vtkFieldData* a, vtkFieldData* b, const std::string& what)
{
  ASSERT_EQ(a->GetNumberOfArrays(), b->GetNumberOfArrays()) << what;
  for (int k = 0; k < a->GetNumberOfArrays(); ++k)
  {
    vtkDataArray* x = a->GetArray(k);
    vtkDataArray* y = x ? b->GetArray(x->GetName()) : nullptr;
    if (!x)
    {
      continue;
    }
    ASSERT_NE(y, nullptr) << what << " " << x->GetName();
    ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues()) << what << " " << x->GetName();
    for (vtkIdType i = 0; i < x->GetNumberOfValues(); ++i)
    {
      const vtkIdType t = i / x->GetNumberOfComponents();
      const int c = static_cast<int>(i % x->GetNumberOfComponents());
      ASSERT_EQ(x->GetComponent(t, c), y->GetComponent(t, c))
        << what << " " << x->GetName() << " tuple " << t << " component " << c;
    }
  }
}

// Bit-identical: points, cells and every point and cell data array.
void ExpectIdentical(vtkDataSet* a, vtkDataSet* b, const std::string& what)
{
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints()) << what;
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3];
    a->GetPoint(p, x);
    b->GetPoint(p, y);
    ASSERT_TRUE(x[0] == y[0] && x[1] == y[1] && x[2] == y[2]) << what << " point " << p;
  }
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells()) << what;
  vtkNew<vtkIdList> ia, ib;
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(a->GetCellType(c), b->GetCellType(c)) << what << " cell " << c;
    a->GetCellPoints(c, ia);
    b->GetCellPoints(c, ib);
    ASSERT_EQ(ia->GetNumberOfIds(), ib->GetNumberOfIds()) << what << " cell " << c;
    for (vtkIdType k = 0; k < ia->GetNumberOfIds(); ++k)
    {
      ASSERT_EQ(ia->GetId(k), ib->GetId(k)) << what << " cell " << c;
    }
  }
  ExpectSameArrays(a->GetPointData(), b->GetPointData(), what + " point data");
  ExpectSameArrays(a->GetCellData(), b->GetCellData(), what + " cell data");
}

// Restores the backend and thread count of the process at the end of a test.
class SMPGrain : public ::testing::Test
{
protected:
  void SetUp() override { this->Backend = vtkSMPTools::GetBackend(); }
  void TearDown() override
  {
    vtkSMPTools::SetBackend(this->Backend.c_str());
    vtkSMPTools::Initialize(0);
    SetModuleThreads(0);
  }
  static void UseThreads(int n)
  {
    ASSERT_TRUE(vtkSMPTools::SetBackend("STDThread"));
    vtkSMPTools::Initialize(n);
  }
  std::string Backend;
};

TEST_F(SMPGrain, ThreadCountIsObserved)
{
  const long before = ThreadsCreated.load();
  std::thread([] {}).join();
  EXPECT_EQ(ThreadsCreated.load() - before, 1) << "pthread_create is not interposed";
}

TEST_F(SMPGrain, FollowsVTKUnlessSet)
{
  SetModuleThreads(0);
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  EXPECT_EQ(ctsplines::LoopThreads(), 1);
  UseThreads(2);
  EXPECT_EQ(ctsplines::LoopThreads(), vtkSMPTools::GetEstimatedNumberOfThreads());
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  SetModuleThreads(3);
  EXPECT_EQ(ctsplines::LoopThreads(), 3);
}

TEST_F(SMPGrain, SmallCallsStartNoThread)
{
  SetModuleThreads(0);
  UseThreads(2); // the module follows VTK's STDThread backend: 2 threads
  for (int run = 0; run < 3; ++run)
  {
    const Outputs out = RunFilters(5, 200, { 0, 0, 0 }); // 50 triangles, 150 cells, 200 queries
    EXPECT_EQ(out.Spline->GetNumberOfCells(), 150);
    EXPECT_EQ(out.SplineThreads, 0);
    EXPECT_EQ(out.TessellationThreads, 0);
    EXPECT_EQ(out.ProbeThreads, 0);
  }
}

TEST_F(SMPGrain, LargeCallsSplitAndMatchSequential)
{
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  const int grid = 40;              // 3,200 triangles, 9,600 Bézier cells
  const vtkIdType queries = 100000; // four locality windows
  const Outputs serial = RunFilters(grid, queries, { 0, 0, 0 });
  auto expectIdentical = [&serial](const Outputs& parallel, const std::string& on) {
    ExpectIdentical(serial.Spline, parallel.Spline, "spline" + on);
    ExpectIdentical(serial.Tessellation, parallel.Tessellation, "tessellation" + on);
    ExpectIdentical(serial.Probe, parallel.Probe, "probe" + on);
  };
  // The pool starts threads when its size changes, that is when a filter splits a loop with
  // another count than the previous one: every filter starts some.
  const Outputs mixed = RunFilters(grid, queries, { 2, 3, 4 });
  EXPECT_GT(mixed.SplineThreads, 0) << "the spline filter did not split";
  EXPECT_GT(mixed.TessellationThreads, 0) << "the tessellator did not split";
  EXPECT_GT(mixed.ProbeThreads, 0) << "the probe did not split";
  expectIdentical(mixed, " on 2, 3, 4 threads");
  // With one count, the pool's threads are started once and then reused.
  for (int threads : { 2, 3 })
  {
    for (int run = 0; run < 2; ++run)
    {
      const Outputs same = RunFilters(grid, queries, { threads, threads, threads });
      const std::string on =
        " on " + std::to_string(threads) + " threads, run " + std::to_string(run);
      if (run > 0)
      {
        EXPECT_EQ(same.SplineThreads + same.TessellationThreads + same.ProbeThreads, 0) << on;
      }
      expectIdentical(same, on);
    }
  }
}

} // namespace

namespace
{
// The spline filter's output with the module's thread count `threads`.
vtkSmartPointer<vtkDataSet> SplineOn(vtkPolyData* input, int threads, int construction)
{
  SetModuleThreads(threads);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputData(input);
  spline->SetConstruction(construction);
  spline->Update();
  return Copy(spline->GetOutput());
}
} // namespace

TEST_F(SMPGrain, SplineStagesMatchOnAnyNumberOfThreads)
{
  // Large enough for every stage to split at the copy grain (read, locality order, renumbering,
  // topology, edge order, validation, construction, cells), triangles in random order.
  ctk::ParameterMesh mesh = ctk::RegularGridMesh(260, ctk::GridDiagonal::Alternating);
  const vtkIdType nT = mesh.NumberOfTriangles();
  ASSERT_GT(nT, 2 * ctsplines::GrainForCopies);
  std::vector<vtkIdType> order(nT);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  const std::vector<ctk::Id> triangles = mesh.Triangles;
  for (vtkIdType t = 0; t < nT; ++t)
  {
    std::copy_n(&triangles[3 * order[t]], 3, &mesh.Triangles[3 * t]);
  }
  const vtkSmartPointer<vtkPolyData> input =
    ctsplines_test::MakeSampledPolyData(mesh, ctk::AnalyticSurface::Franke);
  for (int construction : { vtkCloughTocherSplineFilter::CTi, vtkCloughTocherSplineFilter::Quartic })
  {
    const vtkSmartPointer<vtkDataSet> serial = SplineOn(input, 1, construction);
    ASSERT_EQ(serial->GetNumberOfCells(), 3 * nT);
    for (int threads : { 2, 3 })
    {
      ExpectIdentical(serial, SplineOn(input, threads, construction),
        "construction " + std::to_string(construction) + " on " + std::to_string(threads) +
          " threads");
    }
  }
}

TEST_F(SMPGrain, ReadErrorsNameTheLowestCellOrPointOnAnyNumberOfThreads)
{
  // Reading the input splits at the copy grain: two bad cells (quads) or two bad values in
  // different chunks, the lower one is named on every thread count.
  const ctk::ParameterMesh mesh = ctk::RegularGridMesh(260, ctk::GridDiagonal::Alternating);
  const vtkIdType nT = mesh.NumberOfTriangles(), lowCell = 70001, highCell = 130003;
  ASSERT_GT(nT, highCell);
  const vtkSmartPointer<vtkPolyData> good =
    ctsplines_test::MakeSampledPolyData(mesh, ctk::AnalyticSurface::Franke);
  auto quads = vtkSmartPointer<vtkPolyData>::New();
  quads->ShallowCopy(good);
  vtkNew<vtkCellArray> cells;
  for (vtkIdType t = 0; t < nT; ++t)
  {
    const ctk::Id* p = &mesh.Triangles[3 * t];
    const vtkIdType quad[4] = { p[0], p[1], p[2], p[0] };
    cells->InsertNextCell(t == lowCell || t == highCell ? 4 : 3, quad);
  }
  quads->SetPolys(cells);
  const vtkIdType lowPoint = 30001, highPoint = 60001; // 3 values per point: 2 grains apart
  auto infinite = vtkSmartPointer<vtkPolyData>::New();
  infinite->DeepCopy(good);
  vtkDataArray* du = infinite->GetPointData()->GetArray("dFdu");
  ASSERT_LT(highPoint, du->GetNumberOfTuples());
  du->SetComponent(highPoint, 0, std::numeric_limits<double>::infinity());
  du->SetComponent(lowPoint, 2, std::numeric_limits<double>::infinity());
  const std::pair<vtkPolyData*, std::string> cases[] = {
    { quads, "cell " + std::to_string(lowCell) + " is a polygon with 4 points" },
    { infinite, "non-finite value (inf) at point " + std::to_string(lowPoint) },
  };
  for (const auto& [input, expected] : cases)
  {
    for (int threads : { 1, 2, 3 })
    {
      SetModuleThreads(threads);
      vtkNew<vtkCloughTocherSplineFilter> spline;
      int result = 1;
      const std::string errors = ctsplines_test::RunCapturingErrors(spline, input, result);
      EXPECT_EQ(result, 0);
      EXPECT_NE(errors.find(expected), std::string::npos)
        << threads << " threads: " << errors;
    }
  }
}
