// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/DamageReport.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace armour::analysis {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A unit's body in the scene and in bodies.nc.
struct UnitRef {
  std::size_t sceneIndex = 0;
  std::size_t seriesIndex = 0;
  double dn = 0.0;
};

/// Units: movable bodies with the prefix (default: those the hydro loads act on).
std::vector<UnitRef> findUnits(DamageReport& r, const io::Scene& scene, const fs::path& scenePath,
                               const io::BodySeriesReader& series,
                               const std::map<std::string, std::size_t>& seriesIndex, const std::string& prefixOption) {
  std::string prefix = prefixOption;
  if (prefix.empty() && scene.hydro.enabled && scene.hydro.bodies != "all") prefix = scene.hydro.bodies;
  r.unitPrefix = prefix;
  std::vector<UnitRef> units;
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
  return units;
}

/// Poses before (the scene) and after (the last record) of the units into r.units; returns the
/// poses after of every body of the scene. bodies.nc holds the principal frame; the natural frame
/// the scene and P2 use is q_nat = q_p(t) q_p(0)^-1 q_scene (the first record is the scene's
/// state), and the rotation between two states is the same in either frame.
ReportPoses unitPoses(DamageReport& r, const io::Scene& scene, const io::BodySeriesReader& series,
                      const std::map<std::string, std::size_t>& seriesIndex, const std::vector<UnitRef>& units) {
  const std::size_t last = series.records() - 1;
  std::vector<double> pos, q0, q1;
  series.positions(last, 1, pos);
  series.orientations(0, q0);
  series.orientations(last, q1);
  ReportPoses before, after;
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
  const std::size_t nu = units.size();
  r.units.resize(nu);
  for (std::size_t k = 0; k < nu; ++k) {
    ReportUnit& u = r.units[k];
    u.name = scene.bodies[units[k].sceneIndex].name;
    u.seriesIndex = units[k].seriesIndex;
    u.dn = units[k].dn;
    u.before = before[u.name].position;
    u.orientationBefore = before[u.name].orientation;
    u.after = after[u.name].position;
    u.orientationAfter = after[u.name].orientation;
  }
  r.dnMean = 0.0;
  for (const ReportUnit& u : r.units) r.dnMean += u.dn / static_cast<double>(nu);
  return after;
}

/// The slope frame (the scene's slope, else a plane through the units, else level) and the
/// displacement measures.
void measureUnits(DamageReport& r, const io::Scene& scene) {
  const std::size_t nu = r.units.size();
  std::vector<Eigen::Vector3d> xBefore(nu), xAfter(nu);
  std::vector<Eigen::Quaterniond> qBefore(nu), qAfter(nu);
  std::vector<double> dn(nu);
  for (std::size_t k = 0; k < nu; ++k) {
    xBefore[k] = r.units[k].before;
    qBefore[k] = r.units[k].orientationBefore;
    xAfter[k] = r.units[k].after;
    qAfter[k] = r.units[k].orientationAfter;
    dn[k] = r.units[k].dn;
  }
  if (!scene.statics.slopes.empty()) {
    const io::StaticSlope& s = scene.statics.slopes.front();
    r.frame = SlopeFrame::fromTanAlpha(s.tanAlpha, Eigen::Vector3d(s.origin.x(), 0.0, s.origin.y()));
    r.frameFromSlope = true;
  } else {
    try {
      r.frame = fitSlopeFrame(xBefore);
    } catch (const core::InputError&) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& p : xBefore) mean += p / static_cast<double>(nu);
      r.frame = SlopeFrame::fromTanAlpha(0.0, mean);
    }
  }
  r.displacement = measureDisplacement(xBefore, xAfter, qBefore, qAfter, dn, r.frame, r.displacementSettings);
}

/// P2 and porosity before and after (not for units without an axis).
void measurePacks(DamageReport& r, const ReportPoses& after, const PackMeasurer& measurePack) {
  try {
    r.packBefore = measurePack(r.unitPrefix, r.axis, nullptr);
    r.packAfter = measurePack(r.unitPrefix, r.axis, &after);
  } catch (const core::InputError& e) {
    r.packNote = e.what();
  }
}

