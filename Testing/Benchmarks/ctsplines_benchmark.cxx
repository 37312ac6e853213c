// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_benchmark: wall-clock figures of the module's filters on Franke's function sampled on
// regular grids of about --sizes triangles, printed as one plain table:
//   source          vtkSampledSurfaceSource itself (sampling + exact derivatives + edge gradients)
//   spline <c>      vtkCloughTocherSplineFilter, every construction (Bary, Midpoint boundary,
//                   Iterations 0); "x CTo" is its time over CTo's on the same mesh
//   IM step (CTi)   one IM step: (time at Iterations N - time at Iterations 0) / N on CTi
//   tessellate L4   vtkBezierTriangleTessellator at SubdivisionLevel 4 on the CTi spline
//   probe           vtkSplineParameterProbe, random (u, v) points on the CTi spline
// --stages and --constructions select rows (e.g. to profile one of them).
// The last two are built only when those filters are part of the module. Every figure is the best
// of --repeat runs (the minimum is the least noisy estimate on a shared machine).
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
#include "vtkExecutive.h"
#include "vtkNew.h"
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
#include <random>
#include <sstream>
#include <string>
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
  double MaxTessellatedTriangles = 2e7; // output triangles; bounds the memory of one run
  int IMSteps = 10;
  std::vector<std::string> Stages{ "source", "spline", "im", "tessellate", "probe" };
  std::vector<std::string> Constructions{ "CTo", "CTi", "Fa", "FO", "Ka", "MGo", "MGi", "KaG",
    "Kashyap", "Quartic" };

  bool Has(const std::string& stage) const
  {
    return std::find(this->Stages.begin(), this->Stages.end(), stage) != this->Stages.end();
  }
};

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
              "          [--probe-points 1e6] [--max-tessellated 2e7] [--im-steps 10]\n"
              "          [--stages source,spline,im,tessellate,probe]\n"
              "          [--constructions CTo,CTi,Fa,FO,Ka,MGo,MGi,KaG,Kashyap,Quartic]\n"
              "  --sizes            approximate triangle counts of the grids (comma separated)\n"
              "  --repeat           runs per figure; the best is reported\n"
              "  --threads          vtkSMPTools threads (STDThread backend); 0 = all cores\n"
              "  --level            tessellation SubdivisionLevel (segments per cell edge)\n"
              "  --probe-points     random parameter points per probe run\n"
              "  --max-tessellated  skip tessellations producing more triangles than this\n"
              "  --im-steps         Iterations of the IM row (its time is divided by this)\n"
              "  --stages           rows to run (comma separated)\n"
              "  --constructions    spline filter constructions of the spline rows\n",
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

