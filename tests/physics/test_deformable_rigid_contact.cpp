// SPDX-License-Identifier: GPL-3.0-or-later
// Contact of a deforming body with rigid bodies given by their level sets (issue 26;
// RigidObstacleContact.hpp, docs/theory.md section 19): on a rigid body's flat face the contact is
// the half-space's to round-off; action equals reaction exactly, force and moment; a block comes to
// rest on a rigid slab, which carries its weight and its moment; a rigid slab pushed up lifts it;
// with friction the block holds on the slab below the friction angle, slides above it at
// g (sin theta - mu cos theta), and rides on a moving slab.
#include "contact/LevelSet.hpp"
#include "core/Error.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/RigidObstacleContact.hpp"
#include "support/DeformableFixtures.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

namespace armour::deformable {
namespace {

/// A rigid slab 6 x 6 x 1 m, its level set at 0.1 m cells, centred on the origin in plan, its top
/// face at z = 0 once posed at position (-3, -3, -1).
struct Slab {
  contact::LevelSet levelSet{armour::test::makeBox(6.0, 6.0, 1.0), [] {
                               contact::LevelSetSettings s;
                               s.cellSize = 0.1;
                               return s;
                             }()};
  RigidObstacle at(const Vec3& offset = Vec3::Zero()) const {
    RigidObstacle o;
    o.levelSet = &levelSet;
    o.position = Vec3(-3.0, -3.0, -1.0) + offset;
    return o;
  }
};

TEST(DeformableRigidContact, OnAFlatFaceItIsTheHalfSpacesContact) {
  // A 1 m tet10 cube sunk flat by 1 cm into the slab's top face, and turned 0.3 rad with a
  // corner 5 cm in: the nodal forces match those of the half-space z = 0 (the level set is exact
  // for the face's linear distance away from the slab's edges) to 1e-6 of the largest.
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 2, 2, 2, ElementOrder::Quadratic);
  const auto triangles = surfaceTriangles(mesh, boundaryFaces(mesh));
  const Slab slab;
  const double G = 1e11;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Vec3(1, 2, 0.5).normalized()).toRotationMatrix();
  for (const bool turned : {false, true}) {
    std::vector<Vec3> x(mesh.nodeCount());
    double lowest = 1e9;
    for (std::size_t n = 0; n < x.size(); ++n) {
      x[n] = turned ? Vec3(R * (mesh.nodes[n] - Vec3::Constant(0.5))) : Vec3(mesh.nodes[n] - Vec3(0.5, 0.5, 0.0));
      lowest = std::min(lowest, x[n].z());
    }
    for (auto& p : x) p.z() -= lowest + (turned ? 0.05 : 0.01);
    std::vector<Vec3> plane(x.size(), Vec3::Zero()), rigid(x.size(), Vec3::Zero());
    const double planeEnergy = addHalfSpaceContact(triangles, x, HalfSpace{}, G, plane);
    const ObstacleLoad load = addObstacleContact(triangles, x, slab.at(), G, rigid, true);
    double largest = 0.0, worst = 0.0;
    Vec3 sum = Vec3::Zero();
    for (std::size_t n = 0; n < x.size(); ++n) {
      largest = std::max(largest, plane[n].norm());
      worst = std::max(worst, (plane[n] - rigid[n]).norm());
      sum += rigid[n];
    }
    std::cout << (turned ? "corner 5 cm in" : "flat 1 cm in") << ": largest nodal force " << largest
              << " N, worst difference from the half-space " << worst << " N; energy " << load.energy << " J against "
              << planeEnergy << " J; " << load.triangles << " triangles touch\n";
    ASSERT_GT(largest, 0.0);
    EXPECT_LT(worst, 1e-6 * largest);
    EXPECT_NEAR(load.energy, planeEnergy, 1e-6 * planeEnergy);
    // Action and reaction, force and moment about the slab's position.
    EXPECT_LT((load.force + sum).norm(), 1e-9 * largest);
    Vec3 moment = Vec3::Zero();
    for (std::size_t n = 0; n < x.size(); ++n) moment += (x[n] - slab.at().position).cross(rigid[n]);
    EXPECT_LT((load.torque + moment).norm(), 1e-9 * largest);
  }
}

