// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file HydroStages.hpp
/// From a scene's `hydro:` block to the World's load stages: the one place that knows which
/// model class serves which `hydro.model` (storm -> StormLoads, oscillating -> OscillatingForce,
/// shallow_wave -> ShallowWaveForce).

#include "hydro/HydroSettings.hpp"
#include "simulation/World.hpp"

#include <string>

namespace armour::hydro {

/// Add the load stages the settings ask for to `world` (nothing if !settings.enabled), after
/// checking what can be checked before a run: the storm file opens and validates, and it covers
/// the storm times [time_offset, time_offset + duration] the run will need. Errors throw
/// core::InputError naming the key or file and the fix. Returns one line per stage for the run
/// log ("" when there is none).
std::string attachLoadStages(simulation::World& world, const HydroSettings& settings, double duration);

/// For `armour check`: read every storm record a run of `duration` seconds from the settings'
/// time offset reads, with the checks of storm::StormReader::read (a NaN or infinity in a voxel
/// with data throws core::InputError naming the file, the variable, the time and the voxel), so
/// that a damaged file is refused before the run, not in the middle of it. Call after
/// attachLoadStages (which checks that the file covers the run). Returns a line for the report
/// ("" without a storm).
std::string validateStormRecords(const HydroSettings& settings, double duration);

} // namespace armour::hydro