/// Time series of the displacements, read in blocks of records.
void displacementSeries(DamageReport& r, const io::BodySeriesReader& series) {
  const std::size_t nu = r.units.size();
  std::vector<double> block;
  constexpr std::size_t kBlock = 64; // bodies.nc chunks hold 64 records
  r.timeSeries.reserve(series.records());
  for (std::size_t k0 = 0; k0 < series.records(); k0 += kBlock) {
    const std::size_t n = std::min(kBlock, series.records() - k0);
    series.positions(k0, n, block);
    const std::size_t nb = series.names().size();
    for (std::size_t rec = 0; rec < n; ++rec) {
      DisplacementRecord d{series.times()[k0 + rec]};
      for (std::size_t k = 0; k < nu; ++k) {
        const ReportUnit& u = r.units[k];
        const double* x = &block[(rec * nb + u.seriesIndex) * 3];
        const double dist = (Eigen::Vector3d(x[0], x[1], x[2]) - u.before).norm();
        d.total += dist;
        d.meanDn += dist / u.dn / static_cast<double>(nu);
        d.maxDn = std::max(d.maxDn, dist / u.dn);
        d.moved[0] += dist > 0.2 * u.dn;
        d.moved[1] += dist > 0.5 * u.dn;
        d.moved[2] += dist > 1.0 * u.dn;
      }
      r.timeSeries.push_back(d);
    }
  }
}

/// Displaced units, the trunk width they cover, the porosity and Nod and S.
void countDamage(DamageReport& r, const DamageReportSettings& o) {
  r.displacedDn = o.displacedDn;
  r.displaced = 0;
  double yMin = std::numeric_limits<double>::infinity(), yMax = -yMin;
  for (std::size_t k = 0; k < r.units.size(); ++k) {
    ReportUnit& u = r.units[k];
    u.displaced = r.displacement.units[k].distanceDn > o.displacedDn;
    r.displaced += u.displaced;
    yMin = std::min(yMin, u.before.y());
    yMax = std::max(yMax, u.before.y());
    u.localBefore = r.frame.toLocal(u.before);
  }
  // The trunk width the units cover: their spread along y plus one Dn (each unit covers a strip).
  r.trunkWidth = yMax - yMin + r.dnMean;
  r.porosity = o.porosity;
  r.porositySource = "--porosity";
  if (!std::isfinite(r.porosity)) {
    // The pack's porosity is taken when it is one of an armour layer (0.25-0.75; 0.35-0.65 are
    // usual); a sparse test scene's hull measure is not.
    const std::optional<double> measured = r.packBefore ? r.packBefore->porosity : std::nullopt;
    if (measured && *measured >= 0.25 && *measured <= 0.75) {
      r.porosity = *measured;
      r.porositySource = "the pack before the storm (armour analyse)";
    } else {
      r.porosity = 0.4;
      r.porositySource = measured ? fmt::format("default 0.4 (the pack's, {:.3g}, is not one of an armour layer; give "
                                                "--porosity)",
                                                *measured)
                                  : std::string("default 0.4 (the pack's could not be measured; give --porosity)");
    }
  }
  r.counted = countedDamage(r.displaced, r.dnMean, r.trunkWidth, r.porosity);
}

/// The storm at the gauge and the voxel, and the Hs, Tm, Tp the design formulas take.
void summariseStorm(DamageReport& r, const io::Scene& scene, const DamageReportSettings& o) {
  r.stormFile = o.stormFile;
  if (r.stormFile.empty() && scene.hydro.enabled && scene.hydro.model == hydro::HydroModel::Storm)
    r.stormFile = scene.hydro.storm.file;
  const std::size_t nu = r.units.size();
  Eigen::Vector3d unitsMean = Eigen::Vector3d::Zero();
  for (const ReportUnit& u : r.units) unitsMean += u.before / static_cast<double>(nu);
  r.storm = reportStorm(r.stormFile, scene, o.storm, unitsMean, r.runStart, r.runEnd);
  const ReportStorm& st = r.storm;
  // Wave statistics of fewer than 3 waves say little (a short file, mostly ramp-up): then the
  // provenance's values. Without those there is no sea state (a solitary wave, a single bore): the
  // design formulas, which take Hs of an irregular sea, are then not applicable unless --hs gives one.
  // Hm0 of such a record is still reported with the storm, not used.
  constexpr std::size_t kMinWaves = 3;
  const bool measured = st.waves.waves >= kMinWaves;
  r.hs = o.hs;
  r.tm = o.tm;
  r.tp = o.tp;
  r.hsSource = "--hs";
  if (!std::isfinite(r.hs)) {
    if (measured) {
      r.hs = st.waves.hs;
      r.hsSource = "H1/3 of eta at the gauge";
    } else if (std::isfinite(st.provHs)) {
      r.hs = st.provHs;
      r.hsSource = fmt::format("the storm file's provenance ({} waves at the gauge)", st.waves.waves);
    } else {
      r.hs = kNaN;
      r.hsSource = fmt::format("none: {} waves at the gauge and no Hs in the storm's provenance (a solitary wave or "
                               "a short record has no sea state); give --hs for the design formulas",
                               st.waves.waves);
    }
  }
  if (!std::isfinite(r.tm) && measured) r.tm = st.waves.tm;
  if (!std::isfinite(r.tp)) r.tp = measured || !std::isfinite(st.provTp) ? st.waves.tp : st.provTp;
}

