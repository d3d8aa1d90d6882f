// SPDX-License-Identifier: GPL-3.0-or-later
// The physics suite of issue 22, run for both contact solvers (contact.solver: penalty and
// constraint) on the same level-set narrow phase, with the targets:
//   block on an incline below the friction angle     drift < 1e-4 m over 60 s
//   block on an incline above it                       acceleration within 2 %
//   drop on a floor                                    rebound ratio within 0.05 of e
//   tower of 10 cubes                                  < 1 mm over 60 s
//   a 100:1 mass ratio stack                           at rest (< 1 mm over 10 s)
//   largest and smallest steps                         refused with the limit, or stable
// and the constraint solver's own: 1 and 2 threads bit-identical, a restart from a checkpoint
// bit-identical, warm starts that carry a resting contact.

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/World.hpp"
#include "support/CubeScene.hpp"
#include "support/FloorPile.hpp"
#include "support/ShapeCache.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <tuple>

using namespace armour;
using namespace armour::simulation;
using armour::test::concrete;
using armour::test::CubeScene;

namespace {

constexpr double kG = 9.81;

#ifdef ARMOUR_LONG_TESTS
constexpr bool kLong = true; // test_solvers_long (label slow): the full durations for both solvers
#else
constexpr bool kLong = false;
#endif

/// Simulated seconds of a long test: the issue's `full` for the constraint solver (and in the slow
/// variant for both); in CI the penalty solver, 20 to 40 times slower per simulated second here,
/// runs `ci` seconds of it.
double seconds(ContactSolverKind k, double full, double ci) {
  return kLong || k == ContactSolverKind::Constraint ? full : ci;
}

std::string solverName(ContactSolverKind k) { return k == ContactSolverKind::Penalty ? "penalty" : "constraint"; }

WorldSettings settingsFor(ContactSolverKind kind, bool sleep = false) {
  WorldSettings s;
  s.solver = kind;
  s.sleep.enabled = sleep;
  return s;
}

/// Every body's position, velocity, angular momentum and orientation's w, for bit-for-bit comparisons.
std::vector<double> stateOf(const World& world) {
  std::vector<double> out;
  const auto& b = world.bodies();
  for (BodyId i = 0; i < b.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      out.push_back(b.position(i)[k]);
      out.push_back(b.velocity(i)[k]);
      out.push_back(b.angularMomentumWorld(i)[k]);
    }
    out.push_back(b.orientation(i).w());
  }
  return out;
}

/// A drop on the floor, run until `until` (s): the impact speed (the body's downward speed in the
/// step before the floor first pushed it up) and the largest upward speed within `window` (s) after
/// that: at separation, before gravity slows the rebound.
struct Rebound {
  double impact = 0.0, rebound = 0.0; ///< unit: m/s
};
Rebound measureRebound(World& world, BodyId b, double window, double until) {
  Rebound r;
  double tContact = -1.0;
  while (world.time() < until) {
    const double vz = world.bodies().velocity(b).z();
    world.step();
    if (tContact < 0.0 && world.lastStep().contactPoints > 0 && world.bodies().velocity(b).z() > vz) {
      tContact = world.time();
      r.impact = -vz;
    }
    if (tContact >= 0.0) {
      r.rebound = std::max(r.rebound, world.bodies().velocity(b).z());
      if (world.time() > tContact + window) break;
    }
  }
  return r;
}

/// An off-centre, frictionless drop on the floor, measured by the energy it loses: the energetic
/// restitution e* = sqrt(1 - dE / (m_eff v_n^2 / 2)) (Stronge's coefficient; for a frictionless
/// impact Newton's, Poisson's and Stronge's are one e). dE is the loss of mechanical energy (kinetic
/// plus m g z) from the step before the floor first pushes to the first step it pushes no more;
/// v_n and m_eff = 1 / (1/m + (r x n) . I^-1 (r x n)) are those of the contact point (the patch
/// centre of that first step, r from the centre of mass) just before. Rigid-body impact theory:
/// e* = e whatever the lever arm. Returns e*, or -1 if the contact has not ended within `window` (s).
double energeticRestitution(World& world, BodyId b, double window, double until) {
  world.setRecordContacts(true);
  const auto& bodies = world.bodies();
  const double mass = bodies.info(b).mass;
  const auto energy = [&] { return bodies.kineticEnergy(b) + mass * kG * bodies.position(b).z(); };
  double tContact = -1.0, before = 0.0, available = 0.0;
  while (world.time() < until) {
    const Vec3 v0 = bodies.velocity(b), w0 = bodies.worldAngularVelocity(b), x0 = bodies.position(b);
    const Eigen::Matrix3d inverseInertia = bodies.inverseInertiaWorld(b);
    const double e0 = energy();
    world.step();
    double pushed = 0.0;
    Vec3 point = Vec3::Zero();
    for (const auto& patch : world.contactPatches()) {
      if (patch.bodyA == b && patch.bodyB < 0 && patch.normalForce > 0.0) {
        pushed += patch.normalForce;
        point = patch.point;
      }
    }
    if (tContact < 0.0 && pushed > 0.0) {
      tContact = world.time();
      const Vec3 r = point - x0, rn = r.cross(Vec3::UnitZ());
      const double vn = (v0 + w0.cross(r)).z();
      const double effectiveMass = 1.0 / (1.0 / mass + rn.dot(inverseInertia * rn));
      before = e0;
      available = 0.5 * effectiveMass * vn * vn;
    } else if (tContact >= 0.0 && pushed == 0.0) {
      const double lost = before - energy();
      return std::sqrt(std::max(1.0 - lost / available, 0.0));
    }
    if (tContact >= 0.0 && world.time() > tContact + window) {
      break;
    }
  }
  return -1.0;
}

