// SPDX-License-Identifier: GPL-3.0-or-later
// The external-load stage of the World (simulation/LoadStage.hpp), with simple loads whose effect
// is known exactly:
//  - a constant force on a free body: the velocity Verlet step integrates it exactly, and the
//    World's trapezoidal work W = sum dt/2 (F.v_n + F.v_n+1) equals the kinetic energy gained to
//    round-off (for a constant force the trapezoid is exact: dt/2 (v_n + v_n+1) = x_n+1 - x_n);
//  - a load that cancels gravity holds a body still: the stage's force really reaches the body;
//  - a sleeping cube on a floor wakes when a load appears and not when it stays the same;
//  - an oscillating load doing work does not trip the energy guard, while the same energy rise
//    without the work being accounted would (the guard is not simply off);
//  - a stage with state (its time of last update) restarts bit for bit through captureState /
//    restoreState, and a checkpoint with another stage list is refused.

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/World.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <unistd.h>
#include <cmath>
#include <memory>
#include <numbers>

using namespace armour;
using namespace armour::simulation;

namespace {

/// A world with one material and a cube of 1 m^3 (2400 kg).
struct Scene {
  World world;
  MaterialId material = 0;
  ShapeId cube = 0;
  explicit Scene(WorldSettings settings = {}) : world(settings) {
    material = world.addMaterial(Material{});
    geometry::ShapeRequest r;
    r.volume = 1.0;
    cube = world.addShape("cube", geometry::makeShape("cube", r));
  }
  BodyId addCube(const Vec3& position) {
    BodySpec b;
    b.shape = cube;
    b.material = material;
    b.position = position;
    return world.addBody(b);
  }
};

/// F(t) = base + amplitude sin(omega t) on every body; remembers the last time it saw.
class SineLoad : public LoadStage {
public:
  SineLoad(const Vec3& base, const Vec3& amplitude, double omega) : base_(base), amplitude_(amplitude), omega_(omega) {}
  std::string name() const override { return "sine"; }
  void apply(const World& world, double time, std::span<Vec3> force, std::span<Vec3> torque) override {
    for (BodyId b = 0; b < world.bodies().size(); ++b) {
      force[b] = base_ + amplitude_ * std::sin(omega_ * time);
      torque[b] = Vec3(0.0, 0.0, 0.1 * amplitude_.norm() * std::cos(omega_ * time));
    }
    ++calls_;
    lastTime_ = time;
  }
  std::vector<double> saveState() const override { return {lastTime_, static_cast<double>(calls_)}; }
  void restoreState(const std::vector<double>& s) override {
    if (s.size() != 2) {
      core::failInput("sine", "state has {} values, expected 2", s.size());
    }
    lastTime_ = s[0];
    calls_ = static_cast<long>(s[1]);
  }
  double lastTime() const { return lastTime_; }

private:
  Vec3 base_, amplitude_;
  double omega_;
  double lastTime_ = -1.0;
  long calls_ = 0;
};

} // namespace

TEST(LoadStages, ConstantForceWorkEqualsKineticEnergyGained) {
  WorldSettings s;
  s.gravity = Vec3::Zero();
  s.timeStep = 2e-4;
  Scene scene(s);
  const BodyId b = scene.addCube(Vec3::Zero());
  const Vec3 f(300.0, -40.0, 120.0);
  scene.world.addLoadStage(std::make_shared<SineLoad>(f, Vec3::Zero(), 0.0));
  for (int i = 0; i < 10000; ++i) {
    scene.world.step();
  }
  const double m = scene.world.bodies().info(b).mass;
  const Vec3 v = scene.world.bodies().velocity(b);
  // Exact: v = F t / m (the Verlet kick integrates a constant force exactly), KE = W.
  EXPECT_NEAR((v - f * scene.world.time() / m).norm(), 0.0, 1e-12 * v.norm());
  const double ke = 0.5 * m * v.squaredNorm();
  EXPECT_NEAR(scene.world.externalWork(), ke, 1e-9 * ke);
  EXPECT_NEAR((scene.world.externalForce(b) - f).norm(), 0.0, 0.0);
}

TEST(LoadStages, LoadCancellingGravityHoldsABodyStill) {
  Scene scene;
  const BodyId b = scene.addCube(Vec3(0, 0, 5));
  const double m = scene.world.bodies().info(b).mass;
  scene.world.addLoadStage(std::make_shared<SineLoad>(Vec3(0, 0, m * 9.81), Vec3::Zero(), 0.0));
  scene.world.advanceTo(2.0);
  EXPECT_LT((scene.world.bodies().position(b) - Vec3(0, 0, 5)).norm(), 1e-12);
}

