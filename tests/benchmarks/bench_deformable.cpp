// SPDX-License-Identifier: GPL-3.0-or-later
// Deformable-body benchmark (deformable/DeformableBody): element-steps per core-second of the
// explicit step (internal forces of every element, the nodal gather, the update) for 4- and
// 10-node tets, at the given thread counts. The body is a 1 x 1 x 4 m concrete bar of n x n x 4n
// cells (6 tets each), base fixed, under gravity, with viscosity (5 % of critical) and F-bar, so
// every term of the step runs.
//
//   bench_deformable [--cells 8] [--steps 200] [--threads 1,2]
//   bench_deformable --vcross-drop 3000 [--drop-ms 10] [--viscosity-fraction 0]
//   bench_deformable --anvil-drop vcross|vrcross [--unit-tets 2000] [--anvil-cells 16] [--drop-ms 8]
//                    [--viscosity-fraction 0] [--corner-distance 0.15] [--csv history.csv]
//
// --vcross-drop N: the cost of seed 002's drop instead: the Vcross (14 m^3, arms of 1.26 m)
// meshed with about N tets (gmsh, 10-node), falling flat at 0.5 m/s onto a rigid anvil (a static
// half-space touching its lowest face), gravity on, for --drop-ms milliseconds on 1 thread; prints
// the wall time, element-steps per second and the extreme stresses with their times and places.
// The anvil of seed 002 was an 8 x 8 x 4 m block, not rigid: the stresses are not comparable
// until the anvil deforms.
//
// --anvil-drop SHAPE: seed 002's drop test itself (Table 2, Figs. 3-4; deformable/AnvilDrop.hpp):
// the unit (vcross 14 m^3 or vrcross 18 m^3, --unit-tets tets) standing on one arm, at 0.5 m/s,
// touching an 8 x 8 x 4 m concrete anvil of --anvil-cells cells along its 8 m sides (10-node
// tets, body contact by Munjiza's potential, the anvil's base on a rigid frictionless floor),
// gravity on, 1 thread. Prints the static base stress W / A_base, the largest sigma_1 and
// sigma_1 - sigma_3 in the unit over time, everywhere and away from the singular edges by more
// than --corner-distance: the central cube's twelve edges (the Vcross's re-entrant corners) and the
// four edges of the base face (the edges of a flat punch), with times after impact and places,
// and the first and last times of contact.
//
// Every thread count runs the same steps; the final states must be bit-identical across thread
// counts, or the case prints INVALID and the program exits with status 2. Figures go to
// docs/benchmarks.md with the printed command, date and load.

#include "benchmarks/BenchClock.hpp"
#include "core/BuildInfo.hpp"
#include "deformable/AnvilDrop.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/StressFields.hpp"
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

using armour::bench::cpuNow;
using armour::bench::loadAverages;
using armour::bench::wallNow;

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

/// Distance (unit: m) from p (relative to the unit's centre) to the twelve edges of the central
/// cube [-a/2, a/2]^3: where two arms of a Vcross meet (re-entrant edges).
double distanceToCentralEdges(const Vec3& p, double a) {
  double best = 1e30;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3;
    const int w = (axis + 2) % 3;
    const double along = std::max(0.0, std::abs(p[axis]) - 0.5 * a);
    for (const double su : {-0.5 * a, 0.5 * a}) {
      for (const double sw : {-0.5 * a, 0.5 * a}) {
        best = std::min(best, std::sqrt(along * along + (p[u] - su) * (p[u] - su) + (p[w] - sw) * (p[w] - sw)));
      }
    }
  }
  return best;
}

/// Distance (unit: m) from p (relative to the unit's centre) to the four edges of the base face
/// (the square [-a/2, a/2]^2 at z = -3a/2): the edges of a flat punch, where the contact pressure and
/// the stresses are singular too.
double distanceToBaseEdges(const Vec3& p, double a) {
  const double dz = p.z() + 1.5 * a;
  double best = 1e30;
  for (int axis = 0; axis < 2; ++axis) {
    const int other = 1 - axis;
    const double along = std::max(0.0, std::abs(p[axis]) - 0.5 * a);
    for (const double side : {-0.5 * a, 0.5 * a}) {
      best = std::min(best, std::sqrt(along * along + (p[other] - side) * (p[other] - side) + dz * dz));
    }
  }
  return best;
}

struct DropPeak {
  double value = 0.0; ///< (unit: Pa)
  double time = 0.0;  ///< (unit: s)
  Vec3 where = Vec3::Zero();
  void offer(double v, double t, const Vec3& x) {
    if (v > value) {
      *this = {v, t, x};
    }
  }
};

