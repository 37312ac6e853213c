// SPDX-License-Identifier: GPL-3.0-or-later
// The ranges the filters store in their output arrays (CTSplinesArrayRanges.h) are the ones VTK
// computes itself, and VTK serves them instead of computing them until an array is modified.
#include "CTSplinesArrayRanges.h"
#include "ErrorCapture.h"
#include "FilterTestUtilities.h"
#include "vtkApproximationErrorFilter.h"
#include "vtkBezierCurvatureFilter.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkReflectionLinesFilter.h"
#include "vtkSampledSurfaceSource.h"
#include "vtkSplineContinuityFilter.h"
#include "vtkSplineParameterProbe.h"

#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationInformationVectorKey.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnsignedLongLongArray.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
// The module's thread count for the scope of a test (CTSPLINES_NUM_THREADS).
struct ModuleThreads
{
  explicit ModuleThreads(int n) { setenv("CTSPLINES_NUM_THREADS", std::to_string(n).c_str(), 1); }
  ~ModuleThreads() { unsetenv("CTSPLINES_NUM_THREADS"); }
};

// The same values in a new array of the same type, without information: VTK computes its
// ranges when asked.
vtkSmartPointer<vtkDataArray> FreshCopy(vtkDataArray* a)
{
  auto copy = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(a->GetDataType()));
  copy->SetNumberOfComponents(a->GetNumberOfComponents());
  copy->SetNumberOfTuples(a->GetNumberOfTuples());
  std::memcpy(copy->GetVoidPointer(0), a->GetVoidPointer(0),
    static_cast<size_t>(a->GetNumberOfValues()) * a->GetDataTypeSize());
  return copy;
}

bool HasComponentRanges(vtkDataArray* a, vtkInformationInformationVectorKey* key)
{
  vtkInformationVector* v = a->GetInformation()->Get(key);
  if (!v || v->GetNumberOfInformationObjects() != a->GetNumberOfComponents())
  {
    return false;
  }
  for (int c = 0; c < a->GetNumberOfComponents(); ++c)
  {
    if (!v->GetInformationObject(c)->Has(vtkDataArray::COMPONENT_RANGE()))
    {
      return false;
    }
  }
  return true;
}

// a's ranges are cached (every kind CacheRanges stores, newer than the array; the L2 norm's
// finite range not by CacheRanges, unless VTK computed it since: `stored`) and equal to those VTK
// computes from the same values: each component's and the L2 norm's, plain and finite (-1 on one
// component is component 0).
void ExpectCachedVTKRanges(
  vtkDataArray* a, const std::string& what, bool norms = true, bool stored = true)
{
  vtkInformation* info = a->GetInformation();
  ASSERT_LE(a->GetMTime(), info->GetMTime()) << what;
  ASSERT_TRUE(HasComponentRanges(a, vtkDataArray::PER_COMPONENT())) << what;
  ASSERT_TRUE(HasComponentRanges(a, vtkDataArray::PER_FINITE_COMPONENT())) << what;
  const int nc = a->GetNumberOfComponents();
  EXPECT_EQ(info->Has(vtkDataArray::L2_NORM_RANGE()), nc > 1 && norms) << what;
  EXPECT_TRUE(!stored || !info->Has(vtkDataArray::L2_NORM_FINITE_RANGE())) << what;
  vtkSmartPointer<vtkDataArray> fresh = FreshCopy(a);
  for (int c = -1; c < nc; ++c)
  {
    double cached[2], computed[2], cachedFinite[2], computedFinite[2];
    a->GetRange(cached, c);
    fresh->GetRange(computed, c);
    a->GetFiniteRange(cachedFinite, c);
    fresh->GetFiniteRange(computedFinite, c);
    for (int k = 0; k < 2; ++k)
    {
      EXPECT_EQ(cached[k], computed[k]) << what << " component " << c;
      EXPECT_EQ(cachedFinite[k], computedFinite[k]) << what << " component " << c;
    }
  }
}

