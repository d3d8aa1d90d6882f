// SPDX-License-Identifier: GPL-3.0-or-later
// Storm-load benchmark (hydro/StormLoads): the armour layer of seed 000 (242 Core-Loc units of
// about 5 m^3, Dn = 1.71 m, 21 rows of 12 and 11 on a 1:1.5 slope along a 44.5 m trunk) in a
// synthetic storm file, timed per load update (pressure integration over every unit's surface
// elements) and per force evaluation between updates (drag, optionally added mass), at 1 and 2
// threads.
//
//   bench_hydro [--units 242] [--volume 5] [--element-size 0.1] [--threads 1,2] [--updates 20]
//               [--evaluations 2000] [--storm airy|still] [--added-mass] [--layer-band T]
//               [--keep-file PATH]
//
// The storm is written once with storm::writeSynthStorm (Airy, H = 4 m, T = 10 s on 14 m of water,
// voxels of 0.1 m; or still water) into a temporary folder. --layer-band T keeps data only in the
// voxels within T metres of the plane of the unit centres, as a 3D tank sampled on the units'
// surfaces (seed 000) has: elements elsewhere take the gap fill (docs/theory.md). Every thread count runs the same
// updates; the loads must be bit-identical across thread counts, or the case prints INVALID and the
// program exits with status 2 (timing a wrong result is worthless). Figures go to
// docs/benchmarks.md with the printed command.

#include "benchmarks/BenchClock.hpp"
#include "core/BuildInfo.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "hydro/StormLoads.hpp"
#include "simulation/World.hpp"
#include "storm/StormSynth.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using armour::simulation::BodySpec;
using armour::simulation::Quat;
using armour::simulation::Vec3;
using armour::simulation::World;

using armour::bench::cpuNow;
using armour::bench::wallNow;

struct Options {
  int units = 242;
  double volume = 5.0;        // m^3
  double elementSize = 0.1;   // x Dn
  std::vector<int> threads = {1, 2};
  int updates = 20;
  int evaluations = 2000;
  std::string storm = "airy";
  bool addedMass = false;
  double layerBand = 0.0; // m; 0: data in every voxel
  std::string keepFile;
};

/// The layer's slope (1:1.5) and the point of its plane of unit centres at the toe (x, z) (m).
constexpr double kSlopeCot = 1.5;
constexpr double kToeX = 8.0, kToeZ = -12.0;

/// The armour layer: rows up a 1:1.5 slope from the toe at (x, z) = (8, -12) m, alternately 12 and
/// 11 units along the trunk, spaced 0.95 Dn up the slope and 2 Dn along y (a loose layer: the
/// bodies do not touch, which does not matter here: only their loads are computed).
void placeUnits(World& world, const Options& o, double dn) {
  armour::simulation::Material concrete;
  concrete.name = "concrete";
  const auto material = world.addMaterial(concrete);
  armour::geometry::ShapeRequest request;
  request.volume = o.volume;
  const auto shape = world.addShape("coreloc", armour::geometry::makeShape("coreloc", request));
  const double theta = std::atan(1.0 / kSlopeCot);
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> normal;
  int placed = 0;
  for (int row = 0; placed < o.units; ++row) {
    const int perRow = row % 2 == 0 ? 12 : 11;
    const double s = 0.95 * dn * row;
    for (int j = 0; j < perRow && placed < o.units; ++j, ++placed) {
      BodySpec b;
      b.name = fmt::format("unit_{:03d}", placed);
      b.shape = shape;
      b.material = material;
      const double y = 2.0 + 2.0 * dn * j + (row % 2 == 0 ? 0.0 : dn);
      b.position = Vec3(kToeX + s * std::cos(theta), y, kToeZ + 0.5 * dn + s * std::sin(theta));
      b.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi * (0.5 + 0.5 * normal(rng)),
                                             Vec3(normal(rng), normal(rng), normal(rng)).normalized()));
      b.velocity = 0.2 * Vec3(normal(rng), normal(rng), normal(rng));
      world.addBody(b);
    }
  }
}

