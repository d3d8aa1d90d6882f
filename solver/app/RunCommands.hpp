// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RunCommands.hpp
/// `armour check scene.yaml` and `armour run scene.yaml`: validate a scene file and build its
/// World (shapes, level sets, static pieces) without stepping, or build it and run it.
///
/// Exit codes (with main.cpp): 0 success; 2 a user error (InputError: the scene file, an option,
/// a time step above the stability limit), the message naming the file and the item; 3 the
/// simulation stopped (simulation::SimulationError: non-finite state, overlap guard rail), the
/// state at the stop written beside the run log.

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addRunCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
