// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_benchmark: wall-clock figures of the module's filters on meshes of about --sizes
// triangles, printed as one plain table. --mesh grid: Franke's function on regular grids
// (vtkSampledSurfaceSource); --mesh delaunay: the mesh SciPy's and Matplotlib's users have, the
// Delaunay triangulation (CGAL) of size/2 uniform random points of the unit square, vertices in
// the points' order and triangles in the triangulation's (neither is a locality order), with
// the exact values and gradients of sin 3x cos 2y; --renumber morton renumbers either mesh by a
// Morton key (for comparison). Rows:
//   source          the mesh itself (grid: vtkSampledSurfaceSource; delaunay: CGAL + sampling)
//   spline <c>      vtkCloughTocherSplineFilter, every construction (Bary, Midpoint boundary,
//                   Iterations 0); "x CTo" is its time over CTo's on the same mesh
//   IM step (CTi)   one IM step: (time at Iterations N - time at Iterations 0) / N on CTi
//   tessellate L4   vtkBezierTriangleTessellator at SubdivisionLevel 4 on the CTi spline
//   probe           vtkSplineParameterProbe on the CTi spline: random (u, v) points, or with
//                   --probe-queries rows the rows of a square grid (delaunay_comparison.py's
//                   sorted queries)
// --stages and --constructions select rows (e.g. to profile one of them).
// The machine's bounds are measured first (BenchmarkSupport.h): copy and first-touch write
// bandwidth, and the time of one cubic Bézier jet with normal. "of bound" is the fraction
// reached: output bytes / time over the first-touch bandwidth (source, spline, tessellate), or
// queries x jet time over the time (probe). --memory adds each spline row's peak resident memory
// over its output's size (one extra run). With several --sizes, each spline row's growth
// exponent k (time ~ n^k, from the first size to the last) is printed after the table.
// The last two are built only when those filters are part of the module. Every figure is the best
// of --repeat runs (the minimum is the least noisy estimate on a shared machine).
#include "BenchmarkSupport.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"
#if __has_include("vtkBezierTriangleTessellator.h")
#include "vtkBezierTriangleTessellator.h"
#define CTSPLINES_HAVE_TESSELLATOR 1
#endif
#if __has_include("vtkSplineParameterProbe.h")
#include "vtkSplineParameterProbe.h"
#define CTSPLINES_HAVE_PROBE 1
#endif

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVersion.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
struct Options
{
  std::vector<double> Sizes{ 1e4, 1e5, 1e6 };
  int Repeat = 3;
  int Threads = 0; // 0: vtkSMPTools' default (all cores)
  int Level = 4;
  double ProbePoints = 1e6;
  bool ProbeRows = false; // --probe-queries rows
  double MaxTessellatedTriangles = 2e7; // output triangles; bounds the memory of one run
  int IMSteps = 10;
  std::string Mesh = "grid";   // or "delaunay"
  std::string Renumber = "none"; // or "morton"
  int OutputOrder = vtkCloughTocherSplineFilter::LocalityOrder;
  bool ReuseOutput = true; // the filters' ReuseOutputArrays
  bool Memory = false;
  std::vector<std::string> Stages{ "source", "spline", "im", "tessellate", "probe" };
  std::vector<std::string> Constructions{ "CTo", "CTi", "Fa", "FO", "Ka", "MGo", "MGi", "KaG",
    "Kashyap", "Quartic" };

  bool Has(const std::string& stage) const
  {
    return std::find(this->Stages.begin(), this->Stages.end(), stage) != this->Stages.end();
  }
};

// --reuse-output, for TimeSpline (set once, while the options are read).
bool ReuseOutput = true;

std::vector<std::string> SplitList(const char* v)
{
  std::vector<std::string> items;
  std::stringstream ss(v);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    items.push_back(item);
  }
  return items;
}

/// Construction id by name, or -1.
int ConstructionId(const std::string& name)
{
  for (int c = vtkCloughTocherSplineFilter::CTo; c <= vtkCloughTocherSplineFilter::Quartic; ++c)
  {
    if (name == vtkCloughTocherSplineFilter::GetConstructionName(c))
    {
      return c;
    }
  }
  return -1;
}

