// SPDX-License-Identifier: GPL-3.0-or-later
// Rotational dynamics of single rigid bodies against the conservation laws and the analytic
// solutions of the Euler equations (torque-free and constant torque).
//
// Time scale: the bodies spin at |omega| ~ 1 rad/s, a rotation period of ~6 s; the step sizes
// below are stated as the rotation angle per step, |omega| dt.

#include "dynamics/Integrator.hpp"
#include "dynamics/RigidBodies.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

using namespace armour::dynamics;

namespace {

const Vec3 kNoGravity = Vec3::Zero();

/// One free body; omega is given in the body (principal) frame.
RigidBodies makeBody(const Vec3& moments, const Vec3& omegaBody, const Quat& q = Quat::Identity()) {
  RigidBodies bodies;
  BodyDefinition def;
  def.name = "top";
  def.mass = 1.0;
  def.principalMoments = moments;
  def.orientation = q;
  def.angularVelocity = q * omegaBody;
  bodies.add(def);
  return bodies;
}

/// Torque-free step: no force stage work.
void freeStep(RigidBodies& bodies, double dt) {
  step(bodies, dt, kNoGravity, [](RigidBodies&) {});
}

/// Body-frame angular velocity of body 0.
Vec3 omegaBody(const RigidBodies& bodies) {
  return bodies.inverseInertiaBody(0).cwiseProduct(bodies.angularMomentumBody(0));
}

/// Rotation angle between two orientations (rad), insensitive to the quaternion sign.
double angleBetween(const Quat& a, const Quat& b) { return a.angularDistance(b); }

/// Complete elliptic integral of the first kind K(m), parameter m = k^2, by the arithmetic-
/// geometric mean: K(m) = pi / (2 AGM(1, sqrt(1 - m))) (Abramowitz & Stegun 17.6).
double ellipticK(double m) {
  double a = 1.0;
  double b = std::sqrt(1.0 - m);
  while (std::abs(a - b) > 1e-15 * a) {
    const double next = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = next;
  }
  return std::numbers::pi / (2.0 * a);
}

/// Period of the body-frame angular velocity of a torque-free asymmetric body, I1 < I2 < I3,
/// energy E and |L| = M (Landau & Lifshitz, Mechanics, section 37). For M^2 > 2 E I2:
///   Omega_2 = sqrt((2 E I3 - M^2) / (I2 (I3 - I2))) sn(tau, k),
///   tau = t sqrt((I3 - I2)(M^2 - 2 E I1) / (I1 I2 I3)),
///   k^2 = (I2 - I1)(2 E I3 - M^2) / ((I3 - I2)(M^2 - 2 E I1)),
/// and sn has period 4 K(k^2) in tau, so T = 4 K sqrt(I1 I2 I3 / ((I3 - I2)(M^2 - 2 E I1))).
/// For M^2 < 2 E I2 exchange the indices 1 and 3. Omega_2 changes sign twice per period: the
/// intermediate-axis flip.
double eulerPeriod(const Vec3& moments, double energy, double momentum2) {
  double i1 = moments[0];
  const double i2 = moments[1];
  double i3 = moments[2];
  if (momentum2 < 2.0 * energy * i2) {
    std::swap(i1, i3);
  }
  const double k2 = (i2 - i1) * (2.0 * energy * i3 - momentum2) / ((i3 - i2) * (momentum2 - 2.0 * energy * i1));
  return 4.0 * ellipticK(k2) * std::sqrt(i1 * i2 * i3 / ((i3 - i2) * (momentum2 - 2.0 * energy * i1)));
}

} // namespace