class BothSolvers : public ::testing::TestWithParam<ContactSolverKind> {};

std::string paramName(const ::testing::TestParamInfo<ContactSolverKind>& info) { return solverName(info.param); }

/// A cube on a plane inclined at theta (descending towards +x).
struct Slope : CubeScene {
  BodyId block = 0;
  Vec3 downhill;
  Slope(ContactSolverKind kind, double theta, double mu) : Slope(settingsFor(kind), theta, mu) {}
  Slope(const WorldSettings& settings, double theta, double mu) : CubeScene(concrete(0.3, mu), settings) {
    const Vec3 normal(std::sin(theta), 0, std::cos(theta));
    downhill = Vec3(std::cos(theta), 0, -std::sin(theta));
    addFloor(normal);
    block = addCube(0.5 * normal, Quat(Eigen::AngleAxisd(theta, Vec3::UnitY())));
  }
  [[nodiscard]] double along() const { return world.bodies().position(block).dot(downhill); }
};

} // namespace

TEST_P(BothSolvers, BlockOnInclineBelowFrictionAngleDoesNotCreep) {
  // tan 25 deg = 0.466 < mu = 0.75: static friction holds the block. After 1 s of settling it may
  // not move 1e-4 m in 60 s (issue 22). Penalty: the friction springs hold a constant stretch;
  // constraint: the friction impulse cancels the tangential velocity at every substep.
  Slope s(GetParam(), 25.0 * std::numbers::pi / 180.0, 0.75);
  s.world.advanceTo(1.0);
  const double x0 = s.along();
  s.world.advanceTo(1.0 + seconds(GetParam(), 60.0, 10.0));
  const double drift = std::abs(s.along() - x0);
  RecordProperty("drift_m", std::to_string(drift));
  EXPECT_LT(drift, 1e-4) << solverName(GetParam());
  EXPECT_LT(std::abs(s.along()), 1e-3) << "settling moves it by the elastic stretch only";
}

TEST_P(BothSolvers, BlockOnInclineAboveFrictionAngleSlidesWithCoulombAcceleration) {
  // theta = 35 deg, mu = 0.4: a = g (sin theta - mu cos theta) = 2.413 m/s^2, from the velocity
  // gained between 0.5 and 1.5 s, after the friction springs' transient. A face sliding on a plane
  // does not rock, so the motion is the analytic one for both solvers (measured: relative errors
  // 7e-6 penalty, 1e-6 constraint). 1e-3 of a is the acceleration an error of 3e-4 in mu makes
  // (da/dmu = -g cos theta): the friction law is checked to its fourth digit.
  const double theta = 35.0 * std::numbers::pi / 180.0;
  Slope s(GetParam(), theta, 0.4);
  s.world.advanceTo(0.5);
  const double v0 = s.world.bodies().velocity(s.block).dot(s.downhill);
  s.world.advanceTo(1.5);
  const double v1 = s.world.bodies().velocity(s.block).dot(s.downhill);
  const double expected = kG * (std::sin(theta) - 0.4 * std::cos(theta));
  RecordProperty("acceleration_relative_error", std::to_string((v1 - v0) / expected - 1.0));
  EXPECT_NEAR(v1 - v0, expected, 1e-3 * expected) << solverName(GetParam());
}

TEST_P(BothSolvers, DropReboundsWithTheTargetRestitution) {
  // A cube dropped flat from 0.5 m (3.1 m/s): rebound speed / impact speed within 0.05 of e.
  for (double e : {0.05, 0.5, 0.9}) {
    CubeScene s(concrete(e, 0.5), settingsFor(GetParam()));
    s.addFloor();
    const BodyId b = s.addCube(Vec3(0, 0, 1.0));
    const auto [impact, rebound] = measureRebound(s.world, b, 0.05, 2.0);
    ASSERT_GT(impact, 3.0) << "e = " << e;
    RecordProperty("rebound_ratio_e" + std::to_string(static_cast<int>(100 * e)), std::to_string(rebound / impact));
    EXPECT_NEAR(rebound / impact, e, 0.05) << solverName(GetParam()) << ", e = " << e;
  }
}

TEST_P(BothSolvers, TowerOfTenCubesStandsStill) {
  // Ten unit cubes, 1 mm gaps and 1 cm alternating offsets, sleeping off: after 2 s of settling no
  // cube moves 1 mm in 60 s (issue 22). The penalty solver needs 500 s of a core for it: in CI it is
  // test_stacks_at_rest's TowerOfTenCubesStandsStillWithoutSleeping, here only in the slow variant.
  if (!kLong && GetParam() == ContactSolverKind::Penalty) GTEST_SKIP() << "penalty: test_solvers_long";
  CubeScene s(concrete(0.3, 0.6), settingsFor(GetParam()));
  s.addFloor();
  std::vector<BodyId> blocks;
  for (int k = 0; k < 10; ++k) blocks.push_back(s.addCube(Vec3(k % 2 == 0 ? 0.0 : 0.01, 0.0, 0.5 + k * 1.001)));
  s.world.advanceTo(2.0);
  std::vector<Vec3> start;
  for (BodyId b : blocks) start.push_back(s.world.bodies().position(b));
  s.world.advanceTo(62.0);
  double largest = 0.0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    largest = std::max(largest, (s.world.bodies().position(blocks[i]) - start[i]).norm());
  }
  RecordProperty("largest_move_m", std::to_string(largest));
  EXPECT_LT(largest, 1e-3) << solverName(GetParam());
  EXPECT_GT(s.world.bodies().position(blocks.back()).z(), 9.4) << "the tower stands";
}

