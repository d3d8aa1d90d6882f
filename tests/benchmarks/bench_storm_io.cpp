// SPDX-License-Identifier: GPL-3.0-or-later
// Storm-file I/O benchmark (docs/storm-file.md): write and read the seed-000 grid (100 x 750
// voxels of 0.05 m) for N records of a smooth irregular wave, for several deflate levels, and
// extrapolate to a one-hour storm sampled every 0.05 s (72 000 records).
//
//   bench_storm_io [--records 400] [--deflate 0,1,4] [--double] [--noise 0.01] [--coverage 1]
//                  [--dir /tmp] [--keep] [--no-open-test]
//
// Per deflate level: MB on disk per record, write time per record (StormWriter::append, the field
// synthesis excluded), read time per record in the solver's pattern (StormReader::read of the
// records in sequence, values checked), and the extrapolation to 72 000 records. The read follows
// the write, so the file is in the page cache: a storm file larger than the RAM is read from disk
// at the disk's speed instead (size / bandwidth). The open test writes a one-hour file on a 100 x 2
// grid and times StormReader's constructor (it reads the whole time axis and eta, which do not
// depend on nz). Every value read back is compared with what was written: a benchmark of a wrong
// result is worthless, so a mismatch ends the program with status 2.

#include "storm/StormFile.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace armour::storm;

namespace {

constexpr double kRecordInterval = 0.05;     ///< seed 000: fields sampled every 0.05 s (unit: s)
constexpr std::size_t kStormRecords = 72000; ///< one hour at 0.05 s
constexpr double kRho = 1025.0;              ///< unit: kg/m^3
constexpr double kG = 9.81;                  ///< unit: m/s^2
constexpr double kDepth = 25.0;              ///< still water depth over the bottom of the grid (unit: m)

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// CPU time of the process: on a shared machine the wall time also counts other programs' work.
double cpu() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Wall and CPU time of a stretch of code, accumulated.
struct Stopwatch {
  double wall = 0.0, cpu = 0.0;
  double wall0 = 0.0, cpu0 = 0.0;
  void start() {
    wall0 = now();
    cpu0 = ::cpu();
  }
  void stop() {
    wall += now() - wall0;
    cpu += ::cpu() - cpu0;
  }
};

struct Options {
  std::size_t records = 400;
  std::vector<int> deflate = {0, 1, 4};
  bool doublePrecision = false;
  double noise = 0.01;   ///< relative amplitude of the small-scale noise added to every field (unit: -)
  double coverage = 1.0; ///< fraction of voxels with data, a band of rows around the still water level (unit: -)
  std::string dir = fs::temp_directory_path().string();
  bool keep = false;
  bool openTest = true;
};

/// An irregular linear wave: three components around Tp = 11 s, Hs ~ 7 m (the 100-year storm of
/// seed 000) over a 25 m depth. Smooth in space and time, as the y-averaged CFD fields are.
struct Wave {
  struct Component {
    double a, omega, k, phase;
  };
  std::vector<Component> components;