void Usage(const char* argv0)
{
  std::printf("usage: %s [--sizes 1e4,1e5,1e6] [--repeat 3] [--threads N] [--level 4]\n"
              "          [--probe-points 1e6] [--probe-queries random|rows]\n"
              "          [--max-tessellated 2e7] [--im-steps 10]\n"
              "          [--stages source,spline,im,tessellate,probe]\n"
              "          [--mesh grid|delaunay] [--renumber none|morton] [--memory 0|1]\n"
              "          [--clock wall|cpu|user] [--output-order locality|input] [--reuse-output 1|0]\n"
              "          [--constructions CTo,CTi,Fa,FO,Ka,MGo,MGi,KaG,Kashyap,Quartic]\n"
              "  --sizes            approximate triangle counts of the grids (comma separated)\n"
              "  --repeat           runs per figure; the best is reported\n"
              "  --threads          vtkSMPTools threads (STDThread backend); 0 = all cores\n"
              "  --level            tessellation SubdivisionLevel (segments per cell edge)\n"
              "  --probe-points     parameter points per probe run\n"
              "  --probe-queries    random: uniform random points; rows: the rows of a square\n"
              "                     grid of about --probe-points points (a coherent order)\n"
              "  --max-tessellated  skip tessellations producing more triangles than this\n"
              "  --im-steps         Iterations of the IM row (its time is divided by this)\n"
              "  --stages           rows to run (comma separated)\n"
              "  --constructions    spline filter constructions of the spline rows\n"
              "  --mesh             grid: Franke on a regular grid; delaunay: sin 3x cos 2y on the\n"
              "                     Delaunay triangulation of size/2 random points, numbered as\n"
              "                     the points and the triangulation come (no locality order)\n"
              "  --renumber         morton: renumber the mesh by Morton keys first\n"
              "  --output-order     the spline filter's OutputOrder (default locality)\n"
              "  --reuse-output     ReuseOutputArrays of the spline filter, tessellator, probe\n"
              "                     (default 1: runs after the first write into the previous\n"
              "                     output's arrays; 0: every run allocates its output)\n"
              "  --memory           1: peak resident memory of each spline row (one more run)\n"
              "  --clock            cpu: this process' CPU time instead of wall-clock time (with\n"
              "                     --threads 1 on a machine shared with other jobs); user: its\n"
              "                     user CPU time, without the kernel's zeroing of fresh pages\n"
              "                     (the steadier measure of a change on a VM; the bounds are\n"
              "                     still measured in process CPU time)\n",
    argv0);
}

bool ParseNumber(const char* s, double& out)
{
  char* end = nullptr;
  out = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(out);
}