struct AnvilDropOptions {
  std::string shape = "vcross";
  std::size_t unitTets = 2000;
  int anvilCells = 16;
  double milliseconds = 8.0;
  double viscosityFraction = 0.0;
  double cornerDistance = 0.15;
  double contactDamping = 0.0;
  double bodyFriction = 0.0;
  double contactPenalty = 0.0;
  std::string csv;
};

/// Seed 002's drop onto the concrete anvil: returns 0.
int anvilDrop(const AnvilDropOptions& o) {
  omp_set_num_threads(1);
  armour::deformable::AnvilDropSettings settings;
  settings.shape = o.shape;
  settings.volume = o.shape == "vrcross" ? 18.0 : 14.0;
  settings.unitTets = o.unitTets;
  settings.anvilCells = o.anvilCells;
  settings.body.contactDamping = o.contactDamping;
  settings.body.bodyFriction = o.bodyFriction;
  settings.body.contactPenalty = o.contactPenalty;
  settings.body.material.viscosity = o.viscosityFraction *
      armour::deformable::criticalViscosity(settings.body.material, std::cbrt(settings.volume / o.unitTets));
  const double build0 = wallNow();
  auto drop = armour::deformable::makeAnvilDrop(settings);
  auto& body = drop.body;
  const double buildWall = wallNow() - build0;
  const auto& material = settings.body.material;
  const double weight = material.density * drop.unitVolume * 9.81;
  const double a = (drop.unitCentre.z() + 0.0) * 2.0 / 3.0; // height 3a, base at z = 0
  const double dt = body.stableStep().dt;
  fmt::print("{} on anvil: unit {} tet10 ({:.3f} m^3, arm {:.3f} m, base {:.4f} m^2), anvil {} tet10, {} nodes; "
             "penalty {:.3g} Pa, dt {:.3g} s (l_min {:.3g} m, omega_c {:.3g} rad/s); built in {:.1f} s\n",
             o.shape, drop.unitElements.size(), drop.unitVolume, a, drop.baseArea,
             body.mesh().elementCount() - drop.unitElements.size(), body.nodeCount(), body.bodyContact()->penalty(),
             dt, body.stableStep().lengthMin, body.stableStep().contactFrequency, buildWall);
  fmt::print("  static base stress W / A_base = {:.4f} MPa (W = {:.1f} kN)\n", 1e-6 * weight / drop.baseArea,
             1e-3 * weight);
  std::vector<double> cornerDistance(drop.unitElements.size());
  for (std::size_t k = 0; k < drop.unitElements.size(); ++k) {
    Vec3 centroid = Vec3::Zero();
    for (int c = 0; c < 4; ++c) {
      centroid += 0.25 * body.mesh().nodes[body.mesh().element(drop.unitElements[k])[c]];
    }
    cornerDistance[k] = std::min(distanceToCentralEdges(centroid - drop.unitCentre, a),
                                 distanceToBaseEdges(centroid - drop.unitCentre, a));
  }
  double firstContact = -1.0;
  double lastContact = -1.0;
  DropPeak tension;
  DropPeak differential;
  DropPeak tensionAway;
  DropPeak differentialAway;
  std::FILE* csv = o.csv.empty() ? nullptr : std::fopen(o.csv.c_str(), "w");
  if (csv != nullptr) {
    fmt::print(csv, "time_s,sigma1_Pa,differential_Pa,sigma1_away_Pa,differential_away_Pa,contact_force_z_N\n");
  }
  const double wall0 = wallNow();
  std::uint64_t steps = 0;
  while (body.time() < 1e-3 * o.milliseconds) {
    body.step(dt);
    if (body.bodyContactStats().touchingPairs > 0) {
      lastContact = body.time();
      firstContact = firstContact < 0.0 ? body.time() : firstContact;
    }
    if (++steps % 5 != 0) {
      continue;
    }
    const auto stress = body.elementStresses();
    DropPeak now;
    DropPeak nowDiff;
    DropPeak nowAway;
    DropPeak nowDiffAway;
    for (std::size_t k = 0; k < drop.unitElements.size(); ++k) {
      const auto e = drop.unitElements[k];
      const auto summary = armour::deformable::summarizeStress(stress[e]);
      const auto* c = body.mesh().element(e);
      const Vec3 where = 0.25 * (body.positions()[c[0]] + body.positions()[c[1]] + body.positions()[c[2]] +
                                 body.positions()[c[3]]);
      now.offer(summary.principal[0], body.time(), where);
      nowDiff.offer(summary.differential, body.time(), where);
      if (cornerDistance[k] > o.cornerDistance) {
        nowAway.offer(summary.principal[0], body.time(), where);
        nowDiffAway.offer(summary.differential, body.time(), where);
      }
    }
    tension.offer(now.value, now.time, now.where);
    differential.offer(nowDiff.value, nowDiff.time, nowDiff.where);
    tensionAway.offer(nowAway.value, nowAway.time, nowAway.where);
    differentialAway.offer(nowDiffAway.value, nowDiffAway.time, nowDiffAway.where);
    if (csv != nullptr) {
      double fz = 0.0;
      for (std::size_t n = 0; n < body.nodeCount(); ++n) {
        fz += body.bodyContact()->nodeParts()[n] == 0 ? body.nodalContactForces()[n].z() : 0.0;
      }
      fmt::print(csv, "{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}\n", body.time(), now.value, nowDiff.value,
                 nowAway.value, nowDiffAway.value, fz);
    }
  }
  if (csv != nullptr) {
    std::fclose(csv);
  }
  const double wall = wallNow() - wall0;
  fmt::print("  {} steps, {:.1f} s wall ({:.3g} element-steps per second, stress sampled every 5 steps)\n", steps,
             wall, static_cast<double>(body.mesh().elementCount()) * static_cast<double>(steps) / wall);
  const auto& stages = body.stepTimes();
  fmt::print("  stages: element forces {:.1f} s, gather with contact {:.1f} s, update {:.1f} s, stress sampling and "
             "the rest {:.1f} s\n",
             stages.elementForces, stages.gather, stages.update,
             wall - stages.elementForces - stages.gather - stages.update);
  fmt::print("  contact from {:.2f} to {:.2f} ms\n", 1e3 * firstContact, 1e3 * lastContact);
  for (const auto& [name, p] : {std::pair{"largest sigma_1", tension}, std::pair{"largest sigma_1 - sigma_3", differential},
                                std::pair{"largest sigma_1 away from singular edges", tensionAway},
                                std::pair{"largest sigma_1 - sigma_3 away from singular edges", differentialAway}}) {
    fmt::print("  {}: {:.3f} MPa at {:.2f} ms after impact, element centroid ({:.2f}, {:.2f}, {:.2f}) m\n", name, 1e-6 * p.value,
               1e3 * p.time, p.where.x(), p.where.y(), p.where.z());
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
  AnvilDropOptions anvil;
  std::string anvilShape;
  app.add_option("--anvil-drop", anvilShape, "run seed 002's drop onto the concrete anvil: vcross or vrcross")
      ->check(CLI::IsMember({"vcross", "vrcross"}));
  app.add_option("--unit-tets", anvil.unitTets, "anvil drop: wanted tets in the unit")->check(CLI::Range(10, 1000000));
  app.add_option("--anvil-cells", anvil.anvilCells, "anvil drop: cells along the anvil's 8 m side")
      ->check(CLI::Range(1, 200));
  app.add_option("--corner-distance", anvil.cornerDistance, "anvil drop: 'away from corners' means farther (m)");
  app.add_option("--contact-damping", anvil.contactDamping, "anvil drop: contact damping zeta (pressure zeta rho c w)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--body-friction", anvil.bodyFriction, "anvil drop: Coulomb coefficient between unit and anvil")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--contact-penalty", anvil.contactPenalty, "anvil drop: Munjiza's penalty p (Pa); 0 = 2 E")
      ->check(CLI::Range(0.0, 1e15));
  app.add_option("--csv", anvil.csv, "anvil drop: write the stress history here");
  CLI11_PARSE(app, argc, argv);
  if (!anvilShape.empty()) {
    anvil.shape = anvilShape;
    anvil.milliseconds = dropMs;
    anvil.viscosityFraction = viscosityFraction;
    fmt::print("bench_deformable --anvil-drop {} --unit-tets {} --anvil-cells {} --drop-ms {} --viscosity-fraction {} "
               "--corner-distance {} --contact-damping {} --body-friction {} --contact-penalty {}\nbuild: {}\nload: {}\n",
               anvil.shape, anvil.unitTets, anvil.anvilCells, dropMs, viscosityFraction, anvil.cornerDistance,
               anvil.contactDamping, anvil.bodyFriction, anvil.contactPenalty, armour::core::buildInfo(), loadAverages());
    return anvilDrop(anvil);
  }
  if (dropTets > 0) {
    fmt::print("bench_deformable --vcross-drop {} --drop-ms {} --viscosity-fraction {}\nbuild: {}\nload: {}\n", dropTets,
               dropMs, viscosityFraction, armour::core::buildInfo(), loadAverages());
    return vcrossDrop(dropTets, dropMs, viscosityFraction);
  }

  fmt::print("bench_deformable --cells {} --steps {} --threads {}\n", cells, steps, fmt::join(threads, ","));
  fmt::print("build: {}\nload before: {}\n", armour::core::buildInfo(), loadAverages());
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
  fmt::print("load after: {}\n", loadAverages());
  return valid ? 0 : 2;
}
