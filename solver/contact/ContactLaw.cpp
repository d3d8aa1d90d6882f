// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/ContactLaw.hpp"

#include <cmath>
#include <numbers>

namespace armour::contact {

double restitutionOfClampedDashpot(double zeta) {
  // Unit oscillator x'' + 2 zeta x' + x = 0 entering at x'(0) = 1: the contact ends at t* when the
  // force x + 2 zeta x' returns to zero (not when x does; Schwager and Poschel 2007), and in all
  // three regimes the exit speed is then exactly exp(-zeta t*).
  if (zeta <= 0.0) {
    return 1.0;
  }
  double tEnd = 2.0; // critical damping, the limit of both branches
  if (zeta < 1.0) {
    const double w = std::sqrt(1.0 - zeta * zeta);
    tEnd = (std::numbers::pi - std::atan2(2.0 * zeta * w, 1.0 - 2.0 * zeta * zeta)) / w;
  } else if (zeta > 1.0) {
    const double s = std::sqrt(zeta * zeta - 1.0);
    tEnd = std::atanh(2.0 * zeta * s / (2.0 * zeta * zeta - 1.0)) / s;
  }
  return std::exp(-zeta * tEnd);
}

double dampingRatioFromRestitution(double restitution) {
  if (restitution >= 1.0) {
    return 0.0;
  }
  // e(zeta) decreases monotonically from 1 (zeta = 0) through exp(-2) (zeta = 1) towards 0
  // (about 1 / (4 zeta^2) for large zeta): bisection on [0, 1e3] to round-off.
  double lo = 0.0, hi = 1.0e3;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (restitutionOfClampedDashpot(mid) > restitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double dampingTime(const ContactParameters& p, double effectiveMass, double pairStiffness) {
  if (p.dampingRatio <= 0.0 || pairStiffness <= 0.0) {
    return 0.0;
  }
  return 2.0 * p.dampingRatio * std::sqrt(effectiveMass / pairStiffness);
}

PointForce evaluatePointContact(const ContactParameters& p, const PointContact& c, const PointHistory& previous,
                                double beta, double dt) {
  PointForce out;
  const double k = pointStiffness(p, c.area);
  const double vn = c.relativeVelocity.dot(c.normal); // > 0: separating
  const double fn = std::max(0.0, k * c.depth - beta * k * vn);
  out.normalForce = fn;

  // Carry the stretch into the current tangent plane, keeping its length: the contact frame
  // rotates with the bodies, the spring must not lose or gain force by that rotation.
  Vec3 stretch = previous.stretch - previous.stretch.dot(c.normal) * c.normal;
  const double oldLength = previous.stretch.norm();
  const double newLength = stretch.norm();
  if (newLength > 0.0) {
    stretch *= oldLength / newLength;
  }
  const Vec3 vt = c.relativeVelocity - vn * c.normal;
  stretch += vt * dt;

  const double kt = p.tangentialStiffnessRatio * k;
  Vec3 ft = -kt * stretch - beta * kt * vt;
  const double limit = (previous.sliding ? p.frictionDynamic : p.frictionStatic) * fn;
  const double ftNorm = ft.norm();
  bool sliding = false;
  if (ftNorm > limit) {
    sliding = true;
    ft = ftNorm > 0.0 ? Vec3(ft * (limit / ftNorm)) : Vec3::Zero();
    // The spring keeps exactly the force the cap allows, so that when the point sticks again it
    // starts from the Coulomb force, without a jump.
    stretch = kt > 0.0 ? Vec3(-ft / kt) : Vec3::Zero();
  }
  out.force = fn * c.normal + ft;
  out.history.stretch = stretch;
  out.history.sliding = sliding;
  return out;
}

} // namespace armour::contact