bool Parse(int argc, char** argv, Options& o)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help")
    {
      Usage(argv[0]);
      std::exit(0);
    }
    if (i + 1 >= argc)
    {
      std::fprintf(stderr, "missing value after %s\n", a.c_str());
      return false;
    }
    const char* v = argv[++i];
    double x = 0.0;
    if (a == "--sizes")
    {
      o.Sizes.clear();
      std::stringstream ss(v);
      std::string item;
      while (std::getline(ss, item, ','))
      {
        if (!ParseNumber(item.c_str(), x) || x < 2)
        {
          std::fprintf(stderr, "bad size '%s'\n", item.c_str());
          return false;
        }
        o.Sizes.push_back(x);
      }
    }
    else if (a == "--repeat" && ParseNumber(v, x) && x >= 1)
    {
      o.Repeat = static_cast<int>(x);
    }
    else if (a == "--threads" && ParseNumber(v, x) && x >= 0)
    {
      o.Threads = static_cast<int>(x);
    }
    else if (a == "--level" && ParseNumber(v, x) && x >= 1)
    {
      o.Level = static_cast<int>(x);
    }
    else if (a == "--probe-points" && ParseNumber(v, x) && x >= 1)
    {
      o.ProbePoints = x;
    }
    else if (a == "--probe-queries" && (std::string(v) == "random" || std::string(v) == "rows"))
    {
      o.ProbeRows = std::string(v) == "rows";
    }
    else if (a == "--max-tessellated" && ParseNumber(v, x) && x >= 0)
    {
      o.MaxTessellatedTriangles = x;
    }
    else if (a == "--im-steps" && ParseNumber(v, x) && x >= 1)
    {
      o.IMSteps = static_cast<int>(x);
    }
    else if (a == "--stages")
    {
      o.Stages = SplitList(v);
      for (const std::string& st : o.Stages)
      {
        if (st != "source" && st != "spline" && st != "im" && st != "tessellate" && st != "probe")
        {
          std::fprintf(stderr, "unknown stage '%s'\n", st.c_str());
          return false;
        }
      }
    }
    else if (a == "--mesh" && (std::string(v) == "grid" || std::string(v) == "delaunay"))
    {
      o.Mesh = v;
    }
    else if (a == "--renumber" && (std::string(v) == "none" || std::string(v) == "morton"))
    {
      o.Renumber = v;
    }
    else if (a == "--output-order" && (std::string(v) == "input" || std::string(v) == "locality"))
    {
      o.OutputOrder = std::string(v) == "input" ? vtkCloughTocherSplineFilter::InputOrder
                                                : vtkCloughTocherSplineFilter::LocalityOrder;
    }
    else if (a == "--reuse-output" && ParseNumber(v, x))
    {
      o.ReuseOutput = x != 0;
      ReuseOutput = o.ReuseOutput;
    }
    else if (a == "--memory" && ParseNumber(v, x))
    {
      o.Memory = x != 0;
    }
    else if (a == "--clock" &&
      (std::string(v) == "wall" || std::string(v) == "cpu" || std::string(v) == "user"))
    {
      bench::BenchmarkClock() = std::string(v) == "wall"
        ? bench::Clock::Wall
        : (std::string(v) == "cpu" ? bench::Clock::ProcessCpu : bench::Clock::User);
    }
    else if (a == "--constructions")
    {
      o.Constructions = SplitList(v);
      for (const std::string& c : o.Constructions)
      {
        if (ConstructionId(c) < 0)
        {
          std::fprintf(stderr, "unknown construction '%s'\n", c.c_str());
          return false;
        }
      }
    }
    else
    {
      std::fprintf(stderr, "bad option or value: %s %s\n", a.c_str(), v);
      return false;
    }
  }
  return !o.Sizes.empty();
}

/// Best seconds (bench::Clock: wall or this process' CPU) of `repeat` calls of `run`; `run`
/// returns false on failure.
double Best(int repeat, const std::function<bool()>& run, bool& ok)
{
  ok = true;
  return bench::BestSeconds(repeat, [&] { ok = run() && ok; });
}

/// Best seconds of `repeat` re-executions of `algorithm` (marked modified before each).
double BestUpdate(vtkAlgorithm* algorithm, int repeat, bool& ok)
{
  return Best(
    repeat,
    [&] {
      algorithm->Modified();
      return algorithm->GetExecutive()->Update() != 0;
    },
    ok);
}

/// One table row; ns/triangle only for the stages that process the input triangles, and the
/// time relative to CTo's for the spline rows (relative <= 0: none).
/// bound: fraction of the machine's bound reached (<= 0: none); extra: printed after the row.
void Row(long long triangles, const std::string& stage, double seconds, long long items,
  const char* unit, bool perTriangle = true, double relative = 0.0, double bound = 0.0,
  const std::string& extra = "")
{
  char per[32] = "-", rel[32] = "-", of[32] = "-";
  if (bound > 0.0)
  {
    std::snprintf(of, sizeof(of), "%.1f %%", 100.0 * bound);
  }
  if (perTriangle)
  {
    std::snprintf(per, sizeof(per), "%.1f", 1e9 * seconds / double(triangles));
  }
  if (relative > 0.0)
  {
    std::snprintf(rel, sizeof(rel), "%.2f", relative);
  }
  std::printf("%11lld  %-24s %10.4f %12s %7s %9s %12.4g %s%s\n", triangles, stage.c_str(),
    seconds, per, rel, of, double(items) / seconds, unit, extra.c_str());
  std::fflush(stdout);
}