// Every data array of the output with cacheable values (finite, at most 32 components):
// points, point, cell and field data. Arrays passed through from an input checked before have
// their L2 norm's finite range computed by VTK then (stored = false).
void ExpectCachedVTKRanges(vtkDataSet* output, const std::string& what, bool stored = true)
{
  ASSERT_NE(output, nullptr) << what;
  std::vector<std::pair<std::string, vtkDataArray*>> arrays;
  if (vtkPointSet* ps = vtkPointSet::SafeDownCast(output))
  {
    ASSERT_NE(ps->GetPoints(), nullptr) << what;
    arrays.emplace_back("points", ps->GetPoints()->GetData());
  }
  for (vtkFieldData* fd : { static_cast<vtkFieldData*>(output->GetPointData()),
         static_cast<vtkFieldData*>(output->GetCellData()), output->GetFieldData() })
  {
    for (int i = 0; i < fd->GetNumberOfArrays(); ++i)
    {
      if (vtkDataArray* a = fd->GetArray(i))
      {
        arrays.emplace_back(a->GetName() ? a->GetName() : "(unnamed)", a);
      }
    }
  }
  int checked = 0;
  for (const auto& named : arrays)
  {
    vtkDataArray* a = named.second;
    bool finite = true;
    for (vtkIdType i = 0; finite && i < a->GetNumberOfValues(); ++i)
    {
      finite = std::isfinite(a->GetComponent(i / a->GetNumberOfComponents(),
        static_cast<int>(i % a->GetNumberOfComponents())));
    }
    if (finite && a->GetNumberOfTuples() > 0)
    {
      ExpectCachedVTKRanges(a, what + " " + named.first, true, stored);
      ++checked;
    }
  }
  EXPECT_GE(checked, 2) << what;
}

template <typename ArrayT>
vtkSmartPointer<ArrayT> RandomArray(vtkIdType tuples, int nc, double lo, double hi, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(lo, hi);
  auto a = vtkSmartPointer<ArrayT>::New();
  a->SetNumberOfComponents(nc);
  a->SetNumberOfTuples(tuples);
  for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
  {
    a->SetValue(i, static_cast<typename ArrayT::ValueType>(U(rng)));
  }
  return a;
}
} // namespace

// Types and component counts through every loop of the scan (SSE2 pairs, four tuples at a time,
// then a last pair, a last odd tuple or both; one component; many), on arrays split over threads
// and not.
TEST(CachedArrayRanges, AreVTKsOwnForEveryLoop)
{
  for (int threads : { 1, 3 })
  {
    ModuleThreads scope(threads);
    for (vtkIdType tuples : { vtkIdType(1), vtkIdType(2), vtkIdType(3), vtkIdType(4),
           vtkIdType(5), vtkIdType(6), vtkIdType(7), vtkIdType(300001) })
    {
      const std::string size = std::to_string(tuples) + " tuples, " +
        std::to_string(threads) + " threads: ";
      for (int nc : { 1, 2, 3, 5, 18 })
      {
        auto a = RandomArray<vtkDoubleArray>(tuples, nc, -3.0, 7.0, 11 + nc);
        ASSERT_TRUE(ctsplines::CacheRanges(a)) << size << nc;
        ExpectCachedVTKRanges(a, size + "double x " + std::to_string(nc));
      }
      auto f = RandomArray<vtkFloatArray>(tuples, 3, -2.0, 2.0, 5);
      ASSERT_TRUE(ctsplines::CacheRanges(f));
      ExpectCachedVTKRanges(f, size + "float x 3");
      auto i = RandomArray<vtkIntArray>(tuples, 1, -1e6, 1e6, 6);
      ASSERT_TRUE(ctsplines::CacheRanges(i));
      ExpectCachedVTKRanges(i, size + "int");
      auto s = RandomArray<vtkSignedCharArray>(tuples, 1, -100, 100, 7);
      ASSERT_TRUE(ctsplines::CacheRanges(s));
      ExpectCachedVTKRanges(s, size + "signed char");
      auto id = RandomArray<vtkIdTypeArray>(tuples, 2, -1e17, 1e17, 8); // beyond 2^53
      ASSERT_TRUE(ctsplines::CacheRanges(id));
      ExpectCachedVTKRanges(id, size + "id x 2");
      auto u = RandomArray<vtkUnsignedLongLongArray>(tuples, 1, 0, 1e15, 9);
      ASSERT_TRUE(ctsplines::CacheRanges(u));
      ExpectCachedVTKRanges(u, size + "unsigned long long");
    }
  }
}

