// SPDX-License-Identifier: GPL-3.0-or-later
// Deformable-body benchmark (deformable/DeformableBody): element-steps per core-second of the
// explicit step (internal forces of every element, the nodal gather, the update) for 4- and
// 10-node tets, at the given thread counts. The body is a 1 x 1 x 4 m concrete bar of n x n x 4n
// cells (6 tets each), base fixed, under gravity, with viscosity (5 % of critical) and F-bar, so
// every term of the step runs.
//
//   bench_deformable [--cells 8] [--steps 200] [--threads 1,2]
//   bench_deformable --vcross-drop 3000 [--drop-ms 10] [--viscosity-fraction 0]
//
// --vcross-drop N: the cost of seed 002's drop instead: the Vcross (14 m^3, arms of 1.26 m)
// meshed with about N tets (gmsh, 10-node), falling flat at 0.5 m/s onto a rigid anvil (a static
// half-space touching its lowest face), gravity on, for --drop-ms milliseconds on 1 thread; prints
// the wall time, element-steps per second and the extreme stresses with their times and places.
// The anvil of seed 002 was an 8 x 8 x 4 m block, not rigid: the stresses are not comparable
// until the anvil deforms (issue 26, later sessions).
//
// Every thread count runs the same steps; the final states must be bit-identical across thread
// counts, or the case prints INVALID and the program exits with status 2. Figures go to
// docs/benchmarks.md with the printed command, date and load.

#include "core/BuildInfo.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/StressHistory.hpp"
#include "deformable/StructuredBox.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>

#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

namespace {

using armour::deformable::DeformableBody;
using armour::deformable::DeformableSettings;
using armour::deformable::ElementOrder;
using armour::deformable::Vec3;

double wallNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// CPU time of the whole process, all threads (unit: s).
double cpuNow() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string line;
  std::getline(in, line);
  return line;
}

DeformableBody makeBar(ElementOrder order, int cells) {
  DeformableSettings settings;
  settings.material.viscosity = 0.05 * armour::deformable::criticalViscosity(settings.material, 1.0 / cells);
  const auto tets = armour::deformable::structuredBox(Vec3(1.0, 1.0, 4.0), cells, cells, 4 * cells);
  DeformableBody body(armour::deformable::makeDeformableMesh(tets, order, "bench bar"), settings, "bench bar");
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    if (body.mesh().nodes[n].z() < 1e-9) {
      body.fixNode(n);
    }
  }
  return body;
}

struct Timing {
  double wall = 0.0;
  double cpu = 0.0;
  armour::deformable::DeformableStepTimes stages;
  std::vector<Vec3> positions;
};

Timing timeSteps(ElementOrder order, int cells, int steps, int threads) {
  omp_set_num_threads(threads);
  auto body = makeBar(order, cells);
  const double dt = body.stableStep().dt;
  body.step(dt); // first step computes the initial forces: not timed
  const auto before = body.stepTimes();
  Timing t;
  const double wall0 = wallNow();
  const double cpu0 = cpuNow();
  for (int s = 0; s < steps; ++s) {
    body.step(dt);
  }
  t.wall = wallNow() - wall0;
  t.cpu = cpuNow() - cpu0;
  t.positions = body.positions();
  t.stages.elementForces = body.stepTimes().elementForces - before.elementForces;
  t.stages.gather = body.stepTimes().gather - before.gather;
  t.stages.update = body.stepTimes().update - before.update;
  return t;
}