/// Best time of the spline filter on `mesh`; keeps the output in `spline` when asked.
double TimeSpline(vtkPolyData* mesh, int outputOrder, int construction, int iterations,
  int repeat, bool& ok,
  vtkSmartPointer<vtkUnstructuredGrid>* spline = nullptr)
{
  vtkNew<vtkCloughTocherSplineFilter> filter;
  filter->SetInputData(mesh);
  filter->SetConstruction(construction);
  filter->SetOutputOrder(outputOrder);
  filter->SetSplitPointToBary();
  filter->SetBoundaryModeToMidpoint();
  filter->SetIterations(iterations);
  filter->SetReuseOutputArrays(ReuseOutput);
  const double t = BestUpdate(filter, repeat, ok);
  if (spline)
  {
    *spline = vtkSmartPointer<vtkUnstructuredGrid>::New();
    (*spline)->ShallowCopy(filter->GetOutput());
  }
  return t;
}
/// Bytes of a data set's arrays.
double MeshBytes(vtkDataSet* data)
{
  return 1024.0 * data->GetActualMemorySize();
}

vtkSmartPointer<vtkDataArray> DoubleArray(const std::vector<double>& values, int components,
  const char* name)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()) / components);
  std::copy(values.begin(), values.end(), a->GetPointer(0));
  return a;
}

vtkSmartPointer<vtkPolyData> ToPolyData(const bench::SampledMesh& m)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetData(DoubleArray(m.F, 3, "Points"));
  pd->SetPoints(points);
  const vtkIdType nT = static_cast<vtkIdType>(m.Triangles.size() / 3);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nT + 1);
  for (vtkIdType t = 0; t <= nT; ++t)
  {
    offsets->SetValue(t, 3 * t);
  }
  connectivity->SetNumberOfTuples(3 * nT);
  std::copy(m.Triangles.begin(), m.Triangles.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  pd->SetPolys(polys);
  pd->GetPointData()->AddArray(DoubleArray(m.UV, 2, "UV"));
  pd->GetPointData()->AddArray(DoubleArray(m.Fu, 3, "dFdu"));
  pd->GetPointData()->AddArray(DoubleArray(m.Fv, 3, "dFdv"));
  pd->GetCellData()->AddArray(DoubleArray(m.EdgeGradients, 18, "EdgeGradients"));
  return pd;
}

/// The mesh of about `size` triangles; seconds: the time of making it (best of --repeat when
/// the source row is asked for).
vtkSmartPointer<vtkPolyData> MakeMesh(const Options& opt, double size, double& seconds, bool& ok)
{
  const int repeat = opt.Has("source") ? opt.Repeat : 1;
  if (opt.Mesh == "delaunay")
  {
    bench::SampledMesh m;
    seconds = bench::BestSeconds(repeat,
      [&] { m = bench::RandomDelaunayMesh(static_cast<std::int64_t>(size / 2), 12345); });
    if (opt.Renumber == "morton")
    {
      bench::MortonRenumber(m);
    }
    return ToPolyData(m);
  }
  // Two triangles per cell: n^2 cells for about `size` triangles.
  const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(size / 2.0))));
  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToFranke();
  source->SetDomainToGrid();
  source->SetResolution(n);
  seconds = BestUpdate(source, repeat, ok);
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->ShallowCopy(source->GetOutput());
  if (opt.Renumber == "morton")
  {
    std::fprintf(stderr, "--renumber morton is for --mesh delaunay\n");
    ok = false;
  }
  return mesh;
}
/// What every row needs: the options, the machine's bounds, and whether all updates succeeded.
struct Context
{
  const Options& Opt;
  bench::MachineBounds Bounds;
  bool AllOk = true;
  /// (triangles, seconds) of each spline row, by construction, in the order of --sizes.
  std::map<std::string, std::vector<std::pair<double, double>>> SplineTimes;
  /// Fraction of the first-touch bound of writing `bytes` in `seconds`.
  double WriteBound(double bytes, double seconds) const
  {
    return bytes / seconds / (1e9 * Bounds.FirstTouchGBs);
  }
};

