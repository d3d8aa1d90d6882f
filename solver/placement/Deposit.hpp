// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Deposit.hpp
/// Geometric lowering: where a unit lowered along -z first comes within a clearance of what is
/// already there (static planes, static convex pieces, placed bodies). It stands in for the
/// crane's constant-speed descent, which meets the pack at rest (the next unit is lowered only
/// when the pack is at rest), so the contact point is a property of the geometry alone and costs
/// milliseconds instead of a simulated descent. docs/placement.md, "Lowering".
///
/// The touch test is the contact stage's own: a body's surface samples against the other's
/// level set (both ways), and a body's samples against a convex piece's faces, so "first
/// contact" means what the solver will call a contact. Bodies are filed in plan columns so each
/// lowering only looks at neighbours whose bounding spheres can meet.
///
/// The Deposit works in its own frame (the caller may rotate the world into it, e.g. to lower
/// along a slope normal): "down" is -z of that frame.

#include "simulation/World.hpp"

#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace armour::placement {

using simulation::Quat;
using simulation::Vec3;
using Mat3 = Eigen::Matrix3d;

/// Uniformly distributed random rotation (Shoemake 1992, "Uniform random rotations").
Quat uniformRotation(std::mt19937_64& rng);

/// A body in the deposit, with what the touch test needs.
struct Placed {
  Vec3 x = Vec3::Zero();          ///< centroid (unit: m)
  Mat3 R = Mat3::Identity();      ///< body (principal) frame -> deposit frame
  double scale = 1.0;             ///< uniform scale of the shape (unit: -)
  double radius = 0.0;            ///< bounding sphere about the centroid (unit: m)
  const simulation::ShapeModel* shape = nullptr;
};

class Deposit {
public:
  /// A static half-space: solid on the side opposite to the normal. Planes with a horizontal
  /// normal are walls: a unit that would cross one is pushed back inside along its normal.
  struct Plane {
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ(); ///< unit, out of the solid
  };
  /// A static convex piece: n_k . x <= d_k inside.
  struct Piece {
    std::vector<Vec3> normals;
    std::vector<double> offsets;
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero(); ///< bounds of its corners (unit: m)
  };

  /// Plan region [x0, x1] x [y0, y1] filed in square columns of `cellSize` (m; about the largest
  /// body diameter); bodies outside still work, filed in the border columns.
  Deposit(double x0, double x1, double y0, double y1, double cellSize);

  void addPlane(const Plane& plane) { planes_.push_back(plane); }
  /// The convex hull of `corners` (deposit frame).
  void addPiece(const std::vector<Vec3>& corners);
  /// A body already there (fixed or placed earlier). `bodyOrientation` is the body (principal)
  /// frame -> deposit frame.
  void addBody(const simulation::ShapeModel& shape, double scale, const Quat& bodyOrientation, const Vec3& position);

  /// Lower u from `startZ` (infinity: from above everything near) to where it first comes within
  /// `clearance` (m) of something; `step` (m) is the coarse descent step, refined by bisection to
  /// step / 32. Walls push it sideways first. Returns false if it is blocked where it starts or
  /// cannot fit between the walls.
  bool lower(Placed& u, double step, double clearance, double startZ = kAbove) const;

  /// Slide and tilt downhill: random moves (a shift up to `shift` m on both plan axes, a tilt up
  /// to `tilt` rad about a random axis), each lowered again, are kept when they end lower, until
  /// `moves` fail in a row. A unit stuck on a neighbour's corner slips into the hole beside it, as
  /// it would when poured. Moves that take the centroid farther than `maxDrift` (m, in plan) from
  /// where it started are refused. Each move is lowered from `lift` (m) above the current height
  /// (infinity: from above everything), and refused if it overlaps there: a finite lift is much
  /// cheaper when the unit sits low among tall neighbours. True if u moved.
  /// With `cost`, a move is kept when it lowers cost(u) (by more than 1e-3 `costStep`) instead of
  /// the centroid's height.
  bool slideDown(Placed& u, int moves, double shift, double tilt, double step, double clearance,
                 std::mt19937_64& rng, double maxDrift = kAbove, double lift = kAbove,
                 const std::function<double(const Placed&)>& cost = {}, double costStep = 0.0) const;

  /// Keep u (after lower/slideDown) as an obstacle for the next ones.
  void add(const Placed& u);

  /// True when u, where it is, lies within `clearance` of a placed body (not the statics).
  [[nodiscard]] bool touchesBodies(const Placed& u, double clearance) const;
  /// The placed bodies (their indices, in the order they were added) within `clearance` of u.
  [[nodiscard]] std::vector<std::size_t> touching(const Placed& u, double clearance) const;
  /// True when u, where it is, lies within `clearance` of an upward-facing static item (the
  /// slope, the toe, the floor).
  [[nodiscard]] bool touchesStatics(const Placed& u, double clearance) const {
    return u.x.z() <= staticFloor(u, clearance);
  }

  [[nodiscard]] std::size_t bodyCount() const { return placed_.size(); }
  /// Placed body k (in the order added).
  [[nodiscard]] const Placed& body(std::size_t k) const { return placed_[k]; }
  /// The placed bodies (indices, ascending) whose bounding spheres come within `gap` (m) of u's.
  [[nodiscard]] std::vector<std::size_t> near(const Placed& u, double gap) const;

  static constexpr double kAbove = std::numeric_limits<double>::infinity(); ///< "start above everything"

private:
  void insert(const Placed& p);
  /// Lowest centroid height at which u clears every upward-facing static item by `clearance`.
  [[nodiscard]] double staticFloor(const Placed& u, double clearance) const;
  /// Push u inside the walls; false if it cannot fit.
  bool clearWalls(Placed& u, double clearance) const;

  /// f(k) for every placed body k in the grid columns that bodies within `gap` (m) of u's bounding
  /// sphere can occupy, until f returns true; true if it did.
  template <class F> bool anyNear(const Placed& u, double gap, F&& f) const;
  [[nodiscard]] int col(double x) const;
  [[nodiscard]] int row(double y) const;
  double x0_, y0_;
  double cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<Plane> planes_;
  std::vector<Piece> pieces_;
  double maxRadius_ = 0.0;
  std::vector<std::vector<std::size_t>> columns_;
  std::vector<Placed> placed_;
};

} // namespace armour::placement