TEST(DeformableRigidContact, BlockRestsOnARigidSlabThatCarriesItsWeightAndMoment) {
  // A 1 m tet10 concrete block set on the slab, its centre 0.7 m and 0.3 m off the slab's axis,
  // damped to rest as the half-space test (DeformableContact.BlockComesToRest..., but for 200 / omega:
  // the rocking mode is slower than the bounce): the slab
  // carries the weight (22 955 N) within 1e-5 and its moment about the slab's position within
  // 1e-5 of W x 1 m: torque = (c - p) x (0, 0, -W).
  DeformableSettings settings;
  settings.rigidContact = true;
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 2, 2, 2, ElementOrder::Quadratic);
  std::vector<Vec3> start(mesh.nodes);
  for (auto& p : start) p += Vec3(0.2, -0.2, 0.0); // the block spans [0.2, 1.2] x [-0.2, 0.8]
  DeformableSettings probe = settings;
  const double G = DeformableBody(mesh, probe).contactGradient();
  const double cBar = std::sqrt(settings.material.youngModulus / settings.material.density);
  const double omega = std::min(std::sqrt(G / (settings.material.density * 1.0)), 0.5 * std::numbers::pi * cBar);
  settings.massDamping = 2.0 * omega;
  DeformableBody body(mesh, settings, "block on a slab");
  body.setPositions(start);
  const Slab slab;
  body.setObstacles({slab.at()});
  const double dt = body.stableStep().dt;
  while (body.time() < 200.0 / omega) body.step(dt);
  const double weight = settings.material.density * 9.81;
  const ObstacleLoad& load = body.obstacleLoads().front();
  // Gravity acts at the lumped masses' centre, which the Kuhn cells' asymmetry moves off the
  // block's geometric centre (0.7, 0.3, 0.5) by a fraction of a millimetre.
  Vec3 centre = Vec3::Zero();
  double mass = 0.0;
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    centre += body.masses()[n] * body.positions()[n];
    mass += body.masses()[n];
  }
  centre /= mass;
  const Vec3 expectedTorque = (centre - slab.at().position).cross(Vec3(0, 0, -weight));
  std::cout << "block on a rigid slab: " << body.steps() << " steps of " << dt << " s; slab force "
            << load.force.transpose() << " N (weight " << weight << " N), torque " << load.torque.transpose()
            << " N m against " << expectedTorque.transpose() << "; the body's contact force "
            << body.contactForce().transpose() << " N\n";
  EXPECT_NEAR(load.force.z(), -weight, 1e-5 * weight);
  EXPECT_LT(load.force.head<2>().norm(), 1e-9 * weight);
  EXPECT_LT((load.torque - expectedTorque).norm(), 1e-5 * weight * 1.0);
  EXPECT_NEAR(body.contactForce().z(), weight, 1e-5 * weight);
}

TEST(DeformableRigidContact, ARisingSlabLiftsTheBlock) {
  // The slab raised by A = 2.5 mm along A (1 - cos(pi t / T)) / 2, T = 0.1 s, under the block
  // resting on it (gravity on; the largest acceleration A pi^2 / (2 T^2) = 1.2 m/s^2 is below g,
  // so the block never leaves it; viscosity 5 % of critical damps the landing's ringing): the
  // block's base follows the slab within 0.01 mm, and at t = T the slab pushes m (g + a(T)) =
  // m (g - 1.23 m/s^2) within 2 %.
  DeformableSettings settings;
  settings.rigidContact = true;
  settings.material.viscosity = 0.05 * criticalViscosity(settings.material, 0.5);
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 1, 1, 1, ElementOrder::Linear);
  DeformableBody body(mesh, settings, "lifted block");
  const Slab slab;
  const double dt = body.stableStep().dt;
  static constexpr double kA = 0.0025, kT = 0.1;
  const auto lift = [](double t) { return 0.5 * kA * (1.0 - std::cos(std::numbers::pi * std::min(t, kT) / kT)); };
  double rise = 0.0;
  while (body.time() < kT) {
    rise = lift(body.time() + dt); // the pose at the end of the step
    body.setObstacles({slab.at(Vec3(0.0, 0.0, rise))});
    body.step(dt);
  }
  double lowest = 1e9;
  for (std::size_t n = 0; n < body.nodeCount(); ++n) lowest = std::min(lowest, body.positions()[n].z());
  const double mass = settings.material.density * 1.0;
  const double expected = mass * (9.81 - kA * std::numbers::pi * std::numbers::pi / (2.0 * kT * kT));
  const double push = -body.obstacleLoads().front().force.z();
  std::cout << "rising slab: rose " << rise << " m, the block's base at " << lowest << " m; the slab pushes " << push
            << " N against m (g + a) = " << expected << " N (" << 100.0 * (push / expected - 1.0) << " %)\n";
  EXPECT_NEAR(lowest, rise, 1e-5);
  EXPECT_NEAR(push, expected, 0.02 * expected);
}

