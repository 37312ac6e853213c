// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target of the filters (Filters/vtk*.h): bytes -> a vtkPolyData (mixed cell types,
// point and cell arrays present or not, of any type, component count and tuple count, with any
// values) and the Bézier grid the spline filter makes of it, intact or damaged (short arrays,
// cells of other types or point counts, fuzzed points, ids and weights), through one filter of
// the module. Returning 0 with an error is a valid answer; a crash, a sanitizer report, a hang,
// success with non-finite points (for finite input) or ids out of range, or a spline filter,
// tessellator or probe that, run on other inputs of the same sizes first (so that it writes into
// that output's arrays), answers otherwise than a new one (RunRecycled) is a finding.
//
// Input layout (make_seed_corpus.py writes it; values as in FuzzInput.h):
//   filter (byte % 8: spline, tessellator, probe, curvature, continuity, reflection lines,
//   approximation error, sampled source), input mode (% 3: the spline filter's output, the same
//   damaged, the polydata itself), construction (% 10), split point (% 3), boundary mode (% 4),
//   iterations (% 3), subdivision level (1 + % 6), flags (bit 0 Bézier extraction, 1 boundary
//   curve points, 2 unstructured-grid input, 3 merge points / relative chordal tolerance,
//   4 match coincident edges, 5 mesh distance / adaptive tessellation, 6 float points, 7 split
//   sharp edges), #P (% 64), #C (% 96),
//   points (3 #P values), #C cells (type byte: % 8 < 4 triangle, 4 vertex, 5 line, 6 quad,
//   7 polygon of 3 + type / 8 % 6 points; then point ids, byte % #P),
//   arrays UV, dFdu, dFdv (point data), EdgeGradients, BoundaryCurvePoints, GlobalIds,
//   vtkGhostType (cell data), each: present (byte & 1), components (max(1, byte % 24)),
//   tuple count delta (byte - 8), type (byte % 5: double, float, int, id, unsigned char), then
//   its values when present,
//   12 parameter values (probe points, reflection setup, affine map, tessellator angles and
//   tolerances, curvature percentile),
//   damage operations (pairs of bytes) up to the end, in mode 1.
#include "FuzzVTK.h"

#include "CTSplinesRecycledArrays.h"
#include "OutputBits.h"
#include "vtkApproximationErrorFilter.h"
#include "vtkBezierCurvatureFilter.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkReflectionLinesFilter.h"
#include "vtkSampledSurfaceSource.h"
#include "vtkSplineContinuityFilter.h"
#include "vtkSplineParameterProbe.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <array>
#include <vector>

