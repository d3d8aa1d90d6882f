// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/PlaceCommands.hpp"

#include "app/RunCommands.hpp"
#include "io/SceneOverrides.hpp"

#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "placement/PlacedScene.hpp"
#include "placement/Placer.hpp"
#include "simulation/World.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace armour::app {
namespace {

namespace fs = std::filesystem;

struct PlaceOptions {
  std::string file;
  int threads = 0;    ///< OpenMP threads, 0 = OpenMP's default
  std::string output; ///< overrides the placed scene's path when not empty
  std::vector<std::string> sets; ///< --set changes of the placement file
};

void placeScene(const PlaceOptions& o) {
  if (o.threads < 0) core::failInput("--threads", "{}: give a positive number of threads, or 0 for OpenMP's default", o.threads);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  std::ifstream in(o.file, std::ios::binary);
  if (!in) core::failInput(o.file, "cannot open the placement file");
  std::ostringstream text;
  text << in.rdbuf();
  const io::Scene scene = io::readScene(o.file, o.sets);
  if (!scene.placement.enabled)
    core::failInput(o.file, "no `placement:` block; `armour place` needs one (docs/placement.md has examples), or use "
                            "`armour run` for a scene without one");
  const fs::path scenePath = o.output.empty() ? scene.baseDir / scene.placement.output : fs::absolute(o.output);
  if (fs::is_directory(scenePath))
    core::failInput(o.output.empty() ? "placement.output" : "--output",
                    "{} is a folder; give the path of the placed scene file (a .yaml), e.g. {}", scenePath.string(),
                    (scenePath / "placed.yaml").string());
  std::cout << fmt::format("placing {} units of {} ({}), {} threads\n",
                           scene.placement.method == placement::Method::Crane ? "crane-lowered" : "grid-dropped",
                           scene.placement.shape, scene.sourceName, omp_get_max_threads());
  auto last = std::chrono::steady_clock::now();
  const placement::ProgressFn progress = [&](int placed, int total, double time) {
    const auto now = std::chrono::steady_clock::now();
    if (placed < total && std::chrono::duration<double>(now - last).count() < 5.0) return;
    last = now;
    std::cout << fmt::format("  {}/{} units, t = {:.2f} s\n", placed, total, time) << std::flush;
  };
  placement::PlacementResult result;
  try {
    result = placement::place(scene, progress);
  } catch (const simulation::SimulationError& e) {
    std::cerr << "error: the placement stopped: " << e.what() << "\n";
    std::exit(3);
  }
  placement::writePlacementOutputs(io::applyOverridesToText(text.str(), o.sets, o.file), result, scenePath,
                                   scene.output.folder);
  std::cout << placement::summaryText(result);
  std::cout << fmt::format("placed scene: {}\ntables: {}/units.csv, placement.json, placement.txt\n",
                           scenePath.string(), scene.output.folder.string());
}

} // namespace

void addPlaceCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto o = std::make_shared<PlaceOptions>();
  auto* place = app.add_subcommand("place", "build an armour layer on a scene's underlayer (its placement: block): rocks, "
                                            "then units by crane or grid; writes the placed scene");
  place->add_option("file", o->file, "scene file with a placement: block")->required()->check(CLI::ExistingFile);
  place->add_option("--threads", o->threads, "OpenMP threads (0 = OpenMP's default)");
  place->add_option("--output", o->output, "the placed scene's path (default: placement.output beside the file)");
  addSetOption(*place, o->sets);
  place->callback([o] { placeScene(*o); });
}

} // namespace armour::app
