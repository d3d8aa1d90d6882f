// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/ReportStorm.hpp"

#include "core/Error.hpp"
#include "storm/StormFile.hpp"

#include <algorithm>
#include <cmath>
#include <regex>
#include <system_error>

namespace armour::analysis {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// "Hs=7 m", "Hs 7 m", "H=1.5 m" (regular waves) and "Tp 11 s", "T=6 s" in a provenance text.
double provenanceValue(const std::string& text, const char* symbols) {
  const std::regex re(std::string("\\b(?:") + symbols + ")\\s*[= ]\\s*([0-9]+(?:\\.[0-9]+)?)\\s*(?:m|s)\\b");
  std::smatch m;
  if (std::regex_search(text, m, re)) return std::stod(m[1].str());
  return kNaN;
}

} // namespace

ReportStorm reportStorm(const fs::path& stormPath, const io::Scene& scene, const ReportStormSettings& o,
                        const Eigen::Vector3d& unitsMean, double runStart, double runEnd) {
  ReportStorm s;
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
  s.waves = waveStatistics(times, eta);
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
  if (o.window == "run") {
    while (k0 + 1 < times.size() && times[k0 + 1] - s.offset <= runStart) ++k0;
    k1 = k0;
    while (k1 < times.size() && times[k1] - s.offset < runEnd) ++k1;
    k1 = std::min(k1 + 1, times.size());
  }
  for (std::size_t k = k0; k < k1; ++k) {
    const double runTime = times[k] - s.offset;
    reader.read(k, record);
    const std::size_t v = iz * h.nx() + ix;
    s.samples.push_back({times[k], runTime, record.p[v], eta[k], record.alpha[v]});
  }
  return s;
}

} // namespace armour::analysis
