// SPDX-License-Identifier: GPL-3.0-or-later
// Rigid bodies with level-set penalty contact against analytic results: rebound with the target
// restitution, energy conservation of elastic bounces, static friction on an incline below the
// friction angle (no creep) and the sliding acceleration above it.

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "simulation/World.hpp"
#include "support/CubeScene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <omp.h>

using namespace armour;
using namespace armour::simulation;
using armour::test::concrete;
using armour::test::CubeScene;
using armour::test::noSleep;

namespace {

/// Drop a cube flat from `gap` above the floor; return (impact speed, rebound speed) of the first
/// bounce. The rebound speed is the largest upward speed within 50 ms of the first contact: it is
/// reached when the cube leaves the floor (contact lasts about 5 ms here).
std::pair<double, double> firstBounce(double restitution, double gap, const WorldSettings& settings = noSleep()) {
  CubeScene s(concrete(restitution, 0.5), settings);
  s.addFloor();
  const BodyId b = s.addCube(Vec3(0, 0, 0.5 + gap));
  double impact = 0.0, rebound = 0.0, tContact = -1.0;
  while (s.world.time() < 2.0) {
    const double vz = s.world.bodies().velocity(b).z();
    s.world.step();
    if (tContact < 0.0 && s.world.lastStep().contactPoints > 0) {
      tContact = s.world.time();
      impact = -vz;
    }
    if (tContact >= 0.0) {
      rebound = std::max(rebound, s.world.bodies().velocity(b).z());
      if (s.world.time() > tContact + 0.05) {
        break;
      }
    }
  }
  return {impact, rebound};
}

} // namespace

TEST(ContactPhysics, DropReboundsWithTheTargetRestitution) {
  // Flat landing from 0.5 m (3.1 m/s): every bottom sample engages at once and the patch behaves
  // as one linear spring-dashpot, so the rebound ratio should be e. The issue allows 0.03: gravity
  // acts during the ~5 ms of contact (g T / v = 0.016) and the step smears entry and exit.
  for (double e : {0.05, 0.3, 0.6, 0.9}) {
    const auto [vin, vout] = firstBounce(e, 0.5);
    ASSERT_GT(vin, 3.0);
    RecordProperty("rebound_ratio_e" + std::to_string(static_cast<int>(100 * e)), std::to_string(vout / vin));
    EXPECT_NEAR(vout / vin, e, 0.03) << "e = " << e << ", impact " << vin << " m/s, rebound " << vout << " m/s";
  }
}

TEST(ContactPhysics, ImplicitDashpotDropReboundsNearTheTargetAtItsLongerStep) {
  // contact.dashpot: implicit (theory.md section 6, "The dashpot over a step"): the automatic step
  // no longer shrinks with the damping ratio (e = 0.01: 4.3 times the explicit one's), and the
  // flat drop above still rebounds within 0.03 of e, as the explicit dashpot does (the issue
  // allows 0.05): the dashpot's rate is lowered by 1 + zeta omega dt, which raises the rebound a
  // little (measured in session 21: 0.0116, 0.0479, 0.3025).
  for (double e : {0.01, 0.05, 0.3}) {
    WorldSettings implicitSettings = noSleep();
    implicitSettings.dashpot = DashpotIntegration::Implicit;
    CubeScene explicitScene(concrete(e, 0.5)), implicitScene(concrete(e, 0.5), implicitSettings);
    explicitScene.addCube(Vec3(0, 0, 1));
    implicitScene.addCube(Vec3(0, 0, 1));
    const double zeta = contact::dampingRatioFromRestitution(e);
    const double ratio = contact::stableStepOfImplicitDashpot(zeta) / (2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta));
    EXPECT_NEAR(implicitScene.world.timeStep() / explicitScene.world.timeStep(), ratio, 1e-12 * ratio) << "e = " << e;
    const auto [vin, vout] = firstBounce(e, 0.5, implicitSettings);
    ASSERT_GT(vin, 3.0);
    RecordProperty("implicit_rebound_ratio_e" + std::to_string(static_cast<int>(100 * e)), std::to_string(vout / vin));
    EXPECT_NEAR(vout / vin, e, 0.03) << "e = " << e << ", step x" << ratio << ", impact " << vin << " m/s, rebound "
                                     << vout << " m/s";
  }
}

