// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StormCommands.hpp
/// `armour storm-file synth | check | info`: analytic storm files for tests and demos, and the
/// validation and summary of any storm file (docs/storm-file.md).

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addStormCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
