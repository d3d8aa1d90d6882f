// SPDX-License-Identifier: GPL-3.0-or-later
// The shape registry as a whole: every generator meets its requested volume (the library promises
// 0.1 %; scaling makes it exact, so 1e-9 is asserted), yields a valid solid centred on its centroid,
// and the library refuses bad requests with messages that list the valid choices.

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace armour::geometry;
using armour::core::InputError;

namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class EveryGenerator : public ::testing::TestWithParam<std::string> {};

} // namespace

TEST(ShapeLibrary, RegistryIsComplete) {
  std::set<std::string> names;
  for (const auto& g : shapeGenerators()) {
    EXPECT_TRUE(names.insert(g.name).second) << "duplicate name " << g.name;
    EXPECT_FALSE(g.summary.empty()) << g.name;
    EXPECT_FALSE(g.proportions.empty()) << g.name << ": document the proportions";
    EXPECT_FALSE(g.source.empty()) << g.name << ": document the source";
    for (const auto& p : g.parameters) {
      EXPECT_LE(p.min, p.defaultValue) << g.name << "." << p.name;
      EXPECT_LE(p.defaultValue, p.max) << g.name << "." << p.name;
      EXPECT_FALSE(p.unit.empty()) << g.name << "." << p.name << ": every parameter states its unit";
    }
  }
  for (const char* required : {"cube", "antifer", "dolos", "coreloc", "accropode", "xbloc", "tetrapod", "cubipod",
                               "vcross", "vrcross", "rock", "voronoi-rock"}) {
    EXPECT_TRUE(names.count(required)) << "missing generator " << required;
  }
}

TEST_P(EveryGenerator, HitsRequestedVolumeAndIsValid) {
  for (double volume : {0.001, 5.0, 16.0}) { // a flume model unit, seed 000's Core-Loc, seed 003's Antifer
    ShapeRequest request;
    request.volume = volume;
    request.seed = 7;
    const TriangleMesh mesh = makeShape(GetParam(), request);
    const MassProperties mp = computeMassProperties(mesh);
    EXPECT_NEAR(mp.volume, volume, 1e-9 * volume) << GetParam();
    EXPECT_LT(mp.centroid.norm(), 1e-9 * mp.nominalDiameter()) << GetParam() << ": centroid at the origin";
    const MeshInspection inspection = inspectMesh(mesh);
    EXPECT_TRUE(inspection.valid()) << GetParam();
    EXPECT_EQ(inspection.components, 1u) << GetParam();
    EXPECT_GE(mesh.triangleCount(), 12u);
    EXPECT_LE(mesh.triangleCount(), 20000u) << GetParam() << ": keep unit meshes light";
  }
}

TEST_P(EveryGenerator, VolumeInvariantUnderRigidTransform) {
  ShapeRequest request;
  request.volume = 8.0;
  TriangleMesh mesh = makeShape(GetParam(), request);
  transform(mesh, armour::test::someRotation(), Vec3(250.0, -40.0, 12.0));
  EXPECT_NEAR(computeMassProperties(mesh).volume, 8.0, 1e-10 * 8.0) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Library, EveryGenerator, ::testing::ValuesIn([] {
                           std::vector<std::string> names;
                           for (const auto& g : shapeGenerators()) {
                             names.push_back(g.name);
                           }
                           return names;
                         }()),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

TEST(ShapeLibrary, CubeAspectRatios) {
  ShapeRequest request;
  request.volume = 6.0;
  request.params = {{"aspect_y", 2.0}, {"aspect_z", 3.0}};
  const auto box = makeShape("cube", request).bounds().size();
  EXPECT_NEAR(box.x(), 1.0, 1e-12);
  EXPECT_NEAR(box.y(), 2.0, 1e-12);
  EXPECT_NEAR(box.z(), 3.0, 1e-12);
}

TEST(ShapeLibrary, BadRequestsAreRefusedWithTheFix) {
  ShapeRequest ok;
  EXPECT_NE(errorOf([&] { makeShape("tetrahedron", ok); }).find("valid shapes are: cube, antifer"), std::string::npos);
  ShapeRequest unknownParam;
  unknownParam.params = {{"waist", 0.3}};
  const auto msg = errorOf([&] { makeShape("cube", unknownParam); });
  EXPECT_NE(msg.find("unknown parameter 'waist'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("aspect_y, aspect_z"), std::string::npos) << msg;
  ShapeRequest outOfRange;
  outOfRange.params = {{"aspect_y", 100.0}};
  EXPECT_NE(errorOf([&] { makeShape("cube", outOfRange); }).find("outside its range [0.05, 20]"), std::string::npos);
  ShapeRequest negative;
  negative.volume = -1.0;
  EXPECT_NE(errorOf([&] { makeShape("cube", negative); }).find("must be positive"), std::string::npos);
  ShapeRequest nan;
  nan.volume = std::nan("");
  EXPECT_NE(errorOf([&] { makeShape("cube", nan); }).find("must be positive"), std::string::npos);
}
