// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/PlaceCommands.hpp"

#include "core/TextFile.hpp"
#include "app/PlacementCheckpoint.hpp"
#include "app/RunCommands.hpp"
#include "app/StopSignals.hpp"
#include "io/SceneOverrides.hpp"

#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "placement/PlacedScene.hpp"
#include "placement/Placer.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/Interpenetration.hpp"
#include "simulation/World.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <optional>
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
  bool restart = false;          ///< continue from the output folder's place-checkpoint.nc
  double checkpointMinutes = 10.0; ///< wall time between checkpoints (unit: min); 0 = only when stopped
};

/// The command that continues a stopped placement.
std::string restartCommand(const PlaceOptions& o) {
  std::string again = fmt::format("armour place {} --restart", shellWord(o.file));
  if (!o.output.empty()) again += " --output " + shellWord(o.output);
  for (const std::string& set : o.sets) again += " --set " + shellWord(set);
  return again;
}

void placeScene(const PlaceOptions& o) {
  if (o.threads < 0) core::failInput("--threads", "{}: give a positive number of threads, or 0 for OpenMP's default", o.threads);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  const std::string text = core::readTextFile(o.file, "the placement file");
  const io::Scene scene = io::readScene(o.file, o.sets);
  if (!scene.placement.enabled)
    core::failInput(o.file, "no `placement:` block; `armour place` needs one (docs/placement.md has examples), or use "
                            "`armour run` for a scene without one");
  const fs::path scenePath = o.output.empty() ? scene.baseDir / scene.placement.output : fs::absolute(o.output);
  if (fs::is_directory(scenePath))
    core::failInput(o.output.empty() ? "placement.output" : "--output",
                    "{} is a folder; give the path of the placed scene file (a .yaml), e.g. {}", scenePath.string(),
                    (scenePath / "placed.yaml").string());
  // The tables and the checkpoint go beside the placed scene: with --output elsewhere, the default
  // folder "<file stem>-out" is taken there, so two placements of one file do not share them.
  const fs::path folder = o.output.empty() || scene.output.folderGiven
                              ? scene.output.folder
                              : scenePath.parent_path() / fs::path(scene.output.folder).filename();
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
  // Checkpoints: the World's state plus the placement's own progress, for the scene as resolved
  // (its identity) and the placement file's text as run (with the --set changes).
  const std::string effectiveText = io::applyOverridesToText(text, o.sets, o.file);
  PlacementCheckpoint checkpoint(scene, effectiveText, folder / "place-checkpoint.nc");
  std::optional<placement::PlacementProgress> resume;
  if (o.restart) {
    resume = checkpoint.read();
    std::cout << fmt::format("continuing the placement from {} ({} units placed{})\n", checkpoint.path().string(),
                             resume->unitsDone, resume->finalSettle ? ", in the final settle" : "");
  }
  if (!(o.checkpointMinutes >= 0.0) || !std::isfinite(o.checkpointMinutes))
    core::failInput("--checkpoint-minutes", "{}: give the wall time between checkpoints in minutes (>= 0; 0 = only "
                                            "when stopped by SIGINT or SIGTERM)", o.checkpointMinutes);
  std::error_code ec;
  // The placed scene's folder too, now: not after an hour of placing (its files are written last).
  fs::create_directories(scenePath.parent_path(), ec);
  if (ec) core::failInput(o.output.empty() ? "placement.output" : "--output",
                          "cannot create the folder {} of the placed scene ({}); give a path in a writable folder",
                          scenePath.parent_path().string(), ec.message());
  fs::create_directories(folder, ec);
  if (ec) core::failInput(folder.string(), "cannot create the output folder ({}); set output.folder in {} or --set "
                                           "output.folder=... to a writable place",
                          ec.message(), o.file);
  const StopSignals signals;
  placement::PlaceOptions options;
  if (resume) options.resume = &*resume;
  options.safePoint = checkpoint.safePoint(signals, o.checkpointMinutes);
  placement::PlacementResult result;
  try {
    result = placement::place(scene, progress, options);
  } catch (const placement::PlacementStopped& e) {
    std::cerr << fmt::format("{}: {} by {}; checkpoint written to {}\ncontinue with: {}\n", o.file, e.what(),
                             signalName(signals.received()), checkpoint.path().string(), restartCommand(o));
    throw CLI::RuntimeError(kExitStopped);
  } catch (const simulation::SimulationError& e) {
    std::cerr << "error: the placement stopped: " << e.what() << "\n";
    std::exit(3);
  }
  placement::writePlacementOutputs(effectiveText, result, scenePath, folder);
  fs::remove(checkpoint.path(), ec); // the placed scene is the result now
  std::cout << placement::summaryText(result);
  std::cout << fmt::format("placed scene: {}\ntables: {}/units.csv, placement.json, placement.txt\n",
                           scenePath.string(), folder.string());
  // A placement can end with units inside the statics or each other (a grid reaching past the end
  // of its slope, units pushed through a thin static piece): `armour run` and `storm` would refuse
  // the placed scene, so say so now, with the fix, instead of exiting 0.
  const auto overlaps = simulation::measureInterpenetration(*result.built.world, result.built.planes);
  std::cout << simulation::describeInterpenetration(overlaps) << "\n";
  try {
    simulation::refuseInterpenetration(overlaps, scenePath.string());
  } catch (const core::InputError& e) {
    core::failInput(o.file, "the placement ended with bodies inside each other or the statics, which `armour run` "
                            "refuses: {}. Check that the placement grid fits on its underlayer (rows x dy against the "
                            "slope's length: fewer rows, or a higher crest); the placed scene and its tables were "
                            "written for inspection",
                    e.what());
  }
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
  place->add_flag("--restart", o->restart, "continue a stopped placement from the output folder's place-checkpoint.nc "
                                           "(same file and --set changes)");
  place->add_option("--checkpoint-minutes", o->checkpointMinutes,
                    "wall time between checkpoints (min; 0 = only when stopped by SIGINT/SIGTERM)")
      ->capture_default_str();
  place->callback([o] { placeScene(*o); });
}

} // namespace armour::app
