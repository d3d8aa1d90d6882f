// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SchemaCommands.hpp
/// `armour schema`: the scene file's key tables, generated from the schema the reader reads with
/// (io/SceneSchema.hpp); `--check-doc` and `--update-doc` keep docs/scene-file.md's tables current.

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addSchemaCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