TEST(LoadStages, SleepingBodyWakesWhenItsLoadChanges) {
  Scene scene;
  scene.world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), scene.material});
  const BodyId b = scene.addCube(Vec3(0, 0, 0.5));
  const double weight = scene.world.bodies().info(b).mass * 9.81;
  // A steady load of 5 % of the weight sideways, well inside friction (mu 0.75): the cube rests.
  auto load = std::make_shared<SineLoad>(Vec3(0.05 * weight, 0, 0), Vec3::Zero(), 0.0);
  scene.world.addLoadStage(load);
  scene.world.advanceTo(2.0);
  ASSERT_EQ(scene.world.bodies().motionType(b), dynamics::MotionType::Sleeping)
      << "the cube under a steady load should fall asleep";
  scene.world.advanceTo(3.0);
  EXPECT_EQ(scene.world.bodies().motionType(b), dynamics::MotionType::Sleeping)
      << "an unchanged load must not wake it";
  // A wave arrives: the load grows past friction. The sleeper must wake and slide.
  auto push = std::make_shared<SineLoad>(Vec3(0.9 * weight, 0, 0), Vec3::Zero(), 0.0);
  scene.world.addLoadStage(push);
  const double x0 = scene.world.bodies().position(b).x();
  scene.world.advanceTo(3.5);
  EXPECT_NE(scene.world.bodies().motionType(b), dynamics::MotionType::Sleeping);
  EXPECT_GT(scene.world.bodies().position(b).x() - x0, 0.01) << "pushed past friction, the cube must slide";
}

TEST(LoadStages, OscillatingWorkDoesNotTripTheEnergyGuard) {
  // A cube on a floor shaken sideways at 1.2 x its friction limit: it slides back and forth, the
  // load doing work in and taking it out each cycle. The guard must see that work.
  Scene scene;
  scene.world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), scene.material});
  const BodyId b = scene.addCube(Vec3(0, 0, 0.5));
  const double weight = scene.world.bodies().info(b).mass * 9.81;
  scene.world.addLoadStage(std::make_shared<SineLoad>(Vec3::Zero(), Vec3(1.2 * 0.75 * weight, 0, 0), 2.0 * std::numbers::pi));
  EXPECT_NO_THROW(scene.world.advanceTo(10.0));
  EXPECT_GT(std::abs(scene.world.externalWork()), 0.0);

  // The guard is not simply off: the same world pushed upward by an unaccounted energy (a
  // velocity kick by hand, no work recorded) trips it.
  Scene other;
  const BodyId c = other.addCube(Vec3(0, 0, 5));
  while (other.world.stepCount() < 60) { // past the guard's first check, which sets its reference
    other.world.step();
  }
  other.world.bodies().setVelocity(c, Vec3(0, 0, 50.0));
  EXPECT_THROW(other.world.advanceTo(1.0), SimulationError);
}

TEST(LoadStages, StageStateRestartsBitForBit) {
  const auto build = [](std::shared_ptr<SineLoad>& load) {
    auto scene = std::make_unique<Scene>();
    scene->world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), scene->material});
    scene->addCube(Vec3(0, 0, 0.6));
    scene->addCube(Vec3(0.3, 0, 1.7));
    load = std::make_shared<SineLoad>(Vec3(2000, 0, 0), Vec3(0, 0, 8000), 3.0);
    scene->world.addLoadStage(load);
    return scene;
  };
  std::shared_ptr<SineLoad> la, lb;
  auto a = build(la);
  a->world.advanceTo(0.5);
  const WorldState saved = a->world.captureState();
  ASSERT_EQ(saved.loadStages.size(), 1u);
  a->world.advanceTo(1.0);
  auto b = build(lb);
  b->world.restoreState(saved);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(lb->lastTime()), std::bit_cast<std::uint64_t>(saved.loadStages[0].second[0]));

  // Through checkpoint.nc: the stage states, external loads and sleep loads survive exactly.
  const auto file = std::filesystem::temp_directory_path() / ("armour_test_load_stages_" + std::to_string(::getpid()) + ".nc");
  Checkpoint c;
  c.state = saved;
  writeCheckpoint(file, c);
  const Checkpoint back = readCheckpoint(file);
  std::filesystem::remove(file);
  ASSERT_EQ(back.state.loadStages.size(), 1u);
  EXPECT_EQ(back.state.loadStages[0].first, "sine");
  EXPECT_EQ(back.state.loadStages[0].second, saved.loadStages[0].second);
  for (std::size_t i = 0; i < saved.bodies.size(); ++i) {
    EXPECT_EQ(back.state.bodies[i].externalForce, saved.bodies[i].externalForce);
    EXPECT_EQ(back.state.bodies[i].externalTorque, saved.bodies[i].externalTorque);
    EXPECT_EQ(back.state.bodies[i].sleepLoad, saved.bodies[i].sleepLoad);
  }
  EXPECT_NE(saved.bodies[0].externalForce, Vec3::Zero());
  b->world.advanceTo(1.0);
  for (BodyId i = 0; i < 2; ++i) {
    EXPECT_EQ(a->world.bodies().position(i), b->world.bodies().position(i)) << "body " << i;
    EXPECT_EQ(a->world.bodies().velocity(i), b->world.bodies().velocity(i)) << "body " << i;
  }
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a->world.externalWork()), std::bit_cast<std::uint64_t>(b->world.externalWork()));

  // Another stage list: refused with a message that says so.
  Scene plain;
  plain.world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), plain.material});
  plain.addCube(Vec3(0, 0, 0.6));
  plain.addCube(Vec3(0.3, 0, 1.7));
  try {
    plain.world.restoreState(saved);
    ADD_FAILURE() << "restoring a state with a load stage into a world without one must fail";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("load stages"), std::string::npos) << e.what();
  }
}