// The extremes are found wherever they are: first, last, in either set of SSE2 pairs (tuples
// 4 k to 4 k + 1 and 4 k + 2 to 4 k + 3), or in a tuple split across a pair's registers.
TEST(CachedArrayRanges, FindExtremesAtEveryPosition)
{
  for (int nc : { 2, 3 })
  {
    for (vtkIdType at : { vtkIdType(0), vtkIdType(1), vtkIdType(2), vtkIdType(3), vtkIdType(6),
           vtkIdType(4997), vtkIdType(4998), vtkIdType(4999) })
    {
      for (int c = 0; c < nc; ++c)
      {
        auto a = RandomArray<vtkDoubleArray>(5000, nc, -1.0, 1.0, 3);
        a->SetComponent(at, c, -50.0 - c);
        a->SetComponent(4999 - at, c, 60.0 + c);
        ASSERT_TRUE(ctsplines::CacheRanges(a));
        double r[2];
        a->GetRange(r, c);
        EXPECT_EQ(r[0], -50.0 - c) << nc << " components, tuple " << at << ", component " << c;
        EXPECT_EQ(r[1], 60.0 + c) << nc << " components, tuple " << at << ", component " << c;
        ExpectCachedVTKRanges(a, "extremes");
      }
    }
  }
}

// VTK serves the stored ranges (a value changed behind its back is not seen) until the array is
// modified; then it computes them again.
TEST(CachedArrayRanges, AreServedUntilTheArrayIsModified)
{
  auto a = RandomArray<vtkDoubleArray>(100000, 3, 0.0, 1.0, 4);
  ASSERT_TRUE(ctsplines::CacheRanges(a));
  double before[2];
  a->GetRange(before, 1);
  a->GetPointer(0)[3 * 500 + 1] = 42.0; // no Modified()
  double served[2], norm[2];
  a->GetRange(served, 1);
  EXPECT_EQ(served[0], before[0]);
  EXPECT_EQ(served[1], before[1]);
  a->GetRange(norm, -1);
  EXPECT_LT(norm[1], 2.0);
  a->Modified();
  double computed[2];
  a->GetRange(computed, 1);
  EXPECT_EQ(computed[1], 42.0);
  a->GetRange(norm, -1);
  EXPECT_GT(norm[1], 42.0);
  // Stored again from the new values.
  ASSERT_TRUE(ctsplines::CacheRanges(a));
  ExpectCachedVTKRanges(a, "after Modified");
}

