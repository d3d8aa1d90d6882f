// SPDX-License-Identifier: GPL-3.0-or-later
// armour analyse on a pack whose answers are known: a tower of three 1 m cubes resting on a floor
// (each on the one below, overlapping by its self-weight's elastic depth). Contact numbers are
// 2 (floor + cube above), 2 (below + above) and 1 (below); unit-unit pairs 2, so the coordination
// number is 2 x 2 / 3; the largest pair force is the bottom contact's, the weight of the three
// cubes; all nose axes (z) are aligned, so P2 = 1 in both forms; against itself every
// displacement is zero, and against a copy moved by 0.5 m along y every unit moved 0.5 Dn.

#include "measure/PackAnalysis.hpp"
#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "simulation/SceneBuilder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace armour;

namespace {

io::Scene settledTower() {
  const std::string yaml = R"(
duration: 1
materials:
  concrete: {density: 2400, friction: 0.7, restitution: 0.1}
bodies:
  - {name: c0, shape: cube, dn: 1, material: concrete, position: [0, 0, 0.5]}
  - {name: c1, shape: cube, dn: 1, material: concrete, position: [0, 0, 1.5]}
  - {name: c2, shape: cube, dn: 1, material: concrete, position: [0, 0, 2.5]}
static:
  - {type: plane, name: floor, material: concrete, point: [0, 0, 0], normal: [0, 0, 1]}
)";
  io::Scene scene = io::parseScene(yaml, std::filesystem::temp_directory_path(), "tower.yaml");
  // Settle it, so the contacts carry the weights.
  simulation::BuiltScene built = simulation::buildWorld(scene);
  built.world->advanceTo(1.0);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const auto b = built.bodyIndexOfSceneBody[i];
    scene.bodies[i].position = built.world->bodies().position(b);
    scene.bodies[i].orientation = built.world->naturalOrientation(b);
  }
  return scene;
}

/// 1 m cubes lying on the face of a 1:2 slope 3 m high (crest edge at x = 6 m), their centroids
/// half a Dn above it (ours): c0 and c1 sqrt(5) m apart up the face, c2 between them 1.2 m along y.
/// The first `count` of them.
io::Scene cubesOnTheFace(std::size_t count) {
  const char* cubes[] = {
      "  - {name: c0, shape: cube, dn: 1, material: concrete, position: [1.776393, 0, 1.447214], orientation: {euler_deg: [0, -26.565051, 0]}}\n",
      "  - {name: c1, shape: cube, dn: 1, material: concrete, position: [3.776393, 0, 2.447214], orientation: {euler_deg: [0, -26.565051, 0]}}\n",
      "  - {name: c2, shape: cube, dn: 1, material: concrete, position: [2.776393, 1.2, 1.947214], orientation: {euler_deg: [0, -26.565051, 0]}}\n"};
  std::string yaml = "duration: 1\nmaterials:\n  concrete: {density: 2400, friction: 0.7, restitution: 0.1}\nbodies:\n";
  for (std::size_t i = 0; i < count; ++i) yaml += cubes[i];
  yaml += "static:\n  - {type: slope, name: bed, material: concrete, origin: [0, 0], tan: 0.5, crest_height: 3}\n";
  return io::parseScene(yaml, std::filesystem::temp_directory_path(), "cubes-on-the-face.yaml");
}

} // namespace

TEST(PackAnalysis, TowerOfCubesHasKnownContactsAndOrder) {
  const io::Scene scene = settledTower();
  measure::AnalyseSettings settings;
  const measure::PackReport r = measure::analysePack(scene, settings);
  ASSERT_EQ(r.units.size(), 3u);
  EXPECT_EQ(r.units[0].contactNumber, 2u);
  EXPECT_EQ(r.units[0].supportNeighbours, 1u);
  EXPECT_EQ(r.units[1].contactNumber, 2u);
  EXPECT_EQ(r.units[2].contactNumber, 1u);
  EXPECT_EQ(r.contacts.unitUnitPairs, 2u);
  EXPECT_NEAR(r.contacts.coordinationNumber, 4.0 / 3.0, 1e-12);
  // The floor carries the three cubes: 3 x 2400 kg x 9.81 m/s^2, to 1 % (the settled tower still
  // rings by less than that after 1 s).
  EXPECT_NEAR(r.contacts.maxForce, 3.0 * 2400.0 * 9.81, 0.01 * 3.0 * 2400.0 * 9.81);
  EXPECT_NEAR(r.p2Q.p2, 1.0, 1e-9);
  EXPECT_NEAR(r.p2Mean.p2, 1.0, 1e-9);
  EXPECT_FALSE(r.frameFromSlope); // no slope: a plane fitted through the centroids

  measure::PoseMap same, moved;
  for (const io::Body& b : scene.bodies) {
    same[b.name] = {b.position, b.orientation};
    moved[b.name] = {b.position - Eigen::Vector3d(0.0, 0.5, 0.0), b.orientation};
  }
  const measure::PackReport still = measure::analysePack(scene, settings, nullptr, &same);
  ASSERT_TRUE(still.displacement.has_value());
  EXPECT_EQ(still.displacement->deltaRms, 0.0);
  const measure::PackReport shifted = measure::analysePack(scene, settings, nullptr, &moved);
  EXPECT_NEAR(shifted.displacement->deltaRms, 0.5, 1e-12);
  EXPECT_NEAR(shifted.displacement->maxDn, 0.5, 1e-12);
  EXPECT_EQ(shifted.displacement->movedCounts[0], 3u); // all moved more than 0.2 Dn
  EXPECT_EQ(shifted.displacement->movedCounts[1], 0u); // none more than 0.5 Dn (exactly 0.5)
}

