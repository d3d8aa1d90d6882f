// SPDX-License-Identifier: GPL-3.0-or-later
// A pile of 30 dolosse at rest (issue 3): no unit moves more than 1 mm over 60 s simulated after
// settling. Thirty dolosse (V = 1 m^3, 2400 kg, height C = 1.81 m) in a 9.5 m x 3.8 m box with a
// floor, dropped as three lattice layers of ten, with the solver's default sleep settings.
//
// Two tests:
//  - DolosPile.BuiltFromScratchSettlesAndStaysAtRest (slow build test_dolos_pile_long only): the
//    lattice collapses into a pile and settles for 20 s; then no unit may move more than 1 mm over
//    60 s, first with sleeping (as the solver runs: the pile falls asleep, measured at 24.5 s, and
//    must not wake) and then, from that exact state, without sleeping (every contact integrated
//    every step: the friction and normal springs alone must hold the pile). Measured: 0.10 mm
//    with sleeping, 0.48 mm (and 0.95 mrad) without; 35 minutes on 2 busy cores.
//    Why 20 s of settling: a unit resting on few contact points can rock about them for a long
//    time (measured with an earlier build: a middle-layer unit on 8 points swung by +-1 mm and
//    +-5 mrad with a period of about 1 s, its amplitude halving only every 2 s or so; after 10 s of
//    settling it still moved 3.3 mm and turned 13 mrad in the following minute).
//  - DolosPile.SettledPileStaysAtRestWithoutSleeping (both builds): the pile as the first test
//    left it, read from a checkpoint (tests/data/scenes/dolos-pile-30-settled.nc: positions,
//    velocities and the friction springs' stretch) into a world with sleeping off; no unit may
//    move more than 1 mm over the window: 2 s here (measured 2.4e-6 m; 23 000 steps of 87 us with
//    30 awake dolosse, 14 s on 2 idle cores, 28 s on one), 60 s in the slow build. Settling from
//    scratch (about 280 000 steps to sleep) does not fit in a CI test, and a scene file of the
//    settled positions is not a settled state: without the stretch of its friction springs the
//    pile slips again (measured: units moved by 9 to 22 mm and one kept sliding by 17 mm over the
//    following minute).
//
// Regenerate the checkpoint after a change to the contact law, the dolos generator (the contact
// history refers to its sample points) or the checkpoint format, from the source folder (one line):
//   ARMOUR_WRITE_DOLOS_PILE=$PWD/tests/data/scenes/dolos-pile-30-settled.nc
//     build/tests/test_dolos_pile_long --gtest_filter=DolosPile.BuiltFromScratch*

#include "io/SceneReader.hpp"
#include "simulation/WorldState.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/Interpenetration.hpp"
#include "simulation/SceneBuilder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace armour;
using namespace armour::simulation;