/// Best wall-clock seconds of `repeat` calls of `run`; `run` returns false on failure.
double Best(int repeat, const std::function<bool()>& run, bool& ok)
{
  double best = 1e300;
  ok = true;
  for (int r = 0; r < repeat; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    ok = run() && ok;
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  return best;
}

/// One table row; ns/triangle only for the stages that process the input triangles, and the
/// time relative to CTo's for the spline rows (relative <= 0: none).
void Row(long long triangles, const std::string& stage, double seconds, long long items,
  const char* unit, bool perTriangle = true, double relative = 0.0)
{
  char per[32] = "-", rel[32] = "-";
  if (perTriangle)
  {
    std::snprintf(per, sizeof(per), "%.1f", 1e9 * seconds / double(triangles));
  }
  if (relative > 0.0)
  {
    std::snprintf(rel, sizeof(rel), "%.2f", relative);
  }
  std::printf("%11lld  %-24s %10.4f %12s %7s %12.4g %s\n", triangles, stage.c_str(), seconds,
    per, rel, double(items) / seconds, unit);
  std::fflush(stdout);
}

/// Best time of the spline filter on `mesh`; keeps the output in `spline` when asked.
double TimeSpline(vtkPolyData* mesh, int construction, int iterations, int repeat, bool& ok,
  vtkSmartPointer<vtkUnstructuredGrid>* spline = nullptr)
{
  vtkNew<vtkCloughTocherSplineFilter> filter;
  filter->SetInputData(mesh);
  filter->SetConstruction(construction);
  filter->SetSplitPointToBary();
  filter->SetBoundaryModeToMidpoint();
  filter->SetIterations(iterations);
  const double t = Best(
    repeat,
    [&] {
      filter->Modified();
      return filter->GetExecutive()->Update() != 0;
    },
    ok);
  if (spline)
  {
    *spline = vtkSmartPointer<vtkUnstructuredGrid>::New();
    (*spline)->ShallowCopy(filter->GetOutput());
  }
  return t;
}
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

  std::printf("ctsplines_benchmark: Franke on regular grids of [0,1]^2 "
              "(vtkSampledSurfaceSource), best of %d run(s)\n",
    opt.Repeat);
  std::printf("VTK %s, SMP backend %s, %d thread(s)\n", vtkVersion::GetVTKVersion(),
    vtkSMPTools::GetBackend(), vtkSMPTools::GetEstimatedNumberOfThreads());
  std::printf("spline filter: split point Bary, boundary Midpoint, Iterations 0; ns/triangle is "
              "per input triangle; x CTo is the time over CTo's; rate is input triangles/s "
              "unless stated\n\n");
  std::printf("%11s  %-24s %10s %12s %7s %12s\n", "triangles", "stage", "seconds", "ns/triangle",
    "x CTo", "rate");

  bool allOk = true;
  for (double size : opt.Sizes)
  {
    // Two triangles per cell: n^2 cells for about `size` triangles.
    const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(size / 2.0))));
    vtkNew<vtkSampledSurfaceSource> source;
    source->SetSurfaceToFranke();
    source->SetDomainToGrid();
    source->SetResolution(n);
    bool ok = true;
    const double tSource = Best(
      opt.Has("source") ? opt.Repeat : 1,
      [&] {
        source->Modified();
        return source->GetExecutive()->Update() != 0;
      },
      ok);
    allOk = allOk && ok;
    vtkNew<vtkPolyData> mesh;
    mesh->ShallowCopy(source->GetOutput());
    const long long nT = mesh->GetNumberOfPolys();
    if (!ok || nT == 0)
    {
      std::fprintf(stderr, "vtkSampledSurfaceSource failed for resolution %d\n", n);
      return 1;
    }
    if (opt.Has("source"))
    {
      Row(nT, "source (Franke grid)", tSource, nT, "tri/s");
    }

    double tCTo = 0.0;
    if (opt.Has("spline"))
    {
      for (const std::string& name : opt.Constructions)
      {
        const int c = ConstructionId(name);
        const double t = TimeSpline(mesh, c, 0, opt.Repeat, ok);
        allOk = allOk && ok;
        if (c == vtkCloughTocherSplineFilter::CTo)
        {
          tCTo = t;
        }
        Row(nT, "spline " + name, t, nT, "tri/s", true, tCTo > 0.0 ? t / tCTo : 0.0);
      }
    }
    if (opt.Has("im"))
    {
      const double t0 = TimeSpline(mesh, vtkCloughTocherSplineFilter::CTi, 0, opt.Repeat, ok);
      allOk = allOk && ok;
      const double tN =
        TimeSpline(mesh, vtkCloughTocherSplineFilter::CTi, opt.IMSteps, opt.Repeat, ok);
      allOk = allOk && ok;
      // Differences of two noisy minima can be tiny or negative on a loaded machine.
      const double step = std::max(tN - t0, 1e-9) / opt.IMSteps;
      Row(nT, "IM step (CTi, " + std::to_string(opt.IMSteps) + " vs 0)", step, nT, "tri/s", true,
        tCTo > 0.0 ? step / tCTo : 0.0);
    }
    vtkSmartPointer<vtkUnstructuredGrid> ctiSpline;
    if (opt.Has("tessellate") || opt.Has("probe"))
    {
      TimeSpline(mesh, vtkCloughTocherSplineFilter::CTi, 0, 1, ok, &ctiSpline);
      allOk = allOk && ok;
    }

#ifdef CTSPLINES_HAVE_TESSELLATOR
    if (opt.Has("tessellate"))
    {
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
        const double t = Best(
          opt.Repeat,
          [&] {
            tess->Modified();
            return tess->GetExecutive()->Update() != 0;
          },
          ok);
        allOk = allOk && ok;
        Row(nT, stage, t, tess->GetOutput()->GetNumberOfPoints(), "output points/s", false);
      }
    }
#endif

#ifdef CTSPLINES_HAVE_PROBE
    if (opt.Has("probe"))
    {
      const vtkIdType np = static_cast<vtkIdType>(opt.ProbePoints);
      vtkNew<vtkPoints> uv;
      uv->SetDataTypeToDouble();
      uv->SetNumberOfPoints(np);
      std::mt19937_64 rng(12345);
      std::uniform_real_distribution<double> uniform(0.0, 1.0);
      for (vtkIdType i = 0; i < np; ++i)
      {
        const double u = uniform(rng);
        uv->SetPoint(i, u, uniform(rng), 0.0);
      }
      vtkNew<vtkPolyData> queries;
      queries->SetPoints(uv);
      vtkNew<vtkSplineParameterProbe> probe;
      probe->SetInputData(queries);
      probe->SetSourceData(ctiSpline);
      const double t = Best(
        opt.Repeat,
        [&] {
          probe->Modified();
          return probe->GetExecutive()->Update() != 0;
        },
        ok);
      allOk = allOk && ok;
      std::ostringstream stage;
      stage << "probe " << double(np) << " pts (CTi)";
      Row(nT, stage.str(), t, np, "evaluations/s", false);
    }
#endif
  }
#ifndef CTSPLINES_HAVE_TESSELLATOR
  std::printf("\n(vtkBezierTriangleTessellator is not part of this build: no tessellation figures)\n");
#endif
#ifndef CTSPLINES_HAVE_PROBE
  std::printf("\n(vtkSplineParameterProbe is not part of this build: no probe figures)\n");
#endif
  if (!allOk)
  {
    std::fprintf(stderr, "some pipeline updates failed (see the VTK errors above)\n");
    return 1;
  }
  return 0;
}