void PrintHeader(const Options& opt, const bench::MachineBounds& bounds)
{
  std::printf("ctsplines_benchmark: %s, %s, output order %s, output arrays %s, best of %d "
              "run(s), %s time\n",
    opt.Mesh == "grid" ? "Franke on regular grids of [0,1]^2 (vtkSampledSurfaceSource)"
                       : "sin 3x cos 2y on random Delaunay meshes of [0,1]^2 (CGAL)",
    opt.Renumber == "morton" ? "renumbered by Morton keys" : "as numbered",
    opt.OutputOrder == vtkCloughTocherSplineFilter::InputOrder ? "input" : "locality",
    opt.ReuseOutput ? "reused" : "new each run", opt.Repeat,
    bench::ClockName());
  std::printf("VTK %s, SMP backend %s, %d thread(s), CTSPLINES_NUM_THREADS %s\n",
    vtkVersion::GetVTKVersion(), vtkSMPTools::GetBackend(),
    vtkSMPTools::GetEstimatedNumberOfThreads(),
    std::getenv("CTSPLINES_NUM_THREADS") ? std::getenv("CTSPLINES_NUM_THREADS") : "unset");
  std::printf("machine bounds (measured now, one thread): copy %.2f GB/s, first-touch write "
              "%.2f GB/s (huge pages advised), cubic jet with normal %.1f ns\n",
    bounds.CopyGBs, bounds.FirstTouchGBs, 1e9 * bounds.JetSeconds);
  std::printf("spline filter: split point Bary, boundary Midpoint, Iterations 0; ns/triangle is "
              "per input triangle; x CTo is the time over CTo's; rate is input triangles/s "
              "unless stated; of bound: output bytes/s over first-touch write (probe: queries "
              "x jet time over time)\n\n");
  std::printf("%11s  %-24s %10s %12s %7s %9s %12s\n", "triangles", "stage", "seconds",
    "ns/triangle", "x CTo", "of bound", "rate");
}

/// One row per construction of --constructions; returns CTo's time (0 when not among them).
double SplineRows(vtkPolyData* mesh, long long nT, Context& ctx)
{
  const Options& opt = ctx.Opt;
  double tCTo = 0.0;
  bool ok = true;
  for (const std::string& name : opt.Constructions)
  {
    const int c = ConstructionId(name);
    vtkSmartPointer<vtkUnstructuredGrid> out;
    const double t = TimeSpline(mesh, opt.OutputOrder, c, 0, opt.Repeat, ok, &out);
    ctx.AllOk = ctx.AllOk && ok;
    if (c == vtkCloughTocherSplineFilter::CTo)
    {
      tCTo = t;
    }
    const double outBytes = 1024.0 * out->GetActualMemorySize();
    char extra[96] = "";
    if (opt.Memory)
    {
      out = nullptr; // measured alone, from fresh memory as a process's first construction
      vtkCloughTocherSplineFilter::ReleaseRetainedMemory();
      const double peak = bench::PeakExtraBytes(
        [&] { TimeSpline(mesh, opt.OutputOrder, c, 0, 1, ok); });
      std::snprintf(extra, sizeof(extra), "  peak %.0f MB = %.2f x output %.0f MB", 1e-6 * peak,
        peak / outBytes, 1e-6 * outBytes);
    }
    ctx.SplineTimes[name].emplace_back(double(nT), t);
    Row(nT, "spline " + name, t, nT, "tri/s", true, tCTo > 0.0 ? t / tCTo : 0.0,
      ctx.WriteBound(outBytes, t), extra);
  }
  return tCTo;
}

