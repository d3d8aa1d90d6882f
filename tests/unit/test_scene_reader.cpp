// SPDX-License-Identifier: GPL-3.0-or-later
// The scene file: every feature parses to the expected values with defaults applied, Euler angles
// follow the x-y'-z'' convention of seed 001, grids expand in the documented order, height fields
// are reproducible from their seed, each kind of user error is reported with its file, line, key
// path, value and fix, and describeScene lists every setting.

#include "core/Error.hpp"
#include "io/Scene.hpp"
#include "io/SceneReader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

namespace {

using armour::core::InputError;
using namespace armour::io;

const std::filesystem::path kScenes = std::filesystem::path(ARMOUR_TEST_DATA) / "scenes";
constexpr double kDeg = std::numbers::pi / 180.0;

/// Values that pass through one multiplication or a libm call are compared to this relative
/// tolerance: a few ulps of round-off, nothing physical.
constexpr double kRoundOff = 1e-12;

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The message of the InputError that parsing `yaml` must throw.
std::string errorFrom(const std::string& yaml) {
  try {
    (void)parseScene(yaml, kScenes, "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << yaml;
  return {};
}

std::string errorFromFile(const std::filesystem::path& path) {
  try {
    (void)readScene(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return {};
}

#define EXPECT_CONTAINS(text, fragment) \
  EXPECT_NE(std::string(text).find(fragment), std::string::npos) << "missing \"" << (fragment) << "\" in:\n" << (text)

const std::string kMaterials = "materials:\n  concrete: {density: 2400, friction: 0.75, restitution: 0.05}\n";

/// duration (line 1), the material (lines 2-3), then `rest` from line 4.
std::string sceneWith(const std::string& rest) { return "duration: 1\n" + kMaterials + rest; }

/// One valid cube body with extra keys appended inside its flow mapping (on line 5).
std::string oneBody(const std::string& extraKeys = "") {
  return sceneWith("bodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 0.5]" + extraKeys + "}\n");
}

/// Rx(a) Ry(b) Rz(c) written out element by element, independent of Eigen's AngleAxis.
Eigen::Matrix3d rx(double a) {
  Eigen::Matrix3d m;
  m << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return m;
}
Eigen::Matrix3d ry(double a) {
  Eigen::Matrix3d m;
  m << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return m;
}
Eigen::Matrix3d rz(double a) {
  Eigen::Matrix3d m;
  m << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return m;
}

/// Rotation of `angle` about unit `axis` by Rodrigues' formula (again not Eigen's AngleAxis).
Eigen::Matrix3d rodrigues(const Vec3& axis, double angle) {
  Eigen::Matrix3d k;
  k << 0, -axis.z(), axis.y(), axis.z(), 0, -axis.x(), -axis.y(), axis.x(), 0;
  return Eigen::Matrix3d::Identity() + std::sin(angle) * k + (1 - std::cos(angle)) * k * k;
}

class EveryFeature : public ::testing::Test {
protected:
  static void SetUpTestSuite() { scene_ = new Scene(readScene(kScenes / "every-feature.yaml")); }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  static const Scene& scene() { return *scene_; }
  static const Body& body(const std::string& name) {
    const auto i = scene_->findBody(name);
    EXPECT_GE(i, 0) << name;
    return scene_->bodies.at(static_cast<std::size_t>(i));
  }
  static std::size_t shapeIndex(const std::string& name) {
    for (std::size_t i = 0; i < scene_->shapes.size(); ++i)
      if (scene_->shapes[i].name == name) return i;
    ADD_FAILURE() << "no shape " << name;
    return 0;
  }

private:
  static inline Scene* scene_ = nullptr;
};

// --------------------------------------------------------------------------------------------
// A scene with every feature
// --------------------------------------------------------------------------------------------

TEST_F(EveryFeature, RunSettings) {
  const Scene& s = scene();
  EXPECT_EQ(s.name, "every-feature");
  EXPECT_EQ(s.description, "every feature");
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.8));
  EXPECT_EQ(s.duration, 2.5);
  EXPECT_FALSE(s.timeStep.automatic);
  EXPECT_EQ(s.timeStep.value, 2.0e-4);
  EXPECT_EQ(s.contact.sampleSpacing, 0.08);
  EXPECT_EQ(s.contact.levelSetCellsPerDn, 30.0);
  EXPECT_EQ(s.contact.maxOverlap, 0.03);
  EXPECT_EQ(s.output.folder, std::filesystem::absolute(kScenes / "results/every").lexically_normal());
  EXPECT_EQ(s.output.vtkInterval, 0.25);
  EXPECT_EQ(s.output.seriesInterval, 0.02);
  EXPECT_EQ(s.output.checkpointInterval, 1.0);
  EXPECT_EQ(s.output.checkpointWallMinutes, 15.0);
  EXPECT_TRUE(s.output.contacts);
  EXPECT_FALSE(s.sleep.enabled);
  EXPECT_EQ(s.sleep.linearSpeed, 0.002);
  EXPECT_EQ(s.sleep.angularSpeed, 0.004);
  EXPECT_EQ(s.sleep.time, 0.25);
  EXPECT_EQ(s.bodyDamping.linear, 0.9);
  EXPECT_EQ(s.bodyDamping.angular, 0.5);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST_F(EveryFeature, Materials) {
  const Scene& s = scene();
  ASSERT_EQ(s.materials.size(), 2u);
  const Material& concrete = s.materials[0];
  EXPECT_EQ(concrete.name, "concrete");
  EXPECT_EQ(concrete.density, 2400.0);
  EXPECT_EQ(concrete.frictionStatic, 0.75);
  EXPECT_EQ(concrete.frictionDynamic, 0.75);
  EXPECT_EQ(concrete.restitution, 0.05);
  EXPECT_FALSE(concrete.dampingRatio.has_value()); // the contact law derives it
  EXPECT_EQ(concrete.penalty, 1e9);                       // default
  EXPECT_DOUBLE_EQ(concrete.tangentialStiffnessRatio, 8.0 / 9.0); // default
  const Material& rock = s.materials[1];
  EXPECT_EQ(rock.frictionStatic, 0.8);
  EXPECT_EQ(rock.frictionDynamic, 0.6);
  EXPECT_EQ(rock.dampingRatio, 0.3);
  EXPECT_FALSE(rock.restitution.has_value()); // given as a damping ratio instead
  EXPECT_EQ(rock.penalty, 2e9);
  EXPECT_EQ(rock.tangentialStiffnessRatio, 0.5);
}

TEST_F(EveryFeature, Shapes) {
  const Scene& s = scene();
  // Named shapes first, then library names and inline shapes in the order bodies use them.
  ASSERT_EQ(s.shapes.size(), 6u);
  const ShapeSpec& rock = s.shapes[shapeIndex("rock7")];
  EXPECT_EQ(rock.source, ShapeSource::Generator);
  EXPECT_EQ(rock.generator, "rock");
  EXPECT_EQ(rock.seed, 7u);
  EXPECT_EQ(rock.params.size(), 2u);
  EXPECT_EQ(rock.params.at("points"), 60.0);
  EXPECT_EQ(rock.params.at("aspect_c"), 0.5);
  const std::filesystem::path blockFile = std::filesystem::absolute(kScenes / "meshes/block.stl").lexically_normal();
  const ShapeSpec& file = s.shapes[shapeIndex("block-file")];
  EXPECT_EQ(file.source, ShapeSource::MeshFile);
  EXPECT_EQ(file.meshFile, blockFile);
  const ShapeSpec& cube = s.shapes[shapeIndex("cube")];
  EXPECT_EQ(cube.generator, "cube");
  EXPECT_EQ(cube.seed, 42u); // a library name used directly takes the scene seed
  EXPECT_TRUE(cube.params.empty());
  EXPECT_EQ(s.shapes[shapeIndex("mesh:" + blockFile.string())].meshFile, blockFile);
  const ShapeSpec& antifer = s.shapes[shapeIndex("bodies[4].shape")];
  EXPECT_EQ(antifer.generator, "antifer");
  EXPECT_EQ(antifer.params.at("taper"), 0.9);
  EXPECT_EQ(s.shapes[shapeIndex("dolos")].generator, "dolos");
}

TEST_F(EveryFeature, Bodies) {
  const Scene& s = scene();
  ASSERT_EQ(s.bodies.size(), 5u + 2u * 3u * 2u);
  const Body& a = body("a");
  EXPECT_EQ(s.shapes[a.shape].name, "cube");
  EXPECT_EQ(s.materials[a.material].name, "concrete");
  ASSERT_TRUE(a.volume.has_value());
  EXPECT_EQ(*a.volume, 8.0); // dn 2 -> 2^3, exact in binary
  EXPECT_EQ(a.position, Vec3(1, 2, 3));
  EXPECT_EQ(a.velocity, Vec3(0.5, 0, -1));
  EXPECT_EQ(a.angularVelocity, Vec3(0, 0.1, 0));
  EXPECT_FALSE(a.fixed);
  const Eigen::Matrix3d expected = rx(30 * kDeg) * ry(45 * kDeg) * rz(60 * kDeg);
  EXPECT_LT((a.orientation.toRotationMatrix() - expected).norm(), kRoundOff);

  const Body& unnamed = body("body1"); // default name from the list index
  EXPECT_EQ(s.shapes[unnamed.shape].name, "rock7");
  EXPECT_EQ(s.materials[unnamed.material].name, "rock");
  EXPECT_EQ(*unnamed.volume, 3.0);
  EXPECT_TRUE(unnamed.fixed);
  EXPECT_EQ(unnamed.orientation.coeffs(), Eigen::Vector4d(0.5, 0.5, 0.5, 0.5)); // (x, y, z, w), already unit

  const Body& c = body("c");
  EXPECT_FALSE(c.volume.has_value()); // a mesh at its own size...
  EXPECT_EQ(c.scale, 2.0);            // ...times 2
  const Body& d = body("d");
  EXPECT_EQ(*d.volume, 8.0);
  EXPECT_EQ(d.scale, 1.0);
  EXPECT_EQ(*body("e").volume, 16.0);
}

TEST_F(EveryFeature, GridExpansion) {
  const Scene& s = scene();
  // count [2, 3, 2], spacing [2.5, 3, 2], first centroid [10, 0, 2]; ix varies fastest, then iy, then iz.
  const std::size_t first = 5;
  std::size_t k = first;
  for (int iz = 0; iz < 2; ++iz)
    for (int iy = 0; iy < 3; ++iy)
      for (int ix = 0; ix < 2; ++ix, ++k) {
        const Body& b = s.bodies.at(k);
        EXPECT_EQ(b.name, "pile_" + std::to_string(ix) + "_" + std::to_string(iy) + "_" + std::to_string(iz));
        EXPECT_EQ(b.position, Vec3(10 + 2.5 * ix, 3.0 * iy, 2 + 2.0 * iz)) << b.name;
        EXPECT_EQ(*b.volume, 1.5);
        EXPECT_EQ(s.shapes[b.shape].name, "dolos");
      }
  // rotation_jitter_deg [0, 20, 0]: each unit is the base orientation (90 deg about x) followed
  // by a turn about its own y axis of at most 20 degrees.
  const Eigen::Matrix3d base = rx(90 * kDeg);
  double largest = 0.0;
  double smallest = 180.0;
  for (std::size_t i = first; i < s.bodies.size(); ++i) {
    const Eigen::Matrix3d relative = base.transpose() * s.bodies[i].orientation.toRotationMatrix();
    // A rotation about y keeps e_y fixed: checked to round-off.
    EXPECT_LT((relative * Vec3::UnitY() - Vec3::UnitY()).norm(), kRoundOff) << s.bodies[i].name;
    const double angle = std::abs(std::atan2(relative(0, 2), relative(0, 0))) / kDeg;
    EXPECT_LE(angle, 20.0 + 1e-9);
    largest = std::max(largest, angle);
    smallest = std::min(smallest, angle);
  }
  // The seed is fixed, so this is deterministic; it fails if the jitter were dropped or made
  // constant (twelve angles with |angle| uniform on [0, 20] spread over less than 5 degrees with
  // probability 12 (1/4)^11 - 11 (1/4)^12 = 2e-6).
  EXPECT_GT(largest - smallest, 5.0);
  // Same file, same seed: the same orientations, bit for bit.
  const Scene again = readScene(kScenes / "every-feature.yaml");
  for (std::size_t i = 0; i < s.bodies.size(); ++i)
    EXPECT_EQ(s.bodies[i].orientation.coeffs(), again.bodies[i].orientation.coeffs());
}

TEST_F(EveryFeature, StaticGeometry) {
  const StaticGeometry& g = scene().statics;
  ASSERT_EQ(g.size(), 7u);
  ASSERT_EQ(g.planes.size(), 1u);
  EXPECT_EQ(g.planes[0].name, "floor");
  EXPECT_EQ(g.planes[0].point, Vec3(0, 0, -2));
  EXPECT_EQ(g.planes[0].normal, Vec3(0, 0, 1)); // [0, 0, 2] normalised

  ASSERT_EQ(g.slopes.size(), 1u);
  const StaticSlope& slope = g.slopes[0];
  EXPECT_EQ(slope.name, "slope1"); // default "<type><list index>"
  EXPECT_EQ(scene().materials[slope.material].name, "rock");
  EXPECT_EQ(slope.origin, Vec2(20, -1));
  EXPECT_NEAR(slope.tanAlpha, 1 / std::sqrt(3.0), kRoundOff);
  EXPECT_EQ(slope.crestHeight, 5.0);
  EXPECT_EQ(slope.toeHeight, 1.5);
  EXPECT_EQ(slope.toeTopWidth, 2.0);
  EXPECT_EQ(slope.toeBaseWidth, 6.0);
  ASSERT_TRUE(slope.roughness.has_value());
  const HeightField& rough = *slope.roughness;
  // The face is 5 / sin 30 = 10 m long: 20 cells of 0.5 m; y from -4 to 4: 16 cells.
  EXPECT_EQ(rough.cellsX, 20);
  EXPECT_EQ(rough.cellsY, 16);
  EXPECT_EQ(rough.seed, 42u); // the scene seed
  EXPECT_EQ(rough.origin, Vec3(20, -4, -1));
  EXPECT_NEAR(rough.tanAlpha, slope.tanAlpha, 0.0);
  // The last corner of the field is the crest edge.
  EXPECT_LT((rough.corner(20, 16) - Vec3(20 + 5 * std::sqrt(3.0), 4, 4)).norm(), 1e-12);

  ASSERT_EQ(g.heightFields.size(), 1u);
  const HeightField& bed = g.heightFields[0].field;
  EXPECT_EQ(g.heightFields[0].name, "bed");
  EXPECT_EQ(bed.origin, Vec3(-10, -5, 0));
  EXPECT_EQ(bed.tanAlpha, 0.1);
  EXPECT_EQ(bed.cellsX, 6);
  EXPECT_EQ(bed.cellsY, 4);
  EXPECT_EQ(bed.seed, 3u);
  EXPECT_EQ(bed.depths.size(), 24u);

  ASSERT_EQ(g.walls.size(), 3u);
  EXPECT_EQ(g.walls[0].normal(), Vec3(0, 1, 0));
  EXPECT_EQ(g.walls[0].position, -6.0);
  EXPECT_EQ(g.walls[1].normal(), Vec3(0, -1, 0));
  EXPECT_EQ(g.walls[2].normal(), Vec3(1, 0, 0));

  ASSERT_EQ(g.meshes.size(), 1u);
  const StaticMesh& crown = g.meshes[0];
  EXPECT_EQ(crown.file, std::filesystem::absolute(kScenes / "meshes/block.stl").lexically_normal());
  EXPECT_EQ(crown.position, Vec3(30, 0, 4));
  EXPECT_EQ(crown.scale, 1.5);
  EXPECT_LT((crown.orientation * Vec3::UnitX() - Vec3::UnitY()).norm(), kRoundOff); // 90 deg about z
}

TEST_F(EveryFeature, DescribeListsEverySetting) {
  const std::string text = describeScene(scene());
  // Every settings key of the file format, with its value and unit as resolved.
  for (const char* fragment :
       {"scene every-feature", "description: every feature", "gravity = [0, 0, -9.8] m/s^2", "duration = 2.5 s",
        "time_step = 0.0002 s (fixed", "time_step_safety = 0.2", "seed = 42", "sample_spacing = 0.08 Dn",
        "level_set_cells_per_dn = 30 (cells per Dn)", "max_overlap = 0.03 Dn", "results/every", "vtk_interval = 0.25 s",
        "series_interval = 0.02 s", "checkpoint_interval = 1 s", "checkpoint_wall_minutes = 15 min", "contacts = true",
        "enabled = false", "linear_speed = 0.002 m/s", "angular_speed = 0.004 rad/s", "time = 0.25 s",
        "concrete: density = 2400 kg/m^3, friction static = 0.75, dynamic = 0.75", "restitution = 0.05 (-)",
        "damping_ratio = 0.3 (-)", "penalty = 1e+09 Pa", "penalty = 2e+09 Pa",
        "tangential_stiffness_ratio = 0.5", "rock7: generator = rock, params = {aspect_c = 0.5, points = 60}",
        "seed = 7", "block-file: mesh = ", "a: shape = cube, volume = 8 m^3 (dn = 2 m), material = concrete",
        "position = [1, 2, 3] m", "velocity = [0.5, 0, -1] m/s", "angular_velocity = [0, 0.1, 0] rad/s",
        "euler_deg = [30, 45, 60]", "body1: shape = rock7", "euler_deg = [90, 90, 0]", "fixed = true", "c: shape = block-file, scale = 2",
        "pile_1_2_1:", "plane floor: point = [0, 0, -2] m, normal = [0, 0, 1]",
        "slope slope1: origin = [20, -1] m (x, z)", "angle_deg = 30", "crest_height = 5 m", "toe_height = 1.5 m",
        "toe_top_width = 2 m", "toe_base_width = 6 m", "roughness: cell_size = 0.5 m, cells = 20 x 16",
        "max_depth = 0.2 m", "heightfield bed: origin = [-10, -5, 0] m, tan = 0.1", "seed = 3",
        "wall north: axis = y, position = 6 m, side = max", "wall back: axis = x", "mesh crown: file = ", "scale = 1.5"})
    EXPECT_CONTAINS(text, fragment);
  // One line per body.
  for (const Body& b : scene().bodies) EXPECT_CONTAINS(text, "  " + b.name + ": shape = ");
}

// --------------------------------------------------------------------------------------------
// Defaults, orientation, height fields, conversions
// --------------------------------------------------------------------------------------------

TEST(SceneDefaults, MinimalSceneTakesEveryDefault) {
  const Scene s = parseScene(oneBody(), kScenes, "minimal.yaml");
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.81));
  EXPECT_TRUE(s.timeStep.automatic);
  EXPECT_EQ(s.timeStep.safety, 0.2);
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.contact.sampleSpacing, 0.1);
  EXPECT_EQ(s.contact.levelSetCellsPerDn, 24.0);
  EXPECT_EQ(s.contact.maxOverlap, 0.25);
  EXPECT_EQ(s.output.folder, std::filesystem::absolute(kScenes / "minimal-out").lexically_normal());
  EXPECT_EQ(s.output.vtkInterval, 0.1);
  EXPECT_EQ(s.output.seriesInterval, 0.01);
  EXPECT_EQ(s.output.checkpointInterval, 1.0);
  EXPECT_EQ(s.output.checkpointWallMinutes, 30.0);
  EXPECT_FALSE(s.output.contacts);
  EXPECT_TRUE(s.sleep.enabled);
  EXPECT_EQ(s.sleep.linearSpeed, 1e-3);
  EXPECT_EQ(s.sleep.angularSpeed, 1e-3);
  EXPECT_EQ(s.sleep.time, 0.5);
  EXPECT_EQ(s.bodyDamping.linear, 0.0) << "off by default";
  EXPECT_EQ(s.bodyDamping.angular, 0.0);
  ASSERT_EQ(s.bodies.size(), 1u);
  const Body& b = s.bodies[0];
  EXPECT_EQ(b.name, "body0");
  EXPECT_EQ(b.orientation.coeffs(), Quat::Identity().coeffs());
  EXPECT_EQ(b.velocity, Vec3::Zero());
  EXPECT_EQ(b.angularVelocity, Vec3::Zero());
  EXPECT_FALSE(b.fixed);
  EXPECT_EQ(s.materials[0].penalty, 1e9);
  // No static geometry and nothing fixed: reported, not refused.
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_CONTAINS(s.warnings[0], "every body falls freely");
}

TEST(SceneContactModel, LevelSetByDefaultFdemOnRequest) {
  // Level set is the default (docs/fidelity.md: cheaper at the same flat-face stiffness).
  const Scene d = parseScene(oneBody(), kScenes, "t.yaml");
  EXPECT_EQ(d.contact.model, ContactModel::LevelSet);
  EXPECT_EQ(d.contact.fdemElementsPerUnit, 2500u);
  const Scene f = parseScene("contact: {model: fdem, fdem: {elements_per_unit: 800}}\n" + oneBody(), kScenes, "t.yaml");
  EXPECT_EQ(f.contact.model, ContactModel::Fdem);
  EXPECT_EQ(f.contact.fdemElementsPerUnit, 800u);
  EXPECT_TRUE(f.warnings.size() <= 1u) << "only the free-fall note";
  // An fdem block under the level-set model is ignored, with a warning naming it.
  const Scene w = parseScene("contact: {fdem: {elements_per_unit: 800}}\n" + oneBody(), kScenes, "t.yaml");
  bool warned = false;
  for (const auto& text : w.warnings) warned = warned || text.find("contact.fdem") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(SceneContactModel, BadValuesNameKeyValueAndFix) {
  EXPECT_CONTAINS(errorFrom("contact: {model: femdem}\n" + oneBody()),
                  "contact.model = femdem: expected one of levelset, fdem");
  EXPECT_CONTAINS(errorFrom("contact: {model: fdem, fdem: {elements_per_unit: 10}}\n" + oneBody()),
                  "contact.fdem.elements_per_unit = 10: expected an integer >= 24");
  EXPECT_CONTAINS(errorFrom("contact: {model: fdem, fdem: {elements_per_unit: 5000000}}\n" + oneBody()),
                  "contact.fdem.elements_per_unit = 5000000: at most 2000000");
  EXPECT_CONTAINS(errorFrom("contact: {model: fdem, fdem: {element_size: 0.1}}\n" + oneBody()),
                  "contact.fdem.element_size: unknown key; valid keys are: elements_per_unit");
}

TEST(SceneOrientation, TaitBryanIsIntrinsicXYZ) {
  // Build x-y'-z'' literally: turn about x, then about the turned y axis, then about the twice
  // turned z axis, each by Rodrigues' formula; compare with Rx Ry Rz and with the reader.
  const double phi = 30 * kDeg, theta = 45 * kDeg, psi = 60 * kDeg;
  const Eigen::Matrix3d r1 = rodrigues(Vec3::UnitX(), phi);
  const Eigen::Matrix3d r2 = rodrigues(r1 * Vec3::UnitY(), theta) * r1;
  const Eigen::Matrix3d r3 = rodrigues(r2 * Vec3::UnitZ(), psi) * r2;
  const Eigen::Matrix3d product = rx(phi) * ry(theta) * rz(psi);
  EXPECT_LT((r3 - product).norm(), kRoundOff);
  EXPECT_LT((quaternionFromTaitBryan(phi, theta, psi).toRotationMatrix() - product).norm(), kRoundOff);
  // The order matters: the extrinsic product Rz Ry Rx differs by O(1) for these angles.
  EXPECT_GT((rz(psi) * ry(theta) * rx(phi) - product).norm(), 0.5);
}

TEST(SceneOrientation, OrderMattersInTheFile) {
  // euler_deg [90, 90, 0]: Ry(90) takes the body's x axis to -z, then Rx(90) takes -z to +y.
  // Turning about the world axes in the other order (x first, then y) would give -z instead.
  const Scene s = parseScene(oneBody(", orientation: {euler_deg: [90, 90, 0]}"), kScenes, "t.yaml");
  const Vec3 bodyX = s.bodies[0].orientation * Vec3::UnitX();
  EXPECT_LT((bodyX - Vec3::UnitY()).norm(), kRoundOff);
  EXPECT_GT((bodyX - Vec3(0, 0, -1)).norm(), 1.0);
}

TEST(SceneOrientation, NonUnitQuaternionIsNormalisedWithAWarning) {
  const Scene s = parseScene(oneBody(", orientation: {quaternion: [1, 0, 0, 1]}"), kScenes, "t.yaml");
  const Quat& q = s.bodies[0].orientation;
  EXPECT_NEAR(q.norm(), 1.0, kRoundOff);
  EXPECT_NEAR(q.w(), std::sqrt(0.5), kRoundOff);
  EXPECT_NEAR(q.z(), std::sqrt(0.5), kRoundOff);
  bool warned = false;
  for (const auto& w : s.warnings) warned = warned || w.find("bodies[0].orientation.quaternion = [1, 0, 0, 1]") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_CONTAINS(s.warnings[0], "t.yaml:5:");
  EXPECT_CONTAINS(s.warnings[0], "not a unit quaternion (norm 1.41421356)");
}

TEST(SceneHeightField, ReproducibleAndWithinZeroToH) {
  const auto field = [](int seed) {
    return sceneWith("bodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 2]}\n"
                     "static:\n  - {type: heightfield, material: concrete, origin: [0, 0, 0], extent: [100, 100], "
                     "max_depth: 0.4, seed: " +
                     std::to_string(seed) + "}\n");
  };
  const Scene a = parseScene(field(5489), kScenes, "t.yaml");
  const Scene b = parseScene(field(5489), kScenes, "t.yaml");
  const Scene c = parseScene(field(5490), kScenes, "t.yaml");
  const auto& da = a.statics.heightFields.at(0).field.depths;
  ASSERT_EQ(da.size(), 10000u);
  EXPECT_EQ(da, b.statics.heightFields.at(0).field.depths); // bit for bit
  EXPECT_NE(da, c.statics.heightFields.at(0).field.depths);
  double sum = 0.0;
  for (double d : da) {
    EXPECT_GE(d, 0.0);
    EXPECT_LT(d, 0.4);
    sum += d;
  }
  // Mean of 10^4 draws of U(0, h): h/2 with standard error h / sqrt(12 x 10^4) = 1.15e-3;
  // 5 standard errors make a false alarm impossible in practice (and the seed is fixed).
  EXPECT_NEAR(sum / 1e4, 0.2, 5 * 0.4 / std::sqrt(12e4));
  // Portability anchor: the C++ standard fixes the 10000th output of std::mt19937_64 seeded with
  // its default 5489 as 9981545732273789042 ([rand.predef]); the field's last cell is that draw.
  const double u = static_cast<double>(9981545732273789042ULL >> 11) * 0x1.0p-53;
  EXPECT_EQ(da.back(), 0.4 * u);
  // Cell geometry: the lowered centre sits below the base-plane centre by exactly its depth.
  const HeightField& f = a.statics.heightFields[0].field;
  EXPECT_EQ(f.lowCentre(3, 7), Vec3(3.5, 7.5, -f.depth(3, 7)));
}

TEST(SceneHeightField, DefaultSeedIsTheSceneSeed) {
  const std::string text = "seed: 99\n" +
                           sceneWith("bodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 2]}\n"
                                     "static:\n  - {type: heightfield, material: concrete, origin: [0, 0, 0], "
                                     "extent: [3, 2], max_depth: 1}\n");
  const Scene s = parseScene(text, kScenes, "t.yaml");
  const HeightField& f = s.statics.heightFields.at(0).field;
  EXPECT_EQ(f.seed, 99u);
  std::mt19937_64 rng(99);
  for (double d : f.depths) EXPECT_EQ(d, static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

TEST(SceneSlope, ProfileOfSeed001Toe) {
  // Toe 1.8 m high, 2 m top, 10 m base (seed 001), slope 1:2 to 10 m.
  StaticSlope s;
  s.origin = Vec2(0, 0);
  s.tanAlpha = 0.5;
  s.crestHeight = 10;
  s.toeHeight = 1.8;
  s.toeTopWidth = 2;
  s.toeBaseWidth = 10;
  const auto p = slopeProfile(s);
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p[0], Vec2(-10, -1.8));
  EXPECT_EQ(p[1], Vec2(-2, 0));
  EXPECT_EQ(p[2], Vec2(0, 0));
  EXPECT_EQ(p[3], Vec2(20, 10));
  EXPECT_EQ(slopeHeight(s, -50), -1.8);       // seabed
  EXPECT_NEAR(slopeHeight(s, -6), -0.9, 1e-15); // half way up the toe's front face
  EXPECT_EQ(slopeHeight(s, -1), 0.0);         // toe top
  EXPECT_EQ(slopeHeight(s, 4), 2.0);          // face
  EXPECT_EQ(slopeHeight(s, 35), 10.0);        // crest
}

TEST(SceneWarnings, NonFatalNotesAreCollected) {
  const std::string text = "shapes:\n  c: {generator: cube, seed: 4}\nmaterials:"
                           "\n  concrete: {density: 2400, friction: 0.75, restitution: 0.05, penalty: 1e6}\n"
                           "duration: 1\nbodies:\n  - {shape: c, dn: 1, material: concrete, position: [0, 0, 2]}\n"
                           "static:\n  - {type: heightfield, material: concrete, origin: [0, 0, 0], extent: [10.5, 4], "
                           "max_depth: 0.2}\n";
  const Scene s = parseScene(text, kScenes, "t.yaml");
  ASSERT_EQ(s.warnings.size(), 3u) << describeScene(s);
  EXPECT_CONTAINS(s.warnings[0], "t.yaml:4: materials.concrete.penalty = 1e6: outside 1e7..1e11 Pa");
  EXPECT_CONTAINS(s.warnings[1], "t.yaml:2: shapes.c.seed = 4: 'cube' is not a random shape");
  EXPECT_CONTAINS(s.warnings[2], "static[0].extent = [10.5, 4]: 10.5 m is not a whole number of 1 m cells: the field "
                                 "covers 10 m");
  EXPECT_EQ(s.statics.heightFields.at(0).field.cellsX, 10);
  EXPECT_EQ(s.statics.heightFields.at(0).field.cellsY, 4);
  // describeScene repeats them for the run log.
  EXPECT_CONTAINS(describeScene(s), "warnings (3):");
}

// --------------------------------------------------------------------------------------------
// Example files: the documented ones parse, and docs/scene-file.md shows them verbatim
// --------------------------------------------------------------------------------------------

TEST(SceneExamples, DocumentedExamplesParseAndMatchTheDocs) {
  const std::string docs = readText(std::filesystem::path(ARMOUR_TEST_DATA) / "../../docs/scene-file.md");
  ASSERT_FALSE(docs.empty());
  for (const char* name : {"block-on-slope.yaml", "dolos-pile.yaml"}) {
    const Scene s = readScene(kScenes / name);
    EXPECT_TRUE(s.warnings.empty()) << name << ": " << s.warnings.front();
    EXPECT_NE(docs.find(readText(kScenes / name)), std::string::npos) << name << " differs from the copy in docs/scene-file.md";
  }
  const Scene slope = readScene(kScenes / "block-on-slope.yaml");
  // The block's bottom face normal (body -z turned) is the slope's outward normal (-sin a, 0, cos a).
  const double a = std::atan(0.5);
  EXPECT_LT((slope.bodies[0].orientation * Vec3::UnitZ() - Vec3(-std::sin(a), 0, std::cos(a))).norm(), 1e-5);
  const Scene pile = readScene(kScenes / "dolos-pile.yaml");
  EXPECT_EQ(pile.bodies.size(), 12u);
  EXPECT_EQ(pile.statics.heightFields.at(0).field.cellsX, 10);
}

// --------------------------------------------------------------------------------------------
// Errors: file, line, key path, value and fix
// --------------------------------------------------------------------------------------------

TEST(SceneErrors, UnknownKeyNamesPathLineAndValidKeys) {
  const std::string e = errorFromFile(kScenes / "broken/unknown-key.yaml");
  EXPECT_CONTAINS(e, "unknown-key.yaml:13: bodies[1].orientaton: unknown key (did you mean 'orientation'?)");
  EXPECT_CONTAINS(e, "valid keys are: name, shape, volume, dn, scale, material, position, orientation, velocity, "
                     "angular_velocity, fixed, grid");
  const std::string top = errorFrom("durration: 1\n" + kMaterials);
  EXPECT_CONTAINS(top, "test.yaml:1: durration: unknown key (did you mean 'duration'?)");
  const std::string nested = errorFrom(oneBody(", grid: {count: [1, 1, 2], spacing: [0, 0, 2], jitter: 3}"));
  EXPECT_CONTAINS(nested, "bodies[0].grid.jitter: unknown key; valid keys are: count, spacing, rotation_jitter_deg");
  const std::string param =
      errorFrom(sceneWith("bodies:\n  - {shape: {generator: dolos, params: {wiast: 0.35}}, dn: 1, material: concrete, "
                          "position: [0, 0, 2]}\n"));
  EXPECT_CONTAINS(param, "bodies[0].shape.params.wiast: unknown key (did you mean 'waist'?); valid keys are: waist");
  const std::string slope = errorFrom(oneBody() + "static:\n  - {type: slope, material: concrete, tan: 0.5, "
                                                  "crest_height: 5, normal: [0, 0, 1]}\n");
  EXPECT_CONTAINS(slope, "test.yaml:7: static[0].normal: unknown key; valid keys are: type, name, material, origin");
}

TEST(SceneErrors, WrongType) {
  const std::string e = errorFrom(sceneWith("bodies:\n  - {shape: cube, dn: big, material: concrete, position: [0, 0, 0.5]}\n"));
  EXPECT_CONTAINS(e, "test.yaml:5: bodies[0].dn = big: expected a number (unit: m), e.g. dn: 1.71");
  const std::string v = errorFrom(sceneWith("bodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0]}\n"));
  EXPECT_CONTAINS(v, "bodies[0].position = [0, 0]: expected a list of 3 numbers (unit: m)");
  const std::string b = errorFrom(oneBody(", fixed: maybe"));
  EXPECT_CONTAINS(b, "bodies[0].fixed = maybe: expected true or false");
  const std::string i = errorFrom("seed: -3\n" + oneBody());
  EXPECT_CONTAINS(i, "test.yaml:1: seed = -3: expected an integer >= 0");
  EXPECT_CONTAINS(errorFrom("duration: 1\n" + oneBody()), "test.yaml:2: duration: key given twice; keep one");
  const std::string m = errorFrom("duration: 1\nmaterials: [concrete]\n");
  EXPECT_CONTAINS(m, "test.yaml:2: materials: expected a mapping of material names");
}

TEST(SceneErrors, MissingRequiredKey) {
  const std::string e = errorFrom(sceneWith("bodies:\n  - {shape: cube, dn: 1, material: concrete}\n"));
  EXPECT_CONTAINS(e, "test.yaml:5: bodies[0]: missing key 'position': a list of 3 numbers (unit: m)");
  const std::string d = errorFrom(kMaterials + "bodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 1]}\n");
  EXPECT_CONTAINS(d, "missing key 'duration': a number (unit: s)");
  const std::string size = errorFrom(sceneWith("bodies:\n  - {shape: cube, material: concrete, position: [0, 0, 1]}\n"));
  EXPECT_CONTAINS(size, "bodies[0]: give one of 'volume' or 'dn'");
  const std::string noBodies = errorFrom("duration: 1\n" + kMaterials);
  EXPECT_CONTAINS(noBodies, "bodies: missing: list at least one body");
  const std::string dissipation =
      errorFrom("duration: 1\nmaterials:\n  concrete: {density: 2400, friction: 0.75}\nbodies: []\n");
  EXPECT_CONTAINS(dissipation, "test.yaml:3: materials.concrete: give one of 'restitution' or 'damping_ratio'");
}

TEST(SceneErrors, OutOfRangeValues) {
  const std::string density = errorFromFile(kScenes / "broken/negative-density.yaml");
  EXPECT_CONTAINS(density, "negative-density.yaml:4: materials.concrete.density = -2400: must be > 0 (unit: kg/m^3), "
                           "e.g. 2400 for concrete");
  const auto material = [](const std::string& body) {
    return "duration: 1\nmaterials:\n  concrete: {" + body +
           "}\nbodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 0.5]}\n";
  };
  EXPECT_CONTAINS(errorFrom(material("density: 2400, friction: -0.1, restitution: 0.05")),
                  "test.yaml:3: materials.concrete.friction = -0.1: must be >= 0 (unit: -)");
  EXPECT_CONTAINS(errorFrom(material("density: 2400, friction: 0.7, restitution: 1.5")),
                  "materials.concrete.restitution = 1.5: must be in (0, 1] (unit: -)");
  EXPECT_CONTAINS(errorFrom(material("density: 2400, friction: 0.7, restitution: 0")),
                  "materials.concrete.restitution = 0: must be in (0, 1] (unit: -)");
  EXPECT_CONTAINS(errorFrom(material("density: 2400, friction: {static: 0.5, dynamic: 0.6}, restitution: 0.1")),
                  "materials.concrete.friction: dynamic = 0.6 exceeds static = 0.5");
  EXPECT_CONTAINS(errorFrom(material("density: 2400, friction: 0.7, restitution: 0.1, damping_ratio: 0.2")),
                  "materials.concrete: give only one of 'restitution' or 'damping_ratio'");
  EXPECT_CONTAINS(errorFrom(material("density: .nan, friction: 0.7, restitution: 0.1")),
                  "materials.concrete.density = .nan: must be a finite number (unit: kg/m^3)");
  EXPECT_CONTAINS(errorFrom(material("density: nan, friction: 0.7, restitution: 0.1")),
                  "materials.concrete.density = nan: must be a finite number");
  EXPECT_CONTAINS(errorFrom("time_step: 0\n" + oneBody()), "test.yaml:1: time_step = 0: must be > 0 (unit: s), e.g. "
                                                           "time_step: 1e-4, or time_step: auto");
  EXPECT_CONTAINS(errorFrom("time_step: -1e-3\n" + oneBody()), "time_step = -1e-3: must be > 0 (unit: s)");
  EXPECT_CONTAINS(errorFrom("time_step: automatic\n" + oneBody()), "time_step = automatic: expected a number (unit: s)");
  EXPECT_CONTAINS(errorFrom(oneBody(", velocity: [0, .inf, 0]")), "bodies[0].velocity[1] = .inf: must be a finite number");
  // A number beyond the range of a double is out of range, not "expected a number" (issue 23,
  // item 13); one too small for a double reads as 0, as everywhere else.
  EXPECT_CONTAINS(errorFrom(material("density: 1e999, friction: 0.7, restitution: 0.1")),
                  "materials.concrete.density = 1e999: out of range: beyond 1.79769e+308, the largest number a double "
                  "holds; give a value of this key's size (unit: kg/m^3), e.g. 2400 for concrete, 2650 for rock");
  EXPECT_CONTAINS(errorFrom(oneBody(", velocity: [0, -2e400, 0]")), "bodies[0].velocity[1] = -2e400: out of range");
  EXPECT_CONTAINS(errorFrom(material("density: 1e-999, friction: 0.7, restitution: 0.1")),
                  "materials.concrete.density = 1e-999: must be > 0");
  EXPECT_CONTAINS(errorFrom(sceneWith("bodies:\n  - {shape: {generator: dolos, params: {waist: 0.5}}, dn: 1, "
                                      "material: concrete, position: [0, 0, 2]}\n")),
                  "bodies[0].shape.params.waist = 0.5: must be in [0.32, 0.42] (unit: -)");
  EXPECT_CONTAINS(errorFrom(oneBody(", grid: {count: [3, 1, 1], spacing: [0, 0, 0]}")),
                  "bodies[0].grid.spacing = [0, 0, 0]: spacing along x must be > 0 when count along it is 3");
  EXPECT_CONTAINS(errorFrom(oneBody(", grid: {count: [0, 1, 1], spacing: [1, 1, 1]}")),
                  "bodies[0].grid.count[0] = 0: expected an integer >= 1");
  EXPECT_CONTAINS(errorFrom(oneBody() + "static:\n  - {type: slope, material: concrete, tan: 0.5, crest_height: 5, "
                                        "toe_height: 1, toe_top_width: 3, toe_base_width: 2}\n"),
                  "static[0].toe_base_width = 2: must be >= toe_top_width = 3 m");
  EXPECT_CONTAINS(errorFrom("body_damping: {linear: -0.9}\n" + oneBody()),
                  "body_damping.linear = -0.9: must be >= 0 (unit: 1/s), e.g. 0.9 (seed 001)");
}

TEST(SceneErrors, UnknownNamesListTheValidOnes) {
  const std::string m = errorFromFile(kScenes / "broken/unknown-material.yaml");
  EXPECT_CONTAINS(m, "unknown-material.yaml:7: bodies[1].material = granite: unknown material; defined materials are: "
                     "concrete, rock");
  const std::string s = errorFrom("shapes:\n  mine: {generator: cube}\n" +
                                  sceneWith("bodies:\n  - {shape: dollos, dn: 1, material: concrete, position: [0, 0, 1]}\n"));
  EXPECT_CONTAINS(s, "bodies[0].shape = dollos: unknown shape (did you mean 'dolos'?); the shape library has: cube, "
                     "antifer, dolos");
  EXPECT_CONTAINS(s, "named shapes: mine");
  const std::string g = errorFrom("shapes:\n  mine: {generator: cubee}\n" + oneBody());
  EXPECT_CONTAINS(g, "test.yaml:2: shapes.mine.generator = cubee: unknown generator (did you mean 'cube'?)");
  const std::string t = errorFrom(oneBody() + "static:\n  - {type: plain, material: concrete}\n");
  EXPECT_CONTAINS(t, "test.yaml:7: static[0].type = plain: unknown static type (did you mean 'plane'?); valid types "
                     "are: plane, slope, heightfield, wall, mesh");
  const std::string w = errorFrom(oneBody() + "static:\n  - {type: wall, material: concrete, axis: z, position: 0, side: min}\n");
  EXPECT_CONTAINS(w, "static[0].axis = z: expected one of x, y");
}

TEST(SceneErrors, YamlSyntaxErrorNamesTheLine) {
  const std::string e = errorFromFile(kScenes / "broken/syntax-error.yaml");
  // The unclosed "{" on line 3 is detected where the parser gives up, on line 4.
  EXPECT_CONTAINS(e, "syntax-error.yaml:4:");
  EXPECT_CONTAINS(e, "YAML syntax error");
  const std::string tab = errorFrom("duration: 1\nmaterials:\n  concrete: {density: 2400\n  friction: [0.75\n");
  EXPECT_CONTAINS(tab, "test.yaml:");
  EXPECT_CONTAINS(errorFrom(""), "test.yaml: the scene is empty");
  EXPECT_CONTAINS(errorFrom("just text"), "test.yaml: expected a mapping of key: value at the top of the file, found "
                                          "'just text'; valid keys are: description, seed");
}

TEST(SceneErrors, MissingMeshNamesTheResolvedPath) {
  const std::string e = errorFromFile(kScenes / "broken/missing-mesh.yaml");
  const std::string resolved = std::filesystem::absolute(kScenes / "meshes/no-such-unit.stl").lexically_normal().string();
  EXPECT_CONTAINS(e, "missing-mesh.yaml:5: bodies[0].shape.mesh = ../meshes/no-such-unit.stl: mesh file not found: " + resolved);
  const std::string ext = errorFrom(sceneWith("bodies:\n  - {shape: {mesh: every-feature.yaml}, material: concrete, "
                                              "position: [0, 0, 1]}\n"));
  EXPECT_CONTAINS(ext, "bodies[0].shape.mesh = every-feature.yaml:");
  const std::string file = errorFrom(oneBody() + "static:\n  - {type: mesh, material: concrete, file: nothing.obj}\n");
  EXPECT_CONTAINS(file, "static[0].file = nothing.obj: mesh file not found: " +
                            std::filesystem::absolute(kScenes / "nothing.obj").lexically_normal().string());
  EXPECT_CONTAINS(errorFromFile(kScenes / "no-such-scene.yaml"), "no-such-scene.yaml: cannot open the scene file");
}

TEST(SceneErrors, BadRotationsAreRefused) {
  EXPECT_CONTAINS(errorFrom(oneBody(", orientation: {quaternion: [0, 0, 0, 0]}")),
                  "test.yaml:5: bodies[0].orientation.quaternion = [0, 0, 0, 0]: a zero quaternion is not a rotation");
  EXPECT_CONTAINS(errorFrom(oneBody(", orientation: {quaternion: [.nan, 0, 0, 1]}")),
                  "bodies[0].orientation.quaternion[0] = .nan: must be a finite number");
  EXPECT_CONTAINS(errorFrom(oneBody(", orientation: {quaternion: [1, 0, 0, 0], euler_deg: [0, 0, 0]}")),
                  "bodies[0].orientation: give only one of 'quaternion' or 'euler_deg'");
  EXPECT_CONTAINS(errorFrom(oneBody(", orientation: {}")), "bodies[0].orientation: give one of 'quaternion' or 'euler_deg'");
  EXPECT_CONTAINS(errorFrom(oneBody() + "static:\n  - {type: plane, material: concrete, normal: [0, 0, 0]}\n"),
                  "static[0].normal = [0, 0, 0]: a zero normal has no direction");
}

TEST(SceneErrors, InconsistentBodies) {
  EXPECT_CONTAINS(errorFrom(oneBody(", scale: 2")), "bodies[0].scale: 'scale' applies to mesh files only");
  EXPECT_CONTAINS(errorFrom(oneBody(", fixed: true, velocity: [1, 0, 0]")),
                  "bodies[0]: a fixed body does not move: remove 'velocity'");
  EXPECT_CONTAINS(errorFrom(sceneWith("bodies:\n  - {name: a, shape: cube, dn: 1, material: concrete, position: [0, 0, 1]}\n"
                                      "  - {name: a, shape: cube, dn: 1, material: concrete, position: [0, 0, 3]}\n")),
                  "test.yaml:6: bodies[1].name = a: duplicate body name (also bodies[0])");
  EXPECT_CONTAINS(errorFrom(sceneWith("bodies:\n  - {name: p_0_0_1, shape: cube, dn: 1, material: concrete, position: [0, 0, 9]}\n"
                                      "  - {name: p, shape: cube, dn: 1, material: concrete, position: [0, 0, 1], "
                                      "grid: {count: [1, 1, 2], spacing: [0, 0, 2]}}\n")),
                  "bodies[1].name = p_0_0_1: duplicate body name (also bodies[0])");
  EXPECT_CONTAINS(errorFrom("shapes:\n  m: {mesh: meshes/block.stl, seed: 3}\n" + oneBody()),
                  "shapes.m.seed: 'seed' applies to random generators only");
  EXPECT_CONTAINS(errorFrom("shapes:\n  dolos: {generator: dolos}\n" + oneBody()),
                  "shapes.dolos: 'dolos' is a shape-library name");
  EXPECT_CONTAINS(errorFrom(sceneWith("bodies:\n  - {shape: {mesh: meshes/block.stl}, volume: 2, dn: 1, "
                                      "material: concrete, position: [0, 0, 1]}\n")),
                  "bodies[0]: give only one of 'volume' or 'dn' or 'scale'");
}

TEST(SceneErrors, EveryBrokenExampleIsRefused) {
  std::size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kScenes / "broken")) {
    EXPECT_THROW((void)readScene(entry.path()), InputError) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 5u);
}

} // namespace