  Wave() {
    const double periods[3] = {11.0, 8.3, 14.2};
    const double amplitudes[3] = {2.6, 1.3, 1.0};
    const double phases[3] = {0.0, 1.7, 4.1};
    for (int i = 0; i < 3; ++i) {
      const double omega = 2.0 * std::numbers::pi / periods[i];
      double k = omega * omega / kG; // deep water guess, then Newton on w^2 = g k tanh(k h)
      for (int it = 0; it < 50; ++it) {
        const double f = kG * k * std::tanh(k * kDepth) - omega * omega;
        const double df = kG * std::tanh(k * kDepth) + kG * k * kDepth / std::pow(std::cosh(k * kDepth), 2);
        k -= f / df;
      }
      components.push_back({amplitudes[i], omega, k, phases[i]});
    }
  }
};

/// A deterministic hash noise in [-1, 1] per voxel, record and variable (no RNG state to carry).
double noiseAt(std::uint64_t voxel, std::uint64_t record, std::uint64_t variable) {
  std::uint64_t h = voxel * 0x9E3779B97F4A7C15ull ^ (record + 1) * 0xC2B2AE3D27D4EB4Full ^ (variable + 7) * 0x165667B19E3779F9ull;
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  return static_cast<double>(h >> 11) / static_cast<double>(1ull << 52) - 1.0;
}

StormHeader makeHeader(const Options& o) {
  StormHeader h;
  for (int i = 0; i < 100; ++i) {
    h.x.push_back(0.025 + 0.05 * i);
  }
  for (int j = 0; j < 750; ++j) {
    h.z.push_back(-kDepth + 0.025 + 0.05 * j);
  }
  h.samples.assign(h.voxels(), 0);
  // Data in a band of rows around the still water level covering `coverage` of the grid.
  const double half = 0.5 * o.coverage * (h.z.back() - h.z.front() + h.dz());
  const double mid = std::clamp(0.0, h.z.front() + half, h.z.back() - half);
  for (std::size_t iz = 0; iz < h.nz(); ++iz) {
    if (std::abs(h.z[iz] - mid) <= half) {
      for (std::size_t ix = 0; ix < h.nx(); ++ix) {
        h.samples[iz * h.nx() + ix] = 20; // m ~ 20 in seed 000
      }
    }
  }
  h.trunkLength = 44.5;
  h.provenance.title = "bench_storm_io: irregular linear wave, Hs ~ 7 m";
  h.provenance.sourceCase = "synthetic: bench_storm_io";
  h.provenance.command = "bench_storm_io";
  return h;
}

void makeRecord(const StormHeader& h, const Wave& wave, const Options& o, std::size_t k, StormRecord& r) {
  const double t = static_cast<double>(k) * kRecordInterval;
  const std::size_t nx = h.nx();
  r.time = t;
  r.eta.assign(nx, 0.0);
  for (std::size_t ix = 0; ix < nx; ++ix) {
    for (const auto& c : wave.components) {
      r.eta[ix] += c.a * std::cos(c.k * h.x[ix] - c.omega * t + c.phase);
    }
  }
  const std::size_t n = h.voxels();
  r.p.resize(n);
  r.u.resize(n);
  r.w.resize(n);
  r.alpha.resize(n);
  r.v.clear();
  const double pScale = kRho * kG * 1.0;
  for (std::size_t iz = 0; iz < h.nz(); ++iz) {
    const double z = h.z[iz];
    for (std::size_t ix = 0; ix < nx; ++ix) {
      const std::size_t i = iz * nx + ix;
      double pd = 0.0, u = 0.0, w = 0.0;
      for (const auto& c : wave.components) {
        const double theta = c.k * h.x[ix] - c.omega * t + c.phase;
        const double zz = std::min(z, 0.0) + kDepth; // no stretching: hold the SWL value above it
        pd += kRho * kG * c.a * std::cosh(c.k * zz) / std::cosh(c.k * kDepth) * std::cos(theta);
        u += c.a * c.omega * std::cosh(c.k * zz) / std::sinh(c.k * kDepth) * std::cos(theta);
        w += c.a * c.omega * std::sinh(c.k * zz) / std::sinh(c.k * kDepth) * std::sin(theta);
      }
      const double eta = r.eta[ix];
      // Water fraction: the free surface smeared over one voxel, as VOF does.
      const double alpha = std::clamp((eta - z) / h.dz() + 0.5, 0.0, 1.0);
      const double hydro = kRho * kG * (0.0 - z);
      const double eps = o.noise;
      r.p[i] = alpha * (hydro + pd) + eps * pScale * noiseAt(i, k, 0);
      r.u[i] = u * (0.2 + 0.8 * alpha) + eps * noiseAt(i, k, 1);
      r.w[i] = w * (0.2 + 0.8 * alpha) + eps * noiseAt(i, k, 2);
      r.alpha[i] = alpha;
    }
  }
}

struct Figures {
  int deflate = 0;
  double bytesPerRecord = 0;
  Stopwatch write, read, open;
};

[[noreturn]] void invalid(const std::string& why) {
  std::fprintf(stderr, "INVALID: %s\n", why.c_str());
  std::exit(2);
}

Figures runLevel(const Options& o, int level) {
  const auto h = makeHeader(o);
  const Wave wave;
  const auto path = (fs::path(o.dir) / fmt::format("bench_storm_io_{}_d{}.nc", ::getpid(), level)).string();
  StormWriteOptions options;
  options.deflateLevel = level;
  options.doublePrecision = o.doublePrecision;
  options.shuffle = true;

  Figures f;
  f.deflate = level;
  StormRecord r;
  {
    f.write.start();
    StormWriter writer(path, h, options);
    f.write.stop();
    for (std::size_t k = 0; k < o.records; ++k) {
      makeRecord(h, wave, o, k, r); // not timed: the CFD side produces the fields
      f.write.start();
      writer.append(r);
      f.write.stop();
    }
    f.write.start();
    writer.finish();
    f.write.stop();
  }
  f.bytesPerRecord = static_cast<double>(fs::file_size(path)) / static_cast<double>(o.records);

  // Read in the solver's pattern: open, then every record in sequence.
  f.open.start();
  StormReader reader(path);
  f.open.stop();
  StormRecord back, expected;
  for (std::size_t k = 0; k < o.records; ++k) {
    f.read.start();
    reader.read(k, back);
    f.read.stop();
    // Spot-check the values (untimed): float rounding is the only allowed difference.
    if (k % 97 == 0 || k + 1 == o.records) {
      makeRecord(h, wave, o, k, expected);
      for (std::size_t i = 0; i < h.voxels(); i += 13) {
        if (h.samples[i] == 0) {
          if (!std::isnan(back.p[i])) {
            invalid(fmt::format("record {} voxel {}: no data but p = {}", k, i, back.p[i]));
          }
          continue;
        }
        const double want = o.doublePrecision ? expected.p[i] : static_cast<double>(static_cast<float>(expected.p[i]));
        if (back.p[i] != want) {
          invalid(fmt::format("record {} voxel {}: p read {} != written {}", k, i, back.p[i], want));
        }
      }
    }
  }
  if (!o.keep) {
    fs::remove(path);
  } else {
    std::printf("kept %s\n", path.c_str());
  }
  return f;
}

/// A one-hour file on a 100 x 2 grid: the cost of StormReader's constructor (time axis and eta).
void openTest(const Options& o) {
  StormHeader h;
  for (int i = 0; i < 100; ++i) {
    h.x.push_back(0.025 + 0.05 * i);
  }
  h.z = {-0.025, 0.025};
  h.samples.assign(h.voxels(), 1);
  h.trunkLength = 44.5;
  const Wave wave;
  const auto path = (fs::path(o.dir) / fmt::format("bench_storm_io_{}_open.nc", ::getpid())).string();
  StormWriteOptions options;
  options.doublePrecision = o.doublePrecision;
  StormRecord r;
  r.p.assign(h.voxels(), 0.0);
  r.u = r.w = r.p;
  r.alpha.assign(h.voxels(), 1.0);
  r.eta.assign(h.nx(), 0.0);
  Stopwatch write, open;
  write.start();
  {
    StormWriter writer(path, h, options);
    for (std::size_t k = 0; k < kStormRecords; ++k) {
      r.time = static_cast<double>(k) * kRecordInterval;
      for (std::size_t ix = 0; ix < h.nx(); ++ix) {
        double eta = 0.0;
        for (const auto& c : wave.components) {
          eta += c.a * std::cos(c.k * h.x[ix] - c.omega * r.time + c.phase);
        }
        r.eta[ix] = eta;
      }
      writer.append(r);
    }
    writer.finish();
  }
  write.stop();
  open.start();
  StormReader reader(path);
  open.stop();
  if (reader.times().size() != kStormRecords) {
    invalid("the one-hour file does not hold 72000 records");
  }
  std::printf("\nOpen test: one-hour file (72000 records) on a 100 x 2 grid: written in %.1f s, %.2f MB; "
              "StormReader constructor (time axis + eta, %.1f MB in memory) %.3f s (CPU %.3f s)\n",
              write.wall, static_cast<double>(fs::file_size(path)) / 1e6,
              static_cast<double>(kStormRecords * h.nx() * sizeof(double)) / 1e6, open.wall, open.cpu);
  fs::remove(path);
}

} // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"armour storm-file I/O benchmark: write and read the seed-000 voxel grid (docs/storm-file.md)"};
  app.add_option("--records", o.records, "records written and read per deflate level")->check(CLI::Range(2, 1000000));
  app.add_option("--deflate", o.deflate, "deflate levels to compare (0 = none .. 9), e.g. 0,1,4")
      ->delimiter(',')
      ->check(CLI::Range(0, 9));
  app.add_flag("--double", o.doublePrecision, "store data in double instead of float");
  app.add_option("--noise", o.noise, "relative amplitude of the small-scale noise in the fields (0 = smooth)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--coverage", o.coverage, "fraction of voxels with data (a band around the still water level)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--dir", o.dir, "folder for the temporary files");
  app.add_flag("--keep", o.keep, "keep the files written");
  app.add_flag("!--no-open-test", o.openTest, "skip the one-hour open test");
  CLI11_PARSE(app, argc, argv);

  try {
    std::string command = "bench_storm_io";
    for (int i = 1; i < argc; ++i) {
      command += std::string(" ") + argv[i];
    }
    std::printf("%s\n", command.c_str());
    std::printf("grid 100 (x) x 750 (z) voxels, %zu records of %.2f s, %s, shuffle on, noise %.3g, coverage %.2f "
                "(Release build; the read follows the write: page cache)\n\n",
                o.records, kRecordInterval, o.doublePrecision ? "double" : "float", o.noise, o.coverage);
    std::printf("| deflate | MB/record | write ms/record (CPU) | read ms/record (CPU) | open s | 1 h storm: GB | "
                "write min (CPU) | read min (CPU) |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const int level : o.deflate) {
      const auto f = runLevel(o, level);
      const double n = static_cast<double>(o.records);
      const double storm = static_cast<double>(kStormRecords);
      std::printf("| %d | %.3f | %.2f (%.2f) | %.2f (%.2f) | %.3f | %.1f | %.1f (%.1f) | %.1f (%.1f) |\n", level,
                  f.bytesPerRecord / 1e6, 1e3 * f.write.wall / n, 1e3 * f.write.cpu / n, 1e3 * f.read.wall / n,
                  1e3 * f.read.cpu / n, f.open.wall, f.bytesPerRecord * storm / 1e9, f.write.wall / n * storm / 60.0,
                  f.write.cpu / n * storm / 60.0, f.read.wall / n * storm / 60.0, f.read.cpu / n * storm / 60.0);
      std::fflush(stdout);
    }
    if (o.openTest) {
      openTest(o);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