TEST(ContactPhysics, ElasticBouncesConserveEnergy) {
  // e = 1 and no friction: nothing dissipates; the penalty spring stores and returns the energy.
  // (With friction a repeatedly bouncing cube starts to rock: the flat bounce is parametrically
  // unstable, a tilt of 1e-17 rad grows about 17-fold per bounce, and the rocking edges then
  // slide and dissipate, as a real block would.) Over 100 bounces the
  // mechanical energy must drift by less than 1 %. Each entry into and exit from contact in
  // mid-step costs O((omega dt)^2) of the bounce energy; at half the default safety factor
  // (omega dt = 0.07 for the face contact) that is below 1e-5 per bounce, 1e-3 over 100 bounces:
  // 1 % leaves that bound a factor of ten and catches a dashpot that dissipates at e = 1.
  WorldSettings settings = noSleep();
  settings.timeStepSafety = 0.1;
  CubeScene s(concrete(1.0, 0.0), settings);
  s.addFloor();
  s.addCube(Vec3(0, 0, 0.5 + 0.02));
  const double bounceEnergy = 2400.0 * 9.81 * 0.02;
  const double e0 = s.world.mechanicalEnergy();
  int bounces = 0;
  bool inContact = false;
  while (bounces < 100 && s.world.time() < 60.0) {
    s.world.step();
    const bool now = s.world.lastStep().contactPoints > 0;
    if (inContact && !now) {
      ++bounces;
      EXPECT_NEAR(s.world.mechanicalEnergy(), e0, 0.01 * bounceEnergy) << "after bounce " << bounces;
    }
    inContact = now;
  }
  EXPECT_EQ(bounces, 100);
}

namespace {

/// A cube resting on a slope of angle theta (rad); returns the world and the body.
struct SlopeScene : CubeScene {
  BodyId block = 0;
  Vec3 normal, downhill;
  SlopeScene(double theta, double mu) : CubeScene(concrete(0.3, mu)) {
    normal = Vec3(std::sin(theta), 0, std::cos(theta)); // slope descends towards +x
    downhill = Vec3(std::cos(theta), 0, -std::sin(theta));
    addFloor(normal);
    const Quat tilt(Eigen::AngleAxisd(theta, Vec3::UnitY()));
    block = addCube(0.5 * normal, tilt);
  }
  double along() const { return world.bodies().position(block).dot(downhill); }
};

} // namespace

TEST(ContactPhysics, BlockOnInclineBelowFrictionAngleDoesNotCreep) {
  // tan(25 deg) = 0.466 < mu = 0.75: static friction holds the block. After it settles onto its
  // springs (1 s) it must not move more than 1e-4 m in 20 s: the tangential springs hold a
  // constant stretch, so the exact answer is no motion at all; 1e-4 m (1e-4 Dn, 5 um/s) is the
  // smallest creep a viscous friction law would show here.
  SlopeScene s(25.0 * std::numbers::pi / 180.0, 0.75);
  s.world.advanceTo(1.0);
  const double x0 = s.along();
  s.world.advanceTo(21.0);
  RecordProperty("drift_m", std::to_string(std::abs(s.along() - x0)));
  EXPECT_LT(std::abs(s.along() - x0), 1e-4);
  EXPECT_LT(std::abs(s.along()), 1e-3) << "elastic stretch only";
}

TEST(ContactPhysics, BlockOnInclineAboveFrictionAngleSlidesWithCoulombAcceleration) {
  // theta = 35 deg, mu = 0.4: a = g (sin theta - mu cos theta) = 2.413 m/s^2, to 1 %: the error an
  // error of 0.003 in mu makes (da/dmu = -g cos theta). Measured from the velocity gain between
  // 0.5 s and 1.5 s (after the contact has settled).
  const double theta = 35.0 * std::numbers::pi / 180.0;
  SlopeScene s(theta, 0.4);
  s.world.advanceTo(0.5);
  const double v0 = s.world.bodies().velocity(s.block).dot(s.downhill);
  s.world.advanceTo(1.5);
  const double v1 = s.world.bodies().velocity(s.block).dot(s.downhill);
  const double expected = 9.81 * (std::sin(theta) - 0.4 * std::cos(theta));
  RecordProperty("acceleration_relative_error", std::to_string((v1 - v0) / expected - 1.0));
  EXPECT_NEAR((v1 - v0) / 1.0, expected, 0.01 * expected);
}