TEST_P(BothSolvers, MassRatio100StackRests) {
  // The 4.64 m cube (100 x the mass) balanced on the 1 m cube: after 5 s of settling neither moves
  // 1 mm in 10 s and the heavy one stays upright.
  const double big = std::cbrt(100.0);
  CubeScene s(concrete(0.3, 0.6), settingsFor(GetParam()));
  s.addFloor();
  const BodyId light = s.addCube(Vec3(0, 0, 0.5));
  const BodyId heavy = s.addCube(Vec3(0, 0, 1.0 + 0.5 * big), Quat::Identity(), Vec3::Zero(), big);
  s.world.advanceTo(5.0);
  const Vec3 l0 = s.world.bodies().position(light), h0 = s.world.bodies().position(heavy);
  s.world.advanceTo(15.0);
  const double moved = std::max((s.world.bodies().position(light) - l0).norm(),
                                (s.world.bodies().position(heavy) - h0).norm());
  RecordProperty("largest_move_m", std::to_string(moved));
  EXPECT_LT(moved, 1e-3) << solverName(GetParam());
  EXPECT_NEAR(s.world.bodies().position(heavy).z(), 1.0 + 0.5 * big, 0.01) << "the heavy cube stays on top";
}

/// Six Core-Locs (Dn 1 m) dropped in a cluster onto a floor: the state after `seconds`, and the
/// body-pair directions served by near-sample lists on the way.
std::pair<std::vector<double>, std::size_t> dropCoreLocs(ContactSolverKind kind, double slackPerDn, double seconds) {
  WorldSettings settings = settingsFor(kind);
  settings.sampleListSlackPerDn = slackPerDn;
  World world(settings);
  const MaterialId m = world.addMaterial(concrete(0.3, 0.6));
  const ShapeId shape = world.addShape("coreloc", test::unitShape("coreloc")); // one mesh for both runs
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), m});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 6; ++k) {
    simulation::BodySpec b;
    b.shape = shape;
    b.material = m;
    // Two columns of three, 2.2 m apart (a Core-Loc of Dn 1 m spans about 2 m), thrown at each
    // other at 1.5 m/s so that they collide in the air and tumble together on the floor.
    b.position = Vec3(2.2 * (k % 2), 0.3 * (k / 2), 1.1 + 2.2 * (k / 2));
    b.velocity = Vec3(k % 2 == 0 ? 1.5 : -1.5, 0.0, 0.0);
    b.orientation = Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    world.addBody(b);
  }
  std::size_t reuses = 0;
  while (world.time() < seconds) {
    world.step();
    reuses += world.lastStep().sampleListReuses;
  }
  return {stateOf(world), reuses};
}

TEST_P(BothSolvers, NearSampleListsLeaveTheStateBitIdentical) {
  // The lists are exact (contact/NarrowPhase.hpp): with and without them a tumbling Core-Loc pile
  // ends in the same bits, and the lists served most of the pair directions on the way.
  const double t = GetParam() == ContactSolverKind::Penalty ? 0.4 : 1.5;
  const auto [with, reuses] = dropCoreLocs(GetParam(), 0.05, t);
  const auto [without, none] = dropCoreLocs(GetParam(), 0.0, t);
  EXPECT_EQ(none, 0u);
  EXPECT_GT(reuses, 100u) << "the lists must serve for the test to test them";
  ASSERT_EQ(with.size(), without.size());
  for (std::size_t i = 0; i < with.size(); ++i) EXPECT_EQ(with[i], without[i]) << "state entry " << i;
}

TEST_P(BothSolvers, BodyDampingDecaysMotionAsTheExponentialAndSetsTheTerminalSpeed) {
  // body_damping (seed 001's PhysX damping, 0.9 1/s, "to model air and water resistance"):
  //  - without gravity a cube moving at 1 m/s and spinning at 2 rad/s keeps exp(-c t) of both after
  //    1 s, to round-off (the decay is exact per step, so any step gives exp(-c n dt));
  //  - falling, it reaches the terminal speed g / c; the split (step, then decay) gives
  //    g dt e / (1 - e), e = exp(-c dt): within 0.5 % of g / c at the solvers' steps (c dt / 2).
  WorldSettings settings = settingsFor(GetParam());
  settings.bodyDamping = {0.9, 0.6};
  settings.gravity = Vec3::Zero();
  {
    CubeScene s(concrete(0.3, 0.5), settings);
    simulation::BodySpec b;
    b.shape = s.cube;
    b.material = s.material;
    b.velocity = Vec3(1.0, 0.0, 0.0);
    b.angularVelocity = Vec3(0.0, 0.0, 2.0);
    const BodyId id = s.world.addBody(b);
    const double dt = s.world.timeStep();
    const int steps = static_cast<int>(std::llround(1.0 / dt));
    for (int i = 0; i < steps; ++i) s.world.step();
    const double t = steps * dt;
    EXPECT_NEAR(s.world.bodies().velocity(id).x(), std::exp(-0.9 * t), 1e-12) << solverName(GetParam());
    EXPECT_NEAR(s.world.bodies().worldAngularVelocity(id).z(), 2.0 * std::exp(-0.6 * t), 1e-12);
  }
  settings.gravity = Vec3(0.0, 0.0, -kG);
  CubeScene s(concrete(0.3, 0.5), settings);
  const BodyId id = s.addCube(Vec3(0.0, 0.0, 0.0));
  s.world.advanceTo(10.0); // 9 decay times
  const double terminal = kG / 0.9;
  EXPECT_NEAR(-s.world.bodies().velocity(id).z(), terminal, 0.005 * terminal) << solverName(GetParam());
}