/// Seed 002's drop on a rigid anvil: returns 0.
int vcrossDrop(std::size_t tets, double milliseconds, double viscosityFraction) {
  omp_set_num_threads(1);
  armour::geometry::ShapeRequest request;
  request.volume = 14.0;
  const auto surface = armour::geometry::makeShape("vcross", request);
  armour::geometry::TetrahedralizeOptions options;
  options.targetTetCount = tets;
  options.keepSurface = false;
  const auto mesh = armour::geometry::tetrahedralize(surface, options);
  double lowest = 1e9;
  for (const auto& p : mesh.vertices) {
    lowest = std::min(lowest, p.z());
  }
  DeformableSettings settings;
  settings.halfSpaces = {armour::deformable::HalfSpace{Vec3(0.0, 0.0, lowest), Vec3::UnitZ()}};
  settings.material.viscosity =
      viscosityFraction * armour::deformable::criticalViscosity(settings.material, std::cbrt(14.0 / mesh.tets.size()));
  DeformableBody body(armour::deformable::makeDeformableMesh(mesh, ElementOrder::Quadratic, "vcross"), settings,
                      "vcross drop");
  body.setVelocities(std::vector<Vec3>(body.nodeCount(), Vec3(0.0, 0.0, -0.5)));
  const double dt = body.stableStep().dt;
  armour::deformable::StressHistory history;
  const double wall0 = wallNow();
  std::uint64_t steps = 0;
  while (body.time() < 1e-3 * milliseconds) {
    body.step(dt);
    if (++steps % 5 == 0) {
      history.record(body);
    }
  }
  const double wall = wallNow() - wall0;
  const auto& peak = history.extremes();
  fmt::print("vcross drop: {} tet10, {} nodes, G = {:.3g} Pa/m, dt = {:.3g} s (l_min {:.3g} m, omega_c {:.3g} rad/s), "
             "{} steps, viscosity {:.3g} Pa s\n",
             body.mesh().elementCount(), body.nodeCount(), body.contactGradient(), dt, body.stableStep().lengthMin,
             body.stableStep().contactFrequency, steps, settings.material.viscosity);
  fmt::print("  {:.2f} s wall, {:.3g} element-steps per second\n", wall,
             static_cast<double>(body.mesh().elementCount()) * static_cast<double>(steps) / wall);
  for (const auto& [name, p] : {std::pair{"largest tension sigma_1", peak.tension},
                                std::pair{"largest differential stress", peak.differential},
                                std::pair{"largest von Mises", peak.vonMises}}) {
    fmt::print("  {}: {:.3f} MPa at t = {:.2f} ms, element {} at ({:.2f}, {:.2f}, {:.2f}) m\n", name, 1e-6 * p.value,
               1e3 * p.time, p.element, p.location.x(), p.location.y(), p.location.z());
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Deformable-body step benchmark (element-steps per core-second)"};
  int cells = 8;
  int steps = 200;
  std::vector<int> threads = {1, 2};
  app.add_option("--cells", cells, "cells across the 1 m bar (n x n x 4n cells, 6 tets each)")->check(CLI::Range(1, 64));
  app.add_option("--steps", steps, "timed steps per case")->check(CLI::Range(1, 1000000));
  app.add_option("--threads", threads, "thread counts")->delimiter(',');
  std::size_t dropTets = 0;
  double dropMs = 10.0;
  double viscosityFraction = 0.0;
  app.add_option("--vcross-drop", dropTets, "run seed 002's Vcross drop on a rigid anvil with about this many tets");
  app.add_option("--drop-ms", dropMs, "simulated time of the drop (ms)")->check(CLI::Range(0.01, 1000.0));
  app.add_option("--viscosity-fraction", viscosityFraction, "viscosity as a fraction of 2 h sqrt(E rho)")
      ->check(CLI::Range(0.0, 1.0));
  CLI11_PARSE(app, argc, argv);
  if (dropTets > 0) {
    fmt::print("bench_deformable --vcross-drop {} --drop-ms {} --viscosity-fraction {}\nbuild: {}\nload: {}\n", dropTets,
               dropMs, viscosityFraction, armour::core::buildInfo(), loadAverage());
    return vcrossDrop(dropTets, dropMs, viscosityFraction);
  }

  fmt::print("bench_deformable --cells {} --steps {} --threads {}\n", cells, steps, fmt::join(threads, ","));
  fmt::print("build: {}\nload before: {}\n", armour::core::buildInfo(), loadAverage());
  bool valid = true;
  for (const auto order : {ElementOrder::Linear, ElementOrder::Quadratic}) {
    const std::size_t elements = 6UL * cells * cells * 4 * cells;
    std::vector<Vec3> reference;
    for (const int n : threads) {
      const auto t = timeSteps(order, cells, steps, n);
      const double elementSteps = static_cast<double>(elements) * steps;
      bool same = true;
      if (reference.empty()) {
        reference = t.positions;
      } else {
        same = std::memcmp(reference.data(), t.positions.data(), reference.size() * sizeof(Vec3)) == 0;
        valid = valid && same;
      }
      fmt::print("tet{:<2} {:>7} elements {} threads: {:.3f} s wall, {:.3f} s cpu, {:.3g} element-steps per "
                 "wall-second, {:.3g} per core-second (wall x threads), cpu/wall {:.2f}{}\n",
                 static_cast<int>(order), elements, n, t.wall, t.cpu, elementSteps / t.wall,
                 elementSteps / (t.wall * n), t.cpu / t.wall, same ? "" : "  INVALID: differs from 1 thread");
      fmt::print("        stages: element forces {:.1f} %, gather {:.1f} %, update {:.1f} %\n",
                 100.0 * t.stages.elementForces / t.wall, 100.0 * t.stages.gather / t.wall,
                 100.0 * t.stages.update / t.wall);
    }
  }
  fmt::print("load after: {}\n", loadAverage());
  return valid ? 0 : 2;
}