// ---------------------------------------------------------------------------------------------
// hydro: the loads block
// ---------------------------------------------------------------------------------------------

TEST(SceneHydro, AbsentMeansNoLoads) {
  const Scene s = parseScene(oneBody(), kScenes, "dry.yaml");
  EXPECT_FALSE(s.hydro.enabled);
  EXPECT_EQ(s.sleep.wakeLoadFraction, 0.01);
  EXPECT_CONTAINS(describeScene(s), "hydro: none");
}

TEST(SceneHydro, StormBlockWithDefaults) {
  const Scene s = parseScene(oneBody() + "seed: 9\nhydro:\n  storm: {file: storms/s.nc}\n", kScenes, "wet.yaml");
  ASSERT_TRUE(s.hydro.enabled);
  EXPECT_EQ(s.hydro.model, armour::hydro::HydroModel::Storm);
  EXPECT_EQ(s.hydro.bodies, "all");
  const auto& st = s.hydro.storm;
  EXPECT_EQ(st.file, std::filesystem::absolute(kScenes / "storms/s.nc").lexically_normal().string());
  EXPECT_EQ(st.timeOffset, 0.0);
  EXPECT_EQ(st.updateInterval, 0.1);
  EXPECT_EQ(st.betweenUpdates, armour::hydro::BetweenUpdates::Hold);
  EXPECT_EQ(st.wetAlpha, 0.5);
  EXPECT_EQ(st.elementSizePerDn, 0.1);
  EXPECT_TRUE(st.pressure);
  EXPECT_TRUE(st.variability.enabled);
  EXPECT_EQ(st.variability.seed, 9u) << "the variability seed defaults to the scene seed";
  EXPECT_EQ(st.variability.patchesPerAxis, 2);
  EXPECT_TRUE(st.drag.enabled);
  EXPECT_EQ(st.drag.coefficient, 1.0);
  EXPECT_FALSE(st.addedMass.enabled);
  const std::string text = describeScene(s);
  EXPECT_CONTAINS(text, "model = storm");
  EXPECT_CONTAINS(text, "update_interval = 0.1 s");
  EXPECT_EQ(st.rampTime, 0.0) << "no ramp unless asked";
  EXPECT_CONTAINS(text, "ramp_time = 0 s");
  EXPECT_CONTAINS(text, "offset = [0, 0] m");
}