TEST(FreeRotation, AsymmetricTumblingConservesMomentumAndEnergy) {
  // Moments 1, 2, 3 kg m^2, spinning about a general axis; |omega| = 1.3 rad/s (period 4.8 s).
  const Vec3 moments(1.0, 2.0, 3.0);
  RigidBodies bodies = makeBody(moments, Vec3(1.0, 0.5, -0.7), Quat(0.9, 0.1, -0.3, 0.2).normalized());
  const double dt = 2e-3; // |omega| dt = 2.6e-3 rad: ~2400 steps per rotation
  const double l0 = bodies.angularMomentumWorld(0).norm();
  const double e0 = bodies.kineticEnergy(0);
  double maxMomentumError = 0.0;
  double maxEnergyError = 0.0;
  double maxBodyMomentumError = 0.0;
  for (int n = 0; n < 100000; ++n) {
    freeStep(bodies, dt);
    maxMomentumError = std::max(maxMomentumError, std::abs(bodies.angularMomentumWorld(0).norm() - l0) / l0);
    maxBodyMomentumError = std::max(maxBodyMomentumError, std::abs(bodies.angularMomentumBody(0).norm() - l0) / l0);
    maxEnergyError = std::max(maxEnergyError, std::abs(bodies.kineticEnergy(0) - e0) / e0);
  }
  // |L| is exact by construction (the world L is untouched by the free-rotation flows); its
  // body-frame image R^T L differs only by the round-off of one rotation (~1e-16).
  EXPECT_LE(maxMomentumError, 1e-12);
  EXPECT_LE(maxBodyMomentumError, 1e-12);
  // Energy: the splitting conserves a modified energy within O((omega dt)^2) of T, with no
  // drift (symplectic). Measured 4.3e-8 at omega dt = 2.6e-3; 1e-6 leaves a factor ~20, and a
  // first-order or drifting method (error ~ omega dt ~ 1e-3 or growing with time) fails it.
  EXPECT_LE(maxEnergyError, 1e-6);
  RecordProperty("max_relative_energy_error", std::to_string(maxEnergyError));
  std::printf("tumbling: max |dL|/L = %.3e (world), %.3e (body); max |dE|/E = %.3e\n", maxMomentumError,
              maxBodyMomentumError, maxEnergyError);
}

TEST(FreeRotation, WorldAngularMomentumVectorIsConstant) {
  const Vec3 moments(1.0, 2.0, 3.0);
  RigidBodies bodies = makeBody(moments, Vec3(0.3, -1.1, 0.8), Quat(0.2, 0.7, -0.1, 0.4).normalized());
  const Vec3 l0 = bodies.angularMomentumWorld(0);
  double maxError = 0.0;
  double maxCacheError = 0.0;
  for (int n = 0; n < 20000; ++n) {
    freeStep(bodies, 5e-3); // |omega| dt = 7e-3 rad
    maxError = std::max(maxError, (bodies.angularMomentumWorld(0) - l0).norm() / l0.norm());
    // L recomputed from the reported state (q, omega) = R diag(I) R^T omega: checks that the
    // angular-velocity cache and the orientation stay consistent with the conserved L.
    const Quat& q = bodies.orientation(0);
    const Vec3 fromOmega = q * moments.cwiseProduct(q.conjugate() * bodies.worldAngularVelocity(0));
    maxCacheError = std::max(maxCacheError, (fromOmega - l0).norm() / l0.norm());
  }
  // The vector L is conserved exactly by the splitting (each sub-flow is a rotation of the body
  // frame that leaves R L_body fixed); 1e-10 allows for round-off in the omega round trip.
  EXPECT_LE(maxError, 1e-10);
  EXPECT_LE(maxCacheError, 1e-10);
  std::printf("world L: max |L - L0|/|L0| = %.3e, from (q, omega): %.3e\n", maxError, maxCacheError);
}

TEST(FreeRotation, IntermediateAxisFlipPeriodMatchesEllipticSolution) {
  const Vec3 moments(1.0, 2.0, 3.0);
  // Near the intermediate axis: omega_body = (0.1, 1, 0.1) rad/s.
  RigidBodies bodies = makeBody(moments, Vec3(0.1, 1.0, 0.1));
  const double energy = bodies.kineticEnergy(0);
  const double momentum2 = bodies.angularMomentumWorld(0).squaredNorm();
  const double expected = eulerPeriod(moments, energy, momentum2); // 22.9 s here
  const double dt = 5e-3;                                          // |omega| dt = 5e-3 rad
  std::vector<double> downCrossings;
  double previous = omegaBody(bodies)[1];
  double t = 0.0;
  while (t < 4.5 * expected) {
    freeStep(bodies, dt);
    t += dt;
    const double current = omegaBody(bodies)[1];
    if (previous > 0.0 && current <= 0.0) {
      downCrossings.push_back(t - dt * current / (current - previous)); // linear interpolation
    }
    previous = current;
  }
  ASSERT_GE(downCrossings.size(), 4u) << "the body did not flip about its intermediate axis";
  double maxRelativeError = 0.0;
  for (std::size_t c = 1; c < downCrossings.size(); ++c) {
    const double period = downCrossings[c] - downCrossings[c - 1];
    maxRelativeError = std::max(maxRelativeError, std::abs(period - expected) / expected);
  }
  // Within 1 % (measured 5e-7): the splitting error in the period is O((omega dt)^2), and the
  // linear interpolation of the crossing time is far below dt / T ~ 2e-4. Near the separatrix
  // the period is sensitive to energy, dT/T ~ 30 dE/E for this state (1e-3 in E gives 3.4 % in
  // T), so the test also fails an integrator whose energy error reaches ~3e-4.
  EXPECT_LE(maxRelativeError, 0.01);
  std::printf("flip period: analytic %.6f s, measured max relative error %.3e over %zu periods\n", expected,
              maxRelativeError, downCrossings.size() - 1);
}

