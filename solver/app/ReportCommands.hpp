// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ReportCommands.hpp
/// `armour report RUN_DIR`: the damage report of a storm run (issue 9). Stub: being written.

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addReportCommands(CLI::App& app, GlobalOptions& global);

} // namespace armour::app
