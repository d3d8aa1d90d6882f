// SPDX-License-Identifier: GPL-3.0-or-later
// `armour stress`'s stages (issue 26): the contact loads a rigid run records on its units
// (simulation/UnitLoads) and the quasi-static stress they set up (deformable/UnitStress), against
// equilibrium, the peak of each window, and Euler-Bernoulli bending of a beam on two supports.
#include "analysis/StressEvents.hpp"
#include "deformable/UnitStress.hpp"
#include "io/SceneReader.hpp"
#include "io/UnitLoadsFile.hpp"
#include "simulation/SceneBuilder.hpp"
#include "simulation/UnitLoads.hpp"

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>

using namespace armour;
namespace fs = std::filesystem;

namespace {

constexpr double kG = 9.81;
constexpr double kRho = 2400.0;

/// A 4 x 0.5 x 0.5 m beam (V = 1 m^3) along x, on two fixed 0.1 m wide supports centred at
/// x = -1.5 and 1.5 m, tops at z = 0.25 m (ours).
io::Scene beamScene(const std::string& solver) {
  const std::string yaml = fmt::format(R"(
duration: 3
materials:
  concrete: {{density: {}, friction: 0.7, restitution: 0.1}}
shapes:
  beam: {{generator: cube, params: {{aspect_y: 0.125, aspect_z: 0.125}}}}
  support: {{generator: cube, params: {{aspect_y: 10, aspect_z: 5}}}}
bodies:
  - {{name: beam, shape: beam, volume: 1, material: concrete, position: [0, 0, 0.50002]}}
  - {{name: left, shape: support, volume: 0.05, material: concrete, position: [-1.5, 0, 0], fixed: true}}
  - {{name: right, shape: support, volume: 0.05, material: concrete, position: [1.5, 0, 0], fixed: true}}
static:
  - {{type: plane, name: floor, material: concrete, point: [0, 0, -0.25], normal: [0, 0, 1]}}
contact: {{solver: {}}}
)",
                                       kRho, solver);
  return io::parseScene(yaml, fs::temp_directory_path(), "beam.yaml");
}

fs::path freshFolder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("armour_unit_stress_{}_{}", name, ::getpid());
  fs::remove_all(dir);
  return dir;
}

simulation::UnitLoadsSettings unitSettings(const simulation::BuiltScene& built, double interval) {
  simulation::UnitLoadsSettings s;
  s.bodies = {built.bodyIndexOfSceneBody[0]};
  s.sceneBodies = {0};
  for (simulation::BodyId b = 0; b < built.world->bodies().size(); ++b)
    s.names.push_back(built.world->bodies().info(b).name);
  s.interval = interval;
  return s;
}

/// The world-frame moment of a record's loads about the unit's centre of mass (unit: N m).
Eigen::Vector3d netMoment(const io::UnitLoadRecord& r) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const auto& l : r.loads) m += r.orientation * l.point.cross(l.force);
  return m;
}

/// The world-frame sum of a record's loads (unit: N).
Eigen::Vector3d netForce(const io::UnitLoadRecord& r) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const auto& l : r.loads) f += r.orientation * l.force;
  return f;
}

class BeamOnSupports : public ::testing::TestWithParam<const char*> {};

/// Euler-Bernoulli's sigma_xx at the world point w of the beam: N / A + M_y z' / I - M_z y' / I
/// (square section, I = I_y = I_z; y', z' from the beam's axis), with N and the moment M of the
/// section taken by statics of the part beyond it: the recorded loads there and its weight, q per
/// metre (the supports' friction can hold an axial force and a sideways couple set when the beam
/// came to rest: statically indeterminate, so they are taken from the record, not assumed zero).
double beamStress(const io::UnitLoadRecord& r, const Eigen::Vector3d& w, double q, double I) {
  const double side = w.x() >= 0.0 ? 1.0 : -1.0;
  const Eigen::Vector3d c(w.x(), r.position.y(), r.position.z()); // the section's centre
  double N = 0.0;
  Eigen::Vector3d M = Eigen::Vector3d::Zero();
  for (const auto& l : r.loads) {
    const Eigen::Vector3d p = r.position + r.orientation * l.point, f = r.orientation * l.force;
    if (side * (p.x() - w.x()) <= 0.0) continue;
    N += side * f.x();
    M += (p - c).cross(f);
  }
  const double length = 2.0 - std::abs(w.x()); // the part beyond, and its weight at its middle
  M += Eigen::Vector3d(side * length / 2.0, 0.0, 0.0).cross(Eigen::Vector3d(0.0, 0.0, -q * length));
  return N / 0.25 + side * (M.y() * (w.z() - c.z()) - M.z() * (w.y() - c.y())) / I;
}

