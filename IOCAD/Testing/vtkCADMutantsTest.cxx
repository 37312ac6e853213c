// SPDX-License-Identifier: GPL-3.0-or-later
// Malformed STEP and IGES files through vtkCADFaceSampler and vtkWatertightSplineStitcher in
// this process: seeded mutants of the box-with-hole model (CADMutants.h) must never crash or
// hang the process; each either converts or fails with RequestData returning 0 and an error
// message. The one-line changes of gmsh-doc's models that crashed OpenCASCADE's translation are
// named cases (skipped when the CAD.FetchModels fixture could not fetch the models).
#include "CADBRepSampling.h"
#include "CADMutants.h"
#include "CADTestFiles.h"
#include "CADTestShapes.h"
#include "ErrorCapture.h"

#include "vtkCADFaceSampler.h"
#include "vtkWatertightSplineStitcher.h"

#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkNew.h"

#include <IGESControl_Controller.hxx>
#include <Standard_ConstructionError.hxx>
#include <Standard_DomainError.hxx>
#include <IGESControl_Writer.hxx>
#include <STEPControl_Writer.hxx>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

namespace
{
using ctsplines_test::ErrorCapture;

std::string ReadText(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteText(const std::string& path, const std::string& text)
{
  std::ofstream(path, std::ios::binary) << text;
}

std::string BoxWithHoleFile(const std::string& ext)
{
  const std::string path = ctsplines_test::TempPath("mutants_box_with_hole" + ext);
  if (ext == ".step")
  {
    STEPControl_Writer writer;
    writer.Transfer(ctsplines_test::BoxWithHole(), STEPControl_AsIs);
    EXPECT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
  }
  else
  {
    IGESControl_Controller::Init();
    IGESControl_Writer writer("MM", 1); // faces as B-rep
    writer.AddShape(ctsplines_test::BoxWithHole());
    writer.ComputeModel();
    EXPECT_TRUE(writer.Write(path.c_str()));
  }
  return path;
}

/// A model fetched by the CAD.FetchModels fixture, or "" (the test is then skipped).
std::string FetchedModel(const std::string& name)
{
  const char* dir = std::getenv("CTSPLINES_CAD_MODELS");
  const std::string path = dir ? std::string(dir) + "/" + name : std::string();
  return !path.empty() && std::ifstream(path).good() ? path : std::string();
}

struct Outcome
{
  bool Converted = false;
  std::string Errors, Warnings;
  double Seconds = 0;
};

/// Sampler and stitcher on `file` at a coarse tolerance; errors and warnings captured (so not
/// printed).
Outcome Convert(const std::string& file, double readTimeout = 5)
{
  Outcome o;
  const auto start = std::chrono::steady_clock::now();
  vtkNew<vtkCADFaceSampler> sampler;
  sampler->SetFileName(file.c_str());
  sampler->SetTolerance(1e-2);
  sampler->SetReadTimeout(readTimeout);
  vtkNew<vtkWatertightSplineStitcher> stitcher;
  stitcher->SetInputConnection(sampler->GetOutputPort());
  stitcher->SetSurfaceSource(sampler);
  auto errors = ErrorCapture::AttachToAlgorithm(sampler);
  auto stitchErrors = ErrorCapture::AttachToAlgorithm(stitcher);
  auto warnings = vtkSmartPointer<ErrorCapture>::New();
  sampler->AddObserver(vtkCommand::WarningEvent, warnings);
  stitcher->AddObserver(vtkCommand::WarningEvent, warnings);
  if (sampler->GetExecutive()->Update())
  {
    o.Converted = stitcher->GetExecutive()->Update() != 0;
  }
  o.Errors = errors->Message + stitchErrors->Message;
  o.Warnings = warnings->Message;
  o.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return o;
}

/// OCCT's reader writes its statistics to stdout (the reading child too): hundreds of mutants'
/// worth are silenced while this lives.
struct QuietStdout
{
  int Saved;
  QuietStdout()
  {
    std::fflush(stdout);
    this->Saved = dup(1);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    close(null);
  }
  ~QuietStdout()
  {
    std::fflush(stdout);
    dup2(this->Saved, 1);
    close(this->Saved);
  }
};

/// `count` mutants of `original`: none may crash (the test would end) or take more than 30 s
/// (OCCT's parser loops on some, now and then: the 5 s read timeout ends those);
/// a mutant that does not convert must say why. Both outcomes must occur.
void RunMutants(const std::string& original, const std::string& ext, std::uint64_t seed, int count)
{
  const std::string text = ReadText(original);
  ASSERT_FALSE(text.empty());
  std::map<std::string, std::pair<int, int>> byKind; // converted, errors
  int converted = 0, failed = 0;
  double slowest = 0;
  std::string slowestMutant;
  {
    QuietStdout quiet;
    for (int i = 0; i < count; ++i)
    {
      const ctsplines_test::Mutant m = ctsplines_test::MakeMutant(text, seed, static_cast<std::uint64_t>(i));
      const std::string path = ctsplines_test::TempPath("mutant_" + std::to_string(i) + ext);
      WriteText(path, m.Text);
      const Outcome o = Convert(path);
      if (o.Seconds > slowest)
      {
        slowest = o.Seconds;
        slowestMutant = std::to_string(i) + " (" + m.Kind + ")";
      }
      EXPECT_LT(o.Seconds, 30) << "mutant " << i << " (" << m.Kind << ")";
      if (o.Converted)
      {
        ++converted;
        ++byKind[m.Kind].first;
      }
      else
      {
        ++failed;
        ++byKind[m.Kind].second;
        EXPECT_FALSE(o.Errors.empty()) << "mutant " << i << " (" << m.Kind << ") failed without an error message";
      }
      std::remove(path.c_str());
    }
  }
  std::ostringstream summary;
  summary << count << " mutants of " << original << ": " << converted << " converted, " << failed
          << " clean errors, slowest " << slowestMutant << " " << slowest << " s; converted/errors by kind:";
  for (const auto& k : byKind)
  {
    summary << " " << k.first << " " << k.second.first << "/" << k.second.second;
  }
  std::printf("%s\n", summary.str().c_str());
  EXPECT_GT(converted, 0) << summary.str();
  EXPECT_GT(failed, 0) << summary.str();
}

/// `text` with its first line that contains `match` replaced by `line` ("" deletes it).
std::string ReplaceLine(const std::string& text, const std::string& match, const std::string& line)
{
  const std::size_t at = text.find(match);
  EXPECT_NE(at, std::string::npos) << match;
  if (at == std::string::npos)
  {
    return text;
  }
  const std::size_t begin = text.rfind('\n', at) + 1, end = text.find('\n', at);
  return text.substr(0, begin) + line + (line.empty() ? "" : "\n") + text.substr(end + 1);
}

/// `name` (fetched) with one line changed, converted: a clean error or a conversion with a
/// warning, never a crash.
Outcome ConvertChanged(const std::string& name, const std::string& match, const std::string& line,
  const std::string& ext)
{
  const std::string model = FetchedModel(name);
  const std::string path = ctsplines_test::TempPath("changed_" + name + ext);
  WriteText(path, ReplaceLine(ReadText(model), match, line));
  QuietStdout quiet;
  Outcome o = Convert(path);
  std::remove(path.c_str());
  return o;
}
} // namespace

/// Under AddressSanitizer, SIGSEGV is the sanitizer's: RunGuarded's OCCT handler is not set.
bool SanitizerHandlesSegfaults()
{
#if defined(__SANITIZE_ADDRESS__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return true;
#endif
#endif
  return false;
}

/// Skips the test when the CAD.FetchModels fixture could not fetch `name`.
#define SKIP_WITHOUT_MODEL(name)                                                                   \
  if (FetchedModel(name).empty())                                                                  \
  GTEST_SKIP() << name << " was not fetched"

TEST(Mutants, BoxWithHoleStep)
{
  RunMutants(BoxWithHoleFile(".step"), ".step", 20261201, 300);
}

TEST(Mutants, BoxWithHoleIges)
{
  RunMutants(BoxWithHoleFile(".igs"), ".igs", 20261202, 200);
}

TEST(Mutants, Component8)
{
  SKIP_WITHOUT_MODEL("component8.step");
  RunMutants(FetchedModel("component8.step"), ".step", 20261203, 100);
}

TEST(Mutants, GuardTurnsOCCTFailuresIntoErrors)
{
  std::string failure;
  EXPECT_TRUE(ctcad::RunGuarded([] {}, failure));
  EXPECT_FALSE(ctcad::RunGuarded([] { throw Standard_ConstructionError("no such circle"); }, failure));
  EXPECT_EQ(failure, "Standard_ConstructionError: no such circle");
  EXPECT_FALSE(ctcad::RunGuarded([] { throw std::range_error("index 7"); }, failure));
  EXPECT_EQ(failure, "std::range_error: index 7");
  if (SanitizerHandlesSegfaults())
  {
    GTEST_SKIP() << "the sanitizer has SIGSEGV: OCCT keeps off it";
  }
  // A segmentation fault inside the guard is OCCT's exception, again and again.
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_FALSE(ctcad::RunGuarded([] { std::raise(SIGSEGV); }, failure));
    EXPECT_EQ(failure.rfind("OSD_SIGSEGV: ", 0), 0u) << failure;
  }
}

