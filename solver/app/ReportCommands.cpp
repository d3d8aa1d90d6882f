// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/ReportCommands.hpp"

#include "analysis/DesignFormulas.hpp"
#include "analysis/Displacement.hpp"
#include "analysis/WaveStatistics.hpp"
#include "app/PackAnalysis.hpp"
#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "io/BodySeriesReader.hpp"
#include "io/SceneReader.hpp"
#include "storm/StormFile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>


namespace armour::app {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = 180.0 / std::numbers::pi;

struct ReportOptions {
  std::string run;                 ///< the run's output folder
  std::string scene;               ///< default: the scene named in bodies.nc's history
  std::string storm;               ///< default: the scene's hydro storm file
  std::string output;              ///< default: RUN_DIR/report
  std::string prefix;              ///< units: movable bodies whose names start with it (default: the hydro bodies)
  std::string axis = "nose";       ///< unit axis for P2
  std::vector<double> voxel;       ///< (x, z) of the pressure history, in the storm file's coordinates (unit: m)
  /// The storm file's (x, z) of the scene's origin; default: the scene's hydro.storm.offset when the
  /// storm is the scene's, else (0, 0) (unit: m).
  std::vector<double> stormOffset;
  double gaugeX = kNaN;            ///< x of the eta gauge (unit: m); default the slope's toe
  std::string stormWindow = "run"; ///< storm records in storm.csv: "run" (the replayed window) or "all"
  double hs = kNaN;                ///< override of the storm's Hs (unit: m)
  double tm = kNaN;                ///< override of the mean period (unit: s)
  double tp = kNaN;                ///< override of the peak period (unit: s)
  double cotAlpha = kNaN;          ///< override of the slope (unit: -)
  double permeability = 0.4;       ///< van der Meer's P (unit: -)
  double porosity = kNaN;          ///< armour layer porosity for S (unit: -); default the pack's
  double displacedDn = 1.0;        ///< a unit moved by more than this is displaced, for Nod and S (unit: Dn)
  bool breaking = false;           ///< Hudson's K_D for breaking waves
  bool noPlots = false;
};

std::string jsonNumber(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("null"); }
std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    if (static_cast<unsigned char>(c) < 0x20) continue;
    out += c;
  }
  return out + "\"";
}
std::string csvNumber(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("NaN"); }

// ------------------------------------------------------------------------------------------------
// bodies.nc
// ------------------------------------------------------------------------------------------------

