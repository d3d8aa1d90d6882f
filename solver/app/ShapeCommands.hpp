// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ShapeCommands.hpp
/// `armour shape list | export | info | refine | tetra`: the unit-shape library and mesh tools.

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addShapeCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
