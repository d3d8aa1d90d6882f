// SPDX-License-Identifier: GPL-3.0-or-later
// Regression references (issue 27): a few computed quantities kept in small files, so that a
// change that should not change the physics (a refactor, a faster loop) is seen to change nothing.
//  - contact forces: the contact patches of a small fixed scene (units on a floor and on each
//    other, overlapping by millimetres), evaluated without a step, by both contact models;
//  - storm loads: the force and moment of the storm stage on three units in a travelling wave
//    with drag, at a few times.
// Each value must match its reference within 1e-9 of the case's largest value: far above the
// round-off of a changed summation order (threads, a reordered loop), far below any change of
// the model. A change that is meant to change these numbers regenerates the files and says why
// in its commit (tests/data/regression/README.md):
//
//   ARMOUR_REGENERATE_REFERENCES=1 build/tests/test_regression_references
#include "support/HydroFixtures.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace armour;
using namespace armour::test;
using armour::hydro::StormLoads;
namespace fs = std::filesystem;

const fs::path kReferences = fs::path(ARMOUR_TEST_DATA) / "regression";

/// Values by key, in the order they were computed.
using Values = std::vector<std::pair<std::string, double>>;

bool regenerating() {
  const char* v = std::getenv("ARMOUR_REGENERATE_REFERENCES");
  return v != nullptr && std::string(v) == "1";
}

/// Compare `values` with the reference file `name` (or write it when regenerating).
void expectReference(const std::string& name, const Values& values) {
  const fs::path path = kReferences / name;
  if (regenerating()) {
    std::ofstream out(path);
    out << "key,value\n";
    for (const auto& [key, value] : values) out << fmt::format("{},{:.17g}\n", key, value);
    GTEST_SKIP() << "wrote " << path.string();
  }
  std::ifstream in(path);
  ASSERT_TRUE(in) << path.string() << " is missing: ARMOUR_REGENERATE_REFERENCES=1 writes it";
  std::string line;
  std::getline(in, line);
  Values reference;
  while (std::getline(in, line)) {
    const std::size_t comma = line.rfind(',');
    reference.emplace_back(line.substr(0, comma), std::stod(line.substr(comma + 1)));
  }
  ASSERT_EQ(reference.size(), values.size()) << path.string() << ": another number of values (the scene's "
                                                                   "contacts or the model changed)";
  double scale = 0.0;
  for (const auto& [key, value] : reference) scale = std::max(scale, std::abs(value));
  for (std::size_t i = 0; i < values.size(); ++i) {
    EXPECT_EQ(values[i].first, reference[i].first) << path.string() << " line " << i + 2;
    EXPECT_NEAR(values[i].second, reference[i].second, 1e-9 * scale) << path.string() << ": " << values[i].first;
  }
}

/// A body of library shape `name` whose lowest vertex sits `depth` below the height `top` at
/// (x, y): it touches what lies there by that overlap only.
BodyId addResting(Scene& s, const std::string& shape, const Quat& orientation, double x, double y, double top,
                  double depth, const std::string& name) {
  const simulation::ShapeModel& model = s.world.shape(s.shape(shape));
  const Quat toWorld = orientation * model.naturalToBody.conjugate();
  Vec3 lowest = toWorld * model.mesh.vertices.front();
  for (const Vec3& v : model.mesh.vertices) {
    const Vec3 w = toWorld * v;
    if (w.z() < lowest.z()) lowest = w;
  }
  return s.add(shape, Vec3(x - lowest.x(), y - lowest.y(), top - depth - lowest.z()), orientation, 1.0, 2400.0, name);
}