/// The scene a run was made from: bodies.nc's `scene_file`, else (files of older runs) the
/// argument after `run` or `storm` on the last line of the history attribute that has one; looked
/// for as recorded, relative to the current folder and to the run folder's parent (a moved run).
fs::path sceneFromRun(const io::BodySeriesReader& series, const fs::path& runDir) {
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

/// The scene as the run read it: with the run's --set changes (`scene_sets`) and, for a storm
/// replay, the storm settings it ran with (`armour storm --storm --time-offset`: storm_file,
/// storm_time_offset, storm_offset_x/z, storm_ramp_time, hydro_bodies).
io::Scene sceneOfRun(const fs::path& scenePath, const io::BodySeriesReader& series) {
  std::vector<std::string> sets;
  std::istringstream lines(series.textAttribute("scene_sets").value_or(""));
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) sets.push_back(line);
  io::Scene scene = io::readScene(scenePath, sets);
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

// ------------------------------------------------------------------------------------------------
// Storm input: wave statistics of eta at a gauge
// ------------------------------------------------------------------------------------------------

/// "Hs=7 m", "Hs 7 m", "H=1.5 m" (regular waves) and "Tp 11 s", "T=6 s" in a provenance text.
double provenanceValue(const std::string& text, const char* symbols) {
  const std::regex re(std::string("\\b(?:") + symbols + ")\\s*[= ]\\s*([0-9]+(?:\\.[0-9]+)?)\\s*(?:m|s)\\b");
  std::smatch m;
  if (std::regex_search(text, m, re)) return std::stod(m[1].str());
  return kNaN;
}

// ------------------------------------------------------------------------------------------------
// The report
// ------------------------------------------------------------------------------------------------

/// One design formula's verdict for the summary.
struct FormulaResult {
  std::string name;
  std::string source;
  bool applicable = false;
  std::string note; ///< why not applicable, or what the numbers mean
  std::vector<std::pair<std::string, double>> values;
};

struct UnitInfo {
  std::size_t sceneIndex = 0;
  std::size_t seriesIndex = 0;
  double dn = 0.0;
};

void runPython(const fs::path& folder, const fs::path& runDir) {
  runUtility("report.py", {folder.string(), "--run", runDir.string()}, "plots and index.html");
}

/// The storm input of a run: wave statistics of eta at the gauge, the provenance's Hs and Tp, and
/// the pressure history at a voxel over the run's window (storm.csv).
struct StormSummary {
  analysis::WaveStatistics waves;
  double gaugeX = kNaN;         ///< (unit: m)
  double voxelX = kNaN;         ///< (unit: m)
  double voxelZ = kNaN;         ///< (unit: m)
  double waterDensity = 1025.0; ///< (unit: kg/m^3); sea water without a storm file
  double offset = 0.0;          ///< storm time at run time 0 (unit: s)
  double swl = kNaN;            ///< still water level (unit: m)
  double provHs = kNaN;         ///< Hs (or H) the provenance states (unit: m)
  double provTp = kNaN;         ///< Tp (or T) the provenance states (unit: s)
  std::string title;
  std::string csv = "storm_time_s,run_time_s,pressure_Pa,eta_gauge_m,alpha\n";
  std::size_t records = 0;
  double start = kNaN, end = kNaN; ///< first and last record time (unit: s)
};

StormSummary summariseStorm(const fs::path& stormPath, const io::Scene& scene, const ReportOptions& o,
                            const Eigen::Vector3d& unitsMean, double runStart, double runEnd) {
  StormSummary s;
  if (stormPath.empty()) return s;
  const storm::StormReader reader(stormPath.string());
  const storm::StormHeader& h = reader.header();
  const std::vector<double>& times = reader.times();
  s.waterDensity = h.waterDensity;
  s.swl = h.stillWaterLevel;
  s.title = h.provenance.title;
  s.records = times.size();
  s.start = times.front();
  s.end = times.back();
  // The run's time offset applies when the storm is the scene's own (however the path is spelt).
  std::error_code same;
  const bool scenesStorm = scene.hydro.enabled && scene.hydro.model == hydro::HydroModel::Storm &&
                           fs::equivalent(stormPath, fs::path(scene.hydro.storm.file), same);
  s.offset = scenesStorm ? scene.hydro.storm.timeOffset : 0.0;
  // Scene positions in the file's coordinates (hydro.storm.offset: a tank's origin is not the scene's).
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  if (o.stormOffset.size() == 2) {
    shift = Eigen::Vector3d(o.stormOffset[0], 0.0, o.stormOffset[1]);
  } else if (scenesStorm) {
    shift = Eigen::Vector3d(scene.hydro.storm.offsetX, 0.0, scene.hydro.storm.offsetZ);
  }
  const std::string prov = h.provenance.title + " " + h.provenance.sourceCase + " " + h.provenance.comment;
  s.provHs = provenanceValue(prov, "Hs|Hm0|H");
  s.provTp = provenanceValue(prov, "Tp|T");
  const auto nearest = [](const std::vector<double>& axis, double v) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < axis.size(); ++i)
      if (std::abs(axis[i] - v) < std::abs(axis[best] - v)) best = i;
    return best;
  };
  // The gauge: the slope's toe (the waves at the structure), else the offshore column.
  s.gaugeX = o.gaugeX;
  if (!std::isfinite(s.gaugeX))
    s.gaugeX = scene.statics.slopes.empty() ? h.x.front() : scene.statics.slopes.front().origin.x() + shift.x();
  const std::size_t ig = nearest(h.x, s.gaugeX);
  s.gaugeX = h.x[ig];
  std::vector<double> eta(times.size());
  for (std::size_t k = 0; k < times.size(); ++k) eta[k] = reader.eta(k)[ig];
  s.waves = analysis::waveStatistics(times, eta);
  // The voxel: given, or a permanently submerged one with data near the units (seed 000 Fig. 5:
  // "a permanently submerged cell inside the armour layer near the centre of the model").
  std::size_t ix = 0, iz = 0;
  if (o.voxel.size() == 2) {
    ix = nearest(h.x, o.voxel[0]);
    iz = nearest(h.z, o.voxel[1]);
    if (h.samples[iz * h.nx() + ix] == 0)
      core::failInput("--voxel",
                      "{} {}: the voxel x = {} m, z = {} m of {} holds no data (samples = 0); choose a "
                      "voxel in the armour layer",
                      o.voxel[0], o.voxel[1], h.x[ix], h.z[iz], stormPath.string());
  } else {
    const Eigen::Vector3d mean = unitsMean + shift;
    ix = nearest(h.x, mean.x());
    double etaMin = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < times.size(); ++k) etaMin = std::min(etaMin, reader.eta(k)[ix]);
    const double zTarget = std::min(mean.z(), h.stillWaterLevel + etaMin - h.dz());
    double best = std::numeric_limits<double>::infinity();
    bool found = false;
    for (std::size_t j = 0; j < h.nz(); ++j)
      for (std::size_t i = 0; i < h.nx(); ++i) {
        if (h.samples[j * h.nx() + i] == 0) continue;
        // Prefer voxels below the lowest trough (permanently submerged), then the nearest.
        const double penalty = h.z[j] > zTarget ? 1e6 : 0.0;
        const double dist = std::hypot(h.x[i] - mean.x(), h.z[j] - zTarget) + penalty;
        if (dist < best) {
          best = dist;
          ix = i;
          iz = j;
          found = true;
        }
      }
    if (!found) core::failInput(stormPath.string(), "no voxel holds data (samples = 0 everywhere)");
  }
  s.voxelX = h.x[ix];
  s.voxelZ = h.z[iz];
  storm::StormRecord record;
  // The run's window: from the record at or before its start to the one at or after its end.
  std::size_t k0 = 0, k1 = times.size();
  if (o.stormWindow == "run") {
    while (k0 + 1 < times.size() && times[k0 + 1] - s.offset <= runStart) ++k0;
    k1 = k0;
    while (k1 < times.size() && times[k1] - s.offset < runEnd) ++k1;
    k1 = std::min(k1 + 1, times.size());
  }
  for (std::size_t k = k0; k < k1; ++k) {
    const double runTime = times[k] - s.offset;
    reader.read(k, record);
    const std::size_t v = iz * h.nx() + ix;
    s.csv +=
        fmt::format("{},{},{},{},{}\n", times[k], runTime, csvNumber(record.p[v]), eta[k], csvNumber(record.alpha[v]));
  }
  return s;
}