/// A 1 m tet10 block (one Kuhn cell) on the slab with friction mu, gravity tilted by theta about y
/// (down-slope +x), viscosity 5 % of critical: the half-space friction test's block
/// (test_deformable_friction.cpp) on a rigid body instead.
DeformableBody frictionBlock(double thetaDeg, double mu) {
  const double theta = thetaDeg * std::numbers::pi / 180.0;
  DeformableSettings s;
  s.rigidContact = true;
  s.friction = mu;
  s.gravity = 9.81 * Vec3(std::sin(theta), 0.0, -std::cos(theta));
  s.material.viscosity = 0.05 * criticalViscosity(s.material, 0.5);
  return DeformableBody(test::boxMesh(Vec3(1, 1, 1), 1, 1, 1, ElementOrder::Quadratic), s, "block with friction");
}

TEST(DeformableRigidContact, FrictionOnARigidSlabHoldsBelowTheFrictionAngle) {
  // theta = 20 deg under mu = 0.6: from 0.05 to 0.3 s the block may not creep by more than 1e-7 m,
  // and the slab takes the weight's down-slope part m g sin(theta) = 7 851 N within 1 %.
  DeformableBody body = frictionBlock(20.0, 0.6);
  const Slab slab;
  body.setObstacles({slab.at()});
  const double dt = body.stableStep().dt;
  while (body.time() < 0.05) body.step(dt);
  const Vec3 x0 = test::centroidMotion(body).first;
  while (body.time() < 0.3) body.step(dt);
  const Vec3 x1 = test::centroidMotion(body).first;
  const double downSlope = body.settings().material.density * 9.81 * std::sin(20.0 * std::numbers::pi / 180.0);
  const Vec3 f = body.obstacleLoads().front().force;
  std::cout << "friction on a rigid slab, 20 deg, mu 0.6: drift " << (x1 - x0).transpose() << " m; the slab takes "
            << f.transpose() << " N (down-slope weight " << downSlope << " N)\n";
  EXPECT_LT(std::abs(x1.x() - x0.x()), 1e-7);
  EXPECT_NEAR(f.x(), downSlope, 0.01 * downSlope);
}

TEST(DeformableRigidContact, FrictionOnARigidSlabSlidesAtGSinMinusMuCos) {
  // mu = 0.2 < tan 20 deg: a = g (sin theta - mu cos theta) = 1.510 m/s^2 within 2 %.
  DeformableBody body = frictionBlock(20.0, 0.2);
  const Slab slab;
  body.setObstacles({slab.at()});
  const double dt = body.stableStep().dt;
  while (body.time() < 0.05) body.step(dt);
  const Vec3 v1 = test::centroidMotion(body).second;
  const double t1 = body.time();
  while (body.time() < 0.25) body.step(dt);
  const Vec3 v2 = test::centroidMotion(body).second;
  const double theta = 20.0 * std::numbers::pi / 180.0;
  const double expected = 9.81 * (std::sin(theta) - 0.2 * std::cos(theta));
  const double a = (v2.x() - v1.x()) / (body.time() - t1);
  std::cout << "friction on a rigid slab, 20 deg, mu 0.2: acceleration " << a << " m/s^2 against " << expected << "\n";
  EXPECT_NEAR(a, expected, 0.02 * expected);
}

TEST(DeformableRigidContact, AMovingSlabCarriesTheBlockByFriction) {
  // The slab slides along x at 0.1 m/s under the block (gravity down, mu 0.6): the block slips
  // until it moves with the slab (mu g = 5.9 m/s^2: in 17 ms), then sticks to it. At 0.2 s it moves
  // at 0.1 m/s within 1 %. The anchors ride on the slab; anchors fixed in the world would hold the
  // block back.
  DeformableBody body = frictionBlock(0.0, 0.6);
  const Slab slab;
  const double dt = body.stableStep().dt;
  constexpr double kSpeed = 0.1;
  while (body.time() < 0.2) {
    body.setObstacles({slab.at(Vec3(kSpeed * (body.time() + dt), 0.0, 0.0))});
    body.step(dt);
  }
  const Vec3 v = test::centroidMotion(body).second;
  std::cout << "block on a moving slab: velocity " << v.transpose() << " m/s (the slab's " << kSpeed << ")\n";
  EXPECT_NEAR(v.x(), kSpeed, 0.01 * kSpeed);
}

TEST(DeformableRigidContact, ObstaclesNeedRigidContactOn) {
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 1, 1, 1, ElementOrder::Linear);
  DeformableBody body(mesh, DeformableSettings{}, "block");
  const Slab slab;
  try {
    body.setObstacles({slab.at()});
    ADD_FAILURE() << "accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rigid_contact"), std::string::npos) << e.what();
  }
  RigidObstacle none;
  std::vector<Vec3> forces(mesh.nodeCount(), Vec3::Zero());
  EXPECT_THROW(addObstacleContact(surfaceTriangles(mesh, boundaryFaces(mesh)), mesh.nodes, none, 1e9, forces),
               core::InputError);
}

} // namespace
} // namespace armour::deformable
