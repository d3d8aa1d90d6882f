// SPDX-License-Identifier: GPL-3.0-or-later
// Translational velocity Verlet, the stage order, motion types and the awake list, determinism
// across thread counts, and body validation.

#include "core/Error.hpp"
#include "dynamics/Integrator.hpp"
#include "dynamics/RigidBodies.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace armour::dynamics;
using armour::core::InputError;

namespace {

const Vec3 kGravity(0.0, 0.0, -9.81);

BodyDefinition block(const std::string& name, double mass = 2.0) {
  BodyDefinition def;
  def.name = name;
  def.mass = mass;
  def.principalMoments = Vec3(1.0, 2.0, 2.5);
  return def;
}

/// The message of the InputError thrown by add(def), or "" if none.
std::string addError(const BodyDefinition& def) {
  RigidBodies bodies;
  try {
    bodies.add(def);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// Every state array of body i, bit for bit.
bool sameState(const RigidBodies& a, const RigidBodies& b, BodyId i) {
  auto same = [](const auto& u, const auto& v) { return std::memcmp(u.data(), v.data(), sizeof(double) * u.size()) == 0; };
  return same(a.position(i), b.position(i)) && same(a.orientation(i).coeffs(), b.orientation(i).coeffs()) &&
         same(a.velocity(i), b.velocity(i)) && same(a.angularMomentumWorld(i), b.angularMomentumWorld(i)) &&
         same(a.worldAngularVelocity(i), b.worldAngularVelocity(i));
}

} // namespace

TEST(Integrator, BallisticFlightIsExact) {
  RigidBodies bodies;
  BodyDefinition def = block("stone", 4.0);
  def.position = Vec3(100.0, -50.0, 2.0);
  def.velocity = Vec3(3.0, 1.0, 12.0);
  bodies.add(def);
  const Vec3 push(2.0, 0.0, 1.0); // N, a constant applied force on top of gravity
  const ForceStage forces = [&](RigidBodies& b) { b.applyForce(0, push); };
  bodies.clearForces();
  forces(bodies);
  const Vec3 a = push / def.mass + kGravity;
  const double dt = 1e-3;
  double maxPositionError = 0.0;
  double maxVelocityError = 0.0;
  for (int n = 1; n <= 2000; ++n) {
    step(bodies, dt, kGravity, forces);
    const double t = n * dt;
    const Vec3 x = def.position + def.velocity * t + 0.5 * a * t * t;
    const Vec3 v = def.velocity + a * t;
    maxPositionError = std::max(maxPositionError, (bodies.position(0) - x).norm() / x.norm());
    maxVelocityError = std::max(maxVelocityError, (bodies.velocity(0) - v).norm() / v.norm());
  }
  // Velocity Verlet integrates constant acceleration exactly (x is quadratic in t, the update is
  // its Taylor series); 1e-12 bounds the round-off accumulated over 2000 steps (~1e-16 each).
  EXPECT_LE(maxPositionError, 1e-12);
  EXPECT_LE(maxVelocityError, 1e-12);
  std::printf("ballistic: max relative error x %.3e, v %.3e\n", maxPositionError, maxVelocityError);
}

namespace {

/// Spring F = -k x on body 0 (m = 2 kg, k = 50 N/m: omega = 5 rad/s, period 1.26 s).
constexpr double kMass = 2.0;
constexpr double kStiffness = 50.0;

RigidBodies makeOscillator(double x0, double v0) {
  RigidBodies bodies;
  BodyDefinition def = block("mass", kMass);
  def.position = Vec3(x0, 0.0, 0.0);
  def.velocity = Vec3(v0, 0.0, 0.0);
  bodies.add(def);
  return bodies;
}

void spring(RigidBodies& b) { b.applyForce(0, -kStiffness * b.position(0)); }

double oscillatorPositionAt(double tEnd, int steps) {
  RigidBodies bodies = makeOscillator(0.3, 1.0);
  bodies.clearForces();
  spring(bodies);
  for (int n = 0; n < steps; ++n) {
    step(bodies, tEnd / steps, Vec3::Zero(), spring);
  }
  return bodies.position(0).x();
}

} // namespace

TEST(Integrator, HarmonicOscillatorConvergesAtSecondOrder) {
  const double omega = std::sqrt(kStiffness / kMass);
  const double tEnd = 2.0;
  const double exact = 0.3 * std::cos(omega * tEnd) + 1.0 / omega * std::sin(omega * tEnd);
  const double e1 = std::abs(oscillatorPositionAt(tEnd, 100) - exact); // omega dt = 0.1
  const double e2 = std::abs(oscillatorPositionAt(tEnd, 200) - exact);
  const double e4 = std::abs(oscillatorPositionAt(tEnd, 400) - exact);
  // Second order: the error falls by 4 when dt halves; 3.6-4.4 allows the O(dt^4) terms.
  EXPECT_GE(e1 / e2, 3.6);
  EXPECT_LE(e1 / e2, 4.4);
  EXPECT_GE(e2 / e4, 3.6);
  EXPECT_LE(e2 / e4, 4.4);
  std::printf("oscillator convergence: errors %.3e %.3e %.3e, ratios %.3f %.3f\n", e1, e2, e4, e1 / e2, e2 / e4);
}

TEST(Integrator, HarmonicOscillatorEnergyIsBounded) {
  const double omega = std::sqrt(kStiffness / kMass);
  const double dt = 0.01; // omega dt = 0.05; 1e5 steps = 1000 s = 796 periods
  const double h2 = (omega * dt) * (omega * dt);
  RigidBodies bodies = makeOscillator(0.3, 1.0);
  bodies.clearForces();
  spring(bodies);
  auto energy = [&] {
    return 0.5 * kMass * bodies.velocity(0).squaredNorm() + 0.5 * kStiffness * bodies.position(0).squaredNorm();
  };
  // Velocity Verlet conserves exactly the modified energy
  //   E~ = 1/2 m v^2 + 1/2 k x^2 (1 - (omega dt)^2 / 4)
  // (its one-step map has unit determinant and this invariant quadratic form), so E oscillates
  // within a band of relative width (omega dt)^2 / 4 / (1 - (omega dt)^2 / 4) and cannot drift.
  auto modified = [&] {
    return 0.5 * kMass * bodies.velocity(0).squaredNorm() +
           0.5 * kStiffness * bodies.position(0).squaredNorm() * (1.0 - h2 / 4.0);
  };
  const double e0 = energy();
  const double m0 = modified();
  double maxEnergyError = 0.0;
  double maxModifiedError = 0.0;
  for (int n = 0; n < 100000; ++n) {
    step(bodies, dt, Vec3::Zero(), spring);
    maxEnergyError = std::max(maxEnergyError, std::abs(energy() - e0) / e0);
    maxModifiedError = std::max(maxModifiedError, std::abs(modified() - m0) / m0);
  }
  // The band above, plus 1e-9 of round-off slack.
  EXPECT_LE(maxEnergyError, h2 / 4.0 / (1.0 - h2 / 4.0) + 1e-9);
  // The discrete invariant holds to round-off: 1e-10 bounds 1e5 steps of ~1e-16 each (linear
  // accumulation would give 1e-11). A drifting (non-symplectic) method fails this immediately.
  EXPECT_LE(maxModifiedError, 1e-10);
  std::printf("oscillator energy: max |dE|/E = %.3e (band %.3e), modified energy %.3e\n", maxEnergyError,
              h2 / 4.0 / (1.0 - h2 / 4.0), maxModifiedError);
}

TEST(Integrator, VelocityDependentForcesSeeHalfStepVelocities) {
  // Documented stage order: the force stage after the drift sees v_{n+1/2}. With a linear damper
  // F = -c v and the forces primed at v_0:
  //   v_{1/2} = v_0 (1 - a),  v_1 = v_{1/2} (1 - a),  a = c dt / (2 m).
  RigidBodies bodies;
  BodyDefinition def = block("damped", kMass);
  def.velocity = Vec3(1.5, -0.5, 0.25);
  bodies.add(def);
  const double c = 3.0; // N s/m
  const ForceStage damper = [&](RigidBodies& b) { b.applyForce(0, -c * b.velocity(0)); };
  bodies.clearForces();
  damper(bodies);
  const double dt = 0.01;
  step(bodies, dt, Vec3::Zero(), damper);
  const double a = c * dt / (2.0 * kMass);
  const Vec3 expected = def.velocity * (1.0 - a) * (1.0 - a);
  // Two multiplications of round-off.
  EXPECT_LE((bodies.velocity(0) - expected).norm(), 1e-15 * def.velocity.norm());
  // The force left in the accumulator (reused by the next step's first kick) is -c v_{1/2}
  // (round-off of a few products on a force of ~5 N).
  EXPECT_LE((bodies.force(0) + c * def.velocity * (1.0 - a)).norm(), 1e-14);
}

TEST(Integrator, ForceAtPointAddsTorqueAndEnergyIsConsistent) {
  RigidBodies bodies;
  BodyDefinition def = block("lever", 2.0);
  def.position = Vec3(1.0, 2.0, 3.0);
  def.velocity = Vec3(1.0, 0.0, 2.0);
  def.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3(1.0, 1.0, 0.0).normalized()));
  def.angularVelocity = Vec3(0.5, -0.25, 1.0);
  bodies.add(def);
  bodies.clearForces();
  bodies.applyForceAtPoint(0, Vec3(0.0, 0.0, 10.0), def.position + Vec3(0.5, 0.0, 0.0));
  // r x F = (0.5, 0, 0) x (0, 0, 10) = (0, -5, 0): exact in floating point.
  EXPECT_EQ(bodies.torque(0), Vec3(0.0, -5.0, 0.0));
  EXPECT_EQ(bodies.force(0), Vec3(0.0, 0.0, 10.0));
  // T = 1/2 m v^2 + 1/2 omega . I_world omega with I_world = R diag(I) R^T.
  const Mat3 r = def.orientation.toRotationMatrix();
  const Mat3 inertiaWorld = r * def.principalMoments.asDiagonal() * r.transpose();
  const double expected = 0.5 * def.mass * def.velocity.squaredNorm() +
                          0.5 * def.angularVelocity.dot(inertiaWorld * def.angularVelocity);
  EXPECT_NEAR(bodies.kineticEnergy(0), expected, 1e-14 * expected); // round-off of a few products
  EXPECT_NEAR(bodies.totalKineticEnergy(), expected, 1e-14 * expected);
  // The cached omega reproduces the definition (L = I omega, omega = I^-1 L round trip: four
  // quaternion rotations and two scalings, ~1e-15 relative on |omega| ~ 1.1 rad/s).
  EXPECT_LE((bodies.worldAngularVelocity(0) - def.angularVelocity).norm(), 1e-14);
  EXPECT_LE((bodies.inverseInertiaWorld(0) * inertiaWorld - Mat3::Identity()).norm(), 1e-14); // round-off
  // Material point velocity v + omega x r (round-off of the cached omega).
  const Vec3 p = def.position + Vec3(0.0, 1.0, 0.0);
  EXPECT_LE((bodies.velocityAtPoint(0, p) - (def.velocity + def.angularVelocity.cross(Vec3(0.0, 1.0, 0.0)))).norm(),
            1e-14);
}