/// What the design formulas need of the run and its storm.
struct DesignInputs {
  std::string unitType;      ///< shape-library name of the units
  double ns = kNaN;          ///< Hs / (Delta Dn) (unit: -)
  double cotAlpha = kNaN;    ///< slope (unit: -)
  double steepness = kNaN;   ///< s_om (unit: -)
  double xi = kNaN;          ///< xi_m (unit: -)
  double waves = kNaN;       ///< N in the run (unit: -)
  double tm = kNaN;          ///< mean period (unit: s)
  double duration = 0.0;     ///< the run's duration (unit: s)
  double permeability = 0.4; ///< van der Meer's P (unit: -)
  bool breaking = false;     ///< Hudson's K_D for breaking waves
  std::string noHs = "no storm: Hs unknown (give --storm or --hs)"; ///< why ns is unknown
};

/// Each formula that applies to the unit type, evaluated or marked not applicable with the reason.
std::vector<FormulaResult> designFormulas(const DesignInputs& in) {
  std::vector<FormulaResult> formulas;
  const auto attempt = [&](const char* name, const char* source, const std::function<void(FormulaResult&)>& f) {
    FormulaResult r;
    r.name = name;
    r.source = source;
    if (!std::isfinite(in.ns))
      r.note = in.noHs;
    else if (!std::isfinite(in.cotAlpha))
      r.note = "no slope: give --cot";
    else {
      try {
        f(r);
        r.applicable = true;
      } catch (const core::InputError& e) {
        r.note = std::string("not applicable: ") + e.what();
      }
    }
    formulas.push_back(std::move(r));
  };
  attempt("Hudson", "Hudson (1959); SPM (1984); CEM (2006)", [&](FormulaResult& r) {
    const analysis::HudsonCoefficient& c = analysis::hudsonCoefficient(in.unitType);
    const double kd = in.breaking ? c.kdBreaking : c.kdNonBreaking;
    const double nsH = analysis::hudsonStabilityNumber(kd, in.cotAlpha);
    r.source += "; K_D: " + c.source;
    r.values = {{"K_D", kd}, {"Ns_hudson", nsH}, {"Ns_storm", in.ns}, {"Ns_ratio", in.ns / nsH}};
    r.note =
        fmt::format("{} ({} waves); no damage (0-5 % displaced) expected while Ns_storm <= Ns_hudson: {}",
                    c.description, in.breaking ? "breaking" : "non-breaking", in.ns <= nsH ? "within" : "exceeded");
    if (in.cotAlpha < c.cotMin - 1e-9 || in.cotAlpha > c.cotMax + 1e-9)
      r.note += fmt::format("; K_D is given for cot alpha {}-{}, the slope is {:.3g}", c.cotMin, c.cotMax, in.cotAlpha);
  });
  const bool isRock = in.unitType == "rock" || in.unitType == "voronoi-rock";
  if (isRock) {
    attempt("van der Meer rock", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (rock)", "no mean period Tm: give --tm");
      const analysis::RockDamage d =
          analysis::vanDerMeerRockDamage({in.ns, in.steepness, in.cotAlpha, in.permeability, in.waves});
      r.values = {{"S", d.damage},
                  {"xi_m", d.iribarren},
                  {"xi_mc", d.iribarrenCritical},
                  {"N", in.waves},
                  {"P", in.permeability}};
      r.note = d.plunging ? "plunging waves" : "surging waves";
    });
    attempt("Melby and Kobayashi", "Melby and Kobayashi (1998)", [&](FormulaResult& r) {
      if (!std::isfinite(in.tm)) core::failInput("Melby and Kobayashi", "no mean period Tm: give --tm");
      const analysis::ProgressedDamage d =
          analysis::melbyKobayashiDamage({{in.duration, in.ns, in.tm}}, in.cotAlpha, {in.xi});
      r.values = {{"S", d.damage}, {"sigma_S", d.standardDeviation}, {"t_s", in.duration}};
      r.note = "mean damage after the run's duration, one stage of constant Hs and Tm";
    });
  } else if (in.unitType == "cube") {
    attempt("van der Meer cubes", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (cubes)", "no mean period Tm: give --tm");
      r.values = {{"Nod", analysis::vanDerMeerCubesNod(in.ns, in.waves, in.steepness, in.cotAlpha)}, {"N", in.waves}};
      r.note = "displaced units per Dn-wide strip after N waves";
    });
  } else if (in.unitType == "tetrapod") {
    attempt("van der Meer tetrapods", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (tetrapods)", "no mean period Tm: give --tm");
      r.values = {{"Nod", analysis::vanDerMeerTetrapodsNod(in.ns, in.waves, in.steepness, in.cotAlpha)},
                  {"N", in.waves}};
      r.note = "displaced units per Dn-wide strip after N waves";
    });
  } else if (in.unitType == "accropode") {
    attempt("van der Meer Accropode", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (Accropode)", "no mean period Tm: give --tm");
      const analysis::AccropodeStability a = analysis::vanDerMeerAccropode(in.ns, in.steepness, in.cotAlpha);
      r.values = {{"Ns_start_of_damage", a.startOfDamage}, {"Ns_failure", a.failure}, {"Ns_storm", in.ns}};
      r.note = a.verdict;
    });
  }

  return formulas;
}