TEST(Mutants, NestedGuardsCatchExceptionsInsideAndSignalsOutside)
{
  // Inside a guard, a guard catches OCCT's and standard exceptions itself; the outer one goes on.
  std::string outer, inner, signalled;
  int failures = 0;
  EXPECT_TRUE(ctcad::RunGuarded(
    [&] {
      for (int k = 0; k < 3; ++k)
      {
        failures += !ctcad::RunGuarded([] { throw Standard_DomainError("off the surface"); }, inner);
      }
      failures += !ctcad::RunGuarded([] { throw std::length_error("too long"); }, inner);
    },
    outer));
  EXPECT_EQ(failures, 4);
  EXPECT_EQ(inner, "std::length_error: too long");
  if (SanitizerHandlesSegfaults())
  {
    GTEST_SKIP() << "the sanitizer has SIGSEGV: OCCT keeps off it";
  }
  // A signal inside a nested guard is the outer guard's failure; afterwards a guard on its own
  // catches signals again (its depth was restored).
  for (int k = 0; k < 2; ++k)
  {
    inner.clear();
    EXPECT_FALSE(ctcad::RunGuarded(
      [&] { ctcad::RunGuarded([] { std::raise(SIGSEGV); }, inner); }, signalled));
    EXPECT_EQ(signalled.rfind("OSD_SIGSEGV: ", 0), 0u) << signalled;
    EXPECT_TRUE(inner.empty()) << inner;
    EXPECT_FALSE(ctcad::RunGuarded([] { std::raise(SIGSEGV); }, signalled));
    EXPECT_EQ(signalled.rfind("OSD_SIGSEGV: ", 0), 0u) << signalled;
  }
}