namespace
{
using namespace ctsplines_fuzz;

struct Options
{
  int Filter, Mode, Construction, SplitPoint, BoundaryMode, Iterations, Level;
  std::uint8_t Flags;
  bool Flag(int bit) const { return (this->Flags >> bit) & 1; }
};

vtkSmartPointer<vtkDataArray> NewArray(int kind)
{
  switch (kind)
  {
    case 0: return vtkSmartPointer<vtkDoubleArray>::New();
    case 1: return vtkSmartPointer<vtkFloatArray>::New();
    case 2: return vtkSmartPointer<vtkIntArray>::New();
    case 3: return vtkSmartPointer<vtkIdTypeArray>::New();
    default: return vtkSmartPointer<vtkUnsignedCharArray>::New();
  }
}

/// One array as described in the layout, or nullptr when absent.
vtkSmartPointer<vtkDataArray> ReadArray(FuzzInput& in, const char* name, vtkIdType expected)
{
  const bool present = in.Byte() & 1;
  const int components = std::max(1, in.Choice(24));
  const vtkIdType tuples = std::max<vtkIdType>(0, expected + in.Byte() - 8);
  const int kind = in.Choice(5);
  if (!present)
  {
    return nullptr;
  }
  auto array = NewArray(kind);
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  for (vtkIdType i = 0; i < tuples * components; ++i)
  {
    const double x = in.Value();
    // Integer arrays get a representable value (the conversion of NaN or 1e300 is UB of the
    // fuzzer's making, not the filter's).
    const bool integer = kind >= 2;
    const double low = kind == 4 ? 0.0 : -2e9, high = kind == 4 ? 255.0 : 2e9;
    array->SetComponent(i / components, static_cast<int>(i % components),
      integer ? (std::isfinite(x) ? std::max(low, std::min(high, x)) : 0.0) : x);
  }
  return array;
}

vtkSmartPointer<vtkPolyData> ReadPolyData(FuzzInput& in, const Options& opt)
{
  const vtkIdType np = in.Choice(64);
  const vtkIdType nc = in.Choice(96);
  vtkNew<vtkPoints> points;
  points->SetDataType(opt.Flag(6) ? VTK_FLOAT : VTK_DOUBLE);
  points->SetNumberOfPoints(np);
  for (vtkIdType p = 0; p < np; ++p)
  {
    const double x = in.Value(), y = in.Value(), z = in.Value();
    points->SetPoint(p, x, y, z);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  vtkNew<vtkCellArray> verts, lines, polys;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const std::uint8_t type = in.Byte();
    const int kind = type % 8;
    const int n = kind < 4 ? 3 : kind == 4 ? 1 : kind == 5 ? 2 : kind == 6 ? 4 : 3 + type / 8 % 6;
    std::vector<vtkIdType> ids(n);
    for (vtkIdType& id : ids)
    {
      id = np > 0 ? in.Byte() % np : 0;
    }
    if (np == 0)
    {
      continue; // VTK itself requires ids of existing points
    }
    (kind == 4 ? verts : kind == 5 ? lines : polys)->InsertNextCell(n, ids.data());
  }
  poly->SetVerts(verts);
  poly->SetLines(lines);
  poly->SetPolys(polys);
  const vtkIdType cells = poly->GetNumberOfCells();
  for (const char* name : { "UV", "dFdu", "dFdv" })
  {
    if (auto array = ReadArray(in, name, np))
    {
      poly->GetPointData()->AddArray(array);
    }
  }
  for (const char* name : { "EdgeGradients", "BoundaryCurvePoints", "GlobalIds", "vtkGhostType" })
  {
    auto array = ReadArray(in, name, cells);
    if (!array)
    {
      continue;
    }
    if (std::string(name) == "GlobalIds")
    {
      poly->GetCellData()->SetGlobalIds(array);
    }
    else
    {
      poly->GetCellData()->AddArray(array);
    }
  }
  return poly;
}

/// An integer id array of the output whose values must lie in [low, high).
void RequireIdsInRange(vtkDataArray* ids, double low, double high, const char* what)
{
  for (vtkIdType i = 0; ids && i < ids->GetNumberOfTuples(); ++i)
  {
    const double id = ids->GetComponent(i, 0);
    if (!(id >= low && id < high))
    {
      Finding(what, i);
      return;
    }
  }
}

/// A deep copy of a point set with every point moved by (0, 0, 1): the same sizes, other
/// values. Other data objects: a deep copy.
vtkSmartPointer<vtkDataObject> Moved(vtkDataObject* data)
{
  vtkSmartPointer<vtkDataObject> copy;
  copy.TakeReference(data->NewInstance());
  copy->DeepCopy(data);
  auto* set = vtkPointSet::SafeDownCast(copy);
  for (vtkIdType p = 0; set && set->GetPoints() && p < set->GetNumberOfPoints(); ++p)
  {
    double x[3];
    set->GetPoints()->GetPoint(p, x);
    set->GetPoints()->SetPoint(p, x[0], x[1], x[2] + 1.0);
  }
  return copy;
}

/// The check of ReuseOutputArrays: `reused` runs on other inputs of the same sizes (other()
/// sets them), then on the real ones (real()), writing into the first output's arrays; `fresh`,
/// a new algorithm with the same settings and the real inputs, must give the same answer: both
/// fail, or both succeed with the same output, bit for bit (a value the second run forgot to
/// write would still be the other inputs'). Returns fresh's output, or null when it failed.
template <typename Other, typename Real>
vtkDataObject* RunRecycled(
  vtkAlgorithm* reused, vtkAlgorithm* fresh, Other&& other, Real&& real, const char* what)
{
  other();
  Run(reused);
  real();
  vtkDataObject* second = Run(reused);
  vtkDataObject* output = Run(fresh);
  if (!second != !output || (output && !ctsplines_test::OutputDifference(second, output).empty()))
  {
    Finding(what, 0);
  }
  return output;
}

/// The same cells as a vtkUnstructuredGrid (what redistribution filters output).
vtkSmartPointer<vtkUnstructuredGrid> AsUnstructuredGrid(vtkPolyData* poly)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(poly->GetPoints());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c)
  {
    poly->GetCellPoints(c, ids);
    grid->InsertNextCell(poly->GetCellType(c), ids);
  }
  grid->GetPointData()->ShallowCopy(poly->GetPointData());
  grid->GetCellData()->ShallowCopy(poly->GetCellData());
  return grid;
}

