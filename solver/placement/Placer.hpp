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
#include "placement/PlacementGrid.hpp"
#include "placement/PlacementProgress.hpp"
#include "simulation/SceneBuilder.hpp"

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace armour::placement {

using Vec3 = Eigen::Vector3d;

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

/// Called at each point a placement can be continued from (after each unit is placed, and every
/// 10 ms of simulated time in the final settle) with `capture`, which makes the progress (a copy
/// of the World's state: call it only to write a checkpoint). Return true to stop there: place()
/// then throws PlacementStopped.
using SafePointFn = std::function<bool(const std::function<PlacementProgress()>& capture)>;

/// Thrown by place() when the safe-point callback asked it to stop.
struct PlacementStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// How much of the placement to do.
struct PlaceOptions {
  /// false: lower every unit geometrically (each onto those before it, as method grid does) and
  /// add it at rest, without stepping the World: the pack as released, for checks and tests.
  bool dynamics = true;
  SafePointFn safePoint;                 ///< empty: no safe points
  /// Continue from this progress, captured at a safe point of a placement of the same scene: the
  /// result is bit for bit that of the uninterrupted placement. nullptr: start anew.
  const PlacementProgress* resume = nullptr;
};

/// Place the units of `scene.placement` on the scene. Throws core::InputError for settings that
/// cannot work (naming the key) and simulation::SimulationError if the dynamics fail.
PlacementResult place(const io::Scene& scene, const ProgressFn& progress = {}, const PlaceOptions& options = {});

/// The grid points of a scene's placement block, made and checked as `place` makes them (the
/// trunk between the walls, a generated grid on the scene's slope, or the grid file), without
/// building anything: `armour check` uses it so that a grid that cannot be placed fails there.
struct GridPlan {
  std::vector<GridPoint> points;
  double packingDensity = 0.0; ///< of a generated grid, N Dn^2 / A; 0 for a grid file (unit: -)
  double wallWidth = 0.0;      ///< the trunk between the walls; 0 without both walls (unit: m)
};
/// @pre scene.placement.enabled. Throws core::InputError for a grid that does not fit.
[[nodiscard]] GridPlan planGrid(const io::Scene& scene);

} // namespace armour::placement
