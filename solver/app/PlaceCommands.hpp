// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlaceCommands.hpp
/// `armour place placement.yaml`: build an armour layer (rocks, then units by crane or grid) on
/// the scene's underlayer and write the placed scene beside the file, with the per-unit table and
/// the summary in its output folder (docs/placement.md).
///
/// Exit codes: 0 success; 2 a user error (the file, a key, a grid point that fits nowhere);
/// 3 the dynamics stopped (simulation::SimulationError).

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addPlaceCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