TEST_P(BothSolvers, SleepingByNeighboursLetsTheFarBodiesOfAnIslandSleep) {
  // Two 1 m cubes stacked on the floor (mu = 0.6) and on them a frictionless 0.5 m cube gliding
  // at 1 cm/s: it never rests (ten times the 1 mm/s of sleep) and passes on its weight alone, so
  // the cubes below come to rest. By island (the default) nothing sleeps, the three touching. By
  // neighbours the bottom cube sleeps (it touches only the resting middle cube and the floor),
  // the middle one stays awake beside the moving top, and the top glides on at its speed.
  for (const SleepScope scope : {SleepScope::Island, SleepScope::Neighbours}) {
    WorldSettings settings = settingsFor(GetParam(), true);
    settings.sleep.scope = scope;
    CubeScene s(concrete(0.1, 0.6), settings);
    s.addFloor();
    const BodyId bottom = s.addCube(Vec3(0.0, 0.0, 0.5));
    const BodyId middle = s.addCube(Vec3(0.0, 0.0, 1.5));
    // Two bodies in contact take the smaller friction: the glider's 0 makes its contact frictionless.
    BodySpec glider;
    glider.shape = s.cube;
    glider.material = s.world.addMaterial(concrete(0.1, 0.0));
    glider.scale = 0.5;
    glider.position = Vec3(-0.2, 0.0, 2.25);
    glider.velocity = Vec3(0.01, 0.0, 0.0);
    const BodyId top = s.world.addBody(glider);
    s.world.advanceTo(3.0);
    const Vec3 bottomAt3 = s.world.bodies().position(bottom);
    s.world.advanceTo(seconds(GetParam(), 8.0, 5.0));
    const std::string tag = fmt::format("{} by {}", solverName(GetParam()),
                                        scope == SleepScope::Island ? "island" : "neighbours");
    EXPECT_TRUE(s.world.bodies().isAwake(top)) << tag << ": the glider never rests";
    EXPECT_TRUE(s.world.bodies().isAwake(middle)) << tag << ": the middle cube touches the moving glider";
    EXPECT_EQ(s.world.bodies().isAwake(bottom), scope == SleepScope::Island) << tag;
    // The glider still glides, at least five times faster than sleep allows (measured 0.9 cm/s
    // penalty, 1.5 cm/s constraint: the settled cube's top is not exactly level; the same by both
    // scopes to 3e-4 m/s).
    EXPECT_GT(s.world.bodies().velocity(top).x(), 0.005) << tag;
    // The bottom cube does not move, asleep or awake (its friction springs' stretch aside).
    EXPECT_LT((s.world.bodies().position(bottom) - bottomAt3).norm(), 1e-5) << tag;
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, BothSolvers,
                         ::testing::Values(ContactSolverKind::Penalty, ContactSolverKind::Constraint), paramName);

// ---------------------------------------------------------------------------------------------
// The constraint solver's own guarantees.
// ---------------------------------------------------------------------------------------------

TEST(ConstraintSolver, StepsOutsideTheMeasuredRangeAreRefusedWithTheLimit) {
  for (double dt : {0.1, 1e-8}) {
    WorldSettings settings = settingsFor(ContactSolverKind::Constraint);
    settings.timeStep = dt;
    CubeScene s(concrete(0.3, 0.5), settings);
    s.addFloor();
    s.addCube(Vec3(0, 0, 1));
    try {
      s.world.step();
      ADD_FAILURE() << "a step of " << dt << " s must be refused";
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("0.03333"), std::string::npos) << e.what();
    }
  }
}

TEST(ConstraintSolver, LargestStepDropsAndRestsACube) {
  // At the largest step (1/30 s) a cube dropped from 2 m lands, stops and stays: at 3 s its speed is
  // below 1 mm/s and it sits on its face within 2 mm.
  WorldSettings settings = settingsFor(ContactSolverKind::Constraint);
  settings.timeStep = kMaxConstraintStep;
  CubeScene s(concrete(0.05, 0.6), settings);
  s.addFloor();
  const BodyId b = s.addCube(Vec3(0, 0, 2.5));
  s.world.advanceTo(3.0);
  EXPECT_LT(s.world.bodies().velocity(b).norm(), 1e-3);
  EXPECT_NEAR(s.world.bodies().position(b).z(), 0.5, 2e-3);
}

