// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What bench_solver's scenes are made of: the shapes of a kind of body, instance scales, random
// orientations, the concrete material and the World settings of every case; and the names from
// armour::simulation that the benchmark's files share.

#include "simulation/World.hpp"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace armour::bench {

using armour::simulation::BodySpec;
using armour::simulation::Material;
using armour::simulation::MaterialId;
using armour::simulation::Quat;
using armour::simulation::ShapeId;
using armour::simulation::StaticPlane;
using armour::simulation::Vec3;
using armour::simulation::World;
using armour::simulation::WorldSettings;
using armour::simulation::WorldState;
namespace dyn = armour::dynamics;

constexpr double kGravity = 9.81; // m/s^2

/// Uniformly distributed random rotation (Shoemake 1992).
Quat randomOrientation(std::mt19937_64& rng);

/// The shapes one kind of body is drawn from: one for cube and coreloc, a library of seeded
/// rocks for rock. All at V = 1 m^3 (instances scale them).
struct ShapeSet {
  std::string kind;
  std::vector<ShapeId> ids;
  double radius = 0.0; ///< largest centroid-to-vertex distance at scale 1 (unit: m)
};

/// Add the shapes of `kind` to the world (`rockShapes` seeded rocks for "rock", one shape else).
ShapeSet addShapes(World& world, const std::string& kind, int rockShapes, std::uint64_t seed);

/// Instance scale: rocks vary by +-30 % in volume about the nominal one, units do not.
double drawScale(const std::string& kind, double dn, std::mt19937_64& rng);
constexpr double kMaxScaleOverDn = 1.0913; // cbrt(1.3)

/// The World settings of every case: the defaults, sleep on or off.
WorldSettings baseSettings(bool sleep);
/// The contact solver of every World the benchmark builds (bench_solver --solver).
void setBenchSolver(armour::simulation::ContactSolverKind solver);
/// The near-sample list slack of every World (WorldSettings::sampleListSlackPerDn; 0 = no lists).
void setBenchSampleListSlack(double perDn);
/// The constraint solver's speculative margin of every World (ConstraintSettings::speculativeMargin).
void setBenchSpeculativeMargin(double perDn);

/// Concrete, 2400 kg/m^3, with the given friction (static = dynamic) and restitution.
MaterialId addConcrete(World& world, double friction, double restitution);

} // namespace armour::bench