/// With several sizes: each construction's growth exponent, log(t_last / t_first) over
/// log(n_last / n_first) (issue #12 asks at most 1.05 from 1e5 to 4e6 triangles).
void PrintGrowth(const Context& ctx)
{
  bool header = false;
  for (const auto& named : ctx.SplineTimes)
  {
    const auto& runs = named.second;
    if (runs.size() < 2 || !(runs.back().first > runs.front().first) ||
      !(runs.front().second > 0.0))
    {
      continue;
    }
    if (!header)
    {
      std::printf("\ngrowth exponent of the spline rows, first to last size (time ~ n^k):\n");
      header = true;
    }
    const double k = std::log(runs.back().second / runs.front().second) /
      std::log(runs.back().first / runs.front().first);
    std::printf("  spline %-8s k = %.3f from %.0f to %.0f triangles\n", named.first.c_str(), k,
      runs.front().first, runs.back().first);
  }
}

/// The time of one IM step: CTi with --im-steps iterations against none.
void IMRow(vtkPolyData* mesh, long long nT, double tCTo, Context& ctx)
{
  const Options& opt = ctx.Opt;
  bool ok = true;
  const double t0 =
    TimeSpline(mesh, opt.OutputOrder, vtkCloughTocherSplineFilter::CTi, 0, opt.Repeat, ok);
  ctx.AllOk = ctx.AllOk && ok;
  const double tN =
    TimeSpline(mesh, opt.OutputOrder, vtkCloughTocherSplineFilter::CTi, opt.IMSteps, opt.Repeat, ok);
  ctx.AllOk = ctx.AllOk && ok;
  // Differences of two noisy minima can be tiny or negative on a loaded machine.
  const double step = std::max(tN - t0, 1e-9) / opt.IMSteps;
  Row(nT, "IM step (CTi, " + std::to_string(opt.IMSteps) + " vs 0)", step, nT, "tri/s", true,
    tCTo > 0.0 ? step / tCTo : 0.0);
}

#ifdef CTSPLINES_HAVE_TESSELLATOR
void TessellateRow(vtkUnstructuredGrid* ctiSpline, long long nT, Context& ctx)
{
  const Options& opt = ctx.Opt;
  bool ok = true;
  const double outTriangles =
    double(ctiSpline->GetNumberOfCells()) * opt.Level * opt.Level;
  const std::string stage = "tessellate L" + std::to_string(opt.Level) + " (CTi)";
  if (outTriangles > opt.MaxTessellatedTriangles)
  {
    std::printf("%11lld  %-24s skipped: %.3g output triangles > --max-tessellated %.3g\n",
      nT, stage.c_str(), outTriangles, opt.MaxTessellatedTriangles);
  }
  else
  {
    vtkNew<vtkBezierTriangleTessellator> tess;
    tess->SetInputData(ctiSpline);
    tess->SetSubdivisionLevel(opt.Level);
    tess->SetReuseOutputArrays(opt.ReuseOutput);
    const double t = BestUpdate(tess, opt.Repeat, ok);
    ctx.AllOk = ctx.AllOk && ok;
    Row(nT, stage, t, tess->GetOutput()->GetNumberOfPoints(), "output points/s", false, 0.0,
      ctx.WriteBound(1024.0 * tess->GetOutput()->GetActualMemorySize(), t));
  }
}
#endif