void report(const ReportOptions& o) {
  const fs::path runDir = fs::absolute(o.run).lexically_normal();
  if (!fs::is_directory(runDir))
    core::failInput(o.run, "not a folder; give the output folder of `armour run` (the scene's output.folder, e.g. "
                           "wave-slope-out)");
  if (!(o.displacedDn > 0.0)) core::failInput("--displaced-dn", "{}: must be positive (unit: Dn)", o.displacedDn);
  if (o.stormWindow != "run" && o.stormWindow != "all")
    core::failInput("--storm-window", "'{}': give run or all", o.stormWindow);
  const io::BodySeriesReader series(runDir / "bodies.nc");
  const fs::path scenePath = o.scene.empty() ? sceneFromRun(series, runDir) : fs::path(o.scene);
  const io::Scene scene = sceneOfRun(scenePath, series);

  // Units: movable bodies with the prefix (default: those the hydro loads act on).
  std::string prefix = o.prefix;
  if (prefix.empty() && scene.hydro.enabled && scene.hydro.bodies != "all") prefix = scene.hydro.bodies;
  std::map<std::string, std::size_t> seriesIndex;
  for (std::size_t b = 0; b < series.names().size(); ++b) seriesIndex[series.names()[b]] = b;
  std::vector<UnitInfo> units;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const io::Body& b = scene.bodies[i];
    if (b.fixed || b.name.rfind(prefix, 0) != 0) continue;
    const auto it = seriesIndex.find(b.name);
    if (it == seriesIndex.end())
      core::failInput(series.path().string(),
                      "has no body '{}' of the scene {}: the run was made from another scene; "
                      "give its scene with --scene",
                      b.name, scenePath.string());
    if (!b.volume)
      core::failInput(scenePath.string(),
                      "body '{}' has no volume (a mesh used at its own size): the report needs Dn; "
                      "give the body a volume",
                      b.name);
    units.push_back({i, it->second, std::cbrt(*b.volume)});
  }
  if (units.empty())
    core::failInput(scenePath.string(), "no units: no movable body{}", prefix.empty() ? "" : " named " + prefix + "*");
  const std::size_t nu = units.size();

  // Poses before (the scene) and after (the last record). bodies.nc holds the principal frame; the
  // natural frame the scene and P2 use is q_nat = q_p(t) q_p(0)^-1 q_scene (the first record is
  // the scene's state), and the rotation between two states is the same in either frame.
  const std::size_t last = series.records() - 1;
  std::vector<double> pos, q0, q1;
  series.positions(last, 1, pos);
  series.orientations(0, q0);
  series.orientations(last, q1);
  PoseMap before, after;
  std::vector<Eigen::Vector3d> xBefore(nu), xAfter(nu);
  std::vector<Eigen::Quaterniond> qBefore(nu), qAfter(nu);
  std::vector<double> dn(nu);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const io::Body& b = scene.bodies[i];
    before[b.name] = {b.position, b.orientation};
    const auto it = seriesIndex.find(b.name);
    if (it == seriesIndex.end()) {
      after[b.name] = before[b.name];
      continue;
    }
    const std::size_t s = it->second;
    const Eigen::Quaterniond p0(q0[4 * s], q0[4 * s + 1], q0[4 * s + 2], q0[4 * s + 3]);
    const Eigen::Quaterniond p1(q1[4 * s], q1[4 * s + 1], q1[4 * s + 2], q1[4 * s + 3]);
    after[b.name] = {Eigen::Vector3d(pos[3 * s], pos[3 * s + 1], pos[3 * s + 2]),
                     (p1 * p0.conjugate() * b.orientation).normalized()};
  }
  for (std::size_t k = 0; k < nu; ++k) {
    const std::string& name = scene.bodies[units[k].sceneIndex].name;
    xBefore[k] = before[name].position;
    qBefore[k] = before[name].orientation;
    xAfter[k] = after[name].position;
    qAfter[k] = after[name].orientation;
    dn[k] = units[k].dn;
  }
  double dnMean = 0.0;
  for (double d : dn) dnMean += d / static_cast<double>(nu);

  // The slope frame: the scene's slope, else a plane through the units, else level.
  analysis::SlopeFrame frame;
  bool frameFromSlope = false;
  if (!scene.statics.slopes.empty()) {
    const io::StaticSlope& s = scene.statics.slopes.front();
    frame = analysis::SlopeFrame::fromTanAlpha(s.tanAlpha, Eigen::Vector3d(s.origin.x(), 0.0, s.origin.y()));
    frameFromSlope = true;
  } else {
    try {
      frame = analysis::fitSlopeFrame(xBefore);
    } catch (const core::InputError&) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& p : xBefore) mean += p / static_cast<double>(nu);
      frame = analysis::SlopeFrame::fromTanAlpha(0.0, mean);
    }
  }
  analysis::DisplacementSettings dsettings;
  const analysis::PackDisplacement disp =
      analysis::measureDisplacement(xBefore, xAfter, qBefore, qAfter, dn, frame, dsettings);

  // P2 and porosity before and after, from the pack analysis (not for units without an axis).
  AnalyseSettings asettings;
  asettings.unitPrefix = prefix;
  asettings.axis = o.axis;
  std::optional<PackReport> packBefore, packAfter;
  std::string packNote;
  try {
    packBefore = analysePack(scene, asettings);
    packAfter = analysePack(scene, asettings, &after);
  } catch (const core::InputError& e) {
    packNote = e.what();
    std::cout << fmt::format("P2 and porosity not computed: {}\n", packNote);
  }

  // Time series of the displacements, streamed in blocks of records.
  const fs::path folder = o.output.empty() ? runDir / "report" : fs::absolute(o.output);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) core::failInput(folder.string(), "cannot create the report folder: {}", ec.message());
  std::string timeseries = "time_s,total_displacement_m,mean_displacement_dn,max_displacement_dn,moved_0.2dn,"
                           "moved_0.5dn,moved_1dn\n";
  {
    std::vector<double> block;
    constexpr std::size_t kBlock = 64; // bodies.nc chunks hold 64 records
    for (std::size_t k0 = 0; k0 < series.records(); k0 += kBlock) {
      const std::size_t n = std::min(kBlock, series.records() - k0);
      series.positions(k0, n, block);
      const std::size_t nb = series.names().size();
      for (std::size_t r = 0; r < n; ++r) {
        double total = 0.0, mean = 0.0, maxDn = 0.0;
        std::size_t moved[3] = {0, 0, 0};
        for (std::size_t k = 0; k < nu; ++k) {
          const double* x = &block[(r * nb + units[k].seriesIndex) * 3];
          const double d = (Eigen::Vector3d(x[0], x[1], x[2]) - xBefore[k]).norm();
          total += d;
          mean += d / dn[k] / static_cast<double>(nu);
          maxDn = std::max(maxDn, d / dn[k]);
          moved[0] += d > 0.2 * dn[k];
          moved[1] += d > 0.5 * dn[k];
          moved[2] += d > 1.0 * dn[k];
        }
        timeseries += fmt::format("{},{},{},{},{},{},{}\n", series.times()[k0 + r], total, mean, maxDn, moved[0],
                                  moved[1], moved[2]);
      }
    }
  }

  // units.csv
  std::size_t displaced = 0;
  double yMin = std::numeric_limits<double>::infinity(), yMax = -yMin;
  std::string unitsCsv = "unit,x0,y0,z0,x,y,z,dx,dy,dz,disp_s,disp_t,disp_n,s0,t0,displacement_m,displacement_dn,"
                         "rotation_deg,rocking,dn,displaced\n";
  for (std::size_t k = 0; k < nu; ++k) {
    const auto& u = disp.units[k];
    const bool isDisplaced = u.distanceDn > o.displacedDn;
    displaced += isDisplaced;
    yMin = std::min(yMin, xBefore[k].y());
    yMax = std::max(yMax, xBefore[k].y());
    const Eigen::Vector3d l0 = frame.toLocal(xBefore[k]);
    unitsCsv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                            scene.bodies[units[k].sceneIndex].name, xBefore[k].x(), xBefore[k].y(), xBefore[k].z(),
                            xAfter[k].x(), xAfter[k].y(), xAfter[k].z(), u.displacement.x(), u.displacement.y(),
                            u.displacement.z(), u.local.x(), u.local.y(), u.local.z(), l0.x(), l0.y(), u.distance,
                            u.distanceDn, u.rotation * kDeg, u.rocking ? 1 : 0, dn[k], isDisplaced ? 1 : 0);
  }
  // The trunk width the units cover: their spread along y plus one Dn (each unit covers a strip).
  const double width = yMax - yMin + dnMean;
  double porosity = o.porosity;
  std::string porositySource = "--porosity";
  if (!std::isfinite(porosity)) {
    // The pack's porosity is taken when it is one of an armour layer (0.25-0.75; 0.35-0.65 are
    // usual); a sparse test scene's hull measure is not.
    if (packBefore && packBefore->thickness && packBefore->porosity >= 0.25 && packBefore->porosity <= 0.75) {
      porosity = packBefore->porosity;
      porositySource = "the pack before the storm (armour analyse)";
    } else {
      porosity = 0.4;
      porositySource = packBefore && packBefore->thickness
                           ? fmt::format("default 0.4 (the pack's, {:.3g}, is not one of an armour layer; give "
                                         "--porosity)",
                                         packBefore->porosity)
                           : std::string("default 0.4 (the pack's could not be measured; give --porosity)");
    }
  }
  const analysis::CountedDamage counted = analysis::countedDamage(displaced, dnMean, width, porosity);

  // The storm.
  fs::path stormPath = o.storm;
  if (stormPath.empty() && scene.hydro.enabled && scene.hydro.model == hydro::HydroModel::Storm)
    stormPath = scene.hydro.storm.file;
  const double runStart = series.times().front(), runEnd = series.times().back();
  const double runDuration = runEnd - runStart;
  Eigen::Vector3d unitsMean = Eigen::Vector3d::Zero();
  for (const auto& p : xBefore) unitsMean += p / static_cast<double>(nu);
  const StormSummary st = summariseStorm(stormPath, scene, o, unitsMean, runStart, runEnd);
  // Wave statistics of fewer than 3 waves say little (a short file, mostly ramp-up): then the
  // provenance's values. Without those there is no sea state (a solitary wave, a single bore): the
  // design formulas, which take Hs of an irregular sea, are then not applicable unless --hs gives one.
  // Hm0 of such a record is still reported with the storm, not used.
  constexpr std::size_t kMinWaves = 3;
  const bool measured = st.waves.waves >= kMinWaves;
  double hs = o.hs, tm = o.tm, tp = o.tp;
  std::string hsSource = "--hs";
  if (!std::isfinite(hs)) {
    if (measured) {
      hs = st.waves.hs;
      hsSource = "H1/3 of eta at the gauge";
    } else if (std::isfinite(st.provHs)) {
      hs = st.provHs;
      hsSource = fmt::format("the storm file's provenance ({} waves at the gauge)", st.waves.waves);
    } else {
      hs = kNaN;
      hsSource = fmt::format("none: {} waves at the gauge and no Hs in the storm's provenance (a solitary wave or a "
                             "short record has no sea state); give --hs for the design formulas",
                             st.waves.waves);
    }
  }
  if (!std::isfinite(tm) && measured) tm = st.waves.tm;
  if (!std::isfinite(tp)) tp = measured || !std::isfinite(st.provTp) ? st.waves.tp : st.provTp;

  // Design formulas.
  const io::Body& first = scene.bodies[units.front().sceneIndex];
  const io::ShapeSpec& shape = scene.shapes[first.shape];
  const std::string unitType = shape.source == io::ShapeSource::Generator ? shape.generator : shape.name;
  const double unitDensity = scene.materials[first.material].density;
  double cotAlpha = o.cotAlpha;
  if (!std::isfinite(cotAlpha) && frameFromSlope && frame.tanAlpha() > 0.0) cotAlpha = 1.0 / frame.tanAlpha();
  double delta = kNaN, ns = kNaN, steepness = kNaN, xi = kNaN, nWaves = kNaN;
  try {
    delta = analysis::relativeDensity(unitDensity, st.waterDensity);
  } catch (const core::InputError&) {
  }
  // No wave measured at the gauge (a still-water storm, or eta not sampled): Hs = 0 is not a sea
  // state the formulas take; they are then listed as not applicable.
  if (!(hs > 0.0)) hs = kNaN;
  if (!(tm > 0.0)) tm = kNaN;
  if (std::isfinite(hs) && std::isfinite(delta)) ns = analysis::stabilityNumber(hs, delta, dnMean);
  if (std::isfinite(hs) && std::isfinite(tm)) steepness = analysis::waveSteepness(hs, tm);
  if (std::isfinite(steepness) && std::isfinite(cotAlpha)) xi = analysis::iribarren(1.0 / cotAlpha, steepness);
  if (std::isfinite(tm)) nWaves = std::max(1.0, runDuration / tm);
  DesignInputs design;
  design.unitType = unitType;
  design.ns = ns;
  design.cotAlpha = cotAlpha;
  design.steepness = steepness;
  design.xi = xi;
  design.waves = nWaves;
  design.tm = tm;
  design.duration = runDuration;
  design.permeability = o.permeability;
  design.breaking = o.breaking;
  if (!stormPath.empty()) design.noHs = "no sea state: Hs from " + hsSource;
  const std::vector<FormulaResult> formulas = designFormulas(design);

  // summary.json
  std::string j = "{\n";
  j += fmt::format(
      "  \"run\": {},\n  \"scene\": {},\n  \"records\": {},\n  \"run_start_s\": {},\n  \"run_end_s\": {},\n",
      jsonString(runDir.string()), jsonString(fs::absolute(scenePath).string()), series.records(), runStart, runEnd);
  j += fmt::format("  \"units\": {},\n  \"unit_type\": {},\n  \"dn_mean_m\": {},\n  \"unit_density_kg_m3\": {},\n", nu,
                   jsonString(unitType), dnMean, unitDensity);
  j += fmt::format("  \"slope_cot\": {},\n  \"slope_frame\": {},\n", jsonNumber(cotAlpha),
                   jsonString(frameFromSlope ? "scene slope" : "fitted to the units"));
  std::string counts;
  for (std::size_t k = 0; k < disp.thresholdsDn.size(); ++k)
    counts += fmt::format("{}\"{}\": {}", k ? ", " : "", disp.thresholdsDn[k], disp.movedCounts[k]);
  j += "  \"damage\": {\n";
  j += fmt::format("    \"moved_more_than_dn\": {{{}}},\n    \"rocking_units\": {},\n    \"rocking_angle_deg\": {},\n",
                   counts, disp.rockingCount, dsettings.rockingAngle * kDeg);
  j += fmt::format("    \"displaced_threshold_dn\": {},\n    \"displaced_units\": {},\n    \"trunk_width_m\": {},\n",
                   o.displacedDn, displaced, width);
  j += fmt::format("    \"porosity\": {},\n    \"porosity_source\": {},\n    \"Nod\": {},\n    \"S\": {},\n", porosity,
                   jsonString(porositySource), counted.nod, counted.damage);
  j += fmt::format("    \"delta_rms_m\": {},\n    \"delta_rms_dn\": {},\n    \"mean_displacement_dn\": {},\n"
                   "    \"max_displacement_dn\": {},\n    \"max_displacement_unit\": {},\n"
                   "    \"total_displacement_m\": {},\n    \"max_rotation_deg\": {},\n",
                   disp.deltaRms, disp.deltaRmsOverDn, disp.meanDn, disp.maxDn,
                   jsonString(scene.bodies[units[disp.maxUnit].sceneIndex].name), disp.total, disp.maxRotation * kDeg);
  j += fmt::format("    \"D_m\": {},\n    \"D_z_m\": {},\n    \"D_z_prime_m\": {}\n  }},\n", jsonNumber(disp.D),
                   jsonNumber(disp.x.mean), jsonNumber(disp.x.meanAbsolute));
  j += "  \"pack\": {\n";
  j += fmt::format(
      "    \"axis\": {},\n    \"p2_before\": {},\n    \"p2_after\": {},\n    \"p2_q_before\": {},\n"
      "    \"p2_q_after\": {},\n    \"porosity_before\": {},\n    \"porosity_after\": {},\n    \"note\": {}\n  }},\n",
      jsonString(o.axis), jsonNumber(packBefore ? packBefore->p2Mean.p2 : kNaN),
      jsonNumber(packAfter ? packAfter->p2Mean.p2 : kNaN), jsonNumber(packBefore ? packBefore->p2Q.p2 : kNaN),
      jsonNumber(packAfter ? packAfter->p2Q.p2 : kNaN),
      jsonNumber(packBefore && packBefore->thickness ? packBefore->porosity : kNaN),
      jsonNumber(packAfter && packAfter->thickness ? packAfter->porosity : kNaN), jsonString(packNote));
  j += "  \"storm\": {\n";
  j += fmt::format(
      "    \"file\": {},\n    \"title\": {},\n    \"records\": {},\n    \"start_s\": {},\n    \"end_s\": {},\n"
      "    \"time_offset_s\": {},\n    \"water_density_kg_m3\": {},\n    \"still_water_level_m\": {},\n",
      jsonString(stormPath.string()), jsonString(st.title), st.records, jsonNumber(st.start), jsonNumber(st.end),
      st.offset, st.waterDensity, jsonNumber(st.swl));
  j += fmt::format(
      "    \"gauge_x_m\": {},\n    \"H1_3_m\": {},\n    \"Hmax_m\": {},\n    \"Hm0_m\": {},\n    \"Tm_s\": {},\n"
      "    \"Tp_s\": {},\n    \"waves_at_gauge\": {},\n    \"provenance_Hs_m\": {},\n    \"provenance_Tp_s\": {},\n",
      jsonNumber(st.gaugeX), jsonNumber(st.waves.hs), jsonNumber(st.waves.hmax), jsonNumber(st.waves.hm0),
      jsonNumber(st.waves.tm), jsonNumber(st.waves.tp), st.waves.waves, jsonNumber(st.provHs), jsonNumber(st.provTp));
  j += fmt::format("    \"voxel_x_m\": {},\n    \"voxel_z_m\": {},\n    \"Hs_m\": {},\n    \"Hs_source\": {},\n"
                   "    \"Tm_used_s\": {},\n    \"Tp_used_s\": {}\n  }},\n",
                   jsonNumber(st.voxelX), jsonNumber(st.voxelZ), jsonNumber(hs), jsonString(hsSource), jsonNumber(tm),
                   jsonNumber(tp));
  j += "  \"design\": {\n";
  j += fmt::format(
      "    \"delta\": {},\n    \"Ns\": {},\n    \"s_om\": {},\n    \"xi_m\": {},\n    \"waves_in_run\": {},\n"
      "    \"permeability\": {},\n    \"formulas\": [\n",
      jsonNumber(delta), jsonNumber(ns), jsonNumber(steepness), jsonNumber(xi), jsonNumber(nWaves), o.permeability);
  for (std::size_t f = 0; f < formulas.size(); ++f) {
    const FormulaResult& r = formulas[f];
    std::string values;
    for (std::size_t v = 0; v < r.values.size(); ++v)
      values += fmt::format("{}\"{}\": {}", v ? ", " : "", r.values[v].first, jsonNumber(r.values[v].second));
    j += fmt::format("      {{\"name\": {}, \"source\": {}, \"applicable\": {}, \"values\": {{{}}}, \"note\": {}}}{}\n",
                     jsonString(r.name), jsonString(r.source), r.applicable ? "true" : "false", values,
                     jsonString(r.note), f + 1 < formulas.size() ? "," : "");
  }
  j += "    ]\n  }\n}\n";

  core::writeFileAtomically(folder / "units.csv", [&](std::ostream& out) { out << unitsCsv; });
  core::writeFileAtomically(folder / "timeseries.csv", [&](std::ostream& out) { out << timeseries; });
  core::writeFileAtomically(folder / "storm.csv", [&](std::ostream& out) { out << st.csv; });
  core::writeFileAtomically(folder / "summary.json", [&](std::ostream& out) { out << j; });

  std::cout << fmt::format("damage report of {} ({} units of {}, Dn {:.3g} m, t = {:.6g} .. {:.6g} s)\n",
                           runDir.string(), nu, unitType, dnMean, runStart, runEnd);
  for (std::size_t k = 0; k < disp.thresholdsDn.size(); ++k)
    std::cout << fmt::format("  moved > {:g} Dn    {} units\n", disp.thresholdsDn[k], disp.movedCounts[k]);
  std::cout << fmt::format("  rocking         {} units (rotation > {:g} deg)\n", disp.rockingCount,
                           dsettings.rockingAngle * kDeg);
  std::cout << fmt::format("  Nod {:.3g}, S {:.3g} (> {:g} Dn displaced, width {:.3g} m, porosity {:.3g})\n",
                           counted.nod, counted.damage, o.displacedDn, width, porosity);
  std::cout << fmt::format("  delta_rms {:.4g} m, max {:.3g} Dn, total {:.4g} m\n", disp.deltaRms, disp.maxDn,
                           disp.total);
  // A period the record cannot give (too few waves, none in the title) is said to be unknown, with
  // the option that supplies it, not "nan".
  const auto period = [](double v, const char* option) {
    return std::isfinite(v) ? fmt::format("{:.3g} s", v) : fmt::format("unknown ({})", option);
  };
  if (std::isfinite(hs))
    std::cout << fmt::format("  storm Hs {:.3g} m ({}), Tm {}, Tp {}, Ns {:.3g}\n", hs, hsSource, period(tm, "--tm"),
                             period(tp, "--tp"), ns);
  for (const FormulaResult& r : formulas) {
    std::string values;
    for (const auto& [k, v] : r.values) values += fmt::format(" {}={:.4g}", k, v);
    std::cout << fmt::format("  {}:{} {}\n", r.name, values, r.note);
  }
  std::cout << std::flush; // before the script's own output
  if (!o.noPlots) runPython(folder, runDir);
  std::cout << fmt::format("report: {}/summary.json, units.csv, timeseries.csv, storm.csv{}\n", folder.string(),
                           o.noPlots ? "" : ", index.html");
}

} // namespace

