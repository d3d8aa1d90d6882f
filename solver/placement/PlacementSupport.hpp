// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacementSupport.hpp
/// What the phases of a placement share (internal to the placement stage): independent random
/// streams, the slope frame of a deposit, a Deposit over a built scene's statics and bodies, the
/// scene body of a World body, and a material named in the placement block.

#include "io/Scene.hpp"
#include "placement/Deposit.hpp"
#include "simulation/SceneBuilder.hpp"
#include "simulation/World.hpp"

#include <cstdint>
#include <random>
#include <string>

namespace armour::placement::detail {

/// A generator of independent random streams: stream k of seed s (SplitMix64 of both), so a
/// unit's draws do not depend on how many draws the others took.
std::mt19937_64 stream(std::uint64_t seed, std::uint64_t k);

/// A uniform draw in [0, 1) with 53 bits.
double uniform(std::mt19937_64& rng);

/// Index of the scene material `name`; throws core::InputError naming `key` and the scene's
/// materials when there is none.
std::size_t resolveMaterial(const io::Scene& scene, const std::string& name, const std::string& key);

/// Slope frame of the rock deposit: x up the face, z out of it (a rotation about y by -alpha).
Quat slopeFrame(double tanAlpha);

/// A Deposit over the statics of `built`, in the frame `toFrame` (world -> deposit frame).
Deposit makeDeposit(const simulation::BuiltScene& built, const Quat& toFrame, double cell);

/// Add World body `b` to `deposit`, in the frame `toFrame`.
void addWorldBody(Deposit& deposit, const simulation::World& world, simulation::BodyId b, const Quat& toFrame);

/// The scene file's body for World body `b` as it is now.
io::Body sceneBody(const simulation::World& world, simulation::BodyId b, const std::string& name, std::size_t shape,
                   std::size_t material, double volume, bool fixed);

} // namespace armour::placement::detail