TEST(SceneHydro, EverySettingIsRead) {
  const Scene s = parseScene(oneBody() + R"(hydro:
  bodies: unit_
  storm:
    file: s.nc
    time_offset: 120
    offset: [104, -3.5]
    update_interval: 0.05
    ramp_time: 1.5
    between_updates: interpolate
    wet_alpha: 0.4
    element_size: 0.2
    pressure: false
    variability: {enabled: false, seed: 3, patches_per_axis: 3}
    drag: {enabled: false, coefficient: 1.5}
    added_mass: {enabled: true, coefficient: 0.8}
)", kScenes, "wet.yaml");
  const auto& st = s.hydro.storm;
  EXPECT_EQ(s.hydro.bodies, "unit_");
  EXPECT_EQ(st.timeOffset, 120.0);
  EXPECT_EQ(st.offsetX, 104.0);
  EXPECT_EQ(st.offsetZ, -3.5);
  EXPECT_EQ(st.updateInterval, 0.05);
  EXPECT_EQ(st.rampTime, 1.5);
  EXPECT_EQ(st.betweenUpdates, armour::hydro::BetweenUpdates::Interpolate);
  EXPECT_EQ(st.wetAlpha, 0.4);
  EXPECT_EQ(st.elementSizePerDn, 0.2);
  EXPECT_FALSE(st.pressure);
  EXPECT_FALSE(st.variability.enabled);
  EXPECT_EQ(st.variability.seed, 3u);
  EXPECT_EQ(st.variability.patchesPerAxis, 3);
  EXPECT_FALSE(st.drag.enabled);
  EXPECT_EQ(st.drag.coefficient, 1.5);
  EXPECT_TRUE(st.addedMass.enabled);
  EXPECT_EQ(st.addedMass.coefficient, 0.8);
}