// FiniteRanges serves the ranges CacheRanges stored, which bound every value, until the array
// is modified; never ranges VTK stored itself (they skip NaN), nor a copy's.
TEST(CachedArrayRanges, FiniteRangesHoldUntilTheArrayIsModified)
{
  double range[8];
  EXPECT_FALSE(ctsplines::FiniteRanges(nullptr, range));
  auto a = RandomArray<vtkDoubleArray>(100000, 3, -2.0, 5.0, 9);
  double vtkRange[2];
  a->GetRange(vtkRange, 0); // VTK's own cache
  EXPECT_FALSE(ctsplines::FiniteRanges(a, range));
  a->Modified();
  ASSERT_TRUE(ctsplines::CacheRanges(a));
  ASSERT_TRUE(ctsplines::FiniteRanges(a, range));
  for (int c = 0; c < 3; ++c)
  {
    a->GetRange(vtkRange, c);
    EXPECT_EQ(range[2 * c], vtkRange[0]) << c;
    EXPECT_EQ(range[2 * c + 1], vtkRange[1]) << c;
  }
  vtkNew<vtkDoubleArray> copy;
  copy->DeepCopy(a);
  EXPECT_FALSE(ctsplines::FiniteRanges(copy, range)) << "a deep copy";
  vtkNew<vtkDoubleArray> view;
  view->ShallowCopy(a);
  EXPECT_FALSE(ctsplines::FiniteRanges(view, range)) << "a shallow copy";

  // A NaN, marked modified, then VTK's ranges (which skip it) stored after the old ones.
  a->SetComponent(500, 1, std::numeric_limits<double>::quiet_NaN());
  a->Modified();
  EXPECT_FALSE(ctsplines::FiniteRanges(a, range));
  for (int c = 0; c < 3; ++c)
  {
    a->GetRange(vtkRange, c);
    a->GetFiniteRange(vtkRange, c);
  }
  EXPECT_FALSE(ctsplines::FiniteRanges(a, range));
  EXPECT_FALSE(ctsplines::CacheRanges(a));
  EXPECT_FALSE(ctsplines::FiniteRanges(a, range));
  // Finite again: stored and served again.
  a->SetComponent(500, 1, 0.25);
  a->Modified();
  ASSERT_TRUE(ctsplines::CacheRanges(a));
  EXPECT_TRUE(ctsplines::FiniteRanges(a, range));

  // Values copied in without Modified() (DeepCopy into an array of the same size does not call
  // it): the stamp is not copied with the information, so it cannot match the MTime it keeps.
  vtkNew<vtkDoubleArray> backup;
  backup->DeepCopy(a);
  backup->SetComponent(7, 2, std::numeric_limits<double>::quiet_NaN());
  backup->Modified();
  a->DeepCopy(backup);
  for (int c = 0; c < 3; ++c)
  {
    a->GetRange(vtkRange, c); // VTK's ranges, which skip the NaN
    a->GetFiniteRange(vtkRange, c);
  }
  EXPECT_FALSE(ctsplines::FiniteRanges(a, range)) << "values deep-copied in";
  // Another array's storage taken in place: another data pointer.
  a->SetComponent(7, 2, 0.5);
  a->Modified();
  ASSERT_TRUE(ctsplines::CacheRanges(a));
  ASSERT_TRUE(ctsplines::FiniteRanges(a, range));
  a->ShallowCopy(backup);
  for (int c = 0; c < 3; ++c)
  {
    a->GetRange(vtkRange, c);
    a->GetFiniteRange(vtkRange, c);
  }
  EXPECT_FALSE(ctsplines::FiniteRanges(a, range)) << "storage shallow-copied in";
}

// The stamp is this module's own: files written from an output must not carry it, or every
// reader without the module warns that it cannot locate the key (ParaView without the plugin).
TEST(CachedArrayRanges, StampIsLeftOutOfWrittenFiles)
{
  vtkNew<vtkPoints> points;
  points->SetData(RandomArray<vtkDoubleArray>(1000, 3, -2.0, 5.0, 11));
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  auto uv = RandomArray<vtkDoubleArray>(1000, 2, 0.0, 1.0, 12);
  uv->SetName("UV");
  poly->GetPointData()->AddArray(uv);
  ctsplines::CacheRanges(poly.GetPointer());
  double range[6];
  ASSERT_TRUE(ctsplines::FiniteRanges(points->GetData(), range));
  ASSERT_TRUE(ctsplines::FiniteRanges(uv, range));

  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(poly);
  writer->SetDataModeToAscii();
  writer->WriteToOutputStringOn();
  ASSERT_EQ(writer->Write(), 1);
  const std::string file = writer->GetOutputString();
  EXPECT_EQ(file.find("FINITE_STAMP"), std::string::npos);
  EXPECT_NE(file.find("L2_NORM_RANGE"), std::string::npos) << "VTK's own range keys are written";

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->ReadFromInputStringOn();
  reader->SetInputString(file);
  auto warnings = vtkSmartPointer<ctsplines_test::ErrorCapture>::New();
  reader->AddObserver(vtkCommand::WarningEvent, warnings);
  reader->Update();
  EXPECT_EQ(warnings->Count, 0) << warnings->Message;
  vtkDataArray* read = reader->GetOutput()->GetPoints()->GetData();
  ASSERT_EQ(read->GetNumberOfTuples(), 1000);
  EXPECT_FALSE(ctsplines::FiniteRanges(read, range)) << "a stamp read back from a file";
}