TEST(Integrator, StaticAndSleepingBodiesAreSkipped) {
  RigidBodies bodies;
  BodyDefinition ground;
  ground.name = "toe";
  ground.motionType = MotionType::Static;
  ground.position = Vec3(0.0, 0.0, -1.0);
  const BodyId toe = bodies.add(ground);
  BodyDefinition resting = block("resting");
  resting.motionType = MotionType::Sleeping;
  resting.position = Vec3(5.0, 0.0, 0.0);
  resting.orientation = Quat(0.9, 0.1, 0.2, 0.3).normalized();
  const BodyId sleeper = bodies.add(resting);
  BodyDefinition falling = block("falling");
  falling.angularVelocity = Vec3(0.1, 0.2, 0.3);
  const BodyId faller = bodies.add(falling);

  ASSERT_EQ(bodies.awakeBodies().size(), 1u);
  EXPECT_EQ(bodies.awakeBodies()[0], faller);
  EXPECT_EQ(bodies.inverseMass(toe), 0.0);
  EXPECT_EQ(bodies.inverseInertiaBody(toe), Vec3::Zero());

  // NaN forces on the bodies at rest: if a stage visited them, their state would become NaN.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ForceStage forces = [&](RigidBodies& b) {
    for (BodyId i : {toe, sleeper}) {
      b.applyForce(i, Vec3::Constant(nan));
      b.applyTorque(i, Vec3::Constant(nan));
    }
    b.applyForce(faller, Vec3(1.0, 0.0, 0.0));
  };
  const RigidBodies before = bodies;
  bodies.clearForces();
  forces(bodies);
  for (int n = 0; n < 100; ++n) {
    step(bodies, 1e-3, kGravity, forces);
  }
  // Bit-identical: the integrator never touched them.
  EXPECT_TRUE(sameState(bodies, before, toe));
  EXPECT_TRUE(sameState(bodies, before, sleeper));
  EXPECT_FALSE(sameState(bodies, before, faller));
  EXPECT_TRUE(bodies.position(faller).allFinite());
  EXPECT_EQ(bodies.kineticEnergy(sleeper), 0.0);
  EXPECT_EQ(bodies.kineticEnergy(toe), 0.0);

  // Waking: the sleeper joins the awake list and falls (from rest) under gravity.
  bodies.wake(sleeper);
  ASSERT_EQ(bodies.awakeBodies().size(), 2u);
  const double z0 = bodies.position(sleeper).z();
  const ForceStage none = [](RigidBodies&) {};
  bodies.clearForces();
  for (int n = 0; n < 10; ++n) {
    step(bodies, 1e-2, kGravity, none);
  }
  // Free fall from rest over 0.1 s: z drops by g t^2 / 2, exact for velocity Verlet (round-off
  // of ten steps on z ~ 1e-2 m).
  EXPECT_NEAR(bodies.position(sleeper).z(), z0 - 0.5 * 9.81 * 0.01, 1e-14);

  // Sleeping again zeroes the velocities and drops it from the list.
  bodies.sleep(sleeper);
  EXPECT_EQ(bodies.awakeBodies().size(), 1u);
  EXPECT_EQ(bodies.velocity(sleeper), Vec3::Zero());
  EXPECT_EQ(bodies.worldAngularVelocity(sleeper), Vec3::Zero());

  // A static body defined without mass cannot be made dynamic.
  EXPECT_THROW(bodies.setMotionType(toe, MotionType::Dynamic), InputError);
  EXPECT_EQ(bodies.motionType(toe), MotionType::Static);
}

