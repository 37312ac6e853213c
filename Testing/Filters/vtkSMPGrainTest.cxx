// SPDX-License-Identifier: GPL-3.0-or-later
// The module's parallel loops (vtkCTSplinesThreads; VTK 9.2's STDThread backend would start
// threads on every vtkSMPTools::For call it splits): small filter calls split nothing and start
// no thread, large ones split and start no thread once the pool runs, and results are
// bit-identical to the Sequential backend for any thread count. Threads are counted by
// interposing pthread_create in this executable.
#include "FilterTestUtilities.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCTSplinesThreads.h"
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

#include <atomic>
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
  struct Counts
  {
    long Threads;    // threads started
    vtkIdType Loops; // loops split over the pool
  } SplineCounts, TessellationCounts, ProbeCounts;
};

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
// triangles per cell) of Franke's function, under the active backend.
Outputs RunFilters(int gridCells, vtkIdType queries)
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
  Outputs::Counts before{ ThreadsCreated.load(), vtkCTSplinesThreads::GetNumberOfParallelLoops() };
  auto update = [&before](vtkAlgorithm* filter) {
    filter->Update();
    const Outputs::Counts now{ ThreadsCreated.load(),
      vtkCTSplinesThreads::GetNumberOfParallelLoops() };
    const Outputs::Counts delta{ now.Threads - before.Threads, now.Loops - before.Loops };
    before = now;
    return delta;
  };
  const Outputs::Counts splineCounts = update(spline);
  const Outputs::Counts tessellationCounts = update(tessellator);
  const Outputs::Counts probeCounts = update(probe);
  return { Copy(spline->GetOutput()), Copy(tessellator->GetOutput()), Copy(probe->GetOutput()),
    splineCounts, tessellationCounts, probeCounts };
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
    vtkCTSplinesThreads::SetNumberOfThreads(0);
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
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  EXPECT_EQ(vtkCTSplinesThreads::GetNumberOfThreads(), 1);
  UseThreads(2);
  EXPECT_EQ(vtkCTSplinesThreads::GetNumberOfThreads(), vtkSMPTools::GetEstimatedNumberOfThreads());
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  vtkCTSplinesThreads::SetNumberOfThreads(3);
  EXPECT_EQ(vtkCTSplinesThreads::GetNumberOfThreads(), 3);
  vtkCTSplinesThreads::SetNumberOfThreads(0);
  EXPECT_EQ(vtkCTSplinesThreads::GetNumberOfThreads(), 1);
}

TEST_F(SMPGrain, SmallCallsStartNoThread)
{
  UseThreads(2);
  ASSERT_EQ(vtkCTSplinesThreads::GetNumberOfThreads(), 2);
  for (int run = 0; run < 3; ++run)
  {
    const Outputs out = RunFilters(5, 200); // 50 triangles, 150 Bézier cells, 200 queries
    EXPECT_EQ(out.Spline->GetNumberOfCells(), 150);
    for (const Outputs::Counts& c : { out.SplineCounts, out.TessellationCounts, out.ProbeCounts })
    {
      EXPECT_EQ(c.Threads, 0);
      EXPECT_EQ(c.Loops, 0);
    }
  }
}

TEST_F(SMPGrain, LargeCallsSplitAndMatchSequential)
{
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  const int grid = 40;              // 3,200 triangles, 9,600 Bézier cells
  const vtkIdType queries = 100000; // four locality windows
  const Outputs serial = RunFilters(grid, queries);
  EXPECT_EQ(
    serial.SplineCounts.Loops + serial.TessellationCounts.Loops + serial.ProbeCounts.Loops, 0);
  for (int threads : { 2, 3, 4 }) // other chunk boundaries
  {
    vtkCTSplinesThreads::SetNumberOfThreads(threads);
    for (int run = 0; run < 2; ++run)
    {
      const Outputs parallel = RunFilters(grid, queries);
      const std::string on =
        " on " + std::to_string(threads) + " threads, run " + std::to_string(run);
      EXPECT_GT(parallel.SplineCounts.Loops, 0) << "the spline filter did not split" << on;
      EXPECT_GT(parallel.TessellationCounts.Loops, 0) << "the tessellator did not split" << on;
      EXPECT_GT(parallel.ProbeCounts.Loops, 0) << "the probe did not split" << on;
      if (run > 0) // the pool's threads were started by the first run, and are reused
      {
        EXPECT_EQ(parallel.SplineCounts.Threads + parallel.TessellationCounts.Threads +
            parallel.ProbeCounts.Threads,
          0)
          << on;
      }
      ExpectIdentical(serial.Spline, parallel.Spline, "spline" + on);
      ExpectIdentical(serial.Tessellation, parallel.Tessellation, "tessellation" + on);
      ExpectIdentical(serial.Probe, parallel.Probe, "probe" + on);
    }
  }
}

} // namespace