// Values that are not finite make VTK's plain and finite ranges differ: nothing is stored, and
// VTK computes both itself. Empty arrays store nothing either.
TEST(CachedArrayRanges, LeaveNonFiniteAndEmptyArraysToVTK)
{
  for (double bad : { std::numeric_limits<double>::quiet_NaN(),
         std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity() })
  {
    for (vtkIdType at : { vtkIdType(0), vtkIdType(77), vtkIdType(99999) })
    {
      for (int nc : { 1, 2, 3, 4 })
      {
        auto a = RandomArray<vtkDoubleArray>(100000, nc, 0.0, 1.0, 2);
        a->SetComponent(at, nc - 1, bad);
        EXPECT_FALSE(ctsplines::CacheRanges(a)) << bad << " at " << at << ", " << nc;
        EXPECT_FALSE(a->GetInformation()->Has(vtkDataArray::PER_COMPONENT()));
        EXPECT_FALSE(a->GetInformation()->Has(vtkDataArray::L2_NORM_RANGE()));
      }
    }
  }
  vtkNew<vtkDoubleArray> empty;
  empty->SetNumberOfComponents(3);
  EXPECT_FALSE(ctsplines::CacheRanges(empty));
  EXPECT_FALSE(ctsplines::CacheRanges(static_cast<vtkDataArray*>(nullptr)));
}

// A squared norm that overflows, or reaches VTK's starting value 1e299, leaves the norm's range
// to VTK (its finite range skips such tuples); the components' ranges are stored.
TEST(CachedArrayRanges, LeaveOverflowingNormsToVTK)
{
  for (double big : { 1e200, 1e150 })
  {
    vtkNew<vtkDoubleArray> a;
    a->SetNumberOfComponents(3);
    a->InsertNextTuple3(1.0, 0.0, 0.0);
    a->InsertNextTuple3(big, 0.0, 0.0);
    ASSERT_TRUE(ctsplines::CacheRanges(a)) << big;
    EXPECT_FALSE(a->GetInformation()->Has(vtkDataArray::L2_NORM_RANGE())) << big;
    ExpectCachedVTKRanges(a, "norm of " + std::to_string(big), false);
  }
}

// Values beyond VTK's starting values (1e38 for floats, 1e299 for doubles), from which its ranges
// start, would not be VTK's ranges: nothing is stored.
TEST(CachedArrayRanges, LeaveValuesBeyondVTKsStartToVTK)
{
  vtkNew<vtkFloatArray> f;
  f->InsertNextValue(2e38f);
  f->InsertNextValue(3e38f);
  EXPECT_FALSE(ctsplines::CacheRanges(f));
  vtkNew<vtkDoubleArray> d;
  d->InsertNextValue(-2e299);
  d->InsertNextValue(1.0);
  EXPECT_FALSE(ctsplines::CacheRanges(d));
  d->SetValue(0, -0.9e299);
  d->Modified();
  EXPECT_TRUE(ctsplines::CacheRanges(d));
  ExpectCachedVTKRanges(d, "just below VTK's start");
}