TEST(Integrator, AwakeListFollowsMotionTypeChanges) {
  RigidBodies bodies;
  for (int i = 0; i < 6; ++i) {
    bodies.add(block(fmt::format("b{}", i)));
  }
  bodies.sleep(1);
  bodies.sleep(4);
  bodies.setMotionType(0, MotionType::Static);
  bodies.wake(4);
  bodies.wake(0); // no effect on a static body
  bodies.setMotionType(5, MotionType::Static);
  bodies.setMotionType(5, MotionType::Dynamic); // restores the defined mass
  std::vector<BodyId> awake(bodies.awakeBodies().begin(), bodies.awakeBodies().end());
  std::sort(awake.begin(), awake.end());
  EXPECT_EQ(awake, (std::vector<BodyId>{2, 3, 4, 5}));
  EXPECT_EQ(bodies.inverseMass(5), 0.5);
  EXPECT_EQ(bodies.inverseMass(0), 0.0);
  for (BodyId i = 0; i < bodies.size(); ++i) {
    EXPECT_EQ(bodies.isAwake(i), std::count(awake.begin(), awake.end(), i) == 1) << i;
  }
}

namespace {

/// 100 bodies with random shapes, states and motion types; forces depend on the state so that
/// any difference would grow: a spring to an anchor, linear damping, and an orientation spring.
struct RandomScene {
  RigidBodies bodies;
  std::vector<Vec3> anchors;

