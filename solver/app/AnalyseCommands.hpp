// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file AnalyseCommands.hpp
/// `armour analyse scene.yaml [--state final_state.csv] [--reference ...]`: the pack measures of a
/// scene or a run (measure/PackAnalysis.hpp) as units.csv, pack.json and pack.txt, with PNGs on request;
/// `armour ensemble placement.yaml --runs N`: N placements with seeds S..S+N-1 and the mean +-
/// standard deviation of each measure (seed 001 Table 1). docs/placement.md.

#include "app/CommandContext.hpp"

#include <CLI/CLI.hpp>

namespace armour::app {

void addAnalyseCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