// The beam settles on its supports and falls asleep. Awake and asleep, its recorded loads balance
// its weight (1e-3), and the stress they set up at every element of its lower half away from the
// supports (one depth, 0.5 m) is Euler-Bernoulli's at that element's centroid (beamStress; without
// friction N = 0 and M(x) = R (1.5 - |x|) - q (2 - |x|)^2 / 2 with q = rho g A and R = 2 q),
// within 5 % of the largest: the beam is deep (depth / half span 1 : 3), and the elasticity
// solution departs from Euler-Bernoulli's by terms of order (depth / span)^2, about 3 % here.
TEST_P(BeamOnSupports, BendsAsEulerBernoulliAwakeAndAsleep) {
  const io::Scene scene = beamScene(GetParam());
  simulation::BuiltScene built = simulation::buildWorld(scene);
  simulation::World& world = *built.world;
  const fs::path dir = freshFolder(GetParam());
  simulation::UnitLoadsRecorder recorder(world, unitSettings(built, 0.1), dir);
  world.evaluateContacts();
  recorder.update(world);
  while (world.time() < 3.0) {
    world.step();
    recorder.update(world);
  }
  const simulation::BodyId beam = built.bodyIndexOfSceneBody[0];
  ASSERT_FALSE(world.bodies().isAwake(beam)) << "the beam should be asleep after 3 s at rest";
  const io::UnitLoads loads = io::readUnitLoads(dir);
  ASSERT_EQ(loads.units.size(), 1u);
  const double weight = loads.units[0].mass * kG;
  EXPECT_NEAR(loads.units[0].mass, kRho * 1.0, 1e-6 * kRho);
  // Records at 1.5 s (awake, at rest: the beam sleeps 0.5 s after it comes to rest) and the last.
  std::size_t awake = loads.records.size(), last = loads.records.size() - 1;
  for (std::size_t i = 0; i < loads.records.size(); ++i)
    if (std::abs(loads.records[i].time - 1.0) < 0.06) awake = i;
  ASSERT_LT(awake, loads.records.size());
  deformable::UnitStressSettings settings;
  settings.material.density = kRho;
  settings.tets = 6000;
  settings.spreadRadius = 0.05;
  settings.awayDistance = 0.3;
  const deformable::UnitStressModel model(loads.units[0].surface, settings, "beam");
  const double q = kRho * kG * 0.25, I = 0.5 * std::pow(0.5, 3) / 12.0;
  for (std::size_t i : {awake, last}) {
    const io::UnitLoadRecord& r = loads.records[i];
    const Eigen::Vector3d f = netForce(r);
    EXPECT_NEAR(f.z(), weight, 1e-3 * weight) << "record at t = " << r.time;
    EXPECT_NEAR(f.head<2>().norm(), 0.0, 1e-3 * weight) << "record at t = " << r.time;
    EXPECT_NEAR(netMoment(r).norm(), 0.0, 1e-3 * weight * 1.0) << "record at t = " << r.time << ": " << netMoment(r).transpose();
    deformable::UnitLoadCase c;
    c.angularVelocity = r.angularVelocity;
    for (const auto& l : r.loads) c.loads.push_back({l.point, l.force});
    const deformable::QuasiStaticResult s = model.solve(c);
    const auto& mesh = model.body().mesh();
    double largest = 0.0, worst = 0.0;
    for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int a = 0; a < 4; ++a) centroid += mesh.nodes[static_cast<std::size_t>(mesh.element(e)[a])];
      const Eigen::Vector3d w = r.position + r.orientation * (0.25 * centroid); // the beam's axes are the world's
      const double x = std::abs(w.x());
      if (x > 1.0 || w.z() > r.position.z()) continue; // within a depth of a support, or the upper half
      const double expected = beamStress(r, w, q, I);
      const Eigen::Vector3d axis = r.orientation.conjugate() * Eigen::Vector3d::UnitX();
      const double sxx = axis.dot(s.stress[e] * axis);
      largest = std::max(largest, expected);
      worst = std::max(worst, std::abs(sxx - expected));
    }
    std::cout << GetParam() << ", record at t = " << r.time << ": net force " << f.transpose() << " N (weight " << weight
              << "), moment " << netMoment(r).transpose() << " N m; sigma_xx within " << worst << " Pa of Euler-Bernoulli ("
              << 100.0 * worst / largest << " % of the largest, " << largest << " Pa)\n";
    EXPECT_GT(largest, 0.7 * q * 0.25 / I) << "the lowest centroids lie about 0.02 m above the face";
    EXPECT_LT(worst, 0.05 * largest) << "record at t = " << r.time << ": largest bending stress " << largest << " Pa";
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Solvers, BeamOnSupports, ::testing::Values("penalty", "constraint"));

