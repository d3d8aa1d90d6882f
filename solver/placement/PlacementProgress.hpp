// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacementProgress.hpp
/// What a placement has done so far: the record of each unit, the summary counts, and at a safe
/// point (between units, or in the final settle) everything needed to continue it bit for bit
/// after a stop (PlacementProgress; `armour place --restart`, docs/placement.md "Checkpoints").
/// The World's own state travels beside it in the checkpoint file (simulation::WorldState);
/// the rest is encoded as text (encodeProgress), every double as a C99 hexadecimal float, so it
/// reads back exactly.

#include "simulation/WorldState.hpp"

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

namespace armour::placement {

using Vec3 = Eigen::Vector3d;

/// What happened to one unit.
struct UnitRecord {
  std::string name;
  /// Where it was released: its first touch (its grid point lowered to first contact), or with
  /// settle_each where its own settle left it (unit: m).
  Vec3 gridPoint = Vec3::Zero();
  Eigen::Quaterniond releaseOrientation = Eigen::Quaterniond::Identity(); ///< natural frame -> world at release
  Vec3 touchPoint = Vec3::Zero();  ///< centroid at first touch, after nesting (unit: m)
  double settleDrift = 0.0;        ///< settle_each: distance its own settle took it from its first touch (unit: Dn)
  double releaseTime = 0.0;        ///< simulated time of release (unit: s)
  /// crane: simulated time until the pack was at rest; settle_each: of the unit's own settle (unit: s)
  double restTime = 0.0;
  /// crane: the next unit went before the pack was at rest; settle_each: the unit was frozen at
  /// max_time or held at max drift before it rested (unit: -)
  bool capped = false;
  std::size_t body = 0;            ///< World body index
};

/// The summary of a placement (docs/placement.md, "Summary").
struct PlacementSummary {
  int units = 0, rocks = 0;
  double simulatedTime = 0.0;      ///< unit: s
  double wallSeconds = 0.0;        ///< unit: s
  double dn = 0.0;                 ///< units' nominal diameter (unit: m)
  double gridPackingDensity = 0.0; ///< of the grid as designed, Dn^2 / (dx dy) (unit: -); 0 for grid files
  /// Achieved packing density: units whose centroid lies in the window between the first and
  /// the last row (up the slope, in the slope plane) and between the walls, N Dn^2 / A (unit: -).
  double packingDensity = 0.0;
  double windowArea = 0.0;         ///< A of that window, in the slope plane (unit: m^2)
  int windowUnits = 0;             ///< N in the window (unit: -)
  /// Mean slope-normal height of the units' tops above the underlayer surface (the rocks' mean top
  /// in the window, or the slope plane without rocks), over the window (unit: m).
  double layerThickness = 0.0;
  double porosity = 0.0;           ///< 1 - N V / (A t) over the window (unit: -)
  int cappedUnits = 0;             ///< crane: released before the pack was at rest (unit: -)
  int settleCappedUnits = 0;       ///< settle_each: frozen at max_time (or held at max drift) before they rested (unit: -)
  std::vector<std::string> drifted; ///< settle_each: units whose own settle took them more than max_drift from first touch
  double medianSettleDriftDn = 0.0; ///< settle_each: median drift of the units' own settles (unit: Dn)
  double medianDisplacementDn = 0.0; ///< median distance from release to the end (unit: Dn)
  std::vector<std::string> moving; ///< units still moving faster than the rest speed at the end
  std::vector<std::string> moved;  ///< units that ended more than 1 Dn from where they were released
  double maxDisplacementDn = 0.0;  ///< largest distance from release to the end (unit: Dn)
};

/// How to add again a body the placement added (a rock or a unit) when it continues from a
/// checkpoint: its pose and motion come from the World's state.
struct AddedBody {
  std::string name;
  std::size_t sceneShape = 0; ///< index in the placed scene's shapes (unit: -)
  double scale = 1.0;         ///< of the shape's mesh (unit: -)
  std::size_t material = 0;   ///< index in the scene's materials (unit: -)
  double volume = 0.0;        ///< unit: m^3
  bool fixed = false;         ///< a rock of the underlayer (unit: -)
};

/// Where a placement stands at a safe point.
struct PlacementProgress {
  int unitsDone = 0;             ///< units placed so far, in grid order (unit: -)
  bool finalSettle = false;      ///< the units are all placed and the final settle has begun
  int round = 0;                 ///< final settle: the round under way, from 0 (unit: -)
  double settleStart = 0.0;      ///< final settle: World time it began (unit: s)
  double roundStart = 0.0;       ///< final settle: World time the round began (unit: s)
  std::uint64_t roundStartStep = 0; ///< final settle: World step count when the round began (unit: -)
  double stillSince = -1.0;      ///< final settle: round time since which no point moved faster than the rest speed; < 0: moving (unit: s)
  std::vector<Vec3> roundBefore; ///< final settle: unit centroids when the round began (unit: m)
  std::vector<AddedBody> bodies; ///< every body added so far, rocks then units, in World order
  std::vector<UnitRecord> units; ///< the records of the units placed so far
  std::vector<std::size_t> frozen; ///< settle_each: World bodies held fixed until the release
  std::vector<double> settleDrifts; ///< settle_each: each unit's drift in its own settle (unit: Dn)
  PlacementSummary summary;      ///< the counts so far: capped units and drifted units (the rocks are the fixed bodies)
  double wallSeconds = 0.0;      ///< wall time spent up to here, earlier sessions included (unit: s)
  simulation::WorldState world;  ///< not encoded: stored as the checkpoint's own variables
};

/// The progress (without `world`) as text: one "key value..." record per line.
[[nodiscard]] std::string encodeProgress(const PlacementProgress& progress);

/// Read encodeProgress's text back (`world` left empty). Throws core::InputError naming `where`
/// (the checkpoint file) and the bad line when the text is not such a record.
[[nodiscard]] PlacementProgress decodeProgress(const std::string& text, const std::string& where);

} // namespace armour::placement
