// SPDX-License-Identifier: GPL-3.0-or-later
// Temporary files of the CAD tests, shared by the test programs.
#ifndef CTSplines_IOCAD_Testing_CADTestFiles_h
#define CTSplines_IOCAD_Testing_CADTestFiles_h

#include <gtest/gtest.h>

#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include <unistd.h>

namespace ctsplines_test
{
/// A path in the temporary directory for `name` (a file name with its extension), unique to this
/// process and removed when it exits. ctest runs the tests of one program as parallel processes
/// (-j2), and two CI jobs may share a machine: with fixed names one test read another's file
/// half written (a STEP file that ended early).
inline std::string TempPath(const std::string& name)
{
  struct Removed
  {
    std::mutex Lock;
    std::vector<std::string> Paths;
    ~Removed()
    {
      for (const std::string& p : this->Paths)
      {
        std::remove(p.c_str());
      }
    }
  };
  static Removed removed;
  const std::string path =
    ::testing::TempDir() + "/ctsplines_" + std::to_string(::getpid()) + "_" + name;
  std::lock_guard<std::mutex> lock(removed.Lock);
  removed.Paths.push_back(path);
  return path;
}
} // namespace ctsplines_test

#endif