// A zero extreme is stored as +0 wherever the zeros of either sign are, on any thread count
// (chunks of odd length included).
TEST(CachedArrayRanges, ZeroExtremesDoNotDependOnTheThreads)
{
  const vtkIdType n = 48 * 65537 + 3; // 3 threads: chunks of 65,537 tuples, starting at odd ones
  for (int nc : { 1, 2, 3 })
  {
    for (vtkIdType negativeAt : { vtkIdType(0), vtkIdType(65537), n - 1 })
    {
      auto a = RandomArray<vtkDoubleArray>(n, nc, 0.5, 1.0, 12);
      auto b = RandomArray<vtkDoubleArray>(n, nc, -1.0, -0.5, 13);
      for (int c = 0; c < nc; ++c)
      {
        for (vtkIdType at : { vtkIdType(1), vtkIdType(70001), n - 2 })
        {
          a->SetComponent(at, c, 0.0);
          b->SetComponent(at, c, 0.0);
        }
        a->SetComponent(negativeAt, c, -0.0);
        b->SetComponent(negativeAt, c, -0.0);
      }
      for (int threads : { 1, 2, 3 })
      {
        ModuleThreads scope(threads);
        a->Modified();
        b->Modified();
        ASSERT_TRUE(ctsplines::CacheRanges(a));
        ASSERT_TRUE(ctsplines::CacheRanges(b));
        for (int c = 0; c < nc; ++c)
        {
          const std::string what = std::to_string(nc) + " components, -0 at " +
            std::to_string(negativeAt) + ", " + std::to_string(threads) + " threads";
          double ra[2], rb[2];
          a->GetRange(ra, c);
          b->GetRange(rb, c);
          EXPECT_TRUE(ra[0] == 0.0 && !std::signbit(ra[0])) << what;
          EXPECT_TRUE(rb[1] == 0.0 && !std::signbit(rb[1])) << what;
        }
      }
    }
  }
}

// The data sets of a composite output, each as a data set's (its one-value field arrays too, as
// a CAD face's), and the composite's own field data.
TEST(CachedArrayRanges, CoverEveryBlockOfACompositeOutput)
{
  vtkNew<vtkMultiBlockDataSet> blocks;
  for (unsigned int k = 0; k < 2; ++k)
  {
    vtkNew<vtkPolyData> pd;
    vtkNew<vtkPoints> points;
    points->SetData(RandomArray<vtkDoubleArray>(100 + k, 3, -1.0, 1.0, 20 + k));
    pd->SetPoints(points);
    auto values = RandomArray<vtkDoubleArray>(100 + k, 2, 0.0, 5.0, 30 + k);
    values->SetName("values");
    pd->GetPointData()->AddArray(values);
    auto faceValue = RandomArray<vtkIdTypeArray>(1, 1, 0.0, 100.0, 40 + k);
    faceValue->SetName("face value");
    pd->GetFieldData()->AddArray(faceValue);
    blocks->SetBlock(k, pd);
  }
  auto total = RandomArray<vtkDoubleArray>(1, 1, -1.0, 1.0, 50);
  blocks->GetFieldData()->AddArray(total);
  ctsplines::CacheRanges(blocks.Get());
  for (unsigned int k = 0; k < 2; ++k)
  {
    vtkPolyData* pd = vtkPolyData::SafeDownCast(blocks->GetBlock(k));
    ExpectCachedVTKRanges(pd, "block " + std::to_string(k));
    ExpectCachedVTKRanges(pd->GetFieldData()->GetArray("face value"), "field data");
  }
  ExpectCachedVTKRanges(total, "the composite's field data");
}