TEST(ContactPhysics, UserTimeStepAboveTheLimitIsRefused) {
  WorldSettings settings = noSleep();
  settings.timeStep = 0.1;
  CubeScene s(concrete(0.3, 0.5), settings);
  s.addFloor();
  s.addCube(Vec3(0, 0, 1));
  try {
    s.world.step();
    ADD_FAILURE() << "a 0.1 s step must be refused";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the stability limit"), std::string::npos) << e.what();
  }
}

namespace {

/// A loose pile: 3 x 3 x 2 cubes dropped with small random tilts onto the floor and each other.
std::vector<double> runPile(int threads) {
  omp_set_num_threads(threads);
  CubeScene s(concrete(0.3, 0.6));
  s.addFloor();
  std::mt19937_64 rng(11);
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        const double tilt = 0.2 * ((rng() >> 11) * 0x1.0p-53 - 0.5);
        s.addCube(Vec3(1.05 * i + 0.3 * k, 1.05 * j, 0.52 + 1.04 * k),
                  Quat(Eigen::AngleAxisd(tilt, Vec3(1, 1, 0).normalized())));
      }
    }
  }
  for (int n = 0; n < 600; ++n) {
    s.world.step();
  }
  std::vector<double> state;
  const auto& b = s.world.bodies();
  for (BodyId i = 0; i < b.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      state.push_back(b.position(i)[k]);
      state.push_back(b.velocity(i)[k]);
      state.push_back(b.angularMomentumWorld(i)[k]);
    }
    state.push_back(b.orientation(i).w());
  }
  EXPECT_GT(s.world.lastStep().contactPoints, 50u) << "the pile must be in contact to test anything";
  return state;
}

} // namespace

TEST(ContactPhysics, OneAndTwoThreadsGiveBitIdenticalStates) {
  // Pairs are evaluated in parallel but summed in pair order: the state must not depend on the
  // thread count, bit for bit (Box2D's determinism test).
  const int saved = omp_get_max_threads();
  const auto one = runPile(1);
  const auto two = runPile(2);
  omp_set_num_threads(saved);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i], two[i]) << "state entry " << i;
  }
}

TEST(ContactPhysics, RestingOverlapIsWeightOverFaceStiffness) {
  // A cube at rest on its face: the penalty pressure E_p d / L over exactly the face area A
  // (projected tributary areas) carries the weight, so d = m g L / (E_p A) = 2.354e-5 m for
  // 2400 kg, L = 1 m, A = 1 m^2, E_p = 1e9 Pa. Within 1 %: the damped settling must be over.
  CubeScene s(concrete(0.3, 0.6));
  s.addFloor();
  const BodyId b = s.addCube(Vec3(0, 0, 0.5));
  s.world.advanceTo(0.5);
  const double depth = 0.5 - s.world.bodies().position(b).z();
  EXPECT_NEAR(depth, 2400.0 * 9.81 / 1e9, 0.01 * 2400.0 * 9.81 / 1e9);
}

TEST(ContactPhysics, ConvexStaticPiecesActLikeTheirFaces) {
  // A floor made of a static box (a convex piece) must carry a cube exactly like a plane: the
  // same resting overlap m g L / (E_p A). And a cube dropped over the edge of a narrower block
  // must be caught by the block's top face, not fall through.
  CubeScene s(concrete(0.3, 0.6));
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? 5.0 : -5.0, (i & 2) ? 5.0 : -5.0, (i & 4) ? 0.0 : -1.0);
  }
  s.world.addConvex("block", corners, s.material);
  const BodyId b = s.addCube(Vec3(0, 0, 0.5));
  const BodyId edge = s.addCube(Vec3(4.7, 0, 0.6)); // overhangs the block by 0.2 m
  s.world.advanceTo(0.5);
  const double depth = 0.5 - s.world.bodies().position(b).z();
  EXPECT_NEAR(depth, 2400.0 * 9.81 / 1e9, 0.01 * 2400.0 * 9.81 / 1e9);
  EXPECT_GT(s.world.bodies().position(edge).z(), 0.49) << "the overhanging cube rests on the block";
  EXPECT_EQ(s.world.staticConvexCount(), 1u);
  EXPECT_EQ(s.world.staticConvex(0).normals.size(), 6u) << "Qhull merges coplanar facets: 6 faces";
}
