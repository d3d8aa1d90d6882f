// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchDeposit.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace armour::bench {

Deposit::Deposit(double x0, double x1, double y0, double y1, double cellSize, const std::vector<Plane>& planes)
    : x0_(x0), x1_(x1), y0_(y0), y1_(y1), deposit_(x0, x1, y0, y1, cellSize) {
  for (const Plane& p : planes) deposit_.addPlane(p);
}

Deposit::Result Deposit::place(const armour::simulation::ShapeModel& shape, double scale, double dn, double clearance,
                               int tries, int moves, std::mt19937_64& rng, const Vec3* plan) {
  placement::Placed best;
  Quat bestNatural = Quat::Identity();
  bool found = false;
  std::uniform_real_distribution<double> ux(x0_, x1_), uy(y0_, y1_);
  const double step = 0.05 * dn;
  for (int t = 0, attempts = 0; t < std::max(1, tries) && attempts < 100 * std::max(1, tries); ++attempts) {
    const Quat natural = randomOrientation(rng);
    placement::Placed u;
    u.shape = &shape;
    u.scale = scale;
    u.R = (natural * shape.naturalToBody.conjugate()).toRotationMatrix();
    u.radius = shape.radius * scale;
    u.x = plan != nullptr ? Vec3(plan->x(), plan->y(), 0.0) : Vec3(ux(rng), uy(rng), 0.0);
    if (!deposit_.lower(u, step, clearance)) continue; // through a wall: draw again
    ++t;
    if (!found || u.x.z() < best.x.z()) {
      best = u;
      bestNatural = natural;
      found = true;
    }
  }
  if (!found)
    throw std::invalid_argument("deposit: no pose of a unit fits between the walls; use fewer --layers or a larger box");
  const placement::Mat3 before = best.R;
  deposit_.slideDown(best, moves, 0.25 * dn, 15.0 * std::numbers::pi / 180.0, step, clearance, rng);
  const Quat tilt(placement::Mat3(best.R * before.transpose()));
  deposit_.add(best);
  return {best.x, (tilt * bestNatural).normalized()};
}

} // namespace armour::bench
