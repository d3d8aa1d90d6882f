// SPDX-License-Identifier: GPL-3.0-or-later
// The deformable scene file of `armour deform` (io/DeformableScene, docs/deformable-file.md): the
// shipped case reads to its values with seed 002's defaults applied; each kind of user error is
// refused with the file, line, key path, value and fix.
#include "core/Error.hpp"
#include "io/DeformableScene.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using armour::core::InputError;
using armour::io::readDeformableScene;

const std::filesystem::path kCases = std::filesystem::path(ARMOUR_TEST_DATA) / ".." / ".." / "cases" / "deformable";

/// Write `text` to a scene file in the test's temporary folder and read it.
armour::io::DeformableScene readText(const std::string& text, const std::string& name = "scene.yaml") {
  const auto dir = std::filesystem::temp_directory_path() / "armour_test_deformable_scene";
  std::filesystem::create_directories(dir);
  const auto file = dir / name;
  std::ofstream(file) << text;
  return readDeformableScene(file);
}

/// The error message of reading `text`, or "" if it was accepted.
std::string errorOf(const std::string& text) {
  try {
    (void)readText(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string kMinimal = R"(bodies:
  - shape: cube
    volume: 1
    position: [0, 0, 0.5]
run:
  duration: 0.001
)";

TEST(DeformableScene, TheShippedDropReadsToItsValues) {
  const auto s = readDeformableScene(kCases / "vcross-drop.yaml");
  ASSERT_EQ(s.parts.size(), 2U);
  EXPECT_EQ(s.parts[0].name, "vcross");
  EXPECT_EQ(s.parts[0].shape, "vcross");
  EXPECT_DOUBLE_EQ(s.parts[0].volume, 14.0);
  EXPECT_EQ(s.parts[0].tets, 3000U);
  EXPECT_DOUBLE_EQ(s.parts[0].velocity.z(), -0.5);
  EXPECT_TRUE(s.parts[1].shape.empty());
  EXPECT_EQ(s.parts[1].box, Eigen::Vector3d(8, 8, 4));
  EXPECT_EQ(s.parts[1].cells[0], 12U);
  ASSERT_EQ(s.halfSpaces.size(), 1U);
  EXPECT_DOUBLE_EQ(s.youngModulus, 26.6e9);
  EXPECT_DOUBLE_EQ(s.poissonRatio, 0.205);
  EXPECT_DOUBLE_EQ(s.viscosityFraction, 0.01);
  EXPECT_DOUBLE_EQ(s.contactDamping, 0.2);
  EXPECT_TRUE(s.quadratic);
  EXPECT_DOUBLE_EQ(s.duration, 0.008);
  EXPECT_EQ(s.output.filename(), "vcross-drop-out");
  EXPECT_TRUE(s.output.is_absolute());
}

TEST(DeformableScene, DefaultsAreSeed002sConcrete) {
  const auto s = readText(kMinimal);
  EXPECT_DOUBLE_EQ(s.density, 2340.0);
  EXPECT_DOUBLE_EQ(s.youngModulus, 26.6e9);
  EXPECT_DOUBLE_EQ(s.poissonRatio, 0.205);
  EXPECT_EQ(s.parts[0].tets, 2000U);
  EXPECT_EQ(s.parts[0].name, "body_0");
  EXPECT_EQ(s.stressEvery, 5U);
  EXPECT_EQ(s.output.filename(), "scene-out");
}

TEST(DeformableScene, RigidBodiesAreFixedUnlessToldToMove) {
  const auto s = readText(kMinimal + R"(rigid_bodies:
  - {name: pier, shape: cube, volume: 1, position: [0, 0, -0.5]}
  - {name: block, shape: cube, volume: 2, position: [2, 0, -0.5], fixed: false, density: 2500, velocity: [1, 0, 0]}
  - {name: light, shape: cube, volume: 1, position: [4, 0, -0.5], fixed: false}
contact: {rigid_restitution: 0.2, rigid_penalty_modulus: 4e9}
)");
  ASSERT_EQ(s.rigidBodies.size(), 3U);
  EXPECT_TRUE(s.rigidBodies[0].fixed);
  EXPECT_FALSE(s.rigidBodies[1].fixed);
  EXPECT_DOUBLE_EQ(s.rigidBodies[1].density, 2500.0);
  EXPECT_EQ(s.rigidBodies[1].part.velocity, Eigen::Vector3d(1, 0, 0));
  EXPECT_DOUBLE_EQ(s.rigidBodies[2].density, 0.0); // the material's
  EXPECT_DOUBLE_EQ(s.rigidRestitution, 0.2);
  EXPECT_DOUBLE_EQ(s.rigidPenaltyModulus, 4e9);
  const auto d = readText(kMinimal);
  EXPECT_DOUBLE_EQ(d.rigidRestitution, 0.05); // seed 001
  EXPECT_DOUBLE_EQ(d.rigidPenaltyModulus, 1e9);
}

TEST(DeformableScene, ErrorsNameTheKeyTheValueAndTheFix) {
  const struct {
    std::string text;
    std::string expected;
  } cases[] = {
      {"", "the scene is empty"},
      {kMinimal + "materail: {}\n", "materail: unknown key (did you mean 'material'?)"},
      {kMinimal + "material: {poisson_ratio: 0.5}\n", "material.poisson_ratio = 0.5: must be in (-1, 0.5)"},
      {kMinimal + "element: tet8\n", "element = tet8: expected one of tet4, tet10"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0], box: [1, 1, 1]}\nrun: {duration: 1}\n",
       "give only one of 'shape' or 'box'"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0], cells: [1, 1, 1]}\nrun: {duration: 1}\n",
       "bodies[0].cells: cells belong to a box"},
      {"bodies:\n  - {box: [1, 1, 1], position: [0, 0, 0]}\nrun: {duration: 1}\n", "missing key 'cells'"},
      {"bodies:\n  - {shape: cube, volume: -1, position: [0, 0, 0]}\nrun: {duration: 1}\n",
       "bodies[0].volume = -1: must be > 0"},
      {"bodies:\n  - {shape: cube, volume: 1}\nrun: {duration: 1}\n", "missing key 'position'"},
      {"bodies: []\nrun: {duration: 1}\n", "expected a list of one or more bodies"},
      {kMinimal + "contact: {friction: 0.6}\n", "contact.friction = 0.6: acts on the half-spaces and the rigid bodies, and there are none"},
      {kMinimal + "half_spaces: [{point: [0, 0, 0], normal: [0, 0, 0]}]\n", "a zero vector has no direction"},
      {kMinimal + "contact: {body_friction: 0.6}\n",
       "contact.body_friction = 0.6: acts between the deformable bodies, and there is one"},
      {kMinimal + "contact: {body_friction: -0.6}\n", "contact.body_friction = -0.6: must be >= 0"},
      {kMinimal + "rigid_bodies: [{shape: cube, volume: 1, position: [0, 0, -1], density: 2400}]\n",
       "rigid_bodies[0].density = 2400: is for a moving rigid body; add 'fixed: false' or remove it"},
      {kMinimal + "rigid_bodies: [{shape: cube, volume: 1, position: [0, 0, -1], fixed: false, density: 0}]\n",
       "rigid_bodies[0].density = 0: must be > 0"},
      {kMinimal + "rigid_bodies: [{shape: cube, volume: 1, position: [0, 0, -1]}]\ncontact: {rigid_restitution: 0.1}\n",
       "contact.rigid_restitution = 0.1: sets the contact of moving rigid bodies, and every rigid body is fixed"},
      {kMinimal + "rigid_bodies: [{shape: cube, volume: 1, position: [0, 0, -1], fixed: false}]\n"
                  "contact: {rigid_restitution: 0}\n",
       "contact.rigid_restitution = 0: must be in (0, 1]"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0]}\n", "missing key 'run'"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0]}\nrun: {duration: 0}\n",
       "run.duration = 0: must be > 0"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0], tets: 3000000}\nrun: {duration: 1}\n",
       "more than 2000000 tetrahedra"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0]}\nrun: {duration: 1, mass_scaling: 0.5}\n",
       "run.mass_scaling = 0.5: adds more than a tenth of the unit's mass; give at most 0.1"},
      {"bodies:\n  - {shape: cube, volume: 1, position: [0, 0, 0]}\nrun: {duration: 1, mass_scaling: -0.01}\n",
       "run.mass_scaling = -0.01: must be >= 0"},
  };
  for (const auto& c : cases) {
    const std::string message = errorOf(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << message;
    if (!c.text.empty()) {
      EXPECT_NE(message.find("scene.yaml"), std::string::npos) << message;
    }
  }
}

} // namespace