vtkSmartPointer<vtkUnstructuredGrid> RunSplineFilter(
  vtkPolyData* poly, const Options& opt, bool checkOutput)
{
  auto make = [&opt]() {
    auto spline = vtkSmartPointer<vtkCloughTocherSplineFilter>::New();
    spline->SetConstruction(opt.Construction);
    spline->SetSplitPoint(opt.SplitPoint);
    spline->SetBoundaryMode(opt.BoundaryMode);
    spline->SetIterations(opt.Iterations);
    spline->SetComputeBezierExtraction(opt.Flag(0));
    if (opt.Flag(1))
    {
      spline->SetBoundaryCurvePointsArrayName("BoundaryCurvePoints");
    }
    return spline;
  };
  vtkSmartPointer<vtkDataObject> input = poly;
  if (opt.Flag(2))
  {
    input = AsUnstructuredGrid(poly);
  }
  const vtkSmartPointer<vtkDataObject> moved = Moved(input);
  auto reused = make(), fresh = make();
  fresh->SetInputDataObject(input);
  auto* output = vtkUnstructuredGrid::SafeDownCast(RunRecycled(
    reused, fresh, [&] { reused->SetInputDataObject(moved); },
    [&] { reused->SetInputDataObject(input); },
    "spline filter: an execution into the previous output's arrays differs from a new filter's"));
  if (!output)
  {
    return nullptr;
  }
  if (checkOutput)
  {
    RequireFinitePoints(output, "spline filter succeeded with a non-finite control point");
    RequireIdsInRange(output->GetCellData()->GetArray("MacroTriangleId"), 0,
      poly->GetNumberOfCells(), "spline filter: MacroTriangleId out of range");
  }
  vtkSmartPointer<vtkUnstructuredGrid> result = output;
  return result;
}

/// The grid with cell `cell` replaced by one of another type or point count.
vtkSmartPointer<vtkUnstructuredGrid> ReplaceCell(vtkUnstructuredGrid* grid, vtkIdType cell, int how)
{
  auto copy = vtkSmartPointer<vtkUnstructuredGrid>::New();
  copy->SetPoints(grid->GetPoints());
  copy->GetPointData()->ShallowCopy(grid->GetPointData());
  copy->GetCellData()->ShallowCopy(grid->GetCellData());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    int type = grid->GetCellType(c);
    if (c == cell)
    {
      if (how == 0) // a linear triangle
      {
        ids->SetNumberOfIds(3);
        type = VTK_TRIANGLE;
      }
      else if (how == 1) // a point too few for the order
      {
        ids->SetNumberOfIds(std::max<vtkIdType>(1, ids->GetNumberOfIds() - 1));
      }
      else if (how == 2) // a point too many
      {
        ids->InsertNextId(ids->GetId(0));
      }
      else // another cell type with the same points
      {
        type = VTK_BEZIER_QUADRILATERAL;
      }
    }
    copy->InsertNextCell(type, ids);
  }
  return copy;
}