std::string writeStorm(const Options& o, const fs::path& dir, double dn) {
  armour::storm::SynthSettings s;
  s.model = o.storm == "still" ? armour::storm::SynthModel::Still : armour::storm::SynthModel::Airy;
  s.xMin = 0.0;
  s.xMax = 40.0;
  s.zMin = -14.0;
  s.zMax = 10.0;
  s.voxel = 0.1;
  s.stillWaterLevel = 0.0;
  s.depth = 14.0;
  s.duration = 0.1 * (o.updates + 2);
  s.dt = 0.05;
  s.height = 4.0;
  s.period = 10.0;
  s.rampTime = 0.0;
  s.trunkOrigin = 0.0;
  s.trunkLength = 44.5;
  const std::string path = o.keepFile.empty() ? (dir / "storm.nc").string() : o.keepFile;
  armour::storm::StormWriteOptions w;
  w.deflateLevel = 1;
  if (!(o.layerBand > 0.0)) {
    armour::storm::writeSynthStorm(path, s, w, "bench_hydro");
    return path;
  }
  // Data only near the plane of the unit centres (distance along its normal <= layerBand).
  const armour::storm::StormSynth synth(s, "bench_hydro --layer-band");
  armour::storm::StormHeader h = synth.header();
  const double theta = std::atan(1.0 / kSlopeCot);
  for (std::size_t k = 0; k < h.nz(); ++k) {
    for (std::size_t i = 0; i < h.nx(); ++i) {
      const double d = -(h.x[i] - kToeX) * std::sin(theta) + (h.z[k] - kToeZ - 0.5 * dn) * std::cos(theta);
      h.samples[k * h.nx() + i] = std::abs(d) <= o.layerBand ? 1 : 0;
    }
  }
  armour::storm::StormWriter writer(path, h, w);
  armour::storm::StormRecord r;
  for (std::size_t k = 0; k < synth.recordCount(); ++k) {
    synth.record(synth.recordTime(k), r);
    writer.append(r);
  }
  writer.finish();
  return path;
}

struct Result {
  int threads = 0;
  double constructSeconds = 0.0;
  double updateSeconds = 0.0;   // per update
  double evaluationSeconds = 0.0; // per force evaluation without update
  double readSeconds = 0.0;     // per update: reading the storm records it needs (serial)
  double cpuPerWall = 0.0;      // over the updates
  armour::hydro::StormLoadCounters counters;
  std::vector<Vec3> force, torque;
};