  explicit RandomScene(unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto vec = [&] { return Vec3(u(rng), u(rng), u(rng)); };
    for (int i = 0; i < 100; ++i) {
      BodyDefinition def;
      def.name = fmt::format("unit-{}", i);
      const Vec3 size = Vec3::Constant(1.5) + 0.5 * vec(); // box sides (m)
      def.mass = 2400.0 * size.prod();
      def.principalMoments = def.mass / 12.0 *
                             Vec3(size.y() * size.y() + size.z() * size.z(), size.x() * size.x() + size.z() * size.z(),
                                  size.x() * size.x() + size.y() * size.y());
      def.position = 10.0 * vec();
      def.orientation = Quat(u(rng), u(rng), u(rng), u(rng)).normalized();
      def.motionType = i % 10 == 3 ? MotionType::Static : (i % 10 == 7 ? MotionType::Sleeping : MotionType::Dynamic);
      if (def.motionType == MotionType::Dynamic) {
        def.velocity = vec();
        def.angularVelocity = 2.0 * vec();
      }
      bodies.add(def);
      anchors.push_back(def.position + vec());
    }
  }

  void forces(RigidBodies& b) const {
    for (BodyId i = 0; i < b.size(); ++i) {
      const double m = b.info(i).mass;
      b.applyForceAtPoint(i, -50.0 * m * (b.position(i) - anchors[i]) - 0.5 * m * b.velocity(i),
                          b.toWorld(i, Vec3(0.3, -0.2, 0.1)));
      b.applyTorque(i, -m * (b.orientation(i) * Vec3::UnitZ()).cross(Vec3::UnitZ()));
    }
  }
};

RigidBodies runScene(int threads) {
  omp_set_num_threads(threads);
  RandomScene scene(20240601);
  const ForceStage forces = [&](RigidBodies& b) { scene.forces(b); };
  scene.bodies.clearForces();
  forces(scene.bodies);
  for (int n = 0; n < 200; ++n) {
    step(scene.bodies, 2e-3, kGravity, forces);
  }
  return scene.bodies;
}

} // namespace

