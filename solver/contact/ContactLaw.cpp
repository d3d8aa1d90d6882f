// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/ContactLaw.hpp"

#include <algorithm>
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

double restitutionOfGrowingContact(double zeta, double p) {
  if (p <= 1.0) {
    return restitutionOfClampedDashpot(zeta);
  }
  // Step 2e-3 of the unit time; the exit (the overlap or the clamped force reaching zero) is
  // located by linear interpolation within the last step. Against the closed form at p -> 1 the
  // rebound is within 1e-4 (test_contact_law): the first stage, at y = 0, sees no dashpot, as the
  // model has none there for p > 1.
  constexpr double h = 2.0e-3;
  const double c = 2.0 * zeta * std::sqrt(p);
  const auto force = [&](double y, double v) {
    const double yy = std::max(y, 0.0);
    return std::pow(yy, p) + c * std::pow(yy, 0.5 * (p - 1.0)) * v;
  };
  const auto accel = [&](double y, double v) { return -std::max(force(y, v), 0.0); };
  // Positive while in contact: the force, or the overlap once it is the first to vanish.
  const auto inContact = [&](double y, double v) { return y <= 0.0 ? y : force(y, v); };
  double y = 0.0, v = 1.0;
  for (int i = 0; i < 1000000; ++i) {
    const double k1y = v, k1v = accel(y, v);
    const double k2y = v + 0.5 * h * k1v, k2v = accel(y + 0.5 * h * k1y, v + 0.5 * h * k1v);
    const double k3y = v + 0.5 * h * k2v, k3v = accel(y + 0.5 * h * k2y, v + 0.5 * h * k2v);
    const double k4y = v + h * k3v, k4v = accel(y + h * k3y, v + h * k3v);
    const double y1 = y + h * (k1y + 2.0 * k2y + 2.0 * k3y + k4y) / 6.0;
    const double v1 = v + h * (k1v + 2.0 * k2v + 2.0 * k3v + k4v) / 6.0;
    if (i > 0 && v1 < 0.0 && inContact(y1, v1) <= 0.0) {
      const double g0 = inContact(y, v), g1 = inContact(y1, v1);
      const double theta = g0 > g1 ? g0 / (g0 - g1) : 1.0;
      return std::max(-(v + theta * (v1 - v)), 0.0);
    }
    y = y1, v = v1;
  }
  return 0.0; // overdamped beyond any rebound
}

double DampingByExponent::at(double p) const {
  const double x = std::clamp((p - 1.0) / 0.5, 0.0, static_cast<double>(kCount - 1));
  const int i = std::min(static_cast<int>(x), kCount - 2);
  const double f = x - i;
  return (1.0 - f) * zeta[i] + f * zeta[i + 1];
}

DampingByExponent dampingByExponentFromRestitution(double restitution) {
  DampingByExponent out;
  out.zeta[0] = dampingRatioFromRestitution(restitution);
  for (int i = 1; i < DampingByExponent::kCount; ++i) {
    // e falls with zeta and, at one zeta, with p: the root lies in [0, zeta(p = 1)].
    const double p = 1.0 + 0.5 * i;
    double lo = 0.0, hi = out.zeta[0];
    for (int k = 0; k < 40 && hi > lo; ++k) {
      const double mid = 0.5 * (lo + hi);
      (restitutionOfGrowingContact(mid, p) > restitution ? lo : hi) = mid;
    }
    out.zeta[i] = 0.5 * (lo + hi);
  }
  return out;
}

double contactExponent(double force, double stiffness, double energy) {
  if (!(force > 0.0) || !(stiffness > 0.0) || !(energy > 0.0)) {
    return 1.0;
  }
  // F^2 / (U K) = (p + 1) / p for F = C d^p; it lies in (1, 2], 2 for a uniform depth.
  const double ratio = force * force / (energy * stiffness);
  if (!(ratio > 1.0 + 1.0 / 3.0)) {
    return 3.0;
  }
  const double p = std::clamp(1.0 / (ratio - 1.0), 1.0, 3.0);
  // A face under a small tilt reads p = 1 + (2/3) (Delta / d)^2 for depths d +- Delta: up to
  // p = 1.2 (Delta = 0.55 d) it stays a face, so that a face pressed or sliding under friction
  // torque keeps the one damping ratio of its restitution; from 1.2 to 1.5 the reading rises
  // linearly to 1.5, and above it is p itself (mine: the edge, 2, and the corner, 3, unchanged).
  constexpr double faceUpTo = 1.2, exactFrom = 1.5;
  if (p <= faceUpTo) {
    return 1.0;
  }
  return p >= exactFrom ? p : 1.0 + (p - faceUpTo) * (exactFrom - 1.0) / (exactFrom - faceUpTo);
}

double dampingTime(const ContactParameters& p, double effectiveMass, double pairStiffness, double dt) {
  if (p.dampingRatio <= 0.0 || pairStiffness <= 0.0 || !(effectiveMass > 0.0)) {
    return 0.0;
  }
  const double beta = 2.0 * p.dampingRatio * std::sqrt(effectiveMass / pairStiffness);
  if (dt <= 0.0) {
    return beta; // the explicit dashpot (every pair at every step of the default)
  }
  // The dashpot alone over the step: v' = v - (c dt / m)(v + v') / 2, c = 2 zeta sqrt(m K), so the
  // mean (v + v') / 2 = v / (1 + zeta omega dt): the rate applied to v is c / (1 + zeta omega dt).
  const double zetaOmegaDt = p.dampingRatio * std::sqrt(pairStiffness / effectiveMass) * dt;
  return beta / (1.0 + zetaOmegaDt);
}

double stableStepOfImplicitDashpot(double zeta) {
  // The step x' = x + dt v, v' = a v - omega^2 dt x' with a = (1 - zeta h) / (1 + zeta h) has
  // determinant a and trace 1 + a - h^2: stable while h^2 < 2 (1 + a) = 4 / (1 + zeta h), whose
  // left side grows with h. Bisection on [0, 2] to round-off.
  const double z = std::max(zeta, 0.0);
  double lo = 0.0, hi = 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid * mid * (1.0 + z * mid) < 4.0 ? lo : hi) = mid;
  }
  return lo;
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