Result run(const World& world, const armour::hydro::StormLoadSettings& settings,
           std::shared_ptr<const armour::storm::StormReader> reader, const Options& o, int threads) {
  omp_set_num_threads(threads);
  Result r;
  r.threads = threads;
  double t0 = wallNow();
  armour::hydro::StormLoads stage(world, settings, "unit_", reader);
  r.constructSeconds = wallNow() - t0;
  std::vector<Vec3> force(world.bodies().size()), torque(world.bodies().size());
  // Updates: each apply at k x interval recomputes the loads of every unit (plus one cheap
  // evaluation of drag, included).
  t0 = wallNow();
  const double c0 = cpuNow();
  for (int k = 0; k < o.updates; ++k) {
    std::fill(force.begin(), force.end(), Vec3::Zero());
    std::fill(torque.begin(), torque.end(), Vec3::Zero());
    stage.apply(world, k * settings.updateInterval, force, torque);
  }
  r.cpuPerWall = (cpuNow() - c0) / (wallNow() - t0);
  r.updateSeconds = (wallNow() - t0) / o.updates;
  r.counters = stage.counters();
  // The serial part of an update: the sampler reads the records around the new time (netCDF,
  // decompression). Timed alone on a fresh sampler over the same times.
  {
    armour::storm::StormSampler sampler(*reader);
    t0 = wallNow();
    for (int k = 0; k < o.updates; ++k) {
      sampler.setTime(k * settings.updateInterval + settings.timeOffset);
    }
    r.readSeconds = (wallNow() - t0) / o.updates;
  }
  // Force evaluations between updates: drag (and added mass) from the held quantities.
  const double base = (o.updates - 1) * settings.updateInterval;
  t0 = wallNow();
  for (int i = 0; i < o.evaluations; ++i) {
    std::fill(force.begin(), force.end(), Vec3::Zero());
    std::fill(torque.begin(), torque.end(), Vec3::Zero());
    stage.apply(world, base + 0.5 * settings.updateInterval * i / o.evaluations, force, torque);
  }
  r.evaluationSeconds = (wallNow() - t0) / o.evaluations;
  r.force = force;
  r.torque = torque;
  return r;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Storm-load benchmark: pressure integration and Morison drag on an armour layer"};
  Options o;
  app.add_option("--units", o.units, "number of Core-Loc units")->check(CLI::Range(1, 100000));
  app.add_option("--volume", o.volume, "unit volume (m^3)")->check(CLI::PositiveNumber);
  app.add_option("--element-size", o.elementSize, "surface element edge / Dn")->check(CLI::PositiveNumber);
  app.add_option("--threads", o.threads, "thread counts")->delimiter(',');
  app.add_option("--updates", o.updates, "load updates timed")->check(CLI::Range(2, 100000));
  app.add_option("--evaluations", o.evaluations, "force evaluations between updates timed")
      ->check(CLI::Range(1, 10000000));
  app.add_option("--storm", o.storm, "synthetic storm")->check(CLI::IsMember({"airy", "still"}));
  app.add_flag("--added-mass", o.addedMass, "added mass on (C_a = 1)");
  app.add_option("--layer-band", o.layerBand,
                 "keep data only within this distance of the layer's plane (m), as a 3D tank's file; 0: everywhere")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--keep-file", o.keepFile, "write the storm file here and keep it");
  CLI11_PARSE(app, argc, argv);

  std::string command = "bench_hydro";
  for (int i = 1; i < argc; ++i) {
    command += " ";
    command += argv[i];
  }
  const fs::path dir = fs::temp_directory_path() / fmt::format("armour_bench_hydro_{}", ::getpid());
  fs::create_directories(dir);
  int status = 0;
  try {
    const double dn = std::cbrt(o.volume);
    World world;
    placeUnits(world, o, dn);
    double t0 = wallNow();
    const std::string path = writeStorm(o, dir, dn);
    const double writeSeconds = wallNow() - t0;
    auto reader = std::make_shared<const armour::storm::StormReader>(path);
    const auto& h = reader->header();
    armour::hydro::StormLoadSettings settings;
    settings.file = path;
    settings.elementSizePerDn = o.elementSize;
    settings.addedMass.enabled = o.addedMass;
    settings.variability.enabled = false;

    fmt::print("# bench_hydro: {}\n", armour::core::buildInfo());
    fmt::print("command: {}\n", command);
    fmt::print("storm: {} {} x {} voxels of {:.3g} m, {} records ({:.1f} s to write)\n", o.storm, h.nx(), h.nz(),
               h.dx(), reader->times().size(), writeSeconds);
    fmt::print("units: {} Core-Loc of {} m^3 (Dn {:.3f} m), elements of <= {} Dn\n\n", o.units, o.volume, dn,
               o.elementSize);

    std::vector<Result> results;
    for (const int t : o.threads) {
      results.push_back(run(world, settings, reader, o, t));
    }
    {
      armour::hydro::StormLoads probe(world, settings, "unit_", reader);
      const auto& e = probe.elements(world.bodyShape(0));
      fmt::print("surface elements per unit: {} (area {:.3f} m^2 at scale 1; mean element {:.4f} m^2)\n", e.size(),
                 e.totalArea, e.totalArea / static_cast<double>(e.size()));
      fmt::print("projected-area table: {} ({} directions)\n\n",
                 probe.areaTable(world.bodyShape(0)).exact() ? "exact" : "rasterised",
                 probe.areaTable(world.bodyShape(0)).directions());
    }
    fmt::print("| threads | build stage (s) | per update (ms) | cpu/wall | of which reading records (ms) | "
               "elements sampled | wet (of which gap fill) | bodies evaluated / skipped | ns per element (integration only) | "
               "per force evaluation between updates (us) |\n");
    fmt::print("|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Result& r : results) {
      fmt::print("| {} | {:.3f} | {:.2f} | {:.2f} | {:.2f} | {} | {} ({}) | {} / {} | {:.1f} | {:.2f} |\n", r.threads,
                 r.constructSeconds, 1e3 * r.updateSeconds, r.cpuPerWall, 1e3 * r.readSeconds,
                 r.counters.evaluatedElements,
                 r.counters.wetElements, r.counters.filledElements, r.counters.evaluatedBodies, r.counters.skippedBodies,
                 1e9 * (r.updateSeconds - r.readSeconds) /
                     std::max<double>(1.0, static_cast<double>(r.counters.evaluatedElements)),
                 1e6 * r.evaluationSeconds);
    }
    for (std::size_t i = 1; i < results.size(); ++i) {
      if (results[i].force != results[0].force || results[i].torque != results[0].torque) {
        fmt::print("INVALID: the loads at {} and {} threads differ\n", results[0].threads, results[i].threads);
        status = 2;
      }
    }
    if (o.layerBand > 0.0) {
      // What the gaps cost in accuracy: the same updates on the file with data everywhere.
      Options full = o;
      full.layerBand = 0.0;
      full.keepFile = (dir / "full.nc").string();
      auto fullReader = std::make_shared<const armour::storm::StormReader>(writeStorm(full, dir, dn));
      armour::hydro::StormLoadSettings fullSettings = settings;
      fullSettings.file = full.keepFile;
      const Result reference = run(world, fullSettings, fullReader, full, o.threads.front());
      double diff = 0.0, norm = 0.0, worst = 0.0;
      for (std::size_t b = 0; b < reference.force.size(); ++b) {
        const double d = (results[0].force[b] - reference.force[b]).norm();
        diff += d * d;
        norm += reference.force[b].squaredNorm();
        worst = std::max(worst, d / std::max(1e-30, reference.force[b].norm()));
      }
      fmt::print("\ngap fill against data everywhere (last evaluation): rms force difference {:.2f} % of the rms "
                 "force, largest unit {:.2f} %\n",
                 100.0 * std::sqrt(diff / std::max(1e-30, norm)), 100.0 * worst);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_hydro: {}\n", e.what());
    status = 1;
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  return status;
}