TEST(SceneHydro, AnalyticModels) {
  const Scene o = parseScene(oneBody() + R"(hydro:
  model: oscillating
  oscillating: {amplitude: 5e4, period: 10, wave_number: 0.06, z_min: 5.658, z_swl: 15.568, z_max: 23.568, waves: 12}
)", kScenes, "osc.yaml");
  EXPECT_EQ(o.hydro.model, armour::hydro::HydroModel::Oscillating);
  EXPECT_EQ(o.hydro.oscillating.amplitude, 5e4);
  EXPECT_EQ(o.hydro.oscillating.zSwl, 15.568);
  EXPECT_EQ(o.hydro.oscillating.waves, 12.0);
  const Scene w = parseScene(oneBody() + R"(hydro:
  model: shallow_wave
  shallow_wave: {amplitude: 2e4, cot: 2, toe_x: 3, depth_at_toe: 12}
)", kScenes, "sw.yaml");
  EXPECT_EQ(w.hydro.model, armour::hydro::HydroModel::ShallowWave);
  EXPECT_NEAR(w.hydro.shallowWave.slopeAngle, std::atan(0.5), kRoundOff);
  EXPECT_NEAR(w.hydro.shallowWave.angularFrequency, std::numbers::pi, 1e-5);
  EXPECT_EQ(w.hydro.shallowWave.toeX, 3.0);
  EXPECT_EQ(w.hydro.shallowWave.depthAtToe, 12.0);
}