/// Shortens (by n) or lengthens an array in place; replaces it by one of other components.
void Resize(vtkDataArray* array, int op, int n)
{
  if (!array)
  {
    return;
  }
  const vtkIdType tuples = array->GetNumberOfTuples();
  if (op == 0)
  {
    array->SetNumberOfTuples(std::max<vtkIdType>(0, tuples - 1 - n));
  }
  else if (op == 1)
  {
    array->Resize(tuples + 1 + n);
    array->SetNumberOfTuples(tuples + 1 + n);
    for (vtkIdType t = tuples; t < tuples + 1 + n; ++t)
    {
      for (int c = 0; c < array->GetNumberOfComponents(); ++c)
      {
        array->SetComponent(t, c, 0.0);
      }
    }
  }
}

/// Damage operations (pairs of bytes) applied to a copy of the spline filter's output.
vtkSmartPointer<vtkUnstructuredGrid> Damage(FuzzInput& in, vtkUnstructuredGrid* spline)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->DeepCopy(spline);
  for (int step = 0; step < 8 && in.RestSize() >= 2; ++step)
  {
    const int op = in.Choice(12);
    const int arg = in.Byte();
    const vtkIdType cells = grid->GetNumberOfCells(), points = grid->GetNumberOfPoints();
    vtkPointData* pd = grid->GetPointData();
    vtkCellData* cd = grid->GetCellData();
    switch (op)
    {
      case 0:
      case 1: Resize(pd->GetArray("UV"), op, arg % 4); break;
      case 2: pd->RemoveArray("UV"); break;
      case 3: Resize(cd->GetArray("MacroTriangleId"), arg % 2, arg / 2 % 4); break;
      case 4: Resize(cd->GetArray("MicroTriangleId"), arg % 2, arg / 2 % 4); break;
      case 5:
        if (cells > 0)
        {
          grid = ReplaceCell(grid, arg % cells, arg / 64);
        }
        break;
      case 6:
        if (points > 0)
        {
          const double x = in.Value();
          double p[3];
          grid->GetPoint(arg % points, p);
          p[arg / 64 % 3] = x;
          grid->GetPoints()->SetPoint(arg % points, p);
        }
        break;
      case 7:
        if (vtkDataArray* uv = pd->GetArray("UV"))
        {
          if (uv->GetNumberOfTuples() > 0)
          {
            uv->SetComponent(arg % uv->GetNumberOfTuples(), arg / 128, in.Value());
          }
        }
        break;
      case 8: // UV with another component count
        if (vtkDataArray* uv = pd->GetArray("UV"))
        {
          vtkNew<vtkDoubleArray> other;
          other->SetName("UV");
          other->SetNumberOfComponents(arg % 2 ? 1 : 3);
          other->SetNumberOfTuples(uv->GetNumberOfTuples());
          other->Fill(0.5);
          pd->AddArray(other);
        }
        break;
      case 9: // rational weights, all of one fuzzed value but one
      {
        vtkNew<vtkDoubleArray> weights;
        weights->SetName("RationalWeights");
        weights->SetNumberOfTuples(std::max<vtkIdType>(0, points - arg % 2));
        weights->Fill(1.0);
        if (weights->GetNumberOfTuples() > 0)
        {
          weights->SetValue(arg % weights->GetNumberOfTuples(), in.Value());
        }
        pd->AddArray(weights);
        break;
      }
      case 10:
        if (vtkDataArray* ids = cd->GetArray("MacroTriangleId"))
        {
          if (ids->GetNumberOfTuples() > 0)
          {
            const double v = in.Value();
            ids->SetComponent(arg % ids->GetNumberOfTuples(), 0,
              std::isfinite(v) ? std::max(-1e15, std::min(1e15, v)) : -1.0);
          }
        }
        break;
      default: grid->GetPointData()->RemoveArray("MacroTriangleId"); break;
    }
  }
  return grid;
}

/// A filter property from a fuzzed value: |x|, 0 for NaN or Inf (properties are the caller's
/// choice; the data is what must be robust).
double Magnitude(double x)
{
  return std::isfinite(x) ? std::abs(x) : 0.0;
}

