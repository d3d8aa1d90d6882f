// SPDX-License-Identifier: GPL-3.0-or-later
// Speed of foam-bridge's pieces (docs/benchmarks.md, section foam-bridge):
//  - BM_ReadSurface: foam-proxy reading one legacy VTK surface of N quad faces as OpenFOAM v1912's
//    surfaces function object writes it (ASCII, or binary with --binary-vtk semantics), faces/s;
//  - BM_ReadRawSurface: the same surface as `surfaceFormat raw` writes it at writePrecision 15
//    (p, alpha.water, U: three text files of face centres and values), faces/s;
//  - BM_RecordStatistics: the per-record work of the sampler on N faces (voxel sums, means, eta
//    from 1000 cells, deviations into the histograms), the part the function object adds to a time
//    step, faces/s;
//  - BM_WeibullFit: the four fits at the end of a run from the histograms.
//   build/bin/bench_foam_bridge [--benchmark_filter=...]

#include "bridge/VoxelStatistics.hpp"
#include "proxy/SurfaceSeries.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace armour;

namespace {

/// A surface of n quads on a 0.01 m lattice in the x-z plane, with p, alpha (scalar) and U.
fs::path writeSurface(int n, bool binary) {
  const fs::path file = fs::temp_directory_path() /
                        ("bench-foam-bridge-" + std::to_string(n) + (binary ? "b" : "a") + "-" + std::to_string(::getpid()) + ".vtk");
  if (fs::exists(file)) return file;
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int np = (side + 1) * (side + 1);
  std::ofstream f(file, std::ios::binary);
  f << "# vtk DataFile Version 2.0\nbench\n" << (binary ? "BINARY" : "ASCII") << "\nDATASET POLYDATA\n";
  auto putFloat = [&](float v) {
    if (binary) {
      unsigned char b[4];
      std::memcpy(b, &v, 4);
      f.put(static_cast<char>(b[3])).put(static_cast<char>(b[2])).put(static_cast<char>(b[1])).put(static_cast<char>(b[0]));
    } else {
      f << v << ' ';
    }
  };
  auto putInt = [&](int v) {
    if (binary) {
      const unsigned u = static_cast<unsigned>(v);
      f.put(static_cast<char>(u >> 24)).put(static_cast<char>(u >> 16)).put(static_cast<char>(u >> 8)).put(static_cast<char>(u));
    } else {
      f << v << ' ';
    }
  };
  f << "POINTS " << np << " float\n";
  for (int j = 0; j <= side; ++j)
    for (int i = 0; i <= side; ++i) {
      putFloat(0.01f * static_cast<float>(i));
      putFloat(0.5f);
      putFloat(0.01f * static_cast<float>(j));
    }
  f << "\nPOLYGONS " << n << " " << 5 * n << "\n";
  for (int k = 0; k < n; ++k) {
    const int i = k % side, j = k / side;
    putInt(4);
    putInt(j * (side + 1) + i);
    putInt(j * (side + 1) + i + 1);
    putInt((j + 1) * (side + 1) + i + 1);
    putInt((j + 1) * (side + 1) + i);
  }
  f << "\nCELL_DATA " << n << "\nFIELD FieldData 3\np 1 " << n << " float\n";
  for (int k = 0; k < n; ++k) putFloat(1000.0f + static_cast<float>(k % 97));
  f << "\nalpha.water 1 " << n << " float\n";
  for (int k = 0; k < n; ++k) putFloat(1.0f);
  f << "\nU 3 " << n << " float\n";
  for (int k = 0; k < 3 * n; ++k) putFloat(0.1f);
  f << "\n";
  return file;
}

void BM_ReadSurface(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const fs::path file = writeSurface(n, state.range(1) != 0);
  for (auto _ : state) {
    const proxy::Surface s = proxy::readSurface(file);
    benchmark::DoNotOptimize(s.centreX.data());
  }
  state.counters["faces/s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(state.range(1) ? "binary" : "ascii");
}
BENCHMARK(BM_ReadSurface)->Args({10000, 0})->Args({10000, 1})->Args({200000, 0})->Args({200000, 1})->Unit(benchmark::kMillisecond);

/// The raw output of a surface of n faces: <field>_units.raw for p, alpha.water and U, 15 digits.
fs::path writeRawSurface(int n) {
  const fs::path dir = fs::temp_directory_path() / ("bench-foam-bridge-raw-" + std::to_string(n) + "-" + std::to_string(::getpid()));
  if (fs::exists(dir)) return dir;
  fs::create_directories(dir);
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(0.0, 1.0);
  for (const char* field : {"p", "alpha.water", "U"}) {
    std::FILE* f = std::fopen((dir / (std::string(field) + "_units.raw")).c_str(), "w");
    const bool vector = std::strcmp(field, "U") == 0;
    std::fprintf(f, "# %s  FACE_DATA %d\n# x  y  z  %s\n", field, n, vector ? "U_x  U_y  U_z" : field);
    for (int k = 0; k < n; ++k) {
      const double x = 20.0 + 0.01 * (k % side + 0.5), z = -5.0 + 0.01 * (k / side + 0.5);
      std::fprintf(f, "%.15g 22.25 %.15g", x, z);
      if (vector) std::fprintf(f, " %.15g %.15g %.15g\n", jitter(rng), 1e-3 * jitter(rng), -jitter(rng));
      else if (field[0] == 'p') std::fprintf(f, " %.15g\n", 1.2e5 * (1.0 + 0.1 * jitter(rng)));
      else std::fprintf(f, " 1\n");
    }
    std::fclose(f);
  }
  return dir;
}

void BM_ReadRawSurface(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const fs::path dir = writeRawSurface(n);
  for (auto _ : state) {
    const proxy::Surface s = proxy::readSurfaceIn(dir, "units", {"p", "U", "alpha.water"});
    benchmark::DoNotOptimize(s.centreX.data());
  }
  state.counters["faces/s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ReadRawSurface)->Arg(10000)->Arg(200000)->Unit(benchmark::kMillisecond);

void BM_RecordStatistics(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  bridge::SamplerSettings s;
  s.grid.nx = 100;
  s.grid.nz = 750;
  s.grid.xMin = 0.0;
  s.grid.zMin = -25.0;
  s.grid.trunkLength = 44.5;
  bridge::VoxelStatistics stats(s);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ux(0.0, 5.0), uy(0.0, 44.5), uz(-25.0, 12.5), up(0.0, 2e5);
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = ux(rng);
    y[i] = uy(rng);
    z[i] = uz(rng);
  }
  stats.setSamplePoints(x, y, z);
  stats.setCounts(stats.localCounts());
  bridge::SampleValues values;
  values.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    values.p[i] = up(rng);
    values.alpha[i] = 1.0;
  }
  std::vector<double> sums, levels;
  storm::StormRecord record;
  bridge::DeviationHistogram h;
  for (auto _ : state) {
    stats.sums(values, sums);
    stats.initColumnLevels(levels);
    for (int pass = 0; pass < bridge::VoxelStatistics::kEtaPasses; ++pass)
      for (int c = 0; c < 1000; ++c) stats.addEtaCell(pass, levels, 0.005 * c, 0.01 * (c % 50), c % 50 < 25 ? 1.0 : 0.0);
    stats.finishRecord(0.0, sums, levels, true, record);
    stats.addDeviations(values, record, h);
    benchmark::DoNotOptimize(record.p.data());
  }
  state.counters["faces/s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_RecordStatistics)->Arg(10000)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_WeibullFit(benchmark::State& state) {
  bridge::DeviationHistogram h;
  std::mt19937_64 rng(2);
  std::weibull_distribution<double> w(1.6, 500.0);
  for (int i = 0; i < 1000000; ++i) h.add(i % 2 == 0, (i % 3 == 0 ? -1.0 : 1.0) * w(rng));
  for (auto _ : state) benchmark::DoNotOptimize(h.fit(30000.0, 3.0, "bench").classes[0].shape);
}
BENCHMARK(BM_WeibullFit)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
