// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/ReportCommands.hpp"

#include "analysis/DamageReport.hpp"
#include "measure/PackAnalysis.hpp"
#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "core/JsonWriter.hpp"
#include "io/BodySeriesReader.hpp"
#include "io/RunScene.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

namespace armour::app {
namespace {

namespace fs = std::filesystem;
using core::jsonNumber;
using core::jsonString;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = 180.0 / std::numbers::pi;

struct ReportOptions {
  std::string run;    ///< the run's output folder
  std::string scene;  ///< default: the scene named in bodies.nc's history
  std::string storm;  ///< default: the scene's hydro storm file
  std::string output; ///< default: RUN_DIR/report
  bool noPlots = false;
  /// What the analysis reads (units, axis, storm voxel and gauge, design-formula overrides): the
  /// options fill it directly.
  analysis::DamageReportSettings analysis;
};

std::string csvNumber(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("NaN"); }

/// The analysis' settings with the storm file the options name (a path, given as text).
analysis::DamageReportSettings settingsWithStorm(const ReportOptions& o) {
  analysis::DamageReportSettings s = o.analysis;
  s.stormFile = o.storm;
  return s;
}

/// P2 and porosity of the scene's pack by `armour analyse`'s pack analysis.
analysis::PackMeasurer packMeasurer(const io::Scene& scene) {
  return [&scene](const std::string& unitPrefix, const std::string& axis, const analysis::ReportPoses* state) {
    measure::AnalyseSettings settings;
    settings.unitPrefix = unitPrefix;
    settings.axis = axis;
    measure::PoseMap poses;
    if (state)
      for (const auto& [name, pose] : *state) poses[name] = {pose.position, pose.orientation};
    const measure::PackReport pack = measure::analysePack(scene, settings, state ? &poses : nullptr);
    analysis::PackMeasures m;
    m.p2 = pack.p2Mean.p2;
    m.p2Q = pack.p2Q.p2;
    if (pack.thickness && std::isfinite(pack.porosity)) m.porosity = pack.porosity;
    return m;
  };
}

/// units.csv: per unit, the centroid before and after, the displacement in the world and slope
/// frames, the rotation and the flags.
std::string unitsCsv(const analysis::DamageReport& r) {
  std::string csv = "unit,x0,y0,z0,x,y,z,dx,dy,dz,disp_s,disp_t,disp_n,s0,t0,displacement_m,displacement_dn,"
                    "rotation_deg,rocking,dn,displaced\n";
  for (std::size_t k = 0; k < r.units.size(); ++k) {
    const analysis::ReportUnit& unit = r.units[k];
    const analysis::UnitDisplacement& u = r.displacement.units[k];
    const Eigen::Vector3d& x0 = unit.before;
    const Eigen::Vector3d& x1 = unit.after;
    const Eigen::Vector3d& l0 = unit.localBefore;
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", unit.name, x0.x(), x0.y(),
                       x0.z(), x1.x(), x1.y(), x1.z(), u.displacement.x(), u.displacement.y(), u.displacement.z(),
                       u.local.x(), u.local.y(), u.local.z(), l0.x(), l0.y(), u.distance, u.distanceDn,
                       u.rotation * kDeg, u.rocking ? 1 : 0, unit.dn, unit.displaced ? 1 : 0);
  }
  return csv;
}

/// timeseries.csv: per bodies.nc record, the total, mean and largest displacement and the counts.
std::string timeSeriesCsv(const analysis::DamageReport& r) {
  std::string csv = "time_s,total_displacement_m,mean_displacement_dn,max_displacement_dn,moved_0.2dn,"
                    "moved_0.5dn,moved_1dn\n";
  for (const analysis::DisplacementRecord& d : r.timeSeries)
    csv += fmt::format("{},{},{},{},{},{},{}\n", d.time, d.total, d.meanDn, d.maxDn, d.moved[0], d.moved[1],
                       d.moved[2]);
  return csv;
}

/// storm.csv: the storm records of the window at the voxel and the gauge.
std::string stormCsv(const analysis::DamageReport& r) {
  std::string csv = "storm_time_s,run_time_s,pressure_Pa,eta_gauge_m,alpha\n";
  for (const analysis::ReportStormSample& s : r.storm.samples)
    csv += fmt::format("{},{},{},{},{}\n", s.stormTime, s.runTime, csvNumber(s.pressure), s.eta, csvNumber(s.alpha));
  return csv;
}

/// summary.json.
std::string summaryJson(const analysis::DamageReport& r, const fs::path& runDir, const fs::path& scenePath) {
  const analysis::PackDisplacement& disp = r.displacement;
  const analysis::ReportStorm& st = r.storm;
  std::string j = "{\n";
  j += fmt::format(
      "  \"run\": {},\n  \"scene\": {},\n  \"records\": {},\n  \"run_start_s\": {},\n  \"run_end_s\": {},\n",
      jsonString(runDir.string()), jsonString(fs::absolute(scenePath).string()), r.records, r.runStart, r.runEnd);
  j += fmt::format("  \"units\": {},\n  \"unit_type\": {},\n  \"dn_mean_m\": {},\n  \"unit_density_kg_m3\": {},\n",
                   r.units.size(), jsonString(r.unitType), r.dnMean, r.unitDensity);
  j += fmt::format("  \"slope_cot\": {},\n  \"slope_frame\": {},\n", jsonNumber(r.cotAlpha),
                   jsonString(r.frameFromSlope ? "scene slope" : "fitted to the units"));
  std::string counts;
  for (std::size_t k = 0; k < disp.thresholdsDn.size(); ++k)
    counts += fmt::format("{}\"{}\": {}", k ? ", " : "", disp.thresholdsDn[k], disp.movedCounts[k]);
  j += "  \"damage\": {\n";
  j += fmt::format("    \"moved_more_than_dn\": {{{}}},\n    \"rocking_units\": {},\n    \"rocking_angle_deg\": {},\n",
                   counts, disp.rockingCount, r.displacementSettings.rockingAngle * kDeg);
  j += fmt::format("    \"displaced_threshold_dn\": {},\n    \"displaced_units\": {},\n    \"trunk_width_m\": {},\n",
                   r.displacedDn, r.displaced, r.trunkWidth);
  j += fmt::format("    \"porosity\": {},\n    \"porosity_source\": {},\n    \"Nod\": {},\n    \"S\": {},\n",
                   r.porosity, jsonString(r.porositySource), r.counted.nod, r.counted.damage);
  j += fmt::format("    \"delta_rms_m\": {},\n    \"delta_rms_dn\": {},\n    \"mean_displacement_dn\": {},\n"
                   "    \"max_displacement_dn\": {},\n    \"max_displacement_unit\": {},\n"
                   "    \"total_displacement_m\": {},\n    \"max_rotation_deg\": {},\n",
                   disp.deltaRms, disp.deltaRmsOverDn, disp.meanDn, disp.maxDn,
                   jsonString(r.units[disp.maxUnit].name), disp.total, disp.maxRotation * kDeg);
  j += fmt::format("    \"D_m\": {},\n    \"D_z_m\": {},\n    \"D_z_prime_m\": {}\n  }},\n", jsonNumber(disp.D),
                   jsonNumber(disp.x.mean), jsonNumber(disp.x.meanAbsolute));
  const auto porosityOf = [](const std::optional<analysis::PackMeasures>& p) {
    return p && p->porosity ? *p->porosity : kNaN;
  };
  j += "  \"pack\": {\n";
  j += fmt::format(
      "    \"axis\": {},\n    \"p2_before\": {},\n    \"p2_after\": {},\n    \"p2_q_before\": {},\n"
      "    \"p2_q_after\": {},\n    \"porosity_before\": {},\n    \"porosity_after\": {},\n    \"note\": {}\n  }},\n",
      jsonString(r.axis), jsonNumber(r.packBefore ? r.packBefore->p2 : kNaN),
      jsonNumber(r.packAfter ? r.packAfter->p2 : kNaN), jsonNumber(r.packBefore ? r.packBefore->p2Q : kNaN),
      jsonNumber(r.packAfter ? r.packAfter->p2Q : kNaN), jsonNumber(porosityOf(r.packBefore)),
      jsonNumber(porosityOf(r.packAfter)), jsonString(r.packNote));
  j += "  \"storm\": {\n";
  j += fmt::format(
      "    \"file\": {},\n    \"title\": {},\n    \"records\": {},\n    \"start_s\": {},\n    \"end_s\": {},\n"
      "    \"time_offset_s\": {},\n    \"water_density_kg_m3\": {},\n    \"still_water_level_m\": {},\n",
      jsonString(r.stormFile.string()), jsonString(st.title), st.records, jsonNumber(st.start), jsonNumber(st.end),
      st.offset, st.waterDensity, jsonNumber(st.swl));
  j += fmt::format(
      "    \"gauge_x_m\": {},\n    \"H1_3_m\": {},\n    \"Hmax_m\": {},\n    \"Hm0_m\": {},\n    \"Tm_s\": {},\n"
      "    \"Tp_s\": {},\n    \"waves_at_gauge\": {},\n    \"provenance_Hs_m\": {},\n    \"provenance_Tp_s\": {},\n",
      jsonNumber(st.gaugeX), jsonNumber(st.waves.hs), jsonNumber(st.waves.hmax), jsonNumber(st.waves.hm0),
      jsonNumber(st.waves.tm), jsonNumber(st.waves.tp), st.waves.waves, jsonNumber(st.provHs), jsonNumber(st.provTp));
  j += fmt::format("    \"voxel_x_m\": {},\n    \"voxel_z_m\": {},\n    \"Hs_m\": {},\n    \"Hs_source\": {},\n"
                   "    \"Tm_used_s\": {},\n    \"Tp_used_s\": {}\n  }},\n",
                   jsonNumber(st.voxelX), jsonNumber(st.voxelZ), jsonNumber(r.hs), jsonString(r.hsSource),
                   jsonNumber(r.tm), jsonNumber(r.tp));
  j += "  \"design\": {\n";
  j += fmt::format(
      "    \"delta\": {},\n    \"Ns\": {},\n    \"s_om\": {},\n    \"xi_m\": {},\n    \"waves_in_run\": {},\n"
      "    \"permeability\": {},\n    \"formulas\": [\n",
      jsonNumber(r.delta), jsonNumber(r.ns), jsonNumber(r.steepness), jsonNumber(r.xi), jsonNumber(r.waves),
      r.permeability);
  for (std::size_t f = 0; f < r.formulas.size(); ++f) {
    const analysis::FormulaResult& fr = r.formulas[f];
    std::string values;
    for (std::size_t v = 0; v < fr.values.size(); ++v)
      values += fmt::format("{}\"{}\": {}", v ? ", " : "", fr.values[v].first, jsonNumber(fr.values[v].second));
    j += fmt::format("      {{\"name\": {}, \"source\": {}, \"applicable\": {}, \"values\": {{{}}}, \"note\": {}}}{}\n",
                     jsonString(fr.name), jsonString(fr.source), fr.applicable ? "true" : "false", values,
                     jsonString(fr.note), f + 1 < r.formulas.size() ? "," : "");
  }
  j += "    ]\n  }\n}\n";
  return j;
}

/// The report's summary on the terminal.
void printSummary(const analysis::DamageReport& r, const fs::path& runDir) {
  const analysis::PackDisplacement& disp = r.displacement;
  std::cout << fmt::format("damage report of {} ({} units of {}, Dn {:.3g} m, t = {:.6g} .. {:.6g} s)\n",
                           runDir.string(), r.units.size(), r.unitType, r.dnMean, r.runStart, r.runEnd);
  for (std::size_t k = 0; k < disp.thresholdsDn.size(); ++k)
    std::cout << fmt::format("  moved > {:g} Dn    {} units\n", disp.thresholdsDn[k], disp.movedCounts[k]);
  std::cout << fmt::format("  rocking         {} units (rotation > {:g} deg)\n", disp.rockingCount,
                           r.displacementSettings.rockingAngle * kDeg);
  std::cout << fmt::format("  Nod {:.3g}, S {:.3g} (> {:g} Dn displaced, width {:.3g} m, porosity {:.3g})\n",
                           r.counted.nod, r.counted.damage, r.displacedDn, r.trunkWidth, r.porosity);
  std::cout << fmt::format("  delta_rms {:.4g} m, max {:.3g} Dn, total {:.4g} m\n", disp.deltaRms, disp.maxDn,
                           disp.total);
  // A period the record cannot give (too few waves, none in the title) is said to be unknown, with
  // the option that supplies it, not "nan".
  const auto period = [](double v, const char* option) {
    return std::isfinite(v) ? fmt::format("{:.3g} s", v) : fmt::format("unknown ({})", option);
  };
  if (std::isfinite(r.hs))
    std::cout << fmt::format("  storm Hs {:.3g} m ({}), Tm {}, Tp {}, Ns {:.3g}\n", r.hs, r.hsSource,
                             period(r.tm, "--tm"), period(r.tp, "--tp"), r.ns);
  for (const analysis::FormulaResult& f : r.formulas) {
    std::string values;
    for (const auto& [k, v] : f.values) values += fmt::format(" {}={:.4g}", k, v);
    std::cout << fmt::format("  {}:{} {}\n", f.name, values, f.note);
  }
}

void report(const ReportOptions& o) {
  const fs::path runDir = fs::absolute(o.run).lexically_normal();
  if (!fs::is_directory(runDir))
    core::failInput(o.run, "not a folder; give the output folder of `armour run` (the scene's output.folder, e.g. "
                           "wave-slope-out)");
  if (!(o.analysis.displacedDn > 0.0))
    core::failInput("--displaced-dn", "{}: must be positive (unit: Dn)", o.analysis.displacedDn);
  if (o.analysis.storm.window != "run" && o.analysis.storm.window != "all")
    core::failInput("--storm-window", "'{}': give run or all", o.analysis.storm.window);
  const io::BodySeriesReader series(runDir / "bodies.nc");
  const fs::path scenePath = o.scene.empty() ? io::sceneFileOfRun(series, runDir) : fs::path(o.scene);
  const io::Scene scene = io::sceneOfRun(scenePath, series);
  const analysis::DamageReport r =
      analysis::damageReport(scene, scenePath, series, settingsWithStorm(o), packMeasurer(scene));
  if (!r.packAfter) std::cout << fmt::format("P2 and porosity not computed: {}\n", r.packNote);

  const fs::path folder = o.output.empty() ? runDir / "report" : fs::absolute(o.output);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) core::failInput(folder.string(), "cannot create the report folder: {}", ec.message());
  core::writeFileAtomically(folder / "units.csv", [&](std::ostream& out) { out << unitsCsv(r); });
  core::writeFileAtomically(folder / "timeseries.csv", [&](std::ostream& out) { out << timeSeriesCsv(r); });
  core::writeFileAtomically(folder / "storm.csv", [&](std::ostream& out) { out << stormCsv(r); });
  core::writeFileAtomically(folder / "summary.json",
                            [&](std::ostream& out) { out << summaryJson(r, runDir, scenePath); });
  printSummary(r, runDir);
  std::cout << std::flush; // before the script's own output
  if (!o.noPlots) runUtility("report.py", {folder.string(), "--run", runDir.string()}, "plots and index.html");
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
  cmd->add_option("--units", o->analysis.unitPrefix,
                  "units are the movable bodies whose names start with this (default: the "
                  "hydro bodies)");
  cmd->add_option("--axis", o->analysis.axis, "unit axis for P2")->capture_default_str();
  cmd->add_option("--voxel", o->analysis.storm.voxel,
                  "X Z: the storm voxel whose pressure history to show, in the storm file's coordinates (m; "
                  "default: a submerged voxel with data near the units)")
      ->expected(2);
  cmd->add_option("--gauge", o->analysis.storm.gaugeX,
                  "x of the eta gauge for Hs, Tm, Tp, in the storm file's coordinates (m; default: the slope's toe)");
  cmd->add_option("--storm-offset", o->analysis.storm.stormOffset,
                  "X Z: the storm file's (x, z) of the scene's origin (m; default: the scene's hydro.storm.offset, "
                  "as given to armour storm with --set)")
      ->expected(2);
  cmd->add_option("--storm-window", o->analysis.storm.window, "storm records in storm.csv: run (the replayed ones) or all")
      ->capture_default_str();
  cmd->add_option("--hs", o->analysis.hs, "Hs for the design formulas instead of the gauge's (m)");
  cmd->add_option("--tm", o->analysis.tm, "mean period instead of the gauge's (s)");
  cmd->add_option("--tp", o->analysis.tp, "peak period instead of the gauge's (s)");
  cmd->add_option("--cot", o->analysis.cotAlpha, "slope cot alpha (default: the scene's slope)");
  cmd->add_option("--permeability", o->analysis.permeability, "van der Meer's notional permeability P")->capture_default_str();
  cmd->add_option("--porosity", o->analysis.porosity, "armour layer porosity for S = Nod / (1 - p) (default: the pack's)");
  cmd->add_option("--displaced-dn", o->analysis.displacedDn, "a unit moved more than this many Dn counts as displaced")
      ->capture_default_str();
  cmd->add_flag("--breaking", o->analysis.breaking, "use Hudson's K_D for breaking waves");
  cmd->add_flag("--no-plots", o->noPlots, "write the tables only (no utilities/report.py)");
  cmd->callback([o] { report(*o); });
}

} // namespace armour::app
