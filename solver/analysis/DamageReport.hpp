// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DamageReport.hpp
/// The damage report of a storm run (issue 9; docs/report.md) as data: from the run's scene, its
/// bodies.nc and its storm file, the units' displacements and rotations (world and slope frame),
/// the counts of moved and rocking units, Nod and S, the time series of the displacements, P2
/// and porosity before and after, the storm's Hs, Tm and Tp at the gauge, and the design formulas'
/// verdicts beside them. Nothing is printed or written here: `armour report`
/// (app/ReportCommands.cpp) writes the tables, summary.json and the text.

#include "analysis/DesignFormulas.hpp"
#include "analysis/DesignVerdicts.hpp"
#include "analysis/Displacement.hpp"
#include "analysis/Orientation.hpp"
#include "analysis/ReportStorm.hpp"
#include "io/BodySeriesReader.hpp"
#include "io/Scene.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armour::analysis {

/// The report's choices (the options of `armour report`; NaN: taken from the run).
struct DamageReportSettings {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string unitPrefix;  ///< units: movable bodies whose names start with it (default: the hydro bodies)
  std::string axis = "nose"; ///< unit axis for P2
  std::filesystem::path stormFile; ///< default: the scene's hydro storm file
  ReportStormSettings storm;
  double hs = kNaN;           ///< override of the storm's Hs (unit: m)
  double tm = kNaN;           ///< override of the mean period (unit: s)
  double tp = kNaN;           ///< override of the peak period (unit: s)
  double cotAlpha = kNaN;     ///< override of the slope (unit: -)
  double permeability = 0.4;  ///< van der Meer's P (unit: -)
  double porosity = kNaN;     ///< armour layer porosity for S (unit: -); default the pack's
  double displacedDn = 1.0;   ///< a unit moved by more than this is displaced, for Nod and S (unit: Dn)
  bool breaking = false;      ///< Hudson's K_D for breaking waves
};

/// A body's pose (natural shape frame -> world).
struct ReportPose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};
using ReportPoses = std::map<std::string, ReportPose>;

/// P2 and porosity of the pack at one state.
struct PackMeasures {
  double p2 = std::numeric_limits<double>::quiet_NaN();  ///< P2 of the mean axis (unit: -)
  double p2Q = std::numeric_limits<double>::quiet_NaN(); ///< P2 of the Q tensor (unit: -)
  std::optional<double> porosity; ///< of the layer, when its thickness could be measured (unit: -)
};

/// Measures the pack of the scene's units (movable bodies named unitPrefix*) at `state` (null: the
/// scene's poses), P2 of `axis`. The caller gives it: the pack analysis builds the scene's World
/// for its contacts (app/PackAnalysis), a stage above this one. Throws core::InputError when the
/// pack cannot be measured (units without the axis); the report then goes on without it.
using PackMeasurer =
    std::function<PackMeasures(const std::string& unitPrefix, const std::string& axis, const ReportPoses* state)>;

/// One unit, before (the scene) and after (the last record).
struct ReportUnit {
  std::string name;
  std::size_t seriesIndex = 0; ///< its body in bodies.nc
  double dn = 0.0;             ///< cube root of its volume (unit: m)
  Eigen::Vector3d before = Eigen::Vector3d::Zero(); ///< centroid (unit: m)
  Eigen::Vector3d after = Eigen::Vector3d::Zero();  ///< centroid (unit: m)
  Eigen::Quaterniond orientationBefore = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond orientationAfter = Eigen::Quaterniond::Identity();
  Eigen::Vector3d localBefore = Eigen::Vector3d::Zero(); ///< initial centroid in the slope frame (s, t, n) (unit: m)
  bool displaced = false; ///< moved more than displacedDn
};

/// The units' displacements at one bodies.nc record.
struct DisplacementRecord {
  double time = 0.0;   ///< (unit: s)
  double total = 0.0;  ///< sum of the units' displacements (unit: m)
  double meanDn = 0.0; ///< mean displacement (unit: Dn)
  double maxDn = 0.0;  ///< largest displacement (unit: Dn)
  std::array<std::size_t, 3> moved{}; ///< units moved more than 0.2, 0.5 and 1 Dn
};

/// The damage report of a run.
struct DamageReport {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // The run.
  std::size_t records = 0;                ///< bodies.nc records (unit: -)
  double runStart = 0.0, runEnd = 0.0;    ///< first and last record time (unit: s)
  std::string unitPrefix;                 ///< the units' name prefix used
  std::vector<ReportUnit> units;
  double dnMean = 0.0;                    ///< (unit: m)
  std::string unitType;                   ///< shape-library name of the first unit
  double unitDensity = 0.0;               ///< (unit: kg/m^3)
  SlopeFrame frame;                       ///< the scene's slope, else fitted to the units, else level
  bool frameFromSlope = false;
  double cotAlpha = kNaN;                 ///< (unit: -)
  // The damage.
  DisplacementSettings displacementSettings;
  PackDisplacement displacement;
  std::vector<DisplacementRecord> timeSeries;
  double displacedDn = 1.0;               ///< (unit: Dn)
  std::size_t displaced = 0;              ///< units moved more than displacedDn (unit: -)
  double trunkWidth = 0.0;                ///< the units' spread along y plus one Dn (unit: m)
  double porosity = 0.4;                  ///< used for S (unit: -)
  std::string porositySource;
  CountedDamage counted;
  // The pack.
  std::string axis;
  std::optional<PackMeasures> packBefore, packAfter;
  std::string packNote;                   ///< why the pack was not measured
  // The storm.
  std::filesystem::path stormFile;
  ReportStorm storm;
  double hs = kNaN, tm = kNaN, tp = kNaN; ///< used by the design formulas (unit: m, s, s)
  std::string hsSource;
  // The design formulas.
  double delta = kNaN, ns = kNaN, steepness = kNaN, xi = kNaN, waves = kNaN; ///< (unit: -)
  double permeability = 0.4;              ///< (unit: -)
  std::vector<FormulaResult> formulas;
};

/// The report of the run whose bodies.nc `series` holds, made from `scene` (read from
/// `scenePath`, with the run's settings). Throws core::InputError naming the file and the fix for
/// a scene that does not match the run, units without a volume, no units, or a bad --voxel.
[[nodiscard]] DamageReport damageReport(const io::Scene& scene, const std::filesystem::path& scenePath,
                                        const io::BodySeriesReader& series, const DamageReportSettings& settings,
                                        const PackMeasurer& measurePack);

} // namespace armour::analysis
