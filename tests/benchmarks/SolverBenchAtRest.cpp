// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchAtRest.hpp"

#include "benchmarks/SolverBenchReport.hpp"
#include "benchmarks/SolverBenchScene.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "support/FloorPile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace armour::bench {

namespace {

struct SceneResult {
  double energy = 0.0; ///< largest kinetic energy of any unit in the window (unit: J)
  double move = 0.0;   ///< largest move of any unit over the window (unit: m)
  double turn = 0.0;   ///< largest turn of any unit over the window (unit: rad)
  double cpu = 0.0;    ///< wall time of the scene (unit: s)
};

SceneResult runScene(const AtRestOptions& o, ShapeId shape, World& w, std::uint64_t seed) {
  const auto start = std::chrono::steady_clock::now();
  armour::test::dropOnFloor(w, shape, addConcrete(w, o.friction, o.restitution), o.units, seed);
  w.advanceTo(o.settle);
  const auto n = w.bodies().size();
  std::vector<Vec3> p0(n);
  std::vector<Quat> q0(n);
  for (armour::simulation::BodyId b = 0; b < n; ++b) {
    p0[b] = w.bodies().position(b);
    q0[b] = w.bodies().orientation(b);
  }
  SceneResult r;
  while (w.time() < o.settle + o.window - 1e-9) {
    w.step();
    r.energy = std::max(r.energy, armour::test::largestKineticEnergy(w));
  }
  for (armour::simulation::BodyId b = 0; b < n; ++b) {
    r.move = std::max(r.move, (w.bodies().position(b) - p0[b]).norm());
    r.turn = std::max(r.turn, w.bodies().orientation(b).angularDistance(q0[b]));
  }
  r.cpu = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

} // namespace

int runAtRest(const AtRestOptions& o) {
  geometry::ShapeRequest request;
  request.volume = 1.0;
  const geometry::TriangleMesh mesh = geometry::makeShape(o.shape, request);
  printHeader(fmt::format("At rest: {} x {} on a floor, {} scenes", o.units, o.shape, o.scenes));
  fmt::print("Sleeping off; settle {} s, then the window {} s; friction {}, restitution {}; scene k seeded {} + k.\n\n",
             o.settle, o.window, o.friction, o.restitution, o.seed);
  fmt::print("| scene | largest kinetic energy in the window (J) | largest move (mm) | largest turn (mrad) | wall (s) |\n");
  fmt::print("|---:|---:|---:|---:|---:|\n");
  int moving = 0;
  double worst = 0.0;
  for (int k = 0; k < o.scenes; ++k) {
    World w(baseSettings(false));
    const ShapeId shape = w.addShape(o.shape, mesh);
    const SceneResult r = runScene(o, shape, w, o.seed + static_cast<std::uint64_t>(k));
    fmt::print("| {} | {:.3g} | {:.3g} | {:.3g} | {:.1f} |\n", k, r.energy, 1e3 * r.move, 1e3 * r.turn, r.cpu);
    std::fflush(stdout);
    if (r.energy > 1e-3) ++moving;
    worst = std::max(worst, r.energy);
  }
  fmt::print("\n{} of {} scenes keep more than 1 mJ in the window; the largest {:.3g} J.\n", moving, o.scenes, worst);
  return moving;
}

} // namespace armour::bench