TEST(SceneHydro, ErrorsNameTheKeyAndTheFix) {
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  model: storm\n"), "missing key 'storm'");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {fiel: s.nc}\n"), "hydro.storm.fiel: unknown key");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, update_interval: 0}\n"),
                  "hydro.storm.update_interval = 0: must be > 0");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, ramp_time: -1}\n"),
                  "hydro.storm.ramp_time = -1: must be >= 0");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, offset: [104]}\n"), "hydro.storm.offset");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, between_updates: smooth}\n"),
                  "expected one of hold, interpolate");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  model: wind\n"), "expected one of storm, oscillating, shallow_wave");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc}\n  oscillating: {amplitude: 1}\n"),
                  "hydro.oscillating: settings of model 'oscillating', but hydro.model is 'storm'");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  model: oscillating\n  oscillating: {amplitude: 1, period: 10, "
                                        "z_min: 5, z_swl: 4, z_max: 9}\n"),
                  "needs z_min < z_swl < z_max");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, variability: {patches_per_axis: 9}}\n"),
                  "must be <= 8");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  model: shallow_wave\n  shallow_wave: {amplitude: 1, toe_x: 0, "
                                        "depth_at_toe: 12}\n"),
                  "give one of 'angle_deg' or 'tan' or 'cot'");
}

