// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The deposit both bench_solver scenes are built with: a random pile built geometrically, unit by
// unit (a "rain" deposit), instead of simulating the units' fall. The lowering and the slides are
// the placement stage's (placement/Deposit.hpp); this adds the random plan positions and the
// choice among orientations.

#include "benchmarks/SolverBenchScene.hpp"
#include "placement/Deposit.hpp"

#include <random>
#include <vector>

namespace armour::bench {

/// Random sequential deposit: units are lowered vertically into a region bounded by static
/// planes (the solid is the union of their half-spaces) and earlier units or fixed obstacles.
/// Each unit tries `tries` random orientations (at a random plan position in [x0, x1] x [y0, y1],
/// or a given one), is lowered from above everything it could touch until it comes within
/// `clearance` of something, and the lowest try is kept. It then slides and tilts downhill
/// (placement::Deposit::slideDown: up to Dn / 4 sideways, 15 degrees of tilt) until `moves`
/// moves in a row fail. No unit pushes another, so the pile stays loose and settles by a
/// fraction of Dn when released.
class Deposit {
public:
  using Plane = placement::Deposit::Plane;
  Deposit(double x0, double x1, double y0, double y1, double cellSize, const std::vector<Plane>& planes);

  struct Result {
    Vec3 position = Vec3::Zero();
    Quat orientation = Quat::Identity(); ///< natural shape frame -> world
  };

  /// A fixed body the units must clear (e.g. an underlayer rock).
  void addObstacle(const armour::simulation::ShapeModel& shape, double scale, const Quat& bodyOrientation,
                   const Vec3& position) {
    deposit_.addBody(shape, scale, bodyOrientation, position);
  }

  /// Place one unit; `plan` (if given) fixes its plan position (x, y).
  Result place(const armour::simulation::ShapeModel& shape, double scale, double dn, double clearance, int tries,
               int moves, std::mt19937_64& rng, const Vec3* plan = nullptr);

private:
  double x0_, x1_, y0_, y1_;
  placement::Deposit deposit_;
};

} // namespace armour::bench