TEST(ConstraintSolver, SmallestUsefulStepHoldsTheRestingState) {
  // dt = 1e-5 s (500 x below the default): a resting cube stays within 0.1 mm over 0.2 s.
  WorldSettings settings = settingsFor(ContactSolverKind::Constraint);
  settings.timeStep = 1e-5;
  CubeScene s(concrete(0.3, 0.6), settings);
  s.addFloor();
  const BodyId b = s.addCube(Vec3(0, 0, 0.5));
  s.world.advanceTo(0.2);
  EXPECT_NEAR(s.world.bodies().position(b).z(), 0.5, 1e-4);
}

namespace {

/// A loose pile of 18 cubes (3 x 3 x 2, small random tilts) under the constraint solver.
/// Constraint-solver settings with friction anchors on (contact.constraint.friction_anchors).
WorldSettings withAnchors(bool sleep = false) {
  WorldSettings s = settingsFor(ContactSolverKind::Constraint, sleep);
  s.constraint.frictionAnchors = true;
  return s;
}

/// The pile's settings: the constraint solver, with or without friction anchors, the default
/// reuse distance unless `reuse` >= 0.
WorldSettings pileSettings(bool sleep, bool anchors, double reuse) {
  WorldSettings s = anchors ? withAnchors(sleep) : settingsFor(ContactSolverKind::Constraint, sleep);
  if (reuse >= 0.0) s.constraint.reuseDistance = reuse;
  return s;
}

struct Pile : CubeScene {
  explicit Pile(bool sleep = false, bool anchors = false, double reuse = -1.0)
      : CubeScene(concrete(0.3, 0.6), pileSettings(sleep, anchors, reuse)) {
    addFloor();
    std::mt19937_64 rng(11);
    for (int k = 0; k < 2; ++k) {
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
          const double tilt = 0.2 * ((rng() >> 11) * 0x1.0p-53 - 0.5);
          addCube(Vec3(1.05 * i + 0.3 * k, 1.05 * j, 0.52 + 1.04 * k),
              Quat(Eigen::AngleAxisd(tilt, Vec3(1, 1, 0).normalized())));
        }
      }
    }
  }
  [[nodiscard]] std::vector<double> state() const { return stateOf(world); }
};

/// The pile run 200 steps straight, and run 100, written to a checkpoint file, read into a fresh
/// pile and run 100 more (the restart tests).
struct RestartCheck {
  std::vector<double> straight, restarted;
  std::size_t reusedAtCheckpoint = 0;
  bool cacheSaved = false;
};
RestartCheck restartThroughAFile(bool anchors) {
  RestartCheck r;
  Pile straight(false, anchors);
  for (int n = 0; n < 100; ++n) straight.world.step();
  r.reusedAtCheckpoint = straight.world.lastStep().reusedPairs;
  Checkpoint c;
  c.state = straight.world.captureState();
  r.cacheSaved = !c.state.manifoldCache.empty();
  const auto path = std::filesystem::temp_directory_path() /
                    (anchors ? "armour-test-constraint-anchors-restart.nc" : "armour-test-constraint-restart.nc");
  writeCheckpoint(path, c);
  for (int n = 0; n < 100; ++n) straight.world.step();
  Pile restarted(false, anchors);
  restarted.world.restoreState(readCheckpoint(path).state);
  std::filesystem::remove(path);
  for (int n = 0; n < 100; ++n) restarted.world.step();
  r.straight = straight.state();
  r.restarted = restarted.state();
  return r;
}

std::vector<double> runPile(int threads) {
  omp_set_num_threads(threads);
  Pile p;
  for (int n = 0; n < 200; ++n) p.world.step();
  EXPECT_GT(p.world.lastStep().contactPoints, 30u) << "the pile must be in contact to test anything";
  return p.state();
}

} // namespace

TEST(ConstraintSolver, OneAndTwoThreadsGiveBitIdenticalStates) {
  const int saved = omp_get_max_threads();
  const auto one = runPile(1);
  const auto two = runPile(2);
  omp_set_num_threads(saved);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i], two[i]) << "state entry " << i;
}

TEST(ConstraintSolver, RestartFromACheckpointIsBitIdentical) {
  // 100 steps, a checkpoint file, 100 more; against a fresh pile restored from the file and run
  // 100 steps: the same bits (the warm-start impulses are in the checkpoint).
  // Manifold reuse is on by default: its cache must be in the checkpoint for the bits to agree.
  const RestartCheck r = restartThroughAFile(false);
  ASSERT_GT(r.reusedAtCheckpoint, 0u) << "the test must restart with reused manifolds";
  ASSERT_TRUE(r.cacheSaved);
  ASSERT_EQ(r.straight.size(), r.restarted.size());
  for (std::size_t i = 0; i < r.straight.size(); ++i) EXPECT_EQ(r.straight[i], r.restarted[i]) << "state entry " << i;
}

