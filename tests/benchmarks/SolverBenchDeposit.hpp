// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The deposit both bench_solver scenes are built with: a random pile built geometrically, unit by
// unit (a "rain" deposit), instead of simulating the units' fall.

#include "benchmarks/SolverBenchScene.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <vector>

namespace armour::bench {

/// A unit in the deposit, with what the overlap test needs.
struct Placed {
  Vec3 x = Vec3::Zero();                          ///< centroid (m)
  armour::geometry::Mat3 R = armour::geometry::Mat3::Identity(); ///< body frame -> world
  double scale = 1.0;
  double radius = 0.0;                            ///< bounding sphere (m)
  const armour::simulation::ShapeModel* shape = nullptr;
};

/// Random sequential deposit: a cheap stand-in for pouring or placing units (seconds, where the
/// solver needs minutes to drop 4000 units through metres). Units are lowered vertically into a
/// region bounded by static planes (the solid is the union of their half-spaces) and earlier units
/// or fixed obstacles. Each unit tries `tries` random orientations (at a random plan position in
/// [x0, x1] x [y0, y1], or a given one), is lowered from above everything it could touch until it
/// comes within `clearance` of something (steps of Dn / 20, then bisection), and the lowest try is
/// kept. It then slides and tilts downhill: random moves (up to Dn / 4 sideways, 15 degrees of
/// tilt), each lowered again, are kept when they end lower, until `moves` moves in a row fail. A
/// unit stuck on a neighbour's corner thus slips into the hole beside it, as it would when poured;
/// no unit pushes another, so the pile stays loose and settles by a fraction of Dn when released.
class Deposit {
public:
  struct Plane {
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ(); ///< unit, out of the solid
  };
  Deposit(double x0, double x1, double y0, double y1, double cellSize, std::vector<Plane> planes);

  struct Result {
    Vec3 position = Vec3::Zero();
    Quat orientation = Quat::Identity(); ///< natural shape frame -> world
  };

  /// A fixed body the units must clear (e.g. an underlayer rock).
  void addObstacle(const armour::simulation::ShapeModel& shape, double scale, const Quat& bodyOrientation,
                   const Vec3& position);

  /// Place one unit; `plan` (if given) fixes its plan position (x, y).
  Result place(const armour::simulation::ShapeModel& shape, double scale, double dn, double clearance, int tries,
               int moves, std::mt19937_64& rng, const Vec3* plan = nullptr);

private:
  static constexpr double kAbove = std::numeric_limits<double>::infinity(); ///< "start above everything"

  /// Keep p, filed under the grid column of its plan position.
  void insert(const Placed& p);

  /// Lower u from its height (kAbove: from above everything near) to where it first comes within
  /// the clearance of something. False if its plan position puts it through a wall, or if it is
  /// blocked where it starts.
  bool lower(Placed& u, double dn, double clearance) const;

  [[nodiscard]] int col(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1);
  }
  [[nodiscard]] int row(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1);
  }
  double x0_, x1_, y0_, y1_;
  double cell_;
  std::vector<Plane> planes_;
  int nx_ = 1, ny_ = 1;
  double maxRadius_ = 0.0;
  std::vector<std::vector<std::size_t>> columns_;
  std::vector<Placed> placed_;
};

} // namespace armour::bench