#ifdef CTSPLINES_HAVE_PROBE
/// --probe-points uniform random (u, v) in the unit square, or the centres of a square grid's
/// cells row by row (--probe-queries rows); best of --repeat runs, which from the second on
/// reuse the probe's locator.
void ProbeRow(vtkUnstructuredGrid* ctiSpline, long long nT, Context& ctx)
{
  const Options& opt = ctx.Opt;
  bool ok = true;
  const vtkIdType side = std::max<vtkIdType>(1, std::llround(std::sqrt(opt.ProbePoints)));
  const vtkIdType np = opt.ProbeRows ? side * side : static_cast<vtkIdType>(opt.ProbePoints);
  vtkNew<vtkPoints> uv;
  uv->SetDataTypeToDouble();
  uv->SetNumberOfPoints(np);
  std::mt19937_64 rng(271828); // not the mesh's seed: its points would be the first queries
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (vtkIdType i = 0; i < np; ++i)
  {
    if (opt.ProbeRows)
    {
      uv->SetPoint(i, (double(i % side) + 0.5) / double(side), (double(i / side) + 0.5) / double(side), 0.0);
      continue;
    }
    const double u = uniform(rng);
    uv->SetPoint(i, u, uniform(rng), 0.0);
  }
  vtkNew<vtkPolyData> queries;
  queries->SetPoints(uv);
  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(queries);
  probe->SetSourceData(ctiSpline);
  probe->SetReuseOutputArrays(opt.ReuseOutput);
  const double t = BestUpdate(probe, opt.Repeat, ok);
  ctx.AllOk = ctx.AllOk && ok;
  std::ostringstream stage;
  stage << "probe " << double(np) << (opt.ProbeRows ? " rows" : " pts") << " (CTi)";
  Row(nT, stage.str(), t, np, "evaluations/s", false, 0.0, double(np) * ctx.Bounds.JetSeconds / t);
}
#endif
} // namespace

int main(int argc, char** argv)
{
  Options opt;
  if (!Parse(argc, argv, opt))
  {
    Usage(argv[0]);
    return 2;
  }
  // Debian's VTK defaults to the Sequential backend: ask for threads explicitly.
  if (!vtkSMPTools::SetBackend("STDThread"))
  {
    std::fprintf(stderr, "vtkSMPTools backend STDThread is not available\n");
    return 1;
  }
  vtkSMPTools::Initialize(opt.Threads);
  Context ctx{ opt, bench::MeasureBounds() };
  PrintHeader(opt, ctx.Bounds);
  for (double size : opt.Sizes)
  {
    bool ok = true;
    double tSource = 0.0;
    const vtkSmartPointer<vtkPolyData> mesh = MakeMesh(opt, size, tSource, ok);
    const long long nT = mesh ? mesh->GetNumberOfPolys() : 0;
    if (!ok || nT == 0)
    {
      std::fprintf(stderr, "no %s mesh of size %g\n", opt.Mesh.c_str(), size);
      return 1;
    }
    if (opt.Has("source"))
    {
      Row(nT, opt.Mesh == "grid" ? "source (Franke grid)" : "source (Delaunay, CGAL)", tSource,
        nT, "tri/s", true, 0.0, ctx.WriteBound(MeshBytes(mesh), tSource));
    }
    const double tCTo = opt.Has("spline") ? SplineRows(mesh, nT, ctx) : 0.0;
    if (opt.Has("im"))
    {
      IMRow(mesh, nT, tCTo, ctx);
    }
    vtkSmartPointer<vtkUnstructuredGrid> ctiSpline;
    if (opt.Has("tessellate") || opt.Has("probe"))
    {
      TimeSpline(mesh, opt.OutputOrder, vtkCloughTocherSplineFilter::CTi, 0, 1, ok, &ctiSpline);
      ctx.AllOk = ctx.AllOk && ok;
    }
#ifdef CTSPLINES_HAVE_TESSELLATOR
    if (opt.Has("tessellate"))
    {
      TessellateRow(ctiSpline, nT, ctx);
    }
#endif
#ifdef CTSPLINES_HAVE_PROBE
    if (opt.Has("probe"))
    {
      ProbeRow(ctiSpline, nT, ctx);
    }
#endif
  }
  PrintGrowth(ctx);
#ifndef CTSPLINES_HAVE_TESSELLATOR
  std::printf("\n(vtkBezierTriangleTessellator is not part of this build: no tessellation figures)\n");
#endif
#ifndef CTSPLINES_HAVE_PROBE
  std::printf("\n(vtkSplineParameterProbe is not part of this build: no probe figures)\n");
#endif
  if (!ctx.AllOk)
  {
    std::fprintf(stderr, "some pipeline updates failed (see the VTK errors above)\n");
    return 1;
  }
  return 0;
}