// Every filter's output: the source, the spline, its tessellation, curvature, reflection lines,
// continuity, approximation error and a probe.
TEST(CachedArrayRanges, EveryFilterStoresVTKsOwnRanges)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetDomainToRandomDelaunay();
  source->SetResolution(600);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputConnection(spline->GetOutputPort());
  tessellator->SetSubdivisionLevel(3);
  vtkNew<vtkBezierCurvatureFilter> curvature;
  curvature->SetInputConnection(spline->GetOutputPort());
  vtkNew<vtkReflectionLinesFilter> reflection;
  reflection->SetInputConnection(tessellator->GetOutputPort());
  vtkNew<vtkSplineContinuityFilter> continuity;
  continuity->SetInputConnection(spline->GetOutputPort());
  vtkNew<vtkApproximationErrorFilter> error;
  error->SetInputConnection(spline->GetOutputPort());
  error->SetReferenceConnection(source->GetOutputPort());
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputConnection(source->GetOutputPort());
  probe->SetSourceConnection(spline->GetOutputPort());
  const std::vector<std::pair<std::string, vtkAlgorithm*>> filters = { { "source", source },
    { "spline", spline }, { "tessellator", tessellator }, { "curvature", curvature },
    { "reflection lines", reflection }, { "continuity", continuity }, { "error", error },
    { "probe", probe } };
  for (const auto& f : filters)
  {
    f.second->Update();
    ExpectCachedVTKRanges(
      vtkDataSet::SafeDownCast(f.second->GetOutputDataObject(0)), f.first, f.first == "source");
  }
}

// The probe's output arrays (points, derivatives, normals, ids and the mask) carry VTK's own
// ranges with queries inside and outside the spline (ids -1, mask 0, zero derivatives), with
// and without derivatives, on one thread and on several.
TEST(CachedArrayRanges, ProbeStoresVTKsRangesInsideAndOutside)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetDomainToRandomDelaunay();
  source->SetResolution(40);
  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  std::mt19937 rng(7); // the source is over the unit square: 56 % of these queries lie outside
  std::uniform_real_distribution<double> U(-0.25, 1.25);
  vtkNew<vtkPoints> points;
  const vtkIdType n = 100000; // several of the module's chunks of 2^16 queries
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->SetPoint(i, U(rng), U(rng), 0.0);
  }
  vtkNew<vtkPolyData> queries;
  queries->SetPoints(points);
  for (int threads : { 1, 3 })
  {
    ModuleThreads scope(threads);
    for (bool derivatives : { true, false })
    {
      vtkNew<vtkSplineParameterProbe> probe;
      probe->SetInputData(queries);
      probe->SetSourceConnection(spline->GetOutputPort());
      probe->SetComputeDerivatives(derivatives);
      probe->Update();
      const std::string what = std::to_string(threads) + " thread(s), derivatives " +
        std::to_string(derivatives);
      vtkDataSet* out = probe->GetOutput();
      vtkDataArray* mask = out->GetPointData()->GetArray("vtkValidPointMask");
      ASSERT_NE(mask, nullptr) << what;
      double maskRange[2];
      mask->GetRange(maskRange);
      ASSERT_EQ(maskRange[0], 0.0) << what << ": some queries outside";
      ASSERT_EQ(maskRange[1], 1.0) << what << ": some queries inside";
      EXPECT_EQ(out->GetPointData()->GetArray("dFdu") != nullptr, derivatives) << what;
      ExpectCachedVTKRanges(out, what);
    }
  }
}