vtkSmartPointer<vtkPolyData> ProbePoints(const std::array<double, 12>& param)
{
  vtkNew<vtkPoints> points;
  for (int i = 0; i < 12; i += 2)
  {
    points->InsertNextPoint(param[i], param[i + 1], 0.0);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  return poly;
}

void RunSampledSource(FuzzInput& in, const Options& opt, const std::array<double, 12>& param,
  bool finite)
{
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurface(opt.Construction % 6);
  source->SetDomain(opt.SplitPoint);
  // EquilateralTriangle has 4^Resolution triangles: up to 1024 (a bigger mesh is a request for
  // work, not a hang).
  const bool refined = opt.SplitPoint == vtkSampledSurfaceSource::EquilateralTriangle;
  source->SetResolution(in.Choice(refined ? 8 : 14) - 2);
  source->SetGridDiagonal(opt.BoundaryMode % 3);
  source->SetSeed(in.Byte());
  if (opt.Flag(0))
  {
    source->SetAffineMatrix(param[0], param[1], param[2], param[3]);
    source->SetAffineTranslation(param[4], param[5]);
  }
  RunChecked(source, finite, "sampled source succeeded with a non-finite point");
}

/// The downstream filter on `grid` (a Bézier grid, or the polydata itself in mode 2).
void RunDownstream(const Options& opt, vtkDataObject* grid, vtkPolyData* poly,
  const std::array<double, 12>& param, bool finite)
{
  switch (opt.Filter)
  {
    case 1:
    {
      auto make = [&]() {
        auto tessellator = vtkSmartPointer<vtkBezierTriangleTessellator>::New();
        tessellator->SetSubdivisionLevel(opt.Level);
        tessellator->SetSplitSharpEdges(opt.Flag(7));
        tessellator->SetFeatureAngle(Magnitude(param[0]));
        if (opt.Flag(5)) // adaptive
        {
          tessellator->SetChordalTolerance(Magnitude(param[1]));
          tessellator->SetAngularTolerance(Magnitude(param[2]));
          tessellator->SetRelativeChordalTolerance(opt.Flag(3));
        }
        return tessellator;
      };
      const vtkSmartPointer<vtkDataObject> moved = Moved(grid);
      auto reused = make(), fresh = make();
      fresh->SetInputData(grid);
      vtkDataObject* output = RunRecycled(
        reused, fresh, [&] { reused->SetInputData(moved); }, [&] { reused->SetInputData(grid); },
        "tessellator: an execution into the previous output's arrays differs from a new one's");
      if (output && finite)
      {
        RequireFinitePoints(output, "tessellator succeeded with a non-finite point");
      }
      break;
    }
    case 2:
    {
      // The other queries: the same number, elsewhere (the spline and its locator are reused).
      std::array<double, 12> elsewhere = param;
      for (double& x : elsewhere)
      {
        x = 0.5 * x + 0.25;
      }
      const vtkSmartPointer<vtkPolyData> queries = ProbePoints(param);
      const vtkSmartPointer<vtkPolyData> others = ProbePoints(elsewhere);
      vtkNew<vtkSplineParameterProbe> reused, fresh;
      reused->SetSourceData(grid);
      fresh->SetSourceData(grid);
      fresh->SetInputData(queries);
      RunRecycled(reused, fresh, [&] { reused->SetInputData(others); },
        [&] { reused->SetInputData(queries); },
        "probe: an execution into the previous output's arrays differs from a new probe's");
      break;
    }
    case 3:
    {
      vtkNew<vtkBezierCurvatureFilter> curvature;
      curvature->SetSubdivisionLevel(opt.Level);
      curvature->SetMergePoints(opt.Flag(3));
      curvature->SetRobustRangePercentile(Magnitude(param[0]));
      curvature->SetInputData(grid);
      RunChecked(curvature, finite, "curvature filter succeeded with a non-finite point");
      break;
    }
    case 4:
    {
      vtkNew<vtkSplineContinuityFilter> continuity;
      continuity->SetMatchCoincidentEdges(opt.Flag(4));
      continuity->SetG1Samples(1 + opt.Level);
      continuity->SetInputData(grid);
      Run(continuity);
      break;
    }
    case 5:
    {
      // Reflection lines read point normals: the tessellation's, or dFdu of the polydata.
      vtkSmartPointer<vtkDataObject> surface = grid;
      if (grid != poly)
      {
        vtkNew<vtkBezierTriangleTessellator> tessellator;
        tessellator->SetSubdivisionLevel(opt.Level);
        tessellator->SetInputData(grid);
        surface = Run(tessellator);
      }
      else if (vtkDataArray* du = poly->GetPointData()->GetArray("dFdu"))
      {
        du->SetName("Normals");
      }
      if (surface)
      {
        vtkNew<vtkReflectionLinesFilter> reflection;
        reflection->SetEyePosition(param[0], param[1], param[2]);
        reflection->SetLightLineDirection(param[3], param[4], param[5]);
        reflection->SetLightPlaneOrigin(param[6], param[7], param[8]);
        reflection->SetLightPlaneNormal(param[9], param[10], param[11]);
        reflection->SetSpacing(std::isfinite(param[0]) ? std::abs(param[0]) : 1.0);
        reflection->SetLightDirection(param[3], param[5], param[7]);
        reflection->SetInputData(surface);
        Run(reflection);
      }
      break;
    }
    case 6:
    {
      vtkNew<vtkApproximationErrorFilter> error;
      error->SetMode(opt.Flag(5) ? vtkApproximationErrorFilter::MeshDistance
                                 : vtkApproximationErrorFilter::Parametric);
      error->SetSubdivisionLevel(opt.Level);
      error->SetReferenceSampleLevel(1 + opt.Level % 3);
      error->SetInputData(grid);
      error->SetReferenceData(poly);
      if (vtkDataObject* out = Run(error); out && finite)
      {
        vtkDataArray* maxError = out->GetFieldData()->GetArray("MaxError");
        if (maxError && maxError->GetNumberOfTuples() > 0 &&
          !std::isfinite(maxError->GetComponent(0, 0)))
        {
          Finding("approximation error succeeded with a non-finite MaxError", 0);
        }
      }
      break;
    }
    default: break;
  }
}

} // namespace

