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
#include "measure/PackAnalysis.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace armour::app {

/// What `armour run` and `armour storm` do, as options.
struct RunRequest {
  std::string scene;
  double duration = 0.0;           ///< overrides the scene's when durationGiven (unit: s)
  bool durationGiven = false;
  int threads = 0;                 ///< OpenMP threads, 0 = OpenMP's default
  std::string output;              ///< overrides the scene's output folder when not empty
  bool restart = false;            ///< continue from <output>/checkpoint.nc
  bool profile = false;            ///< print the per-stage wall-time table of the step at the end
  std::vector<std::string> sets;   ///< --set KEY=VALUE changes of the scene (io/SceneOverrides.hpp)
  // `armour storm`: the storm replayed on the scene (empty for `armour run`).
  std::string stormFile;           ///< the storm file (netCDF, docs/storm-file.md)
  std::optional<double> timeOffset; ///< storm time at simulation time 0, instead of the scene's (unit: s)
  std::optional<std::uint64_t> variabilitySeed; ///< seed of the storm's variability draws, instead of the scene's (unit: -)
};

/// Build the scene's world and run it to the end, writing the outputs and run.log into the
/// output folder (docs/output-files.md). Returns the final pose of each of the scene's bodies,
/// the values final_state.csv holds (its 17 digits read back to the same doubles), so a caller
/// (`armour ensemble`) measures the run without reading the file back. Throws core::InputError
/// for bad input and CLI::RuntimeError(3) when the simulation stops (its state written beside
/// the log), or (130) when stopped by SIGINT/SIGTERM after writing a checkpoint.
measure::PoseMap runScene(const RunRequest& request);

/// The repeatable `--set KEY=VALUE` option of the commands that read a scene.
void addSetOption(CLI::App& command, std::vector<std::string>& sets);

void addRunCommands(CLI::App& app, const GlobalOptions& global);

} // namespace armour::app
