// SPDX-License-Identifier: GPL-3.0-or-later
// Support of ctsplines_benchmark: the machine's bounds measured on the spot, peak resident
// memory of a call, and the random Delaunay mesh of the SciPy/Matplotlib comparisons.
#ifndef CTSplines_BenchmarkSupport_h
#define CTSplines_BenchmarkSupport_h

#include "BezierTriangle.h"
#include "DelaunayTriangulation.h"
#include "LargeArrays.h"

#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace bench
{
/// What Seconds measures: wall-clock time; this process' CPU time (all its threads: on a machine
/// shared with other jobs, one thread's CPU time is its work); or its user CPU time, which leaves
/// out the kernel's zeroing of fresh pages (on a VM, that varies several-fold with what the host
/// did with the memory: the steadier measure of a change to the code).
enum class Clock
{
  Wall,
  ProcessCpu,
  User
};
inline Clock& BenchmarkClock()
{
  static Clock clock = Clock::Wall;
  return clock;
}
inline const char* ClockName()
{
  return BenchmarkClock() == Clock::Wall
    ? "wall-clock"
    : (BenchmarkClock() == Clock::ProcessCpu ? "process CPU" : "process user CPU");
}

inline double Seconds(const std::function<void()>& run)
{
  if (BenchmarkClock() == Clock::Wall)
  {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  auto now = [] {
    if (BenchmarkClock() == Clock::User)
    {
      rusage usage;
      getrusage(RUSAGE_SELF, &usage);
      return double(usage.ru_utime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec);
    }
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
  const double t0 = now();
  run();
  return now() - t0;
}

/// Best of `repeat` timings of run.
inline double BestSeconds(int repeat, const std::function<void()>& run)
{
  double best = 1e300;
  for (int r = 0; r < repeat; ++r)
  {
    best = std::min(best, Seconds(run));
  }
  return best;
}

struct MachineBounds
{
  double CopyGBs = 0;       // bytes copied per second (buffer size / time), warm buffers
  double FirstTouchGBs = 0; // bytes per second writing fresh (never touched) huge-page memory
  double JetSeconds = 0;    // one cubic Bézier jet (value, d/du, d/dv) with unit normal
};

/// Measures the bounds on `bytes`-sized buffers, best of `repeat`.
inline MachineBounds MeasureBounds(std::size_t bytes = std::size_t(256) << 20, int repeat = 5)
{
  // With user time, the first touch (the kernel zeroing pages) would look free: the bounds are
  // then measured in process CPU time.
  const Clock clock = BenchmarkClock();
  BenchmarkClock() = clock == Clock::User ? Clock::ProcessCpu : clock;
  struct Restore
  {
    Clock Saved;
    ~Restore() { BenchmarkClock() = this->Saved; }
  } restore{ clock };
  MachineBounds b;
  std::vector<char> src(bytes, 1), dst(bytes, 2);
  b.CopyGBs = 1e-9 * double(bytes) /
    BestSeconds(repeat, [&] { std::memcpy(dst.data(), src.data(), bytes); });
  double firstTouch = 1e300;
  for (int r = 0; r < repeat; ++r)
  {
    // Fresh anonymous pages each time: the page faults and the kernel's zeroing are the cost.
    void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED)
    {
      break;
    }
    ctk::AdviseHugePages(p, bytes);
    firstTouch = std::min(firstTouch, Seconds([&] { std::memset(p, 3, bytes); }));
    munmap(p, bytes);
  }
  b.FirstTouchGBs = 1e-9 * double(bytes) / firstTouch;

  // Jets on a few cached nets at random points: the evaluation itself, no memory traffic.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  constexpr int nets = 16, evaluations = 1 << 20;
  std::vector<ctk::Vec3> P(10 * nets);
  for (ctk::Vec3& x : P)
  {
    x = ctk::Vec3(U(rng), U(rng), U(rng));
  }
  std::vector<ctk::Vec3> w(1024);
  for (ctk::Vec3& x : w)
  {
    const double a = U(rng), c = U(rng) * (1 - a);
    x = ctk::Vec3(a, c, 1 - a - c);
  }
  const ctk::Vec2 A0(0, 0), A1(1, 0), A2(0.3, 0.8);
  double sink = 0;
  b.JetSeconds = BestSeconds(repeat, [&] {
    for (int i = 0; i < evaluations; ++i)
    {
      const ctk::ParametricJet j =
        ctk::EvaluateOverDomain(3, &P[10 * (i % nets)], nullptr, A0, A1, A2, w[i % 1024], 1);
      sink += j.Value.x() + j.Du.cross(j.Dv).normalized().z();
    }
  }) / evaluations;
  if (sink == 0.123)
  {
    b.JetSeconds += 1e-30; // keeps the loop
  }
  return b;
}

/// A /proc/self/status field in bytes (VmRSS, VmHWM), or -1.
inline double StatusBytes(const std::string& field)
{
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
  {
    if (line.compare(0, field.size() + 1, field + ":") == 0)
    {
      return 1024.0 * std::stod(line.substr(field.size() + 1));
    }
  }
  return -1;
}

/// Peak resident memory added by run() over the resident memory before it, in bytes (Linux:
/// resets the high-water mark through /proc/self/clear_refs); -1 when that is unavailable.
inline double PeakExtraBytes(const std::function<void()>& run)
{
  {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    if (!clear)
    {
      return -1;
    }
  }
  const double before = StatusBytes("VmRSS");
  run();
  const double peak = StatusBytes("VmHWM");
  return before < 0 || peak < 0 ? -1 : peak - before;
}

/// A triangle mesh with per-vertex (u, v), positions and derivatives, row-major.
struct SampledMesh
{
  std::vector<std::int64_t> Triangles; // #T by 3
  std::vector<double> UV, F, Fu, Fv;   // #V by 2, 3, 3, 3
  std::vector<double> EdgeGradients;   // #T by 18: f_u, f_v at the midpoints of the local edges
};

/// z = sin 3x cos 2y of the Delaunay benchmarks: position, d/du and d/dv of (x, y, z).
inline void SineCosine(double x, double y, double* f, double* fu, double* fv)
{
  const double s3 = std::sin(3 * x), c3 = std::cos(3 * x), s2 = std::sin(2 * y),
               c2 = std::cos(2 * y);
  const double values[9] = { x, y, s3 * c2, 1, 0, 3 * c3 * c2, 0, 1, -2 * s3 * s2 };
  std::copy_n(values, 3, f);
  std::copy_n(values + 3, 3, fu);
  std::copy_n(values + 6, 3, fv);
}

/// The Delaunay triangulation of `points` uniform random points of [0, 1]^2 (seeded), numbered
/// as a user gets it: vertices in the points' (random) order, triangles in the triangulation's
/// iteration order, counter-clockwise; z = sin 3x cos 2y with its exact gradient.
inline SampledMesh RandomDelaunayMesh(std::int64_t points, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  SampledMesh m;
  m.UV.resize(2 * points);
  for (std::int64_t i = 0; i < points; ++i)
  {
    m.UV[2 * i] = U(rng); // x before y, as drawn since the first benchmarks
    m.UV[2 * i + 1] = U(rng);
  }
  m.F.resize(3 * points);
  m.Fu.resize(3 * points);
  m.Fv.resize(3 * points);
  for (std::int64_t i = 0; i < points; ++i)
  {
    SineCosine(m.UV[2 * i], m.UV[2 * i + 1], &m.F[3 * i], &m.Fu[3 * i], &m.Fv[3 * i]);
  }
  m.Triangles = ctk::DelaunayTriangulation(m.UV);
  const std::size_t nT = m.Triangles.size() / 3;
  m.EdgeGradients.resize(18 * nT);
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int l = 0; l < 3; ++l)
    {
      const std::int64_t a = m.Triangles[3 * t + l], b = m.Triangles[3 * t + (l + 1) % 3];
      double f[3];
      double* g = &m.EdgeGradients[18 * t + 6 * l];
      SineCosine((m.UV[2 * a] + m.UV[2 * b]) / 2, (m.UV[2 * a + 1] + m.UV[2 * b + 1]) / 2, f, g,
        g + 3);
    }
  }
  return m;
}