TEST(PackAnalysis, StateFilesAreReadOrRefusedWithTheLine) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "armour-state-test.csv";
  std::ofstream(file) << "body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz\n0,c0,1,2,3,1,0,0,0,0,0,0\n1,c1,1,2,nan,1,0,0,0,0,0,0\n";
  try {
    (void)measure::readPoses(file);
    FAIL() << "a NaN position accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("armour-state-test.csv:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("column z"), std::string::npos) << e.what();
  }
  std::ofstream(file) << "name,x,y,z\nc0,1,2,3\n";
  try {
    (void)measure::readPoses(file);
    FAIL() << "a file without quaternions accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("column 'qw' missing"), std::string::npos) << e.what();
  }
  std::ofstream(file) << "body,name,x,y,z,qw,qx,qy,qz\n0,c0,1,2,3,0,0,0,2\n";
  const measure::PoseMap poses = measure::readPoses(file);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses.at("c0").position, Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(poses.at("c0").orientation.z(), 1.0, 1e-15); // normalised
  std::filesystem::remove(file);
}

TEST(PackAnalysis, UnitsOnTheUnderlayerAndStackedUnitsAreCounted) {
  // 1 m cubes lying on a 1:2 slope (faces 1 mm into what they rest on; c1 9 m up the face and 1.5 m along the trunk
  // one way, the rock and c3 the other): c0 and c1 on the face, c2
  // on c0 (centroid 1.5 Dn above the face, touching no support: stacked), and c3 on a fixed 0.5 m
  // rock (touching a support; 0.5 Dn above the rock's top, 1 Dn above the face: not stacked).
  const std::string yaml = R"(
duration: 1
materials:
  concrete: {density: 2400, friction: 0.7, restitution: 0.1}
bodies:
  - {name: c0, shape: cube, dn: 1, material: concrete, position: [2.460122, 0, 1.78796], orientation: {euler_deg: [0, -26.565051, 0]}}
  - {name: c1, shape: cube, dn: 1, material: concrete, position: [7.826685, 1.5, 4.471242], orientation: {euler_deg: [0, -26.565051, 0]}}
  - {name: c2, shape: cube, dn: 1, material: concrete, position: [2.013356, 0, 2.681493], orientation: {euler_deg: [0, -26.565051, 0]}}
  - {name: rock, shape: cube, dn: 0.5, material: concrete, fixed: true, position: [7.491275, -1.5, 4.024028], orientation: {euler_deg: [0, -26.565051, 0]}}
  - {name: c3, shape: cube, dn: 1, material: concrete, position: [7.156759, -1.5, 4.693059], orientation: {euler_deg: [0, -26.565051, 0]}}
static:
  - {type: slope, name: underlayer, material: concrete, origin: [0, 0], tan: 0.5, crest_height: 10}
)";
  const io::Scene scene = io::parseScene(yaml, std::filesystem::temp_directory_path(), "slope.yaml");
  const measure::PackReport r = measure::analysePack(scene, measure::AnalyseSettings{});
  ASSERT_TRUE(r.frameFromSlope);
  ASSERT_EQ(r.units.size(), 4u); // the fixed rock is a support
  const double expected[] = {0.499, 0.499, 1.498, 0.997 - 0.499}; // c0, c1, c2, c3 above their underlayer (Dn)
  const bool stacked[] = {false, false, true, false};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(r.units[k].heightAboveUnderlayer, expected[k], 1e-4) << r.units[k].name;
    EXPECT_EQ(r.units[k].stacked, stacked[k]) << r.units[k].name;
  }
  EXPECT_EQ(r.touchingUnderlayer, 3u); // c0, c1 (the slope) and c3 (the rock)
  EXPECT_EQ(r.stackedUnits, 1u);
  EXPECT_NE(measure::packText(r).find("3 units touch it (0.750); 1 stacked (0.250"), std::string::npos) << measure::packText(r);
  // The layer thickness stands on the underlayer's mean top, here the one rock's (0.499 m above
  // the face), as armour place measures it: the units' mean top (0.999, 0.999, 1.998, 1.497 m)
  // less 0.499 m.
  EXPECT_NEAR(r.underlayerTop, 0.499, 1e-4);
  ASSERT_TRUE(r.thickness.has_value());
  EXPECT_NEAR(r.thickness->thickness, (0.999 + 0.999 + 1.998 + 1.497) / 4.0 - 0.499, 1e-4);
  // Per unit, the top and the bottom above that base (Dn = 1 m): a cube lying on a face spans
  // 1 Dn (to 1e-8 m: the scene's tilt of 26.565051 deg is atan(1/2) to 2e-9 rad), and the tops
  // average to the thickness.
  const double tops[] = {0.999 - 0.499, 0.999 - 0.499, 1.998 - 0.499, 1.497 - 0.499};
  double sum = 0.0;
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(r.units[k].topAboveUnderlayer, tops[k], 1e-4) << r.units[k].name;
    EXPECT_NEAR(r.units[k].topAboveUnderlayer - r.units[k].bottomAboveUnderlayer, 1.0, 1e-8) << r.units[k].name;
    sum += r.units[k].topAboveUnderlayer;
  }
  EXPECT_NEAR(sum / 4.0, r.thickness->thickness, 1e-12);
}

