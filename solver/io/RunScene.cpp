// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/RunScene.hpp"

#include "core/Error.hpp"
#include "io/SceneReader.hpp"

#include <sstream>
#include <string>
#include <vector>

namespace armour::io {

namespace fs = std::filesystem;

fs::path sceneFileOfRun(const BodySeriesReader& series, const fs::path& runDir) {
  std::string named = series.textAttribute("scene_file").value_or("");
  if (named.empty()) {
    std::istringstream lines(series.history());
    std::string line;
    while (std::getline(lines, line)) {
      std::istringstream words(line);
      std::string w;
      bool afterCommand = false;
      while (words >> w) {
        if (afterCommand && !w.empty() && w[0] != '-') {
          named = w;
          if (named.size() > 1 && named.front() == '\'' && named.back() == '\'') named = named.substr(1, named.size() - 2);
          break;
        }
        if (w == "run" || w == "storm") afterCommand = true;
      }
    }
  }
  if (named.empty())
    core::failInput(series.path().string(), "names no scene (no scene_file attribute, no `armour run <scene>` in "
                                            "its history); give the scene with --scene");
  for (const fs::path& candidate :
       {fs::path(named), runDir.parent_path() / fs::path(named).filename(), runDir.parent_path() / named})
    if (fs::is_regular_file(candidate)) return candidate;
  core::failInput(series.path().string(),
                  "the run was made from '{}', which is not found from here; give the scene "
                  "with --scene",
                  named);
}

Scene sceneOfRun(const fs::path& scenePath, const BodySeriesReader& series) {
  std::vector<std::string> sets;
  std::istringstream lines(series.textAttribute("scene_sets").value_or(""));
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) sets.push_back(line);
  Scene scene = readScene(scenePath, sets);
  if (const auto file = series.textAttribute("storm_file")) {
    hydro::HydroSettings& h = scene.hydro;
    h.enabled = true;
    h.model = hydro::HydroModel::Storm;
    h.storm.file = *file;
    h.bodies = series.textAttribute("hydro_bodies").value_or(h.bodies);
    h.storm.timeOffset = series.numberAttribute("storm_time_offset").value_or(h.storm.timeOffset);
    h.storm.offsetX = series.numberAttribute("storm_offset_x").value_or(h.storm.offsetX);
    h.storm.offsetZ = series.numberAttribute("storm_offset_z").value_or(h.storm.offsetZ);
    h.storm.rampTime = series.numberAttribute("storm_ramp_time").value_or(h.storm.rampTime);
  }
  return scene;
}

} // namespace armour::io