TEST(Integrator, ResultsAreIndependentOfThreadCount) {
  const int defaultThreads = omp_get_max_threads();
  const RigidBodies one = runScene(1);
  const RigidBodies two = runScene(2);
  omp_set_num_threads(defaultThreads);
  // The parallel path must actually run: 80 awake bodies, above the serial threshold.
  ASSERT_GE(one.awakeBodies().size(), kParallelMinBodies);
  ASSERT_EQ(one.size(), two.size());
  for (BodyId i = 0; i < one.size(); ++i) {
    // Bit-identical: each body's update is independent of the others and of the schedule.
    EXPECT_TRUE(sameState(one, two, i)) << one.describe(i);
  }
  double moved = 0.0;
  const RandomScene initial(20240601);
  for (BodyId i = 0; i < one.size(); ++i) {
    moved = std::max(moved, (one.position(i) - initial.bodies.position(i)).norm());
  }
  EXPECT_GT(moved, 0.01); // the scene is not trivially at rest
}

TEST(Integrator, BadDefinitionsNameTheBody) {
  BodyDefinition negativeMass = block("rock-7", -1.0);
  std::string message = addError(negativeMass);
  EXPECT_NE(message.find("body 'rock-7'"), std::string::npos) << message;
  EXPECT_NE(message.find("mass = -1"), std::string::npos) << message;

  BodyDefinition nanInertia = block("cube-12");
  nanInertia.principalMoments.y() = std::numeric_limits<double>::quiet_NaN();
  message = addError(nanInertia);
  EXPECT_NE(message.find("body 'cube-12'"), std::string::npos) << message;
  EXPECT_NE(message.find("principal moments"), std::string::npos) << message;

  BodyDefinition impossible = block("bad-inertia");
  impossible.principalMoments = Vec3(1.0, 1.0, 3.0); // 3 > 1 + 1: no rigid body has these
  EXPECT_NE(addError(impossible).find("I_a + I_b >= I_c"), std::string::npos);

  BodyDefinition unnamed = block("");
  unnamed.mass = std::numeric_limits<double>::infinity();
  EXPECT_NE(addError(unnamed).find("body #0"), std::string::npos);

  BodyDefinition movingStatic;
  movingStatic.name = "pier";
  movingStatic.motionType = MotionType::Static;
  movingStatic.velocity = Vec3(1.0, 0.0, 0.0);
  EXPECT_NE(addError(movingStatic).find("body 'pier'"), std::string::npos);

  BodyDefinition zeroRotation = block("spinner");
  zeroRotation.orientation = Quat(0.0, 0.0, 0.0, 0.0);
  EXPECT_NE(addError(zeroRotation).find("orientation"), std::string::npos);

  BodyDefinition lost = block("lost");
  lost.position.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(addError(lost).find("position"), std::string::npos);

  // A static body needs no mass, and a thin plate (I_1 + I_2 = I_3) is a valid rigid body.
  BodyDefinition ground;
  ground.motionType = MotionType::Static;
  EXPECT_EQ(addError(ground), "");
  BodyDefinition plate = block("plate");
  plate.principalMoments = Vec3(1.0, 2.0, 3.0);
  EXPECT_EQ(addError(plate), "");
}
