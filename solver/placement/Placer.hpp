// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Placer.hpp
/// `armour place`: build an armour layer the way seeds 000, 001 and 003 do, on the underlayer of
/// a scene, and return the placed scene. docs/placement.md.
///
///  1. Rock underlayer (optional, seed 000): rocks from a library of seeded rock shapes, graded
///     sizes and random orientations, each dropped onto the slope (lowered along the slope
///     normal, the lowest of a few orientations kept, then slid and tilted into the holes) and
///     frozen (fixed bodies).
///  2. Units, one per grid point in order (rows from the toe up, layer by layer), turned as the
///     orientation settings say and lowered vertically to first contact (Deposit.hpp).
///       - crane: each is released at the crane speed the moment it touches, and the pack is
///         simulated until its kinetic energy falls below 1/2 M v_rest^2 (or a time cap), then
///         the next is lowered onto the pack as it now lies;
///       - grid: all are lowered first (each onto those before it), then released together;
///       - with settle_each (either method): each is simulated alone (the others held fixed)
///         until it rests, frozen there, and the next is lowered onto it; all are released
///         together at the end.
///  3. The pack settles (same criterion), and the placed scene, the per-unit table and a summary
///     (packing density achieved, layer thickness, porosity, units that did not settle or moved
///     off their place) are made.

#include "io/Scene.hpp"
#include "simulation/SceneBuilder.hpp"

#include <functional>
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

struct PlacementResult {
  io::Scene scene;                 ///< the placed scene: the input's items plus the new shapes and bodies, no placement
  std::vector<io::ShapeSpec> addedShapes; ///< rock shapes added (also in scene.shapes)
  std::size_t firstAddedBody = 0;  ///< scene.bodies from here on were placed
  std::vector<UnitRecord> units;
  PlacementSummary summary;
  simulation::BuiltScene built;    ///< the World at the end
};

/// Progress for the log: (units placed, units in all, simulated time s).
using ProgressFn = std::function<void(int placed, int total, double time)>;

/// How much of the placement to do.
struct PlaceOptions {
  /// false: lower every unit geometrically (each onto those before it, as method grid does) and
  /// add it at rest, without stepping the World: the pack as released, for checks and tests.
  bool dynamics = true;
};

/// Place the units of `scene.placement` on the scene. Throws core::InputError for settings that
/// cannot work (naming the key) and simulation::SimulationError if the dynamics fail.
PlacementResult place(const io::Scene& scene, const ProgressFn& progress = {}, const PlaceOptions& options = {});

} // namespace armour::placement