TEST(ConstraintSolver, FrictionAnchorsHoldBelowTheFrictionAngleSlideAboveItAndRestartBitIdentical) {
  // contact.constraint.friction_anchors (off by default; docs/theory.md, "Friction"): the anchors
  // may not hold a block that must slide, nor let one creep that must stick, and their slips are
  // in the checkpoint (contact_stretch): a restart gives the same bits.
  const double below = 25.0 * std::numbers::pi / 180.0, above = 35.0 * std::numbers::pi / 180.0;
  Slope holds(withAnchors(), below, 0.75); // tan 25 deg = 0.466 < 0.75
  holds.world.advanceTo(1.0);
  const double x0 = holds.along();
  holds.world.advanceTo(61.0);
  EXPECT_LT(std::abs(holds.along() - x0), 1e-4) << "drift over 60 s (m)";
  Slope slides(withAnchors(), above, 0.4); // a = g (sin 35 - 0.4 cos 35) = 2.413 m/s^2
  slides.world.advanceTo(0.5);
  const double v0 = slides.world.bodies().velocity(slides.block).dot(slides.downhill);
  slides.world.advanceTo(1.5);
  const double v1 = slides.world.bodies().velocity(slides.block).dot(slides.downhill);
  const double expected = kG * (std::sin(above) - 0.4 * std::cos(above));
  EXPECT_NEAR(v1 - v0, expected, 0.02 * expected);

  const RestartCheck r = restartThroughAFile(true);
  ASSERT_EQ(r.straight.size(), r.restarted.size());
  for (std::size_t i = 0; i < r.straight.size(); ++i) EXPECT_EQ(r.straight[i], r.restarted[i]) << "state entry " << i;
  const auto& a = r.straight;
  Pile without;
  for (int n = 0; n < 200; ++n) without.world.step();
  EXPECT_NE(without.state(), a) << "the anchors must act on the pile (else this test checks nothing)";
}

TEST(ConstraintSolver, ManifoldReuseKeepsASettledPileStill) {
  // contact.constraint.reuse_distance (0.001 Dn by default; docs/theory.md, "Manifold reuse"): a
  // pair that has moved less than that since its last full narrow phase keeps its patches, their
  // depths moved with the relative motion. The 18-cube pile, settled for 3 s with full narrow
  // phases (sleeping off), then 3 s more: with reuse most pairs keep their patches and no cube
  // moves 0.1 mm (measured 0.03 mm). With a full narrow phase at every step the same pile creeps
  // 5.3 mm in those 3 s (new samples entering and leaving the margin jolt the patches); that is
  // recorded, not asserted.
  Pile settle(false, false, 0.0);
  settle.world.advanceTo(3.0);
  const WorldState settled = settle.world.captureState();
  Pile reusing;
  Pile full(false, false, 0.0);
  reusing.world.restoreState(settled);
  full.world.restoreState(settled);
  std::size_t reused = 0, pairs = 0;
  while (reusing.world.time() < 6.0 - 1e-9) {
    reusing.world.step();
    full.world.step();
    reused += reusing.world.lastStep().reusedPairs;
    pairs += reusing.world.lastStep().candidatePairs;
    EXPECT_EQ(full.world.lastStep().reusedPairs, 0u);
  }
  EXPECT_GT(reused, pairs / 2) << "most pairs of a resting pile reuse their patches";
  double movedFull = 0.0, movedReusing = 0.0;
  for (BodyId b = 0; b < reusing.world.bodies().size(); ++b) {
    movedFull = std::max(movedFull, (full.world.bodies().position(b) - settled.bodies[b].position).norm());
    movedReusing = std::max(movedReusing, (reusing.world.bodies().position(b) - settled.bodies[b].position).norm());
  }
  RecordProperty("moved_with_reuse_m", std::to_string(movedReusing));
  RecordProperty("moved_without_reuse_m", std::to_string(movedFull));
  EXPECT_LT(movedReusing, 1e-4) << "largest movement of a cube in 3 s at rest (m)";
}

TEST(ConstraintSolver, AUnitRestingUnderAHeavyLoadKeepsItsManifold) {
  // Reuse by the margin (docs/theory.md, "Manifold reuse"): a pair keeps its patches while its
  // step's travel bound plus r stays below the margin they were found with. A 1 m cube resting on
  // the floor under 200 m/s^2 (ours: a storm's load on a unit, 20 g) has a travel bound of
  // 1.1 dt (g dt) = 5.5 mm at 1/200 s, above r = 1 mm (session 18's rule, travel < r, never
  // reused it) and far below the margin of 50 mm. At rest it keeps its patches at every step
  // and stays where it is: no drift above 1e-7 m in 1 s, its overlap rho g Dn / E_p = 0.48 mm
  // within 1 % (the penalty law's spring, which the constraint solver's points are).
  WorldSettings settings = settingsFor(ContactSolverKind::Constraint);
  settings.gravity = Vec3(0.0, 0.0, -200.0);
  CubeScene s(concrete(0.1, 0.6), settings);
  s.addFloor();
  const BodyId b = s.addCube(Vec3(0, 0, 0.5));
  s.world.advanceTo(1.0);
  const Vec3 settled = s.world.bodies().position(b);
  std::size_t reused = 0, steps = 0;
  while (s.world.time() < 2.0 - 1e-9) {
    s.world.step();
    reused += s.world.lastStep().reusedPairs;
    ++steps;
    ASSERT_EQ(s.world.lastStep().candidatePairs, 1u);
  }
  EXPECT_EQ(reused, steps) << "the resting cube's one pair keeps its patches at every step";
  EXPECT_LT((s.world.bodies().position(b) - settled).norm(), 1e-7);
  const double overlap = 2400.0 * 200.0 * 1.0 / Material{}.penaltyModulus; // the defaults: 2400 kg/m^3, 1e9 Pa
  EXPECT_NEAR(0.5 - settled.z(), overlap, 0.01 * overlap);
}

