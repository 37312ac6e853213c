// SPDX-License-Identifier: GPL-3.0-or-later
// Decoding of fuzzer bytes shared by the targets (make_seed_corpus.py writes the same format).
// Reads past the end give zeros, so every input decodes to something.
//
// Value encoding (Value()): a tag byte t, then
//   t < 240          int16 (little endian) / 256: the grid of ordinary values, |x| <= 128;
//   240 <= t < 248   a special value: 0, NaN, +Inf, -Inf, 1e300, -1e300, 1e-310 (denormal), 1e150;
//   t >= 248         a raw little-endian double (any bit pattern).
// Violations (a crash class the sanitizers do not see, e.g. Ok with NaN output) abort through
// Finding(), which libFuzzer reports as a crash with the message.
#ifndef CTSplines_FuzzInput_h
#define CTSplines_FuzzInput_h

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <cstring>
#include <exception>
#include <limits>
#include <map>
#include <string>

namespace ctsplines_fuzz
{
class FuzzInput
{
public:
  FuzzInput(const std::uint8_t* data, std::size_t size)
    : Data(data)
    , Size(size)
  {
  }

  std::uint8_t Byte() { return this->Position < this->Size ? this->Data[this->Position++] : 0; }

  /// A byte mapped to [0, n) (n > 0).
  int Choice(int n) { return this->Byte() % n; }

  bool Flag(std::uint8_t flags, int bit) const { return (flags >> bit) & 1; }

  double Value()
  {
    const double x = this->DecodeValue();
    if (std::isfinite(x))
    {
      this->MaxAbs = std::max(this->MaxAbs, std::abs(x));
    }
    else
    {
      this->NonFinite = true;
    }
    return x;
  }

  /// Largest finite |value| decoded, and whether a non-finite one was.
  double MaxAbs = 0.0;
  bool NonFinite = false;

  /// The bytes not read yet.
  const std::uint8_t* Rest() const { return this->Data + this->Position; }
  std::size_t RestSize() const
  {
    return this->Position < this->Size ? this->Size - this->Position : 0;
  }

private:
  double DecodeValue()
  {
    const std::uint8_t tag = this->Byte();
    if (tag < 240)
    {
      const std::uint16_t bits = static_cast<std::uint16_t>(this->Byte() | (this->Byte() << 8));
      return static_cast<std::int16_t>(bits) / 256.0;
    }
    if (tag < 248)
    {
      static const double specials[8] = { 0.0, std::numeric_limits<double>::quiet_NaN(),
        std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), 1e300,
        -1e300, 1e-310, 1e150 };
      return specials[tag - 240];
    }
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i)
    {
      bits |= static_cast<std::uint64_t>(this->Byte()) << (8 * i);
    }
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }

  const std::uint8_t* Data;
  std::size_t Size;
  std::size_t Position = 0;
};

/// With CTSPLINES_FUZZ_VERBOSE set, prints what a step answered (to check that seeds get deep).
inline void Trace(const char* step, bool ok, const std::string& message)
{
  static const bool verbose = std::getenv("CTSPLINES_FUZZ_VERBOSE") != nullptr;
  if (verbose)
  {
    std::fprintf(stderr, "%s: %s %s\n", step, ok ? "ok" : "failed", message.c_str());
  }
}

/// The input being run, for NonFatalFinding.
struct CurrentInput
{
  const std::uint8_t* Data = nullptr;
  std::size_t Size = 0;
};
inline CurrentInput& Current()
{
  static CurrentInput input;
  return input;
}

/// With CTSPLINES_FUZZ_NONFATAL_DIR set, a finding writes the input to
/// <dir>/<message>-<size>-<hash> and the run goes on (a campaign can then pass a known class
/// still being fixed); returns whether it did.
inline bool NonFatalFinding(const char* what)
{
  static const char* dir = std::getenv("CTSPLINES_FUZZ_NONFATAL_DIR");
  static std::map<std::string, int> saved;
  if (!dir)
  {
    return false;
  }
  if (++saved[what] > 20)
  {
    return true; // enough reproducers of this one in this process
  }
  std::uint64_t hash = 1469598103934665603ull;
  for (std::size_t i = 0; i < Current().Size; ++i)
  {
    hash = (hash ^ Current().Data[i]) * 1099511628211ull;
  }
  std::string name(what);
  for (char& c : name)
  {
    c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  }
  const std::string path = std::string(dir) + "/" + name + "-" + std::to_string(Current().Size) +
    "-" + std::to_string(hash % 1000000007ull);
  if (std::FILE* file = std::fopen(path.c_str(), "wb"))
  {
    std::fwrite(Current().Data, 1, Current().Size, file);
    std::fclose(file);
  }
  return true;
}

/// A property the code promises was broken: report and abort (libFuzzer saves the input).
/// Callers return after it (it returns only for NonFatalFinding).
inline void Finding(const char* what, long long index)
{
  std::fprintf(stderr, "==CTSplines fuzz finding== %s (index %lld)\n", what, index);
  if (!NonFatalFinding(what))
  {
    std::abort();
  }
}

/// Runs one input; an exception escaping the code under test (e.g. a CGAL precondition) is a
/// finding like a crash.
inline int RunGuarded(const std::uint8_t* bytes, std::size_t size,
  int (*run)(const std::uint8_t*, std::size_t))
{
  Current() = { bytes, size };
  try
  {
    return run(bytes, size);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s\n", e.what());
    std::string what = std::string("uncaught exception ") + e.what();
    Finding(what.substr(0, 80).c_str(), 0);
  }
  return 0;
}

template <typename Vector>
void RequireFinite(const Vector& values, const char* what)
{
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    if (!values[i].allFinite())
    {
      Finding(what, static_cast<long long>(i));
      return;
    }
  }
}
} // namespace ctsplines_fuzz

#endif