TEST(FreeRotation, SpinAboutLargestOrSmallestAxisIsStable) {
  const Vec3 moments(1.0, 2.0, 3.0);
  for (int axis : {0, 2}) {
    // The same 10 % perturbation that flips the intermediate axis above.
    Vec3 omega = Vec3::Constant(0.1);
    omega[axis] = 1.0;
    RigidBodies bodies = makeBody(moments, omega);
    const Vec3 l = bodies.angularMomentumWorld(0).normalized();
    double maxAngle = 0.0;
    bool signChanged = false;
    for (int n = 0; n < 20000; ++n) { // 100 s, several nutation periods
      freeStep(bodies, 5e-3);
      signChanged = signChanged || omegaBody(bodies)[axis] <= 0.0;
      const Vec3 bodyAxis = bodies.orientation(0) * Vec3::Unit(axis);
      maxAngle = std::max(maxAngle, std::acos(std::clamp(bodyAxis.dot(l), -1.0, 1.0)));
    }
    EXPECT_FALSE(signChanged) << "axis " << axis;
    // The axis stays on its nutation cone around L: the initial angle is atan(0.224/3) =
    // 0.075 rad (largest axis) and atan(0.361/1) = 0.346 rad (smallest); along the polhode it
    // grows to 0.094 and 0.386 rad (measured), within 1.5 x the initial angle; a flip reaches pi.
    const double initial = axis == 2 ? std::atan(std::hypot(0.1, 0.2) / 3.0) : std::atan(std::hypot(0.2, 0.3) / 1.0);
    EXPECT_LE(maxAngle, 1.5 * initial) << "axis " << axis;
  }
}

TEST(FreeRotation, AxisymmetricAndIsotropicBodiesAreExact) {
  // Symmetric top: T = |L|^2 / (2 I_r) + (1/I_s - 1/I_r) L_s^2 / 2 with s the symmetry axis and
  // I_r the repeated moment; the two flows commute, so (Landau & Lifshitz section 33)
  //   R(t) = Rot(L / |L|, |L| t / I_r) R_0 Rot(e_s, (1/I_s - 1/I_r) L_s t).
  // The splitting reproduces this exactly, whatever the step.
  struct Case {
    Vec3 moments;
    int symmetryAxis;
  };
  for (const Case& c : {Case{Vec3(2.0, 2.0, 3.0), 2}, Case{Vec3(1.0, 2.5, 2.5), 0}, Case{Vec3(2.0, 2.0, 2.0), 2}}) {
    const Quat q0 = Quat(0.6, -0.2, 0.5, 0.3).normalized();
    RigidBodies bodies = makeBody(c.moments, Vec3(0.4, -0.9, 1.2), q0);
    const Vec3 l = bodies.angularMomentumWorld(0);
    const Vec3 bodyL = bodies.angularMomentumBody(0);
    const int r = (c.symmetryAxis + 1) % 3;
    const double dt = 0.1; // |omega| dt = 0.16 rad: a second-order error would be ~1e-3 per step
    double t = 0.0;
    double maxError = 0.0;
    for (int n = 0; n < 500; ++n) {
      freeStep(bodies, dt);
      t += dt;
      const Quat spin(Eigen::AngleAxisd(l.norm() * t / c.moments[r], l.normalized()));
      const Quat precession(Eigen::AngleAxisd(
          (1.0 / c.moments[c.symmetryAxis] - 1.0 / c.moments[r]) * bodyL[c.symmetryAxis] * t,
          Vec3::Unit(c.symmetryAxis)));
      maxError = std::max(maxError, angleBetween(bodies.orientation(0), spin * q0 * precession));
    }
    // Round-off only: it grows linearly with the step count (measured ~1.4e-15 rad per step,
    // independent of dt), so 500 steps give ~7e-13; a truncation error would be ~1e-2 here.
    EXPECT_LE(maxError, 1e-11) << "moments " << c.moments.transpose();
    std::printf("symmetric top (%g, %g, %g): max orientation error %.3e rad\n", c.moments[0], c.moments[1],
                c.moments[2], maxError);
  }
}