TEST(Mutants, OutOfRangeNumberNamesLineAndEntity)
{
  const std::string text = ReadText(BoxWithHoleFile(".step"));
  const std::string path = ctsplines_test::TempPath("mutant_1e400.step");
  WriteText(path, ReplaceLine(text, "CARTESIAN_POINT", "#7 = CARTESIAN_POINT('',(0.,1.E400,0.));"));
  const Outcome o = Convert(path);
  EXPECT_FALSE(o.Converted);
  EXPECT_NE(o.Errors.find("entity #7: the number 1.E400 is out of the range of a double"), std::string::npos) << o.Errors;
  EXPECT_NE(o.Errors.find(path), std::string::npos) << o.Errors;
}

TEST(Mutants, EmptyAndMissingFiles)
{
  const std::string path = ctsplines_test::TempPath("mutant_empty.stp");
  WriteText(path, "");
  Outcome o = Convert(path);
  EXPECT_FALSE(o.Converted);
  EXPECT_NE(o.Errors.find("the file is empty"), std::string::npos) << o.Errors;
  o = Convert(ctsplines_test::TempPath("no_such_file.igs"));
  EXPECT_FALSE(o.Converted);
  EXPECT_NE(o.Errors.find("cannot read IGES file"), std::string::npos) << o.Errors;
}

