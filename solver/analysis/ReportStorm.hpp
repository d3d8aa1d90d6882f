// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ReportStorm.hpp
/// The storm input of a run as `armour report` shows it (docs/report.md): the wave statistics of
/// eta at a gauge (the slope's toe by default), the Hs and Tp the storm file's provenance states,
/// and the pressure, free surface and water fraction at one voxel over the run's window (seed 000
/// Fig. 5: a permanently submerged cell in the armour layer near the units, by default).

#include "analysis/WaveStatistics.hpp"
#include "io/Scene.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace armour::analysis {

/// Where and when to read the storm.
struct ReportStormSettings {
  std::vector<double> voxel; ///< (x, z) of the pressure history, in the storm file's coordinates (unit: m)
  /// The storm file's (x, z) of the scene's origin; default: the scene's hydro.storm.offset when the
  /// storm is the scene's, else (0, 0) (unit: m).
  std::vector<double> stormOffset;
  double gaugeX = std::numeric_limits<double>::quiet_NaN(); ///< x of the eta gauge (unit: m); default the slope's toe
  std::string window = "run"; ///< storm records kept: "run" (the replayed window) or "all"
};

/// One storm record at the voxel and the gauge.
struct ReportStormSample {
  double stormTime = 0.0; ///< (unit: s)
  double runTime = 0.0;   ///< stormTime - the run's time offset (unit: s)
  double pressure = 0.0;  ///< at the voxel (unit: Pa)
  double eta = 0.0;       ///< at the gauge (unit: m)
  double alpha = 0.0;     ///< water fraction at the voxel (unit: -)
};

/// The storm input of a run; NaNs and no samples without a storm file.
struct ReportStorm {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  WaveStatistics waves;         ///< of eta at the gauge over the whole file
  double gaugeX = kNaN;         ///< (unit: m)
  double voxelX = kNaN;         ///< (unit: m)
  double voxelZ = kNaN;         ///< (unit: m)
  double waterDensity = 1025.0; ///< (unit: kg/m^3); sea water without a storm file
  double offset = 0.0;          ///< storm time at run time 0 (unit: s)
  double swl = kNaN;            ///< still water level (unit: m)
  double provHs = kNaN;         ///< Hs (or H) the provenance states (unit: m)
  double provTp = kNaN;         ///< Tp (or T) the provenance states (unit: s)
  std::string title;
  std::vector<ReportStormSample> samples; ///< the records of the window
  std::size_t records = 0;                ///< records in the file (unit: -)
  double start = kNaN, end = kNaN;        ///< first and last record time (unit: s)
};

/// The storm `stormPath` (empty: none) as seen by a run of `scene` over run times
/// [runStart, runEnd]; `unitsMean` is the units' mean centroid before the storm (scene
/// coordinates), near which the default voxel is taken. Throws core::InputError for a --voxel
/// without data and a file without any voxel holding data.
[[nodiscard]] ReportStorm reportStorm(const std::filesystem::path& stormPath, const io::Scene& scene,
                                      const ReportStormSettings& settings, const Eigen::Vector3d& unitsMean,
                                      double runStart, double runEnd);

} // namespace armour::analysis
