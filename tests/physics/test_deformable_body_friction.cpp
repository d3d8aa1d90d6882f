// SPDX-License-Identifier: GPL-3.0-or-later
// Coulomb friction between deformable bodies (issue 26; BodyFriction.hpp, docs/theory.md section
// 19, "Friction between deformable bodies"): a 1 m concrete block on a deformable concrete slab
// (its base held), gravity tilted by theta, sticks below the friction angle and slides above it at
// g (sin theta - mu cos theta), as on a rigid floor; friction and contact are action and
// reaction; the anchors survive a checkpoint bit for bit.
#include "core/Error.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/DeformableCheckpoint.hpp"
#include "deformable/StructuredBox.hpp"
#include "support/DeformableFixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <numbers>

namespace armour::deformable {
namespace {

constexpr double kG = 9.81;
constexpr double kTheta = 20.0 * std::numbers::pi / 180.0;

/// The slab, 3 x 3 x 0.5 m (3 x 3 x 1 cells), its top face at z = 0, then the 1 m block (one Kuhn
/// cell) on it, centred: parts 0 and 1 of one mesh. Nodes of the block come after the slab's.
struct BlockOnSlab {
  DeformableMesh mesh;
  std::size_t slabNodes = 0;
  explicit BlockOnSlab(ElementOrder order) {
    const geometry::TetMesh slab = structuredBox(Vec3(3, 3, 0.5), 3, 3, 1);
    const geometry::TetMesh block = structuredBox(Vec3(1, 1, 1), 1, 1, 1);
    mesh = makeDeformableMesh(mergeTetMeshes({slab, block}, {Vec3(-1.5, -1.5, -0.5), Vec3(-0.5, -0.5, 0.0)}), order,
                              "block on a slab");
    for (std::size_t n = 0; n < mesh.nodeCount(); ++n) {
      if (mesh.nodes[n].z() < 0.0 || (mesh.nodes[n].z() == 0.0 && std::abs(mesh.nodes[n].x()) > 0.5)) ++slabNodes;
    }
  }
  /// Gravity tilted by theta about y (down-slope +x), body friction mu, viscosity 5 % of critical.
  [[nodiscard]] DeformableSettings settings(double mu) const {
    DeformableSettings s;
    s.gravity = kG * Vec3(std::sin(kTheta), 0.0, -std::cos(kTheta));
    s.bodyContact = true;
    s.bodyFriction = mu;
    s.material.viscosity = 0.05 * criticalViscosity(s.material, 0.5);
    return s;
  }
  [[nodiscard]] std::unique_ptr<DeformableBody> make(double mu) const {
    auto body = std::make_unique<DeformableBody>(mesh, settings(mu), "block on a slab");
    for (std::size_t n = 0; n < mesh.nodeCount(); ++n) {
      if (std::abs(mesh.nodes[n].z() + 0.5) < 1e-12) body->fixNode(n); // the slab's base
    }
    return body;
  }
};

/// The block's centroid position and velocity: the nodes above z = 0.5 mm in the reference mesh
/// belong to it, with its base nodes (the block's part of the merged mesh).
std::pair<Vec3, Vec3> blockMotion(const DeformableBody& body) {
  const auto& parts = body.bodyContact()->nodeParts();
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
  double m = 0.0;
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    if (parts[n] != parts.back()) continue;
    x += body.masses()[n] * body.positions()[n];
    v += body.masses()[n] * body.velocities()[n];
    m += body.masses()[n];
  }
  return {x / m, v / m};
}

class DeformableBodyFriction : public ::testing::TestWithParam<ElementOrder> {};

TEST_P(DeformableBodyFriction, BlockOnASlabBelowTheFrictionAngleDoesNotCreep) {
  // theta = 20 deg (tan 0.364) under mu = 0.6: from t = 0.05 s to 0.3 s the block may not move
  // down the slope by more than 1e-6 m against the slab (frictionless: 0.10 m); the contact and
  // friction sum to zero over both bodies (action and reaction), to 1e-9 of the block's weight.
  const BlockOnSlab scene(GetParam());
  auto body = scene.make(0.6);
  const double dt = body->stableStep().dt;
  while (body->time() < 0.05) body->step(dt);
  const Vec3 x0 = blockMotion(*body).first;
  while (body->time() < 0.3) body->step(dt);
  const Vec3 x1 = blockMotion(*body).first;
  Vec3 sum = Vec3::Zero();
  for (const Vec3& f : body->nodalContactForces()) sum += f;
  const double weight = body->settings().material.density * kG;
  std::cout << "tet" << scene.mesh.nodesPerElement() << ", theta 20 deg, mu 0.6: " << body->steps() << " steps of " << dt
            << " s; the block drifts " << (x1 - x0).transpose() << " m from 0.05 to 0.3 s; friction "
            << body->bodyFrictionTotal() << " N on the contactor nodes (the weight's down-slope part "
            << weight * std::sin(kTheta) << " N); contact forces sum to " << sum.norm() << " N\n";
  EXPECT_LT(std::abs(x1.x() - x0.x()), 1e-6);
  EXPECT_LT(sum.norm(), 1e-9 * weight);
}

TEST_P(DeformableBodyFriction, BlockOnASlabAboveTheFrictionAngleSlides) {
  // mu = 0.2: a = g (sin theta - mu cos theta) = 1.510 m/s^2 within 2 %, from the block's velocity
  // at 0.05 and 0.25 s; frictionless, g sin theta = 3.355 m/s^2 within 2 %.
  const BlockOnSlab scene(GetParam());
  for (const double mu : {0.2, 0.0}) {
    auto body = scene.make(mu);
    const double dt = body->stableStep().dt;
    while (body->time() < 0.05) body->step(dt);
    const auto [x1, v1] = blockMotion(*body);
    const double t1 = body->time();
    while (body->time() < 0.25) body->step(dt);
    const auto [x2, v2] = blockMotion(*body);
    const double acceleration = (v2.x() - v1.x()) / (body->time() - t1);
    const double expected = kG * (std::sin(kTheta) - mu * std::cos(kTheta));
    std::cout << "tet" << scene.mesh.nodesPerElement() << ", mu " << mu << ": acceleration " << acceleration
              << " m/s^2 against " << expected << " (" << 100.0 * (acceleration / expected - 1.0) << " %)\n";
    EXPECT_NEAR(acceleration, expected, 0.02 * expected);
  }
}

TEST_P(DeformableBodyFriction, AnchorsSurviveACheckpointBitForBit) {
  // The sliding block (mu 0.2), checkpointed at step 300 of 600 and continued in a new body: the
  // same bits as the run that went through; a checkpoint with body anchors does not load into a
  // body without body friction.
  const BlockOnSlab scene(GetParam());
  auto through = scene.make(0.2);
  const double dt = through->stableStep().dt;
  const auto file = std::filesystem::temp_directory_path() /
                    ("armour_body_friction_checkpoint_" + std::to_string(scene.mesh.nodesPerElement()) + ".bin");
  for (int i = 0; i < 600; ++i) {
    through->step(dt);
    if (i == 299) writeDeformableCheckpoint(*through, file);
  }
  auto restarted = scene.make(0.2);
  readDeformableCheckpoint(file, *restarted);
  for (int i = 300; i < 600; ++i) restarted->step(dt);
  EXPECT_EQ(std::memcmp(through->positions().data(), restarted->positions().data(),
                        through->nodeCount() * sizeof(Vec3)),
            0);
  EXPECT_EQ(std::memcmp(through->velocities().data(), restarted->velocities().data(),
                        through->nodeCount() * sizeof(Vec3)),
            0);
  auto frictionless = scene.make(0.0);
  EXPECT_THROW(readDeformableCheckpoint(file, *frictionless), core::InputError);
  std::filesystem::remove(file);
}

INSTANTIATE_TEST_SUITE_P(Orders, DeformableBodyFriction,
                         ::testing::Values(ElementOrder::Linear, ElementOrder::Quadratic),
                         [](const auto& info) { return info.param == ElementOrder::Linear ? "tet4" : "tet10"; });

TEST(DeformableBodyFrictionSettings, RefusedWithoutBodyContactOrBelowZero) {
  const BlockOnSlab scene(ElementOrder::Linear);
  DeformableSettings s = scene.settings(-0.1);
  EXPECT_THROW(DeformableBody(scene.mesh, s, "block"), core::InputError);
  s = scene.settings(0.5);
  s.bodyContact = false;
  try {
    DeformableBody body(scene.mesh, s, "block");
    ADD_FAILURE() << "body friction without body contact accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body_friction"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace armour::deformable