TEST(SceneHydro, BedIsPorousByDefaultAndImpermeableTakesItsLevel) {
  // Default: porous (every element loaded), as before the switch existed.
  const Scene porous = parseScene(oneBody() + "hydro:\n  storm: {file: s.nc}\n", kScenes, "wet.yaml");
  EXPECT_EQ(porous.hydro.storm.bed.kind, armour::hydro::BedKind::Porous);
  EXPECT_EQ(describeScene(porous).find("bed ="), std::string::npos)
      << "the default is not printed: the checkpoint fingerprint of a porous-bed scene does not change";
  // Impermeable with an explicit level and tolerance.
  const Scene given = parseScene(
      oneBody() + "hydro:\n  storm: {file: s.nc, bed: impermeable, bed_level: -2.5, bed_tolerance: 0.02}\n", kScenes,
      "wet.yaml");
  EXPECT_EQ(given.hydro.storm.bed.kind, armour::hydro::BedKind::Impermeable);
  EXPECT_EQ(given.hydro.storm.bed.level, -2.5);
  EXPECT_EQ(given.hydro.storm.bed.toleranceDn, 0.02);
  EXPECT_CONTAINS(describeScene(given), "bed = impermeable, bed_level = -2.5 m, bed_tolerance = 0.02 Dn");
  // Impermeable without a level: the scene's one horizontal static plane (walls do not count).
  const Scene plane = parseScene(oneBody() + "static:\n  - {type: plane, material: concrete, point: [0, 0, 0.75]}\n"
                                             "  - {type: wall, material: concrete, axis: x, position: -3, side: min}\n"
                                             "hydro:\n  storm: {file: s.nc, bed: impermeable}\n",
                                 kScenes, "wet.yaml");
  EXPECT_EQ(plane.hydro.storm.bed.level, 0.75);
  EXPECT_EQ(plane.hydro.storm.bed.toleranceDn, 0.01) << "the default tolerance";
}

