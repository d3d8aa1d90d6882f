// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file FloorPile.hpp
/// Small piles on a floor (issue 22): units of one shape released in random attitudes above a
/// plane, and the largest kinetic energy of any unit. Shared by `bench_solver at-rest` and
/// test_solvers, so that the test runs the benchmark's scenes (docs/benchmarks.md, "Kept points
/// carry their samples' force").

#include "simulation/World.hpp"

#include <algorithm>
#include <cstdint>
#include <random>

namespace armour::test {

/// A floor (the plane z = 0) and `units` bodies of `shape` above it: plan positions within 0.4 m
/// of the origin, heights 1.2 + 2.2 k m (clear of each other for units of 1 m^3 in any attitude),
/// attitudes drawn from `seed`.
inline void dropOnFloor(simulation::World& w, simulation::ShapeId shape, simulation::MaterialId material, int units,
                        std::uint64_t seed) {
  w.addPlane({"floor", simulation::Vec3::Zero(), simulation::Vec3::UnitZ(), material});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < units; ++k) {
    simulation::BodySpec b;
    b.shape = shape;
    b.material = material;
    b.position = simulation::Vec3(0.4 * u(rng), 0.4 * u(rng), 1.2 + 2.2 * k);
    b.orientation = simulation::Quat(
        Eigen::AngleAxisd(3.0 * u(rng), simulation::Vec3(u(rng), u(rng), u(rng)).normalized()));
    w.addBody(b);
  }
}

/// The largest kinetic energy of any body (unit: J).
inline double largestKineticEnergy(const simulation::World& w) {
  double largest = 0.0;
  for (simulation::BodyId b = 0; b < w.bodies().size(); ++b) largest = std::max(largest, w.bodies().kineticEnergy(b));
  return largest;
}

} // namespace armour::test