TEST(ConstraintSolver, ADamagedManifoldCacheIsRefusedByName) {
  Pile p;
  for (int n = 0; n < 50; ++n) p.world.step();
  WorldState s = p.world.captureState();
  ASSERT_GT(s.manifoldCache.size(), 10u);
  s.manifoldCache.resize(s.manifoldCache.size() - 3);
  Pile q;
  try {
    q.world.restoreState(s);
    FAIL() << "a truncated manifold cache must be refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("manifold_cache"), std::string::npos) << e.what();
  }
}

TEST(ConstraintSolver, WarmStartCarriesTheRestingLoad) {
  // A cube at rest on the floor: the stored normal impulses per substep sum to its weight times
  // the substep (within 1 %), so the next step starts from the right force.
  CubeScene s(concrete(0.3, 0.6), settingsFor(ContactSolverKind::Constraint));
  s.addFloor();
  const BodyId b = s.addCube(Vec3(0, 0, 0.5));
  s.world.setRecordContacts(true);
  s.world.advanceTo(1.0);
  ASSERT_EQ(s.world.contactPatches().size(), 1u);
  const double weight = s.world.bodies().info(b).mass * kG;
  EXPECT_NEAR(s.world.contactPatches()[0].normalForce, weight, 0.01 * weight);
  EXPECT_LE(s.world.contactPatches()[0].points, 4) << "reduced to at most 4 points per patch";
}

TEST(ConstraintSolver, SmallPilesOfConcaveUnitsOnAFloorComeToRest) {
  // Three Dolos, or three Core-Locs, of 1 m^3 dropped on a floor in random attitudes (four scenes
  // each, sleeping off) must come to rest: the largest kinetic energy of any unit between 30 and
  // 40 s below 1 mJ (a 2.4 t unit at 1 mm/s). Before each kept point carried its samples' force
  // (session 14), a unit standing on a leg rocked for ever between neighbouring samples in a limit
  // cycle: 60-72 J in the four Dolos scenes, 48-98 J in the four Core-Loc ones (docs/benchmarks.md,
  // "Kept points carry their samples' force"; bench_solver at-rest, the same scenes); now 1e-8 J or less.
  const std::pair<const char*, std::vector<unsigned>> cases[] = {{"dolos", {100u, 101u, 103u, 104u}},
                                                                 {"coreloc", {100u, 101u, 102u, 103u}}};
  for (const auto& [name, seeds] : cases) {
    for (const unsigned seed : seeds) {
      World w(settingsFor(ContactSolverKind::Constraint));
      const MaterialId m = w.addMaterial(concrete(0.3, 0.75)); // 2400 kg/m^3, as bench_solver's
      test::dropOnFloor(w, w.addShape(name, test::unitShape(name)), m, 3, seed);
      w.advanceTo(30.0);
      double largest = 0.0;
      while (w.time() < 40.0 - 1e-9) {
        w.step();
        largest = std::max(largest, test::largestKineticEnergy(w));
      }
      EXPECT_LT(largest, 1e-3) << name << " scene " << seed << ": a unit still moves after 30 s (J)";
    }
  }
}

TEST(Restitution, EdgeAndCornerDropsReboundWithTheTargetRestitution) {
  // Issue 23 item 10: a unit cube dropped at 3.1 m/s on an edge (turned 45 degrees about x) and on a
  // corner (its diagonal vertical), the centre of mass above the contact, so that rigid-body
  // impact theory gives the centre's rebound speed as e times its impact speed, as for a face drop.
  // For each contact model and solver, within 0.025 of e. An edge's or a corner's penalty contact
  // stiffens with its depth (F = K d / p, p = 2 and 3), so the penalty laws take the damping ratio
  // for the contact's exponent p, read from its points (contactExponent). Before (session 14, one
  // damping ratio for a face), the fdem corner rebounded at 0.434 and the level-set corner at 0.465
  // for e = 0.5; now 0.498 and 0.497 (docs/validation.md, "Restitution at edges and corners").
  struct Case {
    const char* name;
    ContactSolverKind solver;
    ContactModel model;
  };
  const Case cases[] = {{"penalty, level set", ContactSolverKind::Penalty, ContactModel::LevelSet},
                        {"penalty, fdem", ContactSolverKind::Penalty, ContactModel::Fdem},
                        {"constraint", ContactSolverKind::Constraint, ContactModel::LevelSet}};
  const Quat edge(Eigen::AngleAxisd(0.25 * std::numbers::pi, Vec3::UnitX()));
  const Quat corner = Quat::FromTwoVectors(Vec3(1.0, 1.0, 1.0).normalized(), -Vec3::UnitZ());
  for (const Case& c : cases) {
    for (const double e : {0.05, 0.5, 0.9}) {
      for (const auto& [what, q, depth] : {std::tuple{"edge", edge, 0.5 * std::numbers::sqrt2},
                                           std::tuple{"corner", corner, 0.5 * std::numbers::sqrt3}}) {
        WorldSettings settings = settingsFor(c.solver);
        settings.contactModel = c.model;
        CubeScene s(concrete(e, 0.5), settings);
        s.addFloor();
        const BodyId b = s.addCube(Vec3(0, 0, depth + 0.5), q); // the lowest edge or corner 0.5 m up
        // A window of 0.2 s: a corner contact lasts longer than a face contact.
        const auto [impact, rebound] = measureRebound(s.world, b, 0.2, 1.5);
        ASSERT_GT(impact, 3.0) << c.name << ", " << what << ", e = " << e;
        EXPECT_NEAR(rebound / impact, e, 0.025) << c.name << ", " << what << ", e = " << e;
        RecordProperty(std::string(c.model == ContactModel::Fdem ? "fdem_" : "") + solverName(c.solver) + "_" + what +
                           "_e" + std::to_string(static_cast<int>(100 * e)),
                       std::to_string(rebound / impact));
      }
    }
  }
}