namespace {

const std::filesystem::path kScenes = std::filesystem::path(ARMOUR_TEST_DATA) / "scenes";
const std::filesystem::path kSettledPile = kScenes / "dolos-pile-30-settled.nc";

constexpr int kLayers = 3;
constexpr int kPerLayer = 10;             // 5 along x by 2 along y
constexpr double kSpacing = 1.9;          // m between lattice sites: the unit fills a 1.81 m cube
constexpr double kBoxX = 5 * kSpacing;    // m, walls at x = 0 and x = kBoxX
constexpr double kBoxY = 2 * kSpacing;    // m, walls at y = 0 and y = kBoxY
constexpr double kHeight = 1.806;         // m, dolos height C for V = 1 m^3 (V = 0.1691 C^3, waist 0.33)

/// Seconds of rest to watch without sleeping: the issue's 60 s in the slow build, 2 s in the one
/// CI runs.
double restWindow() {
#ifdef ARMOUR_LONG_TESTS
  return 60.0;
#else
  return 2.0;
#endif
}

std::string full(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

std::string sci(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

struct Unit {
  std::string name; ///< layer<k>_<i>: k = the lattice layer it started in (0 = bottom)
  Vec3 position;    ///< centroid (m)
  Quat orientation; ///< natural frame -> world
};

/// The scene: materials, the units, a floor and four walls (default sleep settings). Restitution 0.3 as in the tower test
/// of test_stacks_at_rest: e = 0.05 needs a damping ratio of 1.9 and a 2.6 times smaller step.
std::string pileScene(const std::vector<Unit>& units) {
  std::string s = "description: 30 dolosse dropped as three lattice layers of ten (tests/physics/test_dolos_pile.cpp)\n";
  s += "duration: " + sci(restWindow()) + R"(
materials:
  concrete: {density: 2400, friction: 0.75, restitution: 0.3}
bodies:
)";
  for (const Unit& u : units) {
    const Quat& q = u.orientation;
    s += "  - {name: " + u.name + ", shape: dolos, volume: 1.0, material: concrete, position: [" + full(u.position.x()) +
         ", " + full(u.position.y()) + ", " + full(u.position.z()) + "], orientation: {quaternion: [" + full(q.w()) +
         ", " + full(q.x()) + ", " + full(q.y()) + ", " + full(q.z()) + "]}}\n";
  }
  s += "static:\n  - {type: plane, name: floor, material: concrete, point: [0, 0, 0], normal: [0, 0, 1]}\n";
  s += "  - {type: wall, name: west, material: concrete, axis: x, position: 0, side: min}\n";
  s += "  - {type: wall, name: east, material: concrete, axis: x, position: " + sci(kBoxX) + ", side: max}\n";
  s += "  - {type: wall, name: south, material: concrete, axis: y, position: 0, side: min}\n";
  s += "  - {type: wall, name: north, material: concrete, axis: y, position: " + sci(kBoxY) + ", side: max}\n";
  return s;
}

/// Three lattice layers of ten, 1.9 m apart: a dolos fills a C x C x C box (C = 1.81 m), so each
/// unit takes one of the 24 turns that keep that box axis-aligned plus a random tilt of up to 3 deg
/// (which grows the box by at most 0.09 m): the units start 0.1 m apart and collapse into a pile.
std::vector<Unit> lattice() {
  std::mt19937_64 rng(7);
  const auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  const double pi = std::numbers::pi;
  std::vector<Unit> units;
  for (int k = 0; k < kLayers; ++k) {
    for (int i = 0; i < kPerLayer; ++i) {
      Unit u;
      u.name = "layer" + std::to_string(k) + "_" + std::to_string(i);
      u.position = Vec3(kSpacing * (i % 5 + 0.5), kSpacing * (i / 5 + 0.5), 0.5 * kHeight + 0.02 + k * kSpacing);
      const int turn = static_cast<int>(uniform() * 24);
      const Vec3 tiltAxis = turn / 4 % 3 == 2 ? Vec3::UnitX() : Vec3::UnitY();
      Quat q = Quat(Eigen::AngleAxisd(pi / 2 * (turn % 4), Vec3::UnitZ())) *
               Quat(Eigen::AngleAxisd(turn / 4 % 3 == 0 ? 0.0 : pi / 2, tiltAxis)) *
               Quat(Eigen::AngleAxisd(turn >= 12 ? pi : 0.0, Vec3::UnitX()));
      const Vec3 axis = Vec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5).normalized();
      q = Quat(Eigen::AngleAxisd(3.0 * pi / 180.0 * (2.0 * uniform() - 1.0), axis)) * q;
      u.orientation = q.normalized();
      units.push_back(u);
    }
  }
  return units;
}

/// A built pile and what the tests measure on it.
struct Pile {
  BuiltScene built;
  std::vector<BodyId> bodies; ///< the 30 units
  std::vector<int> layer;     ///< lattice layer each started in

  explicit Pile(const io::Scene& scene) : built(buildWorld(scene)) {
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      bodies.push_back(built.bodyIndexOfSceneBody[i]);
      layer.push_back(scene.bodies[i].name[5] - '0'); // "layer<k>_<i>"
    }
  }
  World& world() { return *built.world; }