// Peak hold: each record holds the step of its window at which the unit's contact force was
// largest, exactly (the sum read from the World at every step).
TEST(UnitLoads, EachRecordHoldsTheLargestContactForceOfItsWindow) {
  io::Scene scene = beamScene("penalty");
  scene.bodies[0].position.z() += 0.05; // dropped 5 cm: impacts and bounces
  scene.bodies[0].angularVelocity = Eigen::Vector3d(0.3, 0.0, 0.0);
  simulation::BuiltScene built = simulation::buildWorld(scene);
  simulation::World& world = *built.world;
  const fs::path dir = freshFolder("peak");
  simulation::UnitLoadsRecorder recorder(world, unitSettings(built, 0.05), dir);
  world.evaluateContacts();
  recorder.update(world);
  std::vector<std::pair<double, double>> sums; // (t, contact force) at every step
  while (world.time() < 0.6) {
    world.step();
    recorder.update(world);
    double sum = 0.0;
    for (const auto& c : world.tracedContacts()) sum += c.force.norm();
    sums.emplace_back(world.time(), sum);
  }
  const io::UnitLoads loads = io::readUnitLoads(dir);
  ASSERT_GE(loads.records.size(), 12u);
  double previousEnd = 0.0;
  std::size_t impacts = 0;
  for (std::size_t i = 1; i < loads.records.size(); ++i) {
    const io::UnitLoadRecord& r = loads.records[i];
    double best = 0.0, at = -1.0;
    for (const auto& [t, f] : sums)
      if (t > previousEnd && t <= r.windowEnd && f > best) best = f, at = t;
    EXPECT_NEAR(r.contactForce, best, 1e-6 * std::max(best, 1.0)) << "window ending at " << r.windowEnd;
    if (best > 0.0) {
      EXPECT_DOUBLE_EQ(r.time, at) << "window ending at " << r.windowEnd;
    }
    impacts += r.contactForce > 3.0 * loads.units[0].mass * kG ? 1 : 0;
    previousEnd = r.windowEnd;
  }
  EXPECT_GE(impacts, 1u) << "the drop should strike harder than three times the weight";
  fs::remove_all(dir);
}

// The kinds of stress peaks (analysis/StressEvents): a sharp rise of the contact force is an
// impact, one while the unit turned in place is rocking, a steady load is sustained.
TEST(StressEvents, KindsFollowTheContactForceAndTheUnitsOwnMotion) {
  std::vector<analysis::StressSample> s(40);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s[i].time = 0.05 * static_cast<double>(i);
    s[i].contactForce = 1e4;
    s[i].sigma1Away = 1e5;
  }
  s[10].contactForce = 5e4, s[10].sigma1Away = 9e5;             // a blow on a unit at rest
  for (std::size_t i = 20; i <= 25; ++i) s[i].angularSpeed = 0.3; // rocking in place
  s[25].contactForce = 4e4, s[25].sigma1Away = 8e5;
  for (std::size_t i = 30; i <= 35; ++i) s[i].position.x() = 0.5 * static_cast<double>(i - 30); // falls into it
  for (std::size_t i = 30; i <= 35; ++i) s[i].angularSpeed = 0.3;
  s[35].contactForce = 4e4, s[35].sigma1Away = 7e5;
  const auto summary = analysis::summarizeUnitStress(s);
  EXPECT_EQ(summary.maxAway, 10u);
  ASSERT_EQ(summary.events.size(), 3u);
  EXPECT_EQ(summary.events[0].sample, 10u);
  EXPECT_EQ(summary.events[0].kind, "impact");
  EXPECT_EQ(summary.events[1].sample, 25u);
  EXPECT_EQ(summary.events[1].kind, "rocking");
  EXPECT_EQ(summary.events[2].sample, 35u);
  EXPECT_EQ(summary.events[2].kind, "impact");
  s[10].contactForce = 1.5e4; // a rise below the threshold (2x): sustained
  EXPECT_EQ(analysis::eventKind(s, 10), "sustained");
}

} // namespace