TEST(SceneHydro, BedErrorsNameTheKeyTheValueAndTheFix) {
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, bed: sealed}\n"),
                  "hydro.storm.bed = sealed: expected one of porous, impermeable");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, bed_level: 0}\n"),
                  "hydro.storm.bed_level: used only with bed: impermeable");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, bed: impermeable, bed_level: 0, "
                                        "bed_tolerance: -0.1}\n"),
                  "hydro.storm.bed_tolerance = -0.1: must be in [0, 1]");
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, bed: impermeable, bed_level: .nan}\n"),
                  "hydro.storm.bed_level");
  // No level and no horizontal plane to take it from.
  EXPECT_CONTAINS(errorFrom(oneBody() + "hydro:\n  storm: {file: s.nc, bed: impermeable}\n"),
                  "missing key 'bed_level': the z of the impermeable bed (m); it is taken from the scene's horizontal "
                  "static plane when there is exactly one, and the scene has 0");
}

// --set KEY=VALUE (io/SceneOverrides): a changed setting reads as if the file said it; missing
// blocks are created; list items are reached by index; bad paths and values name the option.
std::string overrideError(const std::string& yaml, const std::vector<std::string>& sets) {
  try {
    (void)parseScene(yaml, kScenes, "test.yaml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for the overrides of:\n" << yaml;
  return {};
}

TEST(SceneOverrides, ChangeValuesCreateBlocksAndReachListItems) {
  const std::string yaml = "duration: 2\nmaterials:\n  concrete: {density: 2400, friction: 0.6, restitution: 0.1}\n"
                           "static:\n  - {type: plane, name: floor, material: concrete, point: [0, 0, 0], "
                           "normal: [0, 0, 1]}\n"
                           "bodies:\n  - {shape: cube, volume: 1, material: concrete, position: [0, 0, 1]}\n";
  const Scene base = parseScene(yaml, kScenes, "t.yaml");
  const Scene s = parseScene(yaml, kScenes, "t.yaml",
                             {"duration=7.5", "contact.model=fdem", "materials.concrete.friction=0.8",
                              "bodies[0].position=[1, 2, 3]", "static[0].normal=[0, 0.6, 0.8]", "seed=42"});
  EXPECT_EQ(base.duration, 2.0);
  EXPECT_EQ(s.duration, 7.5);
  EXPECT_EQ(s.contact.model, ContactModel::Fdem); // the contact block did not exist: created
  EXPECT_EQ(s.materials[0].frictionStatic, 0.8);
  EXPECT_EQ(s.bodies[0].position, Vec3(1, 2, 3));
  EXPECT_EQ(s.seed, 42u);
  // The last --set of a key wins, as on a command line.
  EXPECT_EQ(parseScene(yaml, kScenes, "t.yaml", {"duration=3", "duration=4"}).duration, 4.0);
  // The overrides go through the same schema checks as the file.
  EXPECT_CONTAINS(overrideError(yaml, {"contact.modle=fdem"}), "contact.modle: unknown key (did you mean 'model'?)");
  EXPECT_CONTAINS(overrideError(yaml, {"duration=-1"}), "duration = -1: must be > 0");
}

TEST(SceneOverrides, BadOptionsNameTheOptionAndTheFix) {
  const std::string yaml = oneBody();
  EXPECT_CONTAINS(overrideError(yaml, {"duration"}), "--set duration: give KEY=VALUE");
  EXPECT_CONTAINS(overrideError(yaml, {"duration="}), "--set duration=: the value is empty");
  EXPECT_CONTAINS(overrideError(yaml, {"hydro..file=x"}), "has an empty part");
  EXPECT_CONTAINS(overrideError(yaml, {"bodies[3].volume=2"}), "'bodies' has 1 items; give an index from 0 to 0");
  EXPECT_CONTAINS(overrideError(yaml, {"bodies[x].volume=2"}), "a list index is a whole number in brackets");
  EXPECT_CONTAINS(overrideError(yaml, {"duration.value=2"}), "'duration' is a single value or a list in the scene");
  EXPECT_CONTAINS(overrideError(yaml, {"materials[0].density=2"}), "'materials' is not a list in the scene");
  EXPECT_CONTAINS(overrideError(yaml, {"gravity=[0, 0"}), "is not valid YAML");
}

TEST(SceneContactSolver, ConstraintSettingsAreReadAndBadOnesNamed) {
  // contact.solver and contact.constraint (issue 22): read with their defaults, refused with the
  // key, the value and the fix when out of range or combined with the fdem model.
  const Scene d = parseScene(oneBody(), kScenes, "t.yaml");
  EXPECT_EQ(d.contact.solver, ContactSolver::Penalty);
  const Scene c = parseScene("contact: {solver: constraint, constraint: {time_step: 0.01, substeps: 8}}\n" + oneBody(),
                             kScenes, "t.yaml");
  EXPECT_EQ(c.contact.solver, ContactSolver::Constraint);
  EXPECT_DOUBLE_EQ(c.contact.constraint.timeStep, 0.01);
  EXPECT_EQ(c.contact.constraint.substeps, 8u);
  EXPECT_DOUBLE_EQ(c.contact.constraint.dampingRatio, 10.0);
  EXPECT_FALSE(c.contact.constraint.frictionAnchors) << "friction anchors are off by default";
  const Scene a = parseScene("contact: {solver: constraint, constraint: {friction_anchors: true}}\n" + oneBody(),
                             kScenes, "t.yaml");
  EXPECT_TRUE(a.contact.constraint.frictionAnchors);
  // Manifold reuse: 0.001 Dn, at most half the speculative margin (else a contact could appear unseen).
  EXPECT_DOUBLE_EQ(c.contact.constraint.reuseDistance, 0.001);
  const Scene small = parseScene("contact: {solver: constraint, constraint: {speculative_margin: 0.001}}\n" + oneBody(),
                                 kScenes, "t.yaml");
  EXPECT_DOUBLE_EQ(small.contact.constraint.reuseDistance, 0.0005) << "the default follows a small margin";
  const std::string reuse = errorFrom("contact: {solver: constraint, constraint: {reuse_distance: 0.03}}\n" + oneBody());
  EXPECT_NE(reuse.find("contact.constraint.reuse_distance"), std::string::npos) << reuse;
  EXPECT_NE(reuse.find("0.025"), std::string::npos) << "the limit: half the margin of 0.05 Dn; " << reuse;
  const std::string fdem = errorFrom("contact: {model: fdem, solver: constraint}\n" + oneBody());
  EXPECT_NE(fdem.find("contact.solver"), std::string::npos) << fdem;
  EXPECT_NE(fdem.find("use contact.model: levelset"), std::string::npos) << fdem;
  const std::string step = errorFrom("contact: {solver: constraint, constraint: {time_step: 0.1}}\n" + oneBody());
  EXPECT_NE(step.find("contact.constraint.time_step"), std::string::npos) << step;
  const std::string sub = errorFrom("contact: {solver: constraint, constraint: {substeps: 100}}\n" + oneBody());
  EXPECT_NE(sub.find("at most 64 substeps"), std::string::npos) << sub;
}

TEST(SceneContactSolver, DashpotIsReadAndABadOneNamed) {
  // contact.dashpot (issue 22 part 3): explicit by default, implicit when asked; another word is
  // refused naming the key, the value and the choices; the scene's description (its checkpoint
  // fingerprint) names it only when implicit.
  const Scene d = parseScene(oneBody(), kScenes, "t.yaml");
  EXPECT_EQ(d.contact.dashpot, ContactDashpot::Explicit);
  EXPECT_EQ(describeScene(d).find("dashpot"), std::string::npos);
  const Scene i = parseScene("contact: {dashpot: implicit}\n" + oneBody(), kScenes, "t.yaml");
  EXPECT_EQ(i.contact.dashpot, ContactDashpot::Implicit);
  EXPECT_NE(describeScene(i).find("dashpot = implicit"), std::string::npos);
  const std::string bad = errorFrom("contact: {dashpot: semi}\n" + oneBody());
  EXPECT_NE(bad.find("contact.dashpot"), std::string::npos) << bad;
  EXPECT_NE(bad.find("semi"), std::string::npos) << bad;
  EXPECT_NE(bad.find("implicit"), std::string::npos) << "the choices: " << bad;
}