  std::vector<Vec3> positions() {
    std::vector<Vec3> p;
    for (BodyId b : bodies) p.push_back(world().bodies().position(b));
    return p;
  }
  /// Largest distance any unit's centroid has moved from `from` (m).
  double largestMove(const std::vector<Vec3>& from) {
    double m = 0.0;
    const auto now = positions();
    for (std::size_t i = 0; i < now.size(); ++i) m = std::max(m, (now[i] - from[i]).norm());
    return m;
  }
  /// Largest rotation of any unit from `from` (rad).
  double largestTurn(const std::vector<Quat>& from) {
    double m = 0.0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      m = std::max(m, world().bodies().orientation(bodies[i]).angularDistance(from[i]));
    }
    return m;
  }
  std::vector<Quat> orientations() {
    std::vector<Quat> q;
    for (BodyId b : bodies) q.push_back(world().bodies().orientation(b));
    return q;
  }
  /// Height of the lowest vertex of each unit (m).
  std::vector<double> lowestPoints() {
    std::vector<double> z;
    for (BodyId b : bodies) {
      const auto& mesh = world().shape(world().bodyShape(b)).mesh; // body frame, unscaled
      double low = 1e9;
      for (const Vec3& v : mesh.vertices) low = std::min(low, world().bodies().toWorld(b, world().bodyScale(b) * v).z());
      z.push_back(low);
    }
    return z;
  }
  /// Continue from `state` with every unit awake (a sleeping unit is at rest: its velocities are zero).
  void restoreAwake(WorldState state) {
    for (BodyState& b : state.bodies) {
      if (b.motion == dynamics::MotionType::Sleeping) b.motion = dynamics::MotionType::Dynamic;
    }
    world().restoreState(state);
  }
  /// Advance to t; a guard rail (SimulationError) fails the test with its message.
  bool advanceTo(double t) {
    try {
      world().advanceTo(t);
      return true;
    } catch (const SimulationError& e) {
      ADD_FAILURE() << "a guard rail stopped the run: " << e.what();
      return false;
    }
  }
};

/// The pile is a pile: every bottom unit stands on the floor, and the top layer lies on the others.
/// Measured on the stored pile: the top units' lowest points 1.63 m above the floor on average
/// (piles of this lattice with other builds: 1.62 to 1.71 m, with 9 or 10 of the 10 off the floor).
/// Asserted: every bottom unit's lowest point below 0.05 m (resting overlaps are 1.6 cm at most),
/// the top layer's mean lowest point more than 1 m above the floor and above every bottom unit's
/// lowest point, and at least 8 top units more than 0.5 m above the floor.
void expectAPile(Pile& pile, const std::string& when) {
  const auto low = pile.lowestPoints();
  double bottomMax = -1e9, topMean = 0.0;
  int topOffFloor = 0;
  for (std::size_t i = 0; i < low.size(); ++i) {
    if (pile.layer[i] == 0) bottomMax = std::max(bottomMax, low[i]);
    if (pile.layer[i] == kLayers - 1) {
      topMean += low[i] / kPerLayer;
      topOffFloor += low[i] > 0.5 ? 1 : 0;
    }
  }
  EXPECT_LT(bottomMax, 0.05) << when << ": the bottom layer must stand on the floor";
  EXPECT_GT(topMean, 1.0) << when << ": the top layer must lie on the others";
  EXPECT_GT(topMean, bottomMax + 1.0) << when;
  EXPECT_GE(topOffFloor, 8) << when << ": top units off the floor";
  ::testing::Test::RecordProperty("top_layer_mean_lowest_point_m", sci(topMean));
}

/// Watch the settled pile for `window` seconds with sleeping on: the assertion of issue 3.
[[maybe_unused]] void expectAtRestWithSleeping(Pile& pile, double settledAt, double window) {
  const auto positions = pile.positions();
  const auto orientations = pile.orientations();
  double asleepAt = -1.0;
  for (int k = 1; k <= static_cast<int>(2.0 * window); ++k) {
    if (!pile.advanceTo(settledAt + 0.5 * k)) return;
    if (asleepAt < 0.0 && pile.world().lastStep().awakeBodies == 0) asleepAt = pile.world().time();
  }
  ::testing::Test::RecordProperty("asleep_at_s", sci(asleepAt));
  const double moved = pile.largestMove(positions);
  const double turned = pile.largestTurn(orientations);
  ::testing::Test::RecordProperty("largest_move_m", sci(moved));
  ::testing::Test::RecordProperty("largest_turn_rad", sci(turned));
  ::testing::Test::RecordProperty("awake_at_end", std::to_string(pile.world().lastStep().awakeBodies));
  // 1 mm over the window for the centroids: 1e-3 Dn (the dolosse are 1 m^3), 200 times below the
  // 0.2 Dn from which seed 000 counts a unit as moved, so a pile at rest cannot add to the damage
  // measure by itself. Turns within 2e-3 rad (as below).
  EXPECT_LT(moved, 1e-3) << "over " << window << " s";
  EXPECT_LT(turned, 2e-3) << "over " << window << " s";
}

