// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/AnalyseCommands.hpp"

#include "measure/PackAnalysis.hpp"
#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "simulation/World.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>


namespace armour::app {
namespace {

namespace fs = std::filesystem;

struct AnalyseOptions {
  std::string scene;
  std::string state;     ///< a run's final_state.csv (or a scene) with the poses to analyse
  std::string reference; ///< poses to measure displacements from
  std::string output;    ///< folder; default <scene stem>-analysis beside the scene
  std::string prefix;
  std::string axis = "nose";
  bool plots = false;
};

/// Draw the PNGs with utilities/plot_pack.py (matplotlib); a missing Python is a warning, not an error.
void plot(const fs::path& csv, const fs::path& folder) {
  runUtility("plot_pack.py", {csv.string(), folder.string()}, "plots");
}

void analyse(const AnalyseOptions& o) {
  const io::Scene scene = io::readScene(o.scene);
  measure::AnalyseSettings settings;
  settings.unitPrefix = o.prefix;
  settings.axis = o.axis;
  settings.stateName = o.state;
  std::optional<measure::PoseMap> state, reference;
  if (!o.state.empty()) state = measure::readPoses(o.state);
  if (!o.reference.empty()) reference = measure::readPoses(o.reference);
  const measure::PackReport report =
      measure::analysePack(scene, settings, state ? &*state : nullptr, reference ? &*reference : nullptr);
  const fs::path folder = o.output.empty() ? scene.baseDir / (scene.name + "-analysis") : fs::absolute(o.output);
  measure::writePackReport(report, folder);
  std::cout << measure::packText(report);
  if (o.plots) plot(folder / "units.csv", folder);
  std::cout << fmt::format("tables: {}/units.csv, pack.json, pack.txt\n", folder.string());
}

} // namespace

void addAnalyseCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto a = std::make_shared<AnalyseOptions>();
  auto* analyseCmd = app.add_subcommand("analyse", "pack measures of a scene or a run: contacts, orientations (P2, "
                                                   "stereonet), packing density, thickness, porosity, displacements");
  analyseCmd->add_option("scene", a->scene, "the scene (e.g. a placed scene)")->required()->check(CLI::ExistingFile);
  analyseCmd->add_option("--state", a->state, "poses to analyse: a run's final_state.csv (default: the scene's own)")
      ->check(CLI::ExistingFile);
  analyseCmd->add_option("--reference", a->reference,
                         "poses to measure displacements from: a final_state.csv or a scene")
      ->check(CLI::ExistingFile);
  analyseCmd->add_option("--output", a->output, "output folder (default: <scene stem>-analysis beside the scene)");
  analyseCmd->add_option("--units", a->prefix, "units are the movable bodies whose names start with this (default: all)");
  analyseCmd->add_option("--axis", a->axis, "unit axis for orientations and P2 (nose, shank, upper-fluke, ...)")
      ->capture_default_str();
  analyseCmd->add_flag("--plots", a->plots, "also draw the PNGs (utilities/plot_pack.py, matplotlib)");
  analyseCmd->callback([a] { analyse(*a); });
}

} // namespace armour::app
