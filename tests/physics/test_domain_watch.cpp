// SPDX-License-Identifier: GPL-3.0-or-later
// Bodies that leave the static domain (simulation/DomainWatch.hpp). A frictionless cube slides
// along a slope's level crest at a constant speed v0 (no force acts along it), so its centroid
// passes the domain's onshore bound x_max at t* = (x_max - x0) / v0: the watch reports it at the
// first step after t*, once, and the cube then falls off the crest's cut edge onto the seabed.

#include "simulation/DomainWatch.hpp"
#include "io/SceneReader.hpp"
#include "simulation/SceneBuilder.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace armour;
using namespace armour::simulation;

TEST(DomainWatch, ACubeSlidingOffTheCrestIsReportedOnceAtItsExitTime) {
  // tests/data/scenes/crest-slide.yaml (ours): a 1:2 slope 1 m high (crest edge at x = 2 m), a
  // 0.5 m cube resting on the crest at x = 3 m moving onshore at 4 m/s; friction 0.
  const io::Scene scene = io::readScene(std::filesystem::path(ARMOUR_TEST_DATA) / "scenes" / "crest-slide.yaml");
  BuiltScene built = buildWorld(scene);
  World& world = *built.world;
  DomainWatch watch(built.domain, world);
  ASSERT_EQ(watch.outsideCount(), 0u);
  const double x0 = 3.0, v0 = 4.0;
  const double exitTime = (built.domain.xMax - x0) / v0;
  ASSERT_GT(exitTime, 0.1); // the domain reaches past the body by its margin
  std::vector<DomainExit> exits;
  while (world.time() < exitTime + 0.5) {
    world.step();
    for (const DomainExit& e : watch.update(world)) exits.push_back(e);
  }
  ASSERT_EQ(exits.size(), 1u);
  // The exit is the first step after t*: within one step of it (the sliding speed is v0 to the
  // contact's round-off: 1e-3 m/s would move t* by 2.5e-4 of it).
  EXPECT_GE(exits[0].time, exitTime - 1e-3 * exitTime);
  EXPECT_LE(exits[0].time, exitTime + world.timeStep() + 1e-3 * exitTime);
  EXPECT_GT(exits[0].position.x(), built.domain.xMax);
  EXPECT_EQ(watch.outsideCount(), 1u);
  // Off the cut edge it falls: 0.5 s after the exit it is well below the crest top (z = 1 m).
  const BodyId b = built.bodyIndexOfSceneBody[0];
  EXPECT_LT(world.bodies().position(b).z(), 0.5);
  EXPECT_NE(watch.describe(world, exits[0]).find("body 'cube' left the static domain"), std::string::npos)
      << watch.describe(world, exits[0]);
  // A watch made after the exit (a restart) counts it as outside without a new exit.
  DomainWatch later(built.domain, world);
  EXPECT_EQ(later.outsideCount(), 1u);
  world.step();
  EXPECT_TRUE(later.update(world).empty());
}