// A unit that fell off the edge of a slope's crest (beyond the static domain, on the seabed, as
// seed 003's sweep at 591 kN left one 40 m onshore) is analysed in the domain of the scene's own
// poses, where it lies on the seabed plane: counted off the model, not refused as lying inside a
// crest stretched to reach it. A state that puts a unit deep inside the slope is refused as input,
// naming the state.
TEST(PackAnalysis, AUnitOffTheCrestEdgeIsOffTheModelAndAUnitInTheSlopeIsRefused) {
  const io::Scene scene = cubesOnTheFace(2);
  measure::PoseMap state = measure::posesOf(scene);
  // c1 at rest on the seabed (z = 0) 40 m onshore of the crest edge (x = 6 m).
  state["c1"].position = Eigen::Vector3d(46.0, 0.0, 0.5 - 1e-6);
  state["c1"].orientation = Eigen::Quaterniond::Identity();
  measure::AnalyseSettings settings;
  settings.stateName = "final_state.csv";
  const measure::PackReport r = measure::analysePack(scene, settings, &state);
  EXPECT_EQ(r.unitsOffDomain, 1u);
  ASSERT_EQ(r.units.size(), 2u);
  EXPECT_EQ(r.units[1].supportNeighbours, 1u); // the seabed
  EXPECT_NE(measure::packText(r).find("off the model       1 units"), std::string::npos) << measure::packText(r);
  // The unit 0.6 m (centroid) into the face: its samples 1 m deep, more than the guard allows.
  state = measure::posesOf(scene);
  state["c1"].position.z() -= 0.6 / std::sqrt(1.25) * 1.0;
  state["c1"].position.x() += 0.6 * 0.5 / std::sqrt(1.25);
  try {
    (void)measure::analysePack(scene, settings, &state);
    FAIL() << "a unit deep inside the slope was analysed";
  } catch (const core::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("final_state.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("cannot be evaluated"), std::string::npos) << what;
  }
}

// Three cubes side by side on a slope: the hull of their centroids (1.3 m^2) is smaller than
// their footprint (3 m^2), so 1 - N V / (A t) comes out at -1.24. That is no porosity: it is
// reported as not available, with the reason, instead of a negative number.
TEST(PackAnalysis, AFewUnitsHaveNoPorosity) {
  const io::Scene scene = cubesOnTheFace(3);
  const measure::PackReport r = measure::analysePack(scene, measure::AnalyseSettings{});
  ASSERT_TRUE(r.thickness.has_value());
  // The hull: a triangle, sqrt(5) m along the face (c0 to c1) by 1.2 m across it (c2), so
  // A = sqrt(5) x 1.2 / 2 = 1.3416 m^2; t = 1 m, N V = 3 m^3: 1 - 3 / 1.3416 = -1.236.
  EXPECT_NEAR(r.packingHull.area, std::sqrt(5.0) * 1.2 / 2.0, 1e-4);
  EXPECT_TRUE(std::isnan(r.porosity));
  EXPECT_NE(r.porosityNote.find("-1.24 is no porosity"), std::string::npos) << r.porosityNote;
  EXPECT_NE(measure::packText(r).find("porosity n/a ("), std::string::npos) << measure::packText(r);
}