TEST(Restitution, OffCentreImpactsOfBlocksAndCoreLocsLoseTheEnergyOfRigidBodyImpactTheory) {
  // Issue 23 item 10, off the centre: a cube turned so that one corner lands first with its centre
  // of mass beside it (25 degrees about x, then 15 about y), and Core-Locs of 1 m^3 in three random
  // attitudes, dropped frictionless at 3.1 m/s. Rigid-body impact theory: the impact keeps e^2 of
  // the energy m_eff v_n^2 / 2 of the contact point's normal motion (energeticRestitution), the
  // lever arm entering through m_eff. The theory is the limit of a short contact: asserted within
  // 0.05 of e with the penalty contact 100 times stiffer than the default (E_p = 1e11 Pa), and with
  // the constraint solver at a step of 1 ms. At the defaults (E_p = 1e9 Pa, 1/200 s) the measured
  // departures are larger and held within 0.2 (session 15: the corner of the cube keeps 0.40,
  // fdem 0.33, at e = 0.5; the constraint solver 0.476, first order in its step:
  // docs/validation.md, "Off-centre impacts"). Before the penalty dashpot took the effective mass
  // at the contact, rotation included, the stiff runs gave 0.30 to 0.42 at e = 0.5.
  // e = 0.05 is not asserted here: e^2 = 0.25 % of the energy is below the measure's resolution.
  struct Case {
    const char* name;
    ContactSolverKind solver;
    ContactModel model;
    bool converged; // stiff contact or short step: the theory's limit
  };
  const Case cases[] = {{"penalty, level set", ContactSolverKind::Penalty, ContactModel::LevelSet, true},
                        {"penalty, fdem", ContactSolverKind::Penalty, ContactModel::Fdem, true},
                        {"constraint", ContactSolverKind::Constraint, ContactModel::LevelSet, true},
                        {"penalty, level set", ContactSolverKind::Penalty, ContactModel::LevelSet, false},
                        {"penalty, fdem", ContactSolverKind::Penalty, ContactModel::Fdem, false},
                        {"constraint", ContactSolverKind::Constraint, ContactModel::LevelSet, false}};
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<std::string, Quat>> drops = {
      {"cube", Quat(Eigen::AngleAxisd(0.2618, Vec3::UnitY()) * Eigen::AngleAxisd(0.4363, Vec3::UnitX()))}};
  for (int k = 0; k < 3; ++k) {
    drops.emplace_back("coreloc", Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized())));
  }
  for (const Case& c : cases) {
    for (const double e : {0.5, 0.9}) {
      for (std::size_t k = 0; k < drops.size(); ++k) {
        const auto& [shape, q] = drops[k];
        WorldSettings settings = settingsFor(c.solver);
        settings.contactModel = c.model;
        Material material = concrete(e, 0.0);
        if (c.converged && c.solver == ContactSolverKind::Constraint) settings.timeStep = 1.0e-3;
        if (c.converged && c.solver == ContactSolverKind::Penalty) material.penaltyModulus = 1.0e11;
        World w(settings);
        const MaterialId m = w.addMaterial(material);
        w.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), m});
        BodySpec spec;
        spec.shape = w.addShape(shape, test::unitShape(shape));
        spec.material = m;
        spec.orientation = q;
        spec.position = Vec3(0.0, 0.0, 10.0);
        const BodyId b = w.addBody(spec);
        double lowest = 0.0; // of the body's surface below its centre, in this attitude
        for (const Vec3& v : w.shape(spec.shape).mesh.vertices) {
          lowest = std::min(lowest, (w.bodies().orientation(b) * v).z());
        }
        w.bodies().setPosition(b, Vec3(0.0, 0.0, 0.5 - lowest)); // the lowest point 0.5 m up
        w.invalidateBoxes();
        const double measured = energeticRestitution(w, b, 0.3, 1.5);
        const std::string tag = std::string(c.name) + (c.converged ? " (stiff or short step)" : " (defaults)") + ", " +
                                shape + " " + std::to_string(k) + ", e = " + std::to_string(e);
        EXPECT_NEAR(measured, e, c.converged ? 0.05 : 0.2) << tag;
        RecordProperty(std::string(c.converged ? "converged_" : "defaults_") +
                           (c.model == ContactModel::Fdem ? "fdem_" : "") + solverName(c.solver) + "_" + shape +
                           std::to_string(k) + "_e" + std::to_string(static_cast<int>(100 * e)),
                       std::to_string(measured));
      }
    }
  }
}