static int RunOne(const std::uint8_t* bytes, std::size_t size)
{
  SilenceVTK();
  // Every output array is kept for the next execution, so that RunRecycled takes the recycling
  // paths (ReuseOutputArrays) on the fuzzer's small inputs too.
  ctsplines::RecycledArrays::SetMinimumBytes(0);
  FuzzInput in(bytes, size);
  Options opt;
  opt.Filter = in.Choice(8);
  opt.Mode = in.Choice(3);
  opt.Construction = in.Choice(10);
  opt.SplitPoint = in.Choice(3);
  opt.BoundaryMode = in.Choice(4);
  opt.Iterations = in.Choice(3);
  opt.Level = 1 + in.Choice(6);
  opt.Flags = in.Byte();
  vtkSmartPointer<vtkPolyData> poly = ReadPolyData(in, opt);
  std::array<double, 12> param;
  for (double& p : param)
  {
    p = in.Value();
  }
  if (opt.Filter == 7)
  {
    RunSampledSource(in, opt, param, !in.NonFinite);
    return 0;
  }
  const bool finiteInput = !in.NonFinite;
  if (opt.Mode == 2 && opt.Filter != 0)
  {
    RunDownstream(opt, poly, poly, param, false);
    return 0;
  }
  vtkSmartPointer<vtkUnstructuredGrid> spline = RunSplineFilter(poly, opt, finiteInput);
  if (!spline || opt.Filter == 0)
  {
    return 0;
  }
  if (opt.Mode == 1)
  {
    spline = Damage(in, spline);
  }
  RunDownstream(opt, spline, poly, param, finiteInput && !in.NonFinite);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size)
{
  return ctsplines_fuzz::RunGuarded(bytes, size, RunOne);
}
