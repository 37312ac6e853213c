// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_cad_mutants OUTDIR SEED COUNT FILE...: writes COUNT seeded mutants (CADMutants.h) of
// each FILE to OUTDIR as <file stem>.<index>.<kind>.<extension> for the mutation campaign
// (cad_mutant_campaign.sh).
#include "CADMutants.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

int main(int argc, char* argv[])
{
  if (argc < 5)
  {
    std::fprintf(stderr, "usage: %s OUTDIR SEED COUNT FILE...\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const std::uint64_t seed = std::strtoull(argv[2], nullptr, 10);
  const long count = std::strtol(argv[3], nullptr, 10);
  for (int a = 4; a < argc; ++a)
  {
    const std::string file = argv[a];
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in || text.str().empty())
    {
      std::fprintf(stderr, "cannot read %s\n", file.c_str());
      return 1;
    }
    const std::size_t slash = file.find_last_of('/'), dot = file.find_last_of('.');
    const std::string stem = file.substr(slash == std::string::npos ? 0 : slash + 1, dot - (slash == std::string::npos ? 0 : slash + 1));
    const std::string ext = file.substr(dot);
    for (long i = 0; i < count; ++i)
    {
      const ctsplines_test::Mutant m = ctsplines_test::MakeMutant(text.str(), seed, static_cast<std::uint64_t>(i));
      const std::string path = dir + "/" + stem + "." + std::to_string(i) + "." + m.Kind + ext;
      std::ofstream out(path, std::ios::binary);
      out << m.Text;
      if (!out)
      {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        return 1;
      }
    }
  }
  return 0;
}