/// The pile's scene: the lattice, sleeping as the scene says (on unless `sleep` is false).
io::Scene pileSceneOf(bool sleep) {
  io::Scene scene = io::parseScene(pileScene(lattice()), kScenes, "dolos-pile-lattice.yaml");
  scene.sleep.enabled = sleep;
  return scene;
}

/// Watch the pile for `window` seconds with nothing asleep: the largest move and turn.
void expectHeldWithoutSleeping(Pile& pile, double window, const std::string& tag) {
  const double start = pile.world().time();
  const auto positions = pile.positions();
  const auto orientations = pile.orientations();
  if (!pile.advanceTo(start + window)) return;
  const double moved = pile.largestMove(positions);
  const double turned = pile.largestTurn(orientations);
  ::testing::Test::RecordProperty("largest_move_without_sleep_m" + tag, sci(moved));
  ::testing::Test::RecordProperty("largest_turn_without_sleep_rad" + tag, sci(turned));
  EXPECT_EQ(pile.world().lastStep().awakeBodies, static_cast<std::size_t>(kLayers * kPerLayer));
  // 1 mm for the centroids: 1e-3 Dn, 200 times below seed 000's 0.2 Dn (as above). Turns within
  // 2e-3 rad: a fluke tip 1.2 m from the centroid
  // then moves less than 2.4 mm (measured over 60 s: 0.95e-3 rad, with 0.48 mm at the centroid).
  EXPECT_LT(moved, 1e-3) << "over " << window << " s without sleeping";
  EXPECT_LT(turned, 2e-3) << "over " << window << " s without sleeping";
}

} // namespace

TEST(DolosPile, SettledPileStaysAtRestWithoutSleeping) {
  // The settled pile from its checkpoint (t = 80 s), every unit awake and sleeping off. Every unit
  // must touch something (the pile is a contact network, not units hanging in the air), the pile
  // must be a pile, and no unit may move more than 1 mm over the window (measured 2.4e-6 m and
  // 9e-6 rad over 2 s, 0.48 mm and 0.95e-3 rad over 60 s).
  const io::Scene scene = pileSceneOf(true);
  const Checkpoint checkpoint = readCheckpoint(kSettledPile, {sceneFingerprint(scene), sceneIdentity(scene), 30});
  Pile pile(pileSceneOf(false));
  pile.restoreAwake(checkpoint.state);
  RecordProperty("checkpoint_time_s", sci(pile.world().time()));
  expectAPile(pile, "stored");
  pile.world().step(); // evaluates the contacts
  for (std::size_t i = 0; i < pile.bodies.size(); ++i) {
    EXPECT_GT(pile.world().contactCount(pile.bodies[i]), 0) << scene.bodies[i].name << " touches nothing";
  }
  expectHeldWithoutSleeping(pile, restWindow(), "");
  expectAPile(pile, "after the window");
}

TEST(DolosPile, SettledPileIsNotRefusedAsInterpenetrating) {
  // Issue 23, item 9: the settled pile (30 dolosse resting on each other and the floor, 80 s of
  // settling) shares little volume at its contacts: every pair far below the 1 % of a unit that
  // `check` and `run` refuse (measured: largest 0.035 % of a unit, RecordProperty largest_share), no centroid
  // inside another unit. The pile must pass, or no placed pack would.
  const io::Scene scene = pileSceneOf(true);
  const Checkpoint checkpoint = readCheckpoint(kSettledPile, {sceneFingerprint(scene), sceneIdentity(scene), 30});
  Pile pile(pileSceneOf(false));
  pile.restoreAwake(checkpoint.state);
  const InterpenetrationReport r = measureInterpenetration(pile.world(), pile.built.planes);
  ASSERT_FALSE(r.overlaps.empty()) << "a settled pile touches: some pairs share a little volume";
  RecordProperty("largest_share", sci(r.overlaps.front().fraction));
  RecordProperty("measure_seconds", sci(r.seconds));
  EXPECT_LT(r.overlaps.front().fraction, 0.002) << describeInterpenetration(r);
  EXPECT_TRUE(refusedOverlaps(r).empty()) << describeInterpenetration(r);
  EXPECT_NO_THROW(refuseInterpenetration(r, "dolos-pile"));
}