/// 2 x 16-bit Morton key of (u, v) in the box [lo, hi].
inline std::uint32_t MortonKey(double u, double v, const double lo[2], const double hi[2])
{
  auto spread = [](std::uint32_t x) {
    x = (x | (x << 8)) & 0x00FF00FFu;
    x = (x | (x << 4)) & 0x0F0F0F0Fu;
    x = (x | (x << 2)) & 0x33333333u;
    return (x | (x << 1)) & 0x55555555u;
  };
  auto cell = [](double x, double a, double b) {
    return static_cast<std::uint32_t>(std::clamp((x - a) / (b - a), 0.0, 1.0) * 65535.0);
  };
  return spread(cell(u, lo[0], hi[0])) | (spread(cell(v, lo[1], hi[1])) << 1);
}

/// Renumbers vertices and triangles of m by the Morton keys of their (u, v) (of a triangle: its
/// centroid's); the vertex order within each triangle is kept.
inline void MortonRenumber(SampledMesh& m)
{
  const std::int64_t nV = static_cast<std::int64_t>(m.UV.size() / 2);
  const std::int64_t nT = static_cast<std::int64_t>(m.Triangles.size() / 3);
  double lo[2] = { 1e300, 1e300 }, hi[2] = { -1e300, -1e300 };
  for (std::int64_t v = 0; v < nV; ++v)
  {
    for (int c = 0; c < 2; ++c)
    {
      lo[c] = std::min(lo[c], m.UV[2 * v + c]);
      hi[c] = std::max(hi[c], m.UV[2 * v + c]);
    }
  }
  auto order = [](std::int64_t n, const std::function<std::uint32_t(std::int64_t)>& key) {
    std::vector<std::pair<std::uint32_t, std::int64_t>> keyed(n);
    for (std::int64_t i = 0; i < n; ++i)
    {
      keyed[i] = { key(i), i };
    }
    std::sort(keyed.begin(), keyed.end());
    return keyed;
  };
  const auto vertices =
    order(nV, [&](std::int64_t v) { return MortonKey(m.UV[2 * v], m.UV[2 * v + 1], lo, hi); });
  std::vector<std::int64_t> newId(nV);
  SampledMesh r;
  r.UV.resize(m.UV.size());
  r.F.resize(m.F.size());
  r.Fu.resize(m.Fu.size());
  r.Fv.resize(m.Fv.size());
  for (std::int64_t k = 0; k < nV; ++k)
  {
    const std::int64_t v = vertices[k].second;
    newId[v] = k;
    std::copy_n(&m.UV[2 * v], 2, &r.UV[2 * k]);
    std::copy_n(&m.F[3 * v], 3, &r.F[3 * k]);
    std::copy_n(&m.Fu[3 * v], 3, &r.Fu[3 * k]);
    std::copy_n(&m.Fv[3 * v], 3, &r.Fv[3 * k]);
  }
  const auto triangles = order(nT, [&](std::int64_t t) {
    const std::int64_t* p = &m.Triangles[3 * t];
    return MortonKey((m.UV[2 * p[0]] + m.UV[2 * p[1]] + m.UV[2 * p[2]]) / 3,
      (m.UV[2 * p[0] + 1] + m.UV[2 * p[1] + 1] + m.UV[2 * p[2] + 1]) / 3, lo, hi);
  });
  r.Triangles.resize(m.Triangles.size());
  r.EdgeGradients.resize(m.EdgeGradients.size());
  for (std::int64_t k = 0; k < nT; ++k)
  {
    const std::int64_t t = triangles[k].second;
    for (int l = 0; l < 3; ++l)
    {
      r.Triangles[3 * k + l] = newId[m.Triangles[3 * t + l]];
    }
    if (!m.EdgeGradients.empty())
    {
      std::copy_n(&m.EdgeGradients[18 * t], 18, &r.EdgeGradients[18 * k]);
    }
  }
  m = std::move(r);
}
} // namespace bench

#endif
