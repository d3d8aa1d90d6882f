// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformCommands.hpp
/// `armour deform SCENE`: run a deformable-body scene (issue 26, seed 002's Solidity_D;
/// docs/deformable-file.md): units and blocks meshed into one deformable mesh, their contact
/// (Munjiza's potential) and static half-spaces, to the scene's duration; VTU frames with the
/// stress fields, the extreme stresses over time, checkpoints and --restart.

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addDeformCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