/// The contact patches of a fixed scene on a floor, overlapping by 3 mm: a cube on the floor, a
/// cube turned 0.3 rad on it (face on face), a Core-Loc on the floor, a Core-Loc on a cube
/// (corner on face) and a dolos on the floor; evaluated without a step.
Values contactForces(simulation::ContactModel model) {
  WorldSettings settings = quietWorld();
  settings.contactModel = model;
  Scene s(settings);
  s.world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), s.material(2650.0)});
  constexpr double kDepth = 0.003; // m
  s.add("cube", Vec3(0.0, 0.0, 0.5 - kDepth), Quat::Identity(), 1.0, 2400.0, "cube");
  s.add("cube", Vec3(0.0, 0.0, 1.5 - 2.0 * kDepth), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())), 1.0, 2400.0,
        "cube_turned");
  addResting(s, "coreloc", someOrientation(1), -4.0, 0.0, 0.0, kDepth, "coreloc_on_floor");
  s.add("cube", Vec3(4.0, 0.0, 0.5 - kDepth), Quat::Identity(), 1.0, 2400.0, "pedestal");
  addResting(s, "coreloc", someOrientation(2), 4.0, 0.0, 1.0 - kDepth, kDepth, "coreloc_on_cube");
  addResting(s, "dolos", someOrientation(3), -8.0, 0.0, 0.0, kDepth, "dolos_on_floor");
  s.world.setRecordContacts(true);
  s.world.evaluateContacts();
  Values v;
  for (const simulation::ContactPatch& p : s.world.contactPatches()) {
    const std::string other =
        p.bodyB < 0 ? std::string("static") : s.world.bodies().info(static_cast<BodyId>(p.bodyB)).name;
    const std::string pair = fmt::format("{}-{}", s.world.bodies().info(p.bodyA).name, other);
    for (int k = 0; k < 3; ++k) v.emplace_back(fmt::format("{} force {}", pair, "xyz"[k]), p.force[k]);
    for (int k = 0; k < 3; ++k) v.emplace_back(fmt::format("{} point {}", pair, "xyz"[k]), p.point[k]);
    v.emplace_back(pair + " normal force", p.normalForce);
  }
  return v;
}

TEST(RegressionReferences, ContactForcesOfTheLevelSetModel) {
  const Values v = contactForces(simulation::ContactModel::LevelSet);
  // Every body of the scene touches something: 6 pairs (the two cubes and the floor, the cubes on
  // each other, the Core-Locs and the dolos on what is below them).
  ASSERT_GE(v.size(), 6u * 7u) << "a contact of the scene was lost";
  expectReference("contact-forces-levelset.csv", v);
}

TEST(RegressionReferences, ContactForcesOfTheFdemModel) {
  const Values v = contactForces(simulation::ContactModel::Fdem);
  ASSERT_GE(v.size(), 6u * 7u) << "a contact of the scene was lost";
  expectReference("contact-forces-fdem.csv", v);
}

class StormLoadReference : public HydroTest {};

/// A wave travelling onshore over 6 m of water: eta = a sin(w t - k x), linear-wave pressure and
/// velocity below it (deep water decay), records every 0.1 s.
TEST_F(StormLoadReference, StormLoadsOnThreeUnits) {
  const std::string path = file("wave.nc");
  constexpr double a = 0.8, T = 4.0, depth = 6.0;
  const double w = 2.0 * std::numbers::pi / T, k = w * w / kG;
  const auto eta = [&](double t, double x) { return a * std::sin(w * t - k * x); };
  std::vector<double> times;
  for (int r = 0; r <= 30; ++r) times.push_back(0.1 * r);
  writeStorm(path, gridHeader(-6.0, 6.0, -depth, 2.0, 0.25, 0.0), times,
             [&](double t, double x, double z) {
               Flow f;
               const double e = eta(t, x), decay = std::exp(k * std::min(z, 0.0));
               f.alpha = z < e ? 1.0 : 0.0;
               f.p = z < e ? kRho * kG * (a * decay * std::sin(w * t - k * x) - z) : 0.0;
               f.u = z < e ? a * w * decay * std::sin(w * t - k * x) : 0.0;
               f.w = z < e ? a * w * decay * std::cos(w * t - k * x) : 0.0;
               return f;
             },
             eta);
  Scene scene;
  scene.add("cube", Vec3(-2.0, 0.0, -2.0), someOrientation(0), 1.0, 2400.0, "cube");
  scene.add("coreloc", Vec3(0.0, 0.0, -0.5), someOrientation(1), 1.0, 2400.0, "coreloc");
  scene.add("dolos", Vec3(2.5, 0.0, -3.0), someOrientation(2), 1.0, 2400.0, "dolos");
  hydro::StormLoadSettings settings = settingsFor(path);
  settings.drag.enabled = true;
  settings.addedMass.enabled = true;
  StormLoads stage(scene.world, settings, "all", path);
  Values v;
  for (const double t : {0.0, 0.5, 1.3, 2.1}) {
    const Loads l = applyAt(stage, scene.world, t);
    for (BodyId b = 0; b < scene.world.bodies().size(); ++b) {
      const std::string& name = scene.world.bodies().info(b).name;
      for (int c = 0; c < 3; ++c) {
        v.emplace_back(fmt::format("t={} {} force {}", t, name, "xyz"[c]), l.force[b][c]);
        v.emplace_back(fmt::format("t={} {} moment {}", t, name, "xyz"[c]), l.torque[b][c]);
      }
    }
  }
  expectReference("storm-loads.csv", v);
}

} // namespace
