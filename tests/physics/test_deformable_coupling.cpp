// SPDX-License-Identifier: GPL-3.0-or-later
// A deformable body among moving rigid bodies (issue 26, "a deformable unit inside a rigid pack";
// simulation/DeformableCoupling.hpp, docs/theory.md section 19, "Moving rigid bodies"):
//  - a deformable cube strikes a free rigid block off its centre in free space: linear momentum
//    is exchanged to round-off, angular momentum to 1e-6, and the energy after the impact equals
//    the energy before within 1 % (the elastic-impact tolerance);
//  - a deformable cube comes to rest on a free rigid block that rests on the World's floor: the
//    block carries the cube's weight, and the floor both, within 0.5 %.
#include "deformable/DeformableBody.hpp"
#include "simulation/DeformableCoupling.hpp"
#include "simulation/World.hpp"
#include "support/DeformableFixtures.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>

namespace armour::simulation {
namespace {

using deformable::Vec3;

/// A deformable tet4 cube of side `side` (n cells a side), its lower corner at `corner`, of
/// seed 002's concrete, with rigid contact on.
std::unique_ptr<deformable::DeformableBody> cubeAt(const Vec3& corner, double side, int n, const Vec3& gravity,
                                                   double massDamping = 0.0) {
  deformable::DeformableMesh mesh =
      deformable::test::boxMesh(Vec3::Constant(side), n, n, n, deformable::ElementOrder::Linear);
  for (auto& x : mesh.nodes) x += corner;
  deformable::DeformableSettings s;
  s.material = deformable::test::concrete();
  s.rigidContact = true;
  s.massDamping = massDamping;
  s.gravity = gravity;
  s.contactGradient = 1e12; // ours: stiff enough that the contact sinks in by micrometres
  return std::make_unique<deformable::DeformableBody>(std::move(mesh), s, "test cube");
}

/// A free concrete (2 340 kg/m^3) rigid body of `mesh` in `world`, its centroid at `position`.
BodyId addConcreteBlock(World& world, const geometry::TriangleMesh& mesh, const Vec3& position,
                        double restitution = 0.05) {
  Material concrete;
  concrete.density = 2340.0;
  concrete.restitution = restitution;
  BodySpec spec;
  spec.material = world.addMaterial(concrete);
  spec.shape = world.addShape("block", mesh);
  spec.position = position;
  return world.addBody(spec);
}

Vec3 momentum(const deformable::DeformableBody& d) {
  Vec3 p = Vec3::Zero();
  for (std::size_t a = 0; a < d.nodeCount(); ++a) p += d.masses()[a] * d.velocities()[a];
  return p;
}

Vec3 angularMomentum(const deformable::DeformableBody& d) {
  Vec3 l = Vec3::Zero();
  for (std::size_t a = 0; a < d.nodeCount(); ++a) l += d.masses()[a] * d.positions()[a].cross(d.velocities()[a]);
  return l;
}

TEST(DeformableCoupling, AnOffCentreImpactExchangesMomentumAndKeepsTheEnergy) {
  WorldSettings ws;
  ws.gravity = Vec3::Zero();
  ws.sleep.enabled = false;
  auto cube = cubeAt(Vec3(-1.02, 0.05, -0.25), 0.5, 2, ws.gravity);
  ws.timeStep = cube->stableStep().dt;
  World world(ws);
  const BodyId block = addConcreteBlock(world, armour::test::makeBox(1.0, 1.0, 1.0), Vec3::Zero()); // face x = -0.5
  auto coupling = std::make_shared<DeformableCoupling>(*cube, std::vector<BodyId>{block});
  world.addLoadStage(coupling);
  std::vector<Vec3> v(cube->nodeCount(), Vec3(2.0, 0.0, 0.0));
  cube->setVelocities(v);

  const auto& bodies = world.bodies();
  const double blockMass = 1.0 / bodies.inverseMass(block);
  const auto totalMomentum = [&] { return Vec3(momentum(*cube) + blockMass * bodies.velocity(block)); };
  const auto totalAngular = [&] {
    return Vec3(angularMomentum(*cube) + blockMass * bodies.position(block).cross(bodies.velocity(block)) +
                bodies.angularMomentumWorld(block));
  };
  const auto energy = [&] { return cube->kineticEnergy() + cube->strainEnergy() + bodies.kineticEnergy(block); };
  const Vec3 p0 = totalMomentum(), l0 = totalAngular();
  const double e0 = energy();
  double worstP = 0.0, worstL = 0.0;
  while (world.time() < 0.03) {
    world.step();
    worstP = std::max(worstP, (totalMomentum() - p0).norm());
    worstL = std::max(worstL, (totalAngular() - l0).norm());
  }
  const double e1 = energy();
  std::cout << "step " << world.timeStep() << " s, " << world.stepCount() << " steps; block velocity "
            << bodies.velocity(block).transpose() << " m/s, spin " << bodies.worldAngularVelocity(block).transpose()
            << " rad/s; cube momentum " << momentum(*cube).transpose() << " N s of " << p0.transpose()
            << "; worst momentum error " << worstP << " N s, angular " << worstL << " N m s of " << l0.norm()
            << "; energy " << e0 << " J before, " << e1 << " J after (" << 100.0 * (e1 / e0 - 1.0) << " %)\n";
  // The impact happened: the block took most of the momentum and spins about z (struck at y > 0).
  ASSERT_GT(bodies.velocity(block).x(), 0.5 * p0.x() / (blockMass + 292.5) );
  EXPECT_LT(bodies.worldAngularVelocity(block).z(), -1e-3);
  EXPECT_LT(worstP, 1e-9 * p0.norm());
  EXPECT_LT(worstL, 1e-6 * blockMass * p0.norm() / blockMass);
  EXPECT_NEAR(e1, e0, 0.01 * e0);
}

TEST(DeformableCoupling, ACubeRestsOnAFreeBlockOnTheFloor) {
  WorldSettings ws;
  ws.sleep.enabled = false;
  auto cube = cubeAt(Vec3(-0.25, -0.25, 0.5005), 0.5, 2, ws.gravity, 200.0); // mass damping: to rest (ours)
  ws.timeStep = cube->stableStep().dt;
  World world(ws);
  const BodyId block = addConcreteBlock(world, armour::test::makeBox(2.0, 2.0, 0.5), Vec3(0.0, 0.0, 0.25));
  world.addPlane(StaticPlane{"floor", Vec3::Zero(), Vec3::UnitZ(), MaterialId{0}}); // the block's concrete, the World's first
  world.addLoadStage(std::make_shared<DeformableCoupling>(*cube, std::vector<BodyId>{block}));
  while (world.time() < 0.3) world.step();

  double cubeMass = 0.0;
  for (double mass : cube->masses()) cubeMass += mass;
  const double blockMass = 1.0 / world.bodies().inverseMass(block);
  const Vec3 onBlock = world.externalForce(block);                 // from the cube
  const Vec3 fromFloor = world.bodies().force(block) - onBlock;   // the World's contacts
  std::cout << "cube " << cubeMass << " kg, block " << blockMass << " kg; the cube presses on the block with "
            << onBlock.transpose() << " N (weight " << cubeMass * 9.81 << " N); the floor holds "
            << fromFloor.transpose() << " N (both weights " << (cubeMass + blockMass) * 9.81
            << " N); block speed " << world.bodies().velocity(block).norm() << " m/s\n";
  EXPECT_NEAR(-onBlock.z(), cubeMass * 9.81, 0.005 * cubeMass * 9.81);
  EXPECT_NEAR(fromFloor.z(), (cubeMass + blockMass) * 9.81, 0.005 * (cubeMass + blockMass) * 9.81);
  EXPECT_LT(world.bodies().velocity(block).norm(), 1e-3);
}

} // namespace
} // namespace armour::simulation
