// SPDX-License-Identifier: GPL-3.0-or-later
// Seeded mutants of a STEP or IGES file's text, as an attacker would make them: truncations,
// flipped bytes, deleted or duplicated lines, an entity that refers to itself or to nothing,
// NaN, 1e400 and 1e300 numbers, a flipped byte in an entity keyword, an empty file, garbage.
// Used by vtkCADMutantsTest and by ctsplines_cad_mutants (the campaign, cad_mutant_campaign.sh).
#ifndef CTSplines_IOCAD_Testing_CADMutants_h
#define CTSplines_IOCAD_Testing_CADMutants_h

#include <cstdint>
#include <random>
#include <regex>
#include <string>
#include <vector>

namespace ctsplines_test
{
struct Mutant
{
  std::string Kind;
  std::string Text;
};

inline const std::vector<std::string>& MutationKinds()
{
  static const std::vector<std::string> kinds{ "truncate", "flip-bytes", "delete-line",
    "duplicate-line", "self-reference", "dangling-reference", "nan", "1e400", "1e300",
    "keyword-flip", "swap-lines", "empty", "garbage" };
  return kinds;
}

namespace detail
{
inline std::vector<std::string> Lines(const std::string& text)
{
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size())
  {
    const std::size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end + 1 - start));
    start = end == std::string::npos ? text.size() : end + 1;
  }
  return lines;
}

inline std::string Join(const std::vector<std::string>& lines)
{
  std::string text;
  for (const std::string& l : lines)
  {
    text += l;
  }
  return text;
}

/// The lines that match `pattern`, or every line when none does.
inline std::vector<std::size_t> Matching(const std::vector<std::string>& lines, const std::regex& pattern)
{
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    if (std::regex_search(lines[i], pattern))
    {
      hits.push_back(i);
    }
  }
  if (hits.empty())
  {
    for (std::size_t i = 0; i < lines.size(); ++i)
    {
      hits.push_back(i);
    }
  }
  return hits;
}

/// Replaces one random match of `pattern` in one random line that has one by `replace(match)`.
template <class Replace>
std::string ReplaceOne(const std::string& text, const std::regex& pattern, std::mt19937_64& rng, Replace replace)
{
  std::vector<std::string> lines = Lines(text);
  const std::vector<std::size_t> hits = Matching(lines, pattern);
  std::string& line = lines[hits[rng() % hits.size()]];
  std::vector<std::smatch> matches;
  for (std::sregex_iterator it(line.begin(), line.end(), pattern), end; it != end; ++it)
  {
    matches.push_back(*it);
  }
  if (matches.empty())
  {
    return text;
  }
  const std::smatch& m = matches[rng() % matches.size()];
  line = line.substr(0, m.position(0)) + replace(m, line) + line.substr(m.position(0) + m.length(0));
  return Join(lines);
}
} // namespace detail

/// Mutant `index` of `text` for `seed` (the same file for the same three).
inline Mutant MakeMutant(const std::string& text, std::uint64_t seed, std::uint64_t index)
{
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + index);
  const std::vector<std::string>& kinds = MutationKinds();
  Mutant m{ kinds[rng() % kinds.size()], text };
  if (text.empty())
  {
    return m;
  }
  // A real number (STEP "1.5E-3", "-2.", IGES "1.5D-3"), a reference "#123", a STEP keyword.
  static const std::regex real(R"([-+]?[0-9]+\.[0-9]*([EeDd][-+]?[0-9]+)?)");
  static const std::regex reference(R"(#[0-9]+)");
  static const std::regex keyword(R"([A-Z][A-Z_0-9]{3,}(?=\())");
  static const std::regex entity(R"(^\s*#([0-9]+)\s*=.*#[0-9]+)");
  std::vector<std::string> lines = detail::Lines(text);
  const std::size_t n = lines.size();
  if (m.Kind == "truncate")
  {
    m.Text = text.substr(0, rng() % text.size());
  }
  else if (m.Kind == "flip-bytes")
  {
    for (int k = 1 + static_cast<int>(rng() % 3); k > 0; --k)
    {
      m.Text[rng() % m.Text.size()] ^= static_cast<char>(1u << (rng() % 8));
    }
  }
  else if (m.Kind == "delete-line" || m.Kind == "duplicate-line" || m.Kind == "swap-lines")
  {
    const std::size_t i = rng() % n, j = rng() % n;
    if (m.Kind == "delete-line")
    {
      lines.erase(lines.begin() + static_cast<long>(i));
    }
    else if (m.Kind == "duplicate-line")
    {
      lines.insert(lines.begin() + static_cast<long>(i), lines[i]);
    }
    else
    {
      std::swap(lines[i], lines[j]);
    }
    m.Text = detail::Join(lines);
  }
  else if (m.Kind == "self-reference")
  {
    // An entity one of whose references is replaced by its own id.
    const std::vector<std::size_t> hits = detail::Matching(lines, entity);
    std::string& line = lines[hits[rng() % hits.size()]];
    std::smatch own;
    if (std::regex_search(line, own, entity))
    {
      const std::string id = "#" + own[1].str();
      const std::size_t eq = line.find('=');
      std::vector<std::smatch> refs;
      for (std::sregex_iterator it(line.begin() + static_cast<long>(eq), line.end(), reference), end; it != end; ++it)
      {
        refs.push_back(*it);
      }
      if (!refs.empty())
      {
        const std::smatch& r = refs[rng() % refs.size()];
        const std::size_t at = eq + static_cast<std::size_t>(r.position(0));
        line = line.substr(0, at) + id + line.substr(at + static_cast<std::size_t>(r.length(0)));
      }
    }
    m.Text = detail::Join(lines);
  }
  else if (m.Kind == "dangling-reference")
  {
    m.Text = detail::ReplaceOne(text, reference, rng, [](const std::smatch&, const std::string&) { return std::string("#987654"); });
  }
  else if (m.Kind == "nan" || m.Kind == "1e400" || m.Kind == "1e300")
  {
    const std::string value = m.Kind == "nan" ? "NaN" : m.Kind == "1e400" ? "1.E400" : "-1.E300";
    m.Text = detail::ReplaceOne(text, real, rng, [&](const std::smatch&, const std::string&) { return value; });
  }
  else if (m.Kind == "keyword-flip")
  {
    m.Text = detail::ReplaceOne(text, keyword, rng, [&](const std::smatch& k, const std::string&) {
      std::string s = k.str(0);
      s[rng() % s.size()] ^= static_cast<char>(1u << (rng() % 6));
      return s;
    });
  }
  else if (m.Kind == "empty")
  {
    m.Text.clear();
  }
  else // garbage: random bytes, or the file's own lines shuffled
  {
    if (rng() % 2)
    {
      m.Text.assign(1 + rng() % 4096, '\0');
      for (char& c : m.Text)
      {
        c = static_cast<char>(rng() % 256);
      }
    }
    else
    {
      std::shuffle(lines.begin(), lines.end(), rng);
      m.Text = detail::Join(lines);
    }
  }
  return m;
}

} // namespace ctsplines_test

#endif
