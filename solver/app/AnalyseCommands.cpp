// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/AnalyseCommands.hpp"

#include "app/PackAnalysis.hpp"
#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "placement/PlacedScene.hpp"
#include "placement/Placer.hpp"
#include "simulation/World.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#ifndef ARMOUR_UTILITIES_DIR
#define ARMOUR_UTILITIES_DIR ""
#endif

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
  const fs::path script = fs::path(ARMOUR_UTILITIES_DIR) / "plot_pack.py";
  if (!fs::exists(script)) {
    std::cout << fmt::format("plots skipped: {} not found\n", script.string());
    return;
  }
  const std::string command = fmt::format("python3 '{}' '{}' '{}'", script.string(), csv.string(), folder.string());
  if (std::system(command.c_str()) != 0)
    std::cout << fmt::format("plots failed (python3 with numpy and matplotlib needed): {}\n", command);
}

void analyse(const AnalyseOptions& o) {
  const io::Scene scene = io::readScene(o.scene);
  AnalyseSettings settings;
  settings.unitPrefix = o.prefix;
  settings.axis = o.axis;
  std::optional<PoseMap> state, reference;
  if (!o.state.empty()) state = readPoses(o.state);
  if (!o.reference.empty()) reference = readPoses(o.reference);
  const PackReport report = analysePack(scene, settings, state ? &*state : nullptr, reference ? &*reference : nullptr);
  const fs::path folder = o.output.empty() ? scene.baseDir / (scene.name + "-analysis") : fs::absolute(o.output);
  writePackReport(report, folder);
  std::cout << packText(report);
  if (o.plots) plot(folder / "units.csv", folder);
  std::cout << fmt::format("tables: {}/units.csv, pack.json, pack.txt\n", folder.string());
}

struct EnsembleOptions {
  std::string file;
  int runs = 16;
  std::uint64_t firstSeed = 1;
  int threads = 0;
  std::string output;
  std::string axis = "nose";
};

struct Stat {
  std::string name;
  std::vector<double> values;
  [[nodiscard]] double mean() const {
    double s = 0.0;
    for (double v : values) s += v;
    return values.empty() ? NAN : s / static_cast<double>(values.size());
  }
  [[nodiscard]] double std() const {
    if (values.size() < 2) return 0.0;
    const double m = mean();
    double s = 0.0;
    for (double v : values) s += (v - m) * (v - m);
    return std::sqrt(s / static_cast<double>(values.size() - 1));
  }
};

