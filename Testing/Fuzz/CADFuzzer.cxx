// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target of the CAD import (IOCAD/): the bytes after a one-byte header are written to
// a temporary STEP or IGES file, read and sampled by vtkCADFaceSampler and, when asked, turned
// into splines by vtkWatertightSplineStitcher. An error is a valid answer; a crash, a sanitizer
// report, a hang or non-finite output points are findings.
//
// Header bits: 0 IGES (.igs) instead of STEP (.step), 1 stitch, 2 RestoreG1, 3 refine the
// stitched spline, 4 read in this process (ReadTimeout 0; only with the environment variable
// CTSPLINES_FUZZ_CAD_IN_PROCESS set, since OCCT's own parser crashes are then findings too):
// a sanitizer report in the child
// process of a bounded read only ends that child (the sampler reports an error), so this is how
// memory errors of the reading and sampling code become findings. Settings are coarse (tolerance 1e-2 of the diagonal, few rounds and
// triangles) so that each input takes a fraction of a second.
#include "FuzzVTK.h"

#include "vtkCADFaceSampler.h"
#include "vtkWatertightSplineStitcher.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace
{
using namespace ctsplines_fuzz;

/// Writes the bytes to a new temporary file with the given suffix; returns its path or "".
std::string WriteTemporary(const std::uint8_t* data, std::size_t size, const char* suffix)
{
  std::string path = std::string("/tmp/ctsplines-fuzz-cad-XXXXXX") + suffix;
  const int fd = mkstemps(path.data(), static_cast<int>(std::strlen(suffix)));
  if (fd < 0)
  {
    return "";
  }
  std::size_t written = 0;
  while (written < size)
  {
    const ssize_t n = write(fd, data + written, size - written);
    if (n <= 0)
    {
      break;
    }
    written += static_cast<std::size_t>(n);
  }
  close(fd);
  return path;
}

/// Removes the temporary file however the run ends (but an abort).
struct TemporaryFile
{
  std::string Path;
  ~TemporaryFile()
  {
    if (!this->Path.empty())
    {
      unlink(this->Path.c_str());
    }
  }
};

int RunOne(const std::uint8_t* bytes, std::size_t size)
{
  SilenceVTK();
  if (size < 1)
  {
    return 0;
  }
  const std::uint8_t flags = bytes[0];
  const TemporaryFile file{ WriteTemporary(bytes + 1, size - 1, flags & 1 ? ".igs" : ".step") };
  if (file.Path.empty())
  {
    return 0;
  }
  vtkNew<vtkCADFaceSampler> sampler;
  sampler->SetFileName(file.Path.c_str());
  sampler->SetTolerance(1e-2);
  sampler->SetMaxRounds(2);
  sampler->SetMaxTrianglesPerFace(2000);
  // In-process reading also turns OpenCASCADE's own crashes in its parser into findings (ASan
  // owns SIGSEGV, so OCCT cannot convert them): for campaigns on the reading code only, by
  // CTSPLINES_FUZZ_CAD_IN_PROCESS=1; CI reads in the child, as users do by default.
  static const bool inProcessAllowed = std::getenv("CTSPLINES_FUZZ_CAD_IN_PROCESS") != nullptr;
  sampler->SetReadTimeout(inProcessAllowed && ((flags >> 4) & 1) ? 0.0 : 10.0);
  sampler->SetRestoreG1((flags >> 2) & 1);
  sampler->SetRefineStitchedSpline((flags >> 3) & 1);
  if (RunChecked(sampler, true, "CAD sampler succeeded with a non-finite point") && (flags & 2))
  {
    vtkNew<vtkWatertightSplineStitcher> stitcher;
    stitcher->SetInputConnection(sampler->GetOutputPort());
    stitcher->SetSurfaceSource(sampler);
    stitcher->SetDeviationSamples(2);
    RunChecked(stitcher, true, "stitcher succeeded with a non-finite control point");
  }
  return 0;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* bytes, std::size_t size)
{
  return ctsplines_fuzz::RunGuarded(bytes, size, RunOne);
}
