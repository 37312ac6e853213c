// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_cad_benchmark MODEL... [--tolerance REL] [--repeat N] [--construction C]
// Wall-clock figures of the watertight CAD conversion (vtkCADFaceSampler + vtkWatertightSplineStitcher)
// per model: the sampler's stages (read, edges, loops, tangent planes, faces), the stitcher's
// (splines, stitch data, merge, deviation) and end to end, each the best of --repeat runs, with
// the counts and the deviation of the run. A program, not a test: run it by hand, e.g. on
// gmsh-doc's component8.step (IOCAD/Testing/fetch_models.sh fetches it).
#include "vtkCADFaceSampler.h"
#include "vtkWatertightSplineStitcher.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{
double Field(vtkFieldData* fd, const char* name, int i = 0)
{
  vtkDataArray* a = fd->GetArray(name);
  return a && i < a->GetNumberOfTuples() ? a->GetComponent(i, 0) : std::nan("");
}

int Usage(const char* argv0)
{
  std::fprintf(stderr,
    "usage: %s MODEL.step|.igs... [--tolerance REL (1e-4)] [--repeat N (3)] [--construction 0..7 (7, KaG)]\n",
    argv0);
  return 2;
}
} // namespace

int main(int argc, char* argv[])
{
  std::vector<std::string> models;
  double tolerance = 1e-4;
  int repeat = 3, construction = 7;
  for (int i = 1; i < argc; ++i)
  {
    const bool value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--tolerance") && value)
    {
      tolerance = std::atof(argv[++i]);
    }
    else if (!std::strcmp(argv[i], "--repeat") && value)
    {
      repeat = std::max(1, std::atoi(argv[++i]));
    }
    else if (!std::strcmp(argv[i], "--construction") && value)
    {
      construction = std::atoi(argv[++i]);
    }
    else if (argv[i][0] == '-')
    {
      return Usage(argv[0]);
    }
    else
    {
      models.emplace_back(argv[i]);
    }
  }
  if (models.empty() || !(tolerance > 0) || construction < 0 || construction > 7)
  {
    return Usage(argv[0]);
  }
  const char* stages[] = { "read", "edges", "loops", "tangent planes", "faces", "splines",
    "stitch data", "merge", "deviation", "end to end" };
  constexpr int nStages = 10;
  std::printf("tolerance %g of the diagonal, construction %d, best of %d runs [s]\n", tolerance,
    construction, repeat);
  for (const std::string& model : models)
  {
    std::vector<double> best(nStages, HUGE_VAL);
    double faces = 0, triangles = 0, freeEdges = 0, deviation = 0;
    for (int r = 0; r < repeat; ++r)
    {
      vtkNew<vtkCADFaceSampler> sampler;
      sampler->SetFileName(model.c_str());
      sampler->SetTolerance(tolerance);
      sampler->SetConstruction(construction);
      vtkNew<vtkWatertightSplineStitcher> stitcher;
      stitcher->SetInputConnection(sampler->GetOutputPort());
      stitcher->SetConstruction(construction);
      stitcher->SetSurfaceSource(sampler);
      const auto start = std::chrono::steady_clock::now();
      stitcher->Update();
      const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      vtkMultiBlockDataSet* sampled = sampler->GetOutput();
      auto* merged = vtkUnstructuredGrid::SafeDownCast(stitcher->GetOutputDataObject(1));
      if (!merged || merged->GetNumberOfCells() == 0)
      {
        std::fprintf(stderr, "%s: the conversion failed\n", model.c_str());
        return 1;
      }
      double t[nStages];
      for (int k = 0; k < 5; ++k)
      {
        t[k] = Field(sampled->GetFieldData(), "StageTimes", k);
      }
      for (int k = 0; k < 4; ++k)
      {
        t[5 + k] = Field(merged->GetFieldData(), "StageTimes", k);
      }
      t[9] = total;
      for (int k = 0; k < nStages; ++k)
      {
        best[k] = std::min(best[k], t[k]);
      }
      faces = sampled->GetNumberOfBlocks();
      triangles = Field(merged->GetFieldData(), "NumberOfMacroTriangles");
      freeEdges = Field(merged->GetFieldData(), "NumberOfFreeEdges");
      deviation = Field(merged->GetFieldData(), "MaxDeviation");
    }
    std::printf("%s: %g faces, %g triangles, %g free edges, max deviation %.3g\n", model.c_str(),
      faces, triangles, freeEdges, deviation);
    for (int k = 0; k < nStages; ++k)
    {
      std::printf("  %-15s %8.3f\n", stages[k], best[k]);
    }
  }
  return 0;
}