TEST(DolosPile, ConstraintSolverBuildsThePileAndItsCreepStaysBounded) {
  // Issue 22, part 4, for the constraint solver (its steps are 50 times longer, so the pile is
  // built from scratch here): the lattice collapses, 60 s with sleeping off, then 10 s with every
  // unit awake. The issue's target, 1 mm over 60 s, is NOT met: the pile settles slowly. Measured
  // (session 14, each kept point carrying its samples' force; 10 s windows from 20 to 80 s): the
  // largest move 10.9, 4.8, 2.9, 2.3, 1.3, 1.6 mm and turn 17, 7.3, 4.4, 3.5, 1.9, 1.5 mrad per
  // window, with 6, 5, 4, 4, 4 and 5 of the 30 units moving more than 0.1 mm (docs/benchmarks.md,
  // "Kept points carry their samples' force"). Before (session 13), one bottom unit crept a steady
  // 0.3-0.6 mm per window, but small Dolos piles rocked in limit cycles that this pile missed.
  // This test guards the rate at 60-70 s (3 mm and 5 mrad); the penalty solver's pile
  // (SettledPileStaysAtRestWithoutSleeping) holds the issue's target.
  io::Scene scene = pileSceneOf(false);
  scene.contact.solver = io::ContactSolver::Constraint;
  Pile pile(scene);
  if (!pile.advanceTo(60.0)) return;
  expectAPile(pile, "settled by the constraint solver");
  const auto positions = pile.positions();
  const auto orientations = pile.orientations();
  if (!pile.advanceTo(70.0)) return;
  const double moved = pile.largestMove(positions);
  const double turned = pile.largestTurn(orientations);
  RecordProperty("largest_move_10s_m", sci(moved));
  RecordProperty("largest_turn_10s_rad", sci(turned));
  EXPECT_LT(moved, 3e-3) << "over 10 s without sleeping";
  EXPECT_LT(turned, 5e-3) << "over 10 s without sleeping";
  expectAPile(pile, "after the window");
}

#ifdef ARMOUR_LONG_TESTS
TEST(DolosPile, BuiltFromScratchSettlesAndStaysAtRest) {
  // The lattice collapses into a pile (the units land at up to 5 m/s), 20 s of settling (see the
  // top of this file), then 60 s with sleeping (the pile must be asleep at the end) and 60 s more
  // from that state without sleeping.
  const io::Scene scene = pileSceneOf(true);
  Pile pile(scene);
  const double settle = 20.0; // s
  if (!pile.advanceTo(settle)) return;
  expectAPile(pile, "settled");
  RecordProperty("awake_after_settling", std::to_string(pile.world().lastStep().awakeBodies));
  expectAtRestWithSleeping(pile, settle, 60.0);
  EXPECT_EQ(pile.world().lastStep().awakeBodies, 0u) << "the pile must have fallen asleep";
  expectAPile(pile, "after the window");
  const WorldState settled = pile.world().captureState();
  if (const char* out = std::getenv("ARMOUR_WRITE_DOLOS_PILE")) {
    Checkpoint c;
    c.state = settled;
    c.sceneFingerprint = sceneFingerprint(scene);
    c.sceneIdentity = sceneIdentity(scene);
    for (BodyId b : pile.bodies) c.bodyNames.push_back(pile.world().bodies().info(b).name);
    writeCheckpoint(out, c);
  }

  Pile awake(pileSceneOf(false));
  awake.restoreAwake(settled);
  expectHeldWithoutSleeping(awake, 60.0, "_from_scratch");
  expectAPile(awake, "after 60 s without sleeping");
}
#endif