// The spline filter stores the ranges its kernel scanned while writing the points (the
// one-sided rules in their main pass, the edge-based ones in their last; in either output
// order; with ghost cells, those of its blocks of points that the kept cells use whole, the
// other blocks scanned again), and those of the cell ids it wrote, or scans them as every filter
// does (IM steps, Kashyap, Quartic): VTK's ranges in every case, also when it runs again into its
// previous output's arrays (ReuseOutputArrays).
TEST(CachedArrayRanges, SplineFilterStoresVTKsRangesForEveryRoute)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetDomainToRandomDelaunay();
  source->SetResolution(3000);
  source->Update();
  vtkNew<vtkPolyData> withGhosts;
  withGhosts->DeepCopy(source->GetOutput());
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  for (vtkIdType t = 0; t < withGhosts->GetNumberOfCells(); ++t)
  {
    ghosts->InsertNextValue(t % 7 == 3 ? vtkDataSetAttributes::DUPLICATECELL : 0);
  }
  withGhosts->GetCellData()->AddArray(ghosts);
  // Ghosts in a band along two sides of the domain, as a piece's: the points only they use,
  // which the output drops, hold the largest x and the smallest y, and most blocks of points
  // have no such point (the kernel's ranges of those blocks are stored, the others scanned).
  vtkNew<vtkPolyData> withBand;
  withBand->DeepCopy(source->GetOutput());
  double bounds[6];
  withBand->GetBounds(bounds);
  vtkNew<vtkUnsignedCharArray> band;
  band->SetName(vtkDataSetAttributes::GhostArrayName());
  for (vtkIdType t = 0; t < withBand->GetNumberOfCells(); ++t)
  {
    double box[6];
    withBand->GetCellBounds(t, box);
    const bool ghost = box[1] > bounds[1] - 0.1 * (bounds[1] - bounds[0]) ||
      box[2] < bounds[2] + 0.1 * (bounds[3] - bounds[2]);
    band->InsertNextValue(ghost ? vtkDataSetAttributes::DUPLICATECELL : 0);
  }
  withBand->GetCellData()->AddArray(band);
  using F = vtkCloughTocherSplineFilter;
  struct Route
  {
    std::string Name;
    int Construction, Iterations, Order;
    vtkPolyData* Input;
  };
  vtkPolyData* plain = source->GetOutput();
  const std::vector<Route> routes = { { "CTi", F::CTi, 0, F::LocalityOrder, plain },
    { "CTo", F::CTo, 0, F::LocalityOrder, plain }, { "Fa", F::Fa, 0, F::LocalityOrder, plain },
    { "MGo", F::MGo, 0, F::LocalityOrder, plain }, { "MGi", F::MGi, 0, F::LocalityOrder, plain },
    { "FO", F::FO, 0, F::LocalityOrder, plain }, { "Ka", F::Ka, 0, F::LocalityOrder, plain },
    { "KaG", F::KaG, 0, F::LocalityOrder, plain },
    { "CTi, IM", F::CTi, 2, F::LocalityOrder, plain },
    { "Kashyap", F::Kashyap, 1, F::LocalityOrder, plain },
    { "Quartic", F::Quartic, 0, F::LocalityOrder, plain },
    { "CTi, input order", F::CTi, 0, F::InputOrder, plain },
    { "CTi, ghosts", F::CTi, 0, F::LocalityOrder, withGhosts },
    { "CTi, ghosts in a band", F::CTi, 0, F::LocalityOrder, withBand },
    { "Quartic, ghosts in a band", F::Quartic, 0, F::LocalityOrder, withBand } };
  for (const Route& route : routes)
  {
    vtkNew<F> spline;
    spline->SetInputData(route.Input);
    spline->SetConstruction(route.Construction);
    spline->SetIterations(route.Iterations);
    spline->SetOutputOrder(route.Order);
    for (int run = 0; run < 2; ++run)
    {
      spline->Modified();
      spline->Update();
      const std::string what = route.Name + (run ? ", run again" : "");
      vtkUnstructuredGrid* out = spline->GetOutput();
      ASSERT_GT(out->GetNumberOfCells(), 0) << what;
      ExpectCachedVTKRanges(out, what);
      if (route.Input == withBand.GetPointer()) // the dropped points held the input's extremes
      {
        double xMax = -VTK_DOUBLE_MAX, yMin = VTK_DOUBLE_MAX, p[3];
        for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
        {
          out->GetPoint(i, p);
          xMax = std::max(xMax, p[0]);
          yMin = std::min(yMin, p[1]);
        }
        EXPECT_LT(xMax, bounds[1] - 0.05 * (bounds[1] - bounds[0])) << what;
        EXPECT_GT(yMin, bounds[2] + 0.05 * (bounds[3] - bounds[2])) << what;
      }
      double range[6];
      EXPECT_TRUE(ctsplines::FiniteRanges(out->GetPoints()->GetData(), range)) << what;
      // The cubic constructions write their previous points again; the quartic's builds a
      // cubic spline first.
      EXPECT_EQ(spline->GetReusedOutputBytes() > 0, run == 1 && route.Construction != F::Quartic)
        << what;
    }
  }
}