/// The unit type, the slope and the design formulas' verdicts.
void designFormulas(DamageReport& r, const io::Scene& scene, const UnitRef& firstUnit, const DamageReportSettings& o) {
  const io::Body& first = scene.bodies[firstUnit.sceneIndex];
  const io::ShapeSpec& shape = scene.shapes[first.shape];
  r.unitType = shape.source == io::ShapeSource::Generator ? shape.generator : shape.name;
  r.unitDensity = scene.materials[first.material].density;
  r.cotAlpha = o.cotAlpha;
  if (!std::isfinite(r.cotAlpha) && r.frameFromSlope && r.frame.tanAlpha() > 0.0) r.cotAlpha = 1.0 / r.frame.tanAlpha();
  try {
    r.delta = relativeDensity(r.unitDensity, r.storm.waterDensity);
  } catch (const core::InputError&) {
  }
  // No wave measured at the gauge (a still-water storm, or eta not sampled): Hs = 0 is not a sea
  // state the formulas take; they are then listed as not applicable.
  if (!(r.hs > 0.0)) r.hs = kNaN;
  if (!(r.tm > 0.0)) r.tm = kNaN;
  if (std::isfinite(r.hs) && std::isfinite(r.delta)) r.ns = stabilityNumber(r.hs, r.delta, r.dnMean);
  if (std::isfinite(r.hs) && std::isfinite(r.tm)) r.steepness = waveSteepness(r.hs, r.tm);
  if (std::isfinite(r.steepness) && std::isfinite(r.cotAlpha)) r.xi = iribarren(1.0 / r.cotAlpha, r.steepness);
  const double runDuration = r.runEnd - r.runStart;
  if (std::isfinite(r.tm)) r.waves = std::max(1.0, runDuration / r.tm);
  r.permeability = o.permeability;
  DesignInputs design;
  design.unitType = r.unitType;
  design.ns = r.ns;
  design.cotAlpha = r.cotAlpha;
  design.steepness = r.steepness;
  design.xi = r.xi;
  design.waves = r.waves;
  design.tm = r.tm;
  design.duration = runDuration;
  design.permeability = o.permeability;
  design.breaking = o.breaking;
  if (!r.stormFile.empty()) design.noHs = "no sea state: Hs from " + r.hsSource;
  r.formulas = designVerdicts(design);
}

} // namespace

DamageReport damageReport(const io::Scene& scene, const fs::path& scenePath, const io::BodySeriesReader& series,
                          const DamageReportSettings& settings, const PackMeasurer& measurePack) {
  DamageReport r;
  r.records = series.records();
  r.runStart = series.times().front();
  r.runEnd = series.times().back();
  r.axis = settings.axis;
  std::map<std::string, std::size_t> seriesIndex;
  for (std::size_t b = 0; b < series.names().size(); ++b) seriesIndex[series.names()[b]] = b;
  const std::vector<UnitRef> units = findUnits(r, scene, scenePath, series, seriesIndex, settings.unitPrefix);
  const ReportPoses after = unitPoses(r, scene, series, seriesIndex, units);
  measureUnits(r, scene);
  measurePacks(r, after, measurePack);
  displacementSeries(r, series);
  countDamage(r, settings);
  summariseStorm(r, scene, settings);
  designFormulas(r, scene, units.front(), settings);
  return r;
}

} // namespace armour::analysis
