// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// bench_peers: the armour pile scene rebuilt in Bullet 3.24 (libbullet-dev, single precision), to
// time a physics engine on the same bodies in the same run. Bullet is linked as a library only;
// this file is built only when CMake finds it (the optional target bench_peers).

#include "benchmarks/PeersConvexPieces.hpp"
#include "benchmarks/SolverBenchDeposit.hpp"
#include "simulation/World.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armour::bench {

/// How Bullet sees each unit.
enum class BulletShape {
  Box,      ///< btBoxShape: cubes only
  Hull,     ///< one btConvexHullShape: the hull of the whole unit
  Compound, ///< btCompoundShape of btConvexHullShape pieces (coreLocPieces for Core-Locs)
};

struct BulletSettings {
  BulletShape shape = BulletShape::Box;
  int corelocPieces = 3;        ///< pieces of a Core-Loc compound: 3 or 5 (PeersConvexPieces.hpp)
  double timeStep = 1.0 / 240.0; ///< fixed step, one per stepSimulation call (unit: s)
  int iterations = 10;           ///< sequential-impulse iterations (Bullet's default) (unit: -)
  bool sleep = true;             ///< Bullet's deactivation, with its default thresholds
  double friction = 0.6;         ///< of every pair (unit: -)
  double restitution = 0.1;      ///< of every pair (unit: -)
};

/// A Bullet world holding the dynamic bodies of an armour World, with the same masses, principal
/// moments, centroids, orientations and velocities, and the pile's walls as static planes.
class BulletPile {
public:
  BulletPile(const armour::simulation::World& world, const std::vector<Deposit::Plane>& walls,
             const BulletSettings& settings);
  ~BulletPile();
  BulletPile(const BulletPile&) = delete;
  BulletPile& operator=(const BulletPile&) = delete;

  void step();
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::size_t bodyCount() const;
  [[nodiscard]] armour::simulation::Vec3 position(std::size_t i) const;
  [[nodiscard]] armour::simulation::Vec3 velocity(std::size_t i) const;
  [[nodiscard]] bool awake(std::size_t i) const;
  /// What the units were made of, for the report.
  [[nodiscard]] const std::string& description() const { return description_; }
  /// The pieces of the compound (empty for box and hull).
  [[nodiscard]] const ConvexPieces& pieces() const { return pieces_; }

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  BulletSettings settings_;
  double time_ = 0.0;
  std::string description_;
  ConvexPieces pieces_;
};

} // namespace armour::bench