void addReportCommands(CLI::App& app, GlobalOptions& /*global*/) {
  auto o = std::make_shared<ReportOptions>();
  auto* cmd = app.add_subcommand("report", "damage report of a storm run: displacements, rocking, Nod and S, P2, the "
                                           "storm's Hs and Tp, and the design formulas beside them (docs/report.md)");
  cmd->add_option("run", o->run, "the run's output folder (with bodies.nc)")->required();
  cmd->add_option("--scene", o->scene,
                  "the run's scene (default: the one bodies.nc names); read with the run's --set changes and "
                  "storm settings");
  cmd->add_option("--storm", o->storm, "storm file (default: the scene's hydro storm file)");
  cmd->add_option("--output", o->output, "report folder (default: RUN_DIR/report)");
  cmd->add_option("--units", o->prefix,
                  "units are the movable bodies whose names start with this (default: the "
                  "hydro bodies)");
  cmd->add_option("--axis", o->axis, "unit axis for P2")->capture_default_str();
  cmd->add_option("--voxel", o->voxel,
                  "X Z: the storm voxel whose pressure history to show, in the storm file's coordinates (m; "
                  "default: a submerged voxel with data near the units)")
      ->expected(2);
  cmd->add_option("--gauge", o->gaugeX,
                  "x of the eta gauge for Hs, Tm, Tp, in the storm file's coordinates (m; default: the slope's toe)");
  cmd->add_option("--storm-offset", o->stormOffset,
                  "X Z: the storm file's (x, z) of the scene's origin (m; default: the scene's hydro.storm.offset, "
                  "as given to armour storm with --set)")
      ->expected(2);
  cmd->add_option("--storm-window", o->stormWindow, "storm records in storm.csv: run (the replayed ones) or all")
      ->capture_default_str();
  cmd->add_option("--hs", o->hs, "Hs for the design formulas instead of the gauge's (m)");
  cmd->add_option("--tm", o->tm, "mean period instead of the gauge's (s)");
  cmd->add_option("--tp", o->tp, "peak period instead of the gauge's (s)");
  cmd->add_option("--cot", o->cotAlpha, "slope cot alpha (default: the scene's slope)");
  cmd->add_option("--permeability", o->permeability, "van der Meer's notional permeability P")->capture_default_str();
  cmd->add_option("--porosity", o->porosity, "armour layer porosity for S = Nod / (1 - p) (default: the pack's)");
  cmd->add_option("--displaced-dn", o->displacedDn, "a unit moved more than this many Dn counts as displaced")
      ->capture_default_str();
  cmd->add_flag("--breaking", o->breaking, "use Hudson's K_D for breaking waves");
  cmd->add_flag("--no-plots", o->noPlots, "write the tables only (no utilities/report.py)");
  cmd->callback([o] { report(*o); });
}

} // namespace armour::app