void ensemble(const EnsembleOptions& o) {
  if (o.runs < 1) core::failInput("--runs", "{}: give at least one member", o.runs);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  std::ifstream in(o.file, std::ios::binary);
  if (!in) core::failInput(o.file, "cannot open the placement file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const fs::path source = fs::absolute(o.file);
  const fs::path folder = o.output.empty() ? source.parent_path() / (source.stem().string() + "-ensemble")
                                           : fs::absolute(o.output);
  fs::create_directories(folder);
  std::vector<Stat> stats{{"delta_rms_m", {}},           {"delta_rms_horizontal_m", {}}, {"p2_mean_director", {}},
                          {"p2_q_tensor", {}},           {"packing_density", {}},        {"layer_thickness_m", {}},
                          {"porosity", {}},              {"coordination_number", {}},    {"max_displacement_dn", {}}};
  std::string rows = "member,seed";
  for (const Stat& s : stats) rows += "," + s.name;
  rows += "\n";
  for (int k = 0; k < o.runs; ++k) {
    // Each member is the file with its seed changed: the height field, the jitter, the
    // orientations and the rocks all follow the scene seed unless the file fixes their own.
    const std::uint64_t seed = o.firstSeed + static_cast<std::uint64_t>(k);
    YAML::Node root = YAML::Load(text);
    root["seed"] = seed;
    YAML::Emitter emitter;
    emitter << root;
    const std::string memberText = emitter.c_str();
    const io::Scene scene = io::parseScene(memberText, source.parent_path(), source.filename().string());
    if (!scene.placement.enabled) core::failInput(o.file, "no placement: block; `armour ensemble` places each member");
    std::cout << fmt::format("member {}/{} (seed {}) ...\n", k + 1, o.runs, seed) << std::flush;
    const placement::PlacementResult placed = placement::place(scene);
    const fs::path memberDir = folder / fmt::format("member-{:03d}", k);
    placement::writePlacementOutputs(memberText, placed, memberDir / "placed.yaml", memberDir);
    // Displacements from where each unit was released (seed 001 test 3: the crane positions).
    PoseMap release;
    for (const auto& u : placed.units) release[u.name] = {u.gridPoint, u.releaseOrientation};
    AnalyseSettings settings;
    settings.unitPrefix = scene.placement.namePrefix + "_";
    settings.axis = o.axis;
    const PackReport report = analysePack(placed.scene, settings, nullptr, &release);
    writePackReport(report, memberDir / "analysis");
    const double values[] = {report.displacement->deltaRms,
                             report.displacement->deltaRmsHorizontal,
                             report.p2Mean.p2,
                             report.p2Q.p2,
                             placed.summary.packingDensity > 0.0 ? placed.summary.packingDensity : report.packingHull.phi,
                             placed.summary.layerThickness,
                             placed.summary.porosity,
                             report.contacts.coordinationNumber,
                             report.displacement->maxDn};
    rows += fmt::format("{},{}", k, seed);
    for (std::size_t s = 0; s < stats.size(); ++s) {
      stats[s].values.push_back(values[s]);
      rows += fmt::format(",{}", values[s]);
    }
    rows += "\n";
  }
  std::string table = fmt::format("ensemble of {} members of {} (seeds {}..{}), mean +- standard deviation:\n", o.runs,
                                  o.file, o.firstSeed, o.firstSeed + static_cast<std::uint64_t>(o.runs) - 1);
  std::string json = "{\n";
  for (std::size_t s = 0; s < stats.size(); ++s) {
    table += fmt::format("  {:<24} {:.4g} +- {:.2g}\n", stats[s].name, stats[s].mean(), stats[s].std());
    json += fmt::format("  \"{}\": {{\"mean\": {}, \"std\": {}}}{}\n", stats[s].name, stats[s].mean(), stats[s].std(),
                        s + 1 < stats.size() ? "," : "");
  }
  json += "}\n";
  core::writeFileAtomically(folder / "ensemble.csv", [&](std::ostream& out) { out << rows; });
  core::writeFileAtomically(folder / "ensemble.txt", [&](std::ostream& out) { out << table; });
  core::writeFileAtomically(folder / "ensemble.json", [&](std::ostream& out) { out << json; });
  std::cout << table << fmt::format("tables: {}/ensemble.csv, ensemble.json; members in member-*/\n", folder.string());
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

  auto e = std::make_shared<EnsembleOptions>();
  auto* ensembleCmd = app.add_subcommand("ensemble", "place N members of a placement file with seeds S..S+N-1 and report "
                                                     "the mean +- standard deviation of each measure (seed 001 Table 1)");
  ensembleCmd->add_option("file", e->file, "scene file with a placement: block")->required()->check(CLI::ExistingFile);
  ensembleCmd->add_option("--runs", e->runs, "members")->capture_default_str();
  ensembleCmd->add_option("--first-seed", e->firstSeed, "seed of the first member")->capture_default_str();
  ensembleCmd->add_option("--threads", e->threads, "OpenMP threads (0 = OpenMP's default)");
  ensembleCmd->add_option("--output", e->output, "output folder (default: <file stem>-ensemble beside the file)");
  ensembleCmd->add_option("--axis", e->axis, "unit axis for P2")->capture_default_str();
  ensembleCmd->callback([e] { ensemble(*e); });
}

} // namespace armour::app