TEST(FreeRotation, AsymmetricOrientationIsSecondOrder) {
  const Vec3 moments(1.0, 2.0, 3.0);
  const Vec3 omega0(1.0, 0.5, -0.7);
  const double tEnd = 4.0;
  auto orientationAt = [&](int steps) {
    RigidBodies bodies = makeBody(moments, omega0);
    for (int n = 0; n < steps; ++n) {
      freeStep(bodies, tEnd / steps);
    }
    return bodies.orientation(0);
  };
  const Quat reference = orientationAt(40 * 64); // error ~ (1/64)^2 of the coarsest: negligible
  const double e1 = angleBetween(orientationAt(40), reference);  // |omega| dt = 0.13 rad
  const double e2 = angleBetween(orientationAt(80), reference);
  const double e4 = angleBetween(orientationAt(160), reference);
  // Second order: halving dt divides the error by 4; 3.6-4.4 allows the O(dt^4) terms at these
  // steps and the reference's own error (<0.3 % of e4).
  EXPECT_GE(e1 / e2, 3.6);
  EXPECT_LE(e1 / e2, 4.4);
  EXPECT_GE(e2 / e4, 3.6);
  EXPECT_LE(e2 / e4, 4.4);
  std::printf("rotation convergence: errors %.3e %.3e %.3e, ratios %.3f %.3f\n", e1, e2, e4, e1 / e2, e2 / e4);
}

TEST(FreeRotation, ConstantTorqueAboutPrincipalAxisGivesExactAngularAcceleration) {
  const Vec3 moments(1.0, 2.0, 3.0);
  const Quat q0 = Quat(0.8, 0.3, -0.4, 0.2).normalized();
  for (int axis = 0; axis < 3; ++axis) {
    RigidBodies bodies = makeBody(moments, Vec3::Zero(), q0);
    const Vec3 worldAxis = q0 * Vec3::Unit(axis);
    const double tau = 1.5; // N m
    const Vec3 torque = tau * worldAxis;
    auto applyTorque = [&](RigidBodies& b) { b.applyTorque(0, torque); };
    bodies.clearForces();
    applyTorque(bodies);
    const double dt = 1e-3;
    double t = 0.0;
    double maxOmegaError = 0.0;
    double maxAngleError = 0.0;
    for (int n = 0; n < 2000; ++n) {
      step(bodies, dt, kNoGravity, applyTorque);
      t += dt;
      const Vec3 exact = tau * t / moments[axis] * worldAxis;
      maxOmegaError = std::max(maxOmegaError, (bodies.worldAngularVelocity(0) - exact).norm() / exact.norm());
      // Angle theta = tau t^2 / (2 I): velocity Verlet is exact for constant acceleration.
      const Quat expected = Quat(Eigen::AngleAxisd(0.5 * tau * t * t / moments[axis], worldAxis)) * q0;
      maxAngleError = std::max(maxAngleError, angleBetween(bodies.orientation(0), expected));
    }
    // Exact by construction (kicks add tau dt/2 to L; the drift turns by omega_{n+1/2} dt);
    // 1e-12 bounds the round-off of 2000 steps.
    EXPECT_LE(maxOmegaError, 1e-12) << "axis " << axis;
    EXPECT_LE(maxAngleError, 1e-12 * 0.5 * tau * t * t / moments[axis]) << "axis " << axis;
    std::printf("constant torque axis %d: omega error %.3e, angle error %.3e rad\n", axis, maxOmegaError,
                maxAngleError);
  }
}