TEST(Mutants, ReadTimeoutAbandonsTheTranslation)
{
  // A time limit far below what the translation takes: the child is killed and the read ends
  // with an error naming the file and the timeout, at once.
  const std::string path = BoxWithHoleFile(".step");
  const Outcome o = Convert(path, 1e-4);
  EXPECT_FALSE(o.Converted);
  EXPECT_NE(o.Errors.find("did not end within the read timeout"), std::string::npos) << o.Errors;
  EXPECT_NE(o.Errors.find(path), std::string::npos) << o.Errors;
  EXPECT_LT(o.Seconds, 5);
}

TEST(Mutants, Component8DeletedEdgeLoop)
{
  SKIP_WITHOUT_MODEL("component8.step");
  // Crashed the process in OCCT's translation before (faces refer to the missing loop).
  const Outcome o = ConvertChanged("component8.step", "#142=EDGE_LOOP", "", ".step");
  EXPECT_FALSE(o.Converted);
  EXPECT_NE(o.Errors.find("no faces in"), std::string::npos) << o.Errors;
  // The face bound that refers to the missing loop.
  EXPECT_NE(o.Errors.find("#121: Parameter n0.2 (bound) : Entity has illegal type"), std::string::npos) << o.Errors;
}

TEST(Mutants, Component8EntityReferringToItself)
{
  SKIP_WITHOUT_MODEL("component8.step");
  // An oriented edge that is its own edge element: OCCT's translation recurses until the stack
  // overflows (a crash no signal handler can convert), in the reading child only.
  const Outcome o = ConvertChanged("component8.step", "#179=ORIENTED_EDGE", "#179=ORIENTED_EDGE('',*,*,#179,.T.);", ".step");
  EXPECT_FALSE(o.Converted);
  EXPECT_NE(o.Errors.find("OpenCASCADE's translation crashed"), std::string::npos) << o.Errors;
  EXPECT_NE(o.Errors.find("component8.step"), std::string::npos) << o.Errors;
}

TEST(Mutants, AS1TU203FlippedByteInVectorKeyword)
{
  SKIP_WITHOUT_MODEL("as1-tu-203.stp");
  // component8.step has no VECTOR entity; as1-tu-203.stp's first one, "VECTOR" -> "WECTOR":
  // crashed the process before. OCCT now skips the lines built on it: fewer faces, said.
  const std::string model = FetchedModel("as1-tu-203.stp");
  const std::string text = ReadText(model);
  const std::size_t at = text.find("VECTOR(");
  ASSERT_NE(at, std::string::npos);
  const std::size_t begin = text.rfind('\n', at) + 1;
  std::string line = text.substr(begin, text.find('\n', at) - begin);
  line[at - begin] ^= 1;
  const Outcome o = ConvertChanged("as1-tu-203.stp", text.substr(begin, text.find('\n', at) - begin), line, ".stp");
  if (o.Converted)
  {
    EXPECT_NE(o.Warnings.find("OpenCASCADE's translation failed on"), std::string::npos) << o.Warnings;
    EXPECT_NE(o.Warnings.find("the model may miss faces"), std::string::npos) << o.Warnings;
  }
  else
  {
    EXPECT_FALSE(o.Errors.empty());
  }
}
