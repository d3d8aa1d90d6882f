// SPDX-License-Identifier: GPL-3.0-or-later
// Frictionless potential contact of a deforming body with a static half-space (issue 26; seed 002
// eq. 5 on deforming elements, HalfSpaceContact.hpp): the nodal forces are the exact gradient of
// the contact energy; a block comes to rest on a floor carrying its weight; a bar dropped flat on a
// rigid anvil at seed 002's 0.5 m/s carries rho c v, stays in contact for the wave's round trip
// 2 L / c, and leaves at its impact speed with its energy.
#include "core/Error.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/HalfSpaceContact.hpp"
#include "support/DeformableFixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

namespace armour::deformable {
namespace {

TEST(DeformableContact, NodalForcesAreTheGradientOfTheContactEnergy) {
  // A 1 m cube of 10-node tets, turned about (1, 2, 0.5) by 0.4 rad and sunk so that a corner is
  // 0.15 m into the floor z = 0: the forces must match minus the central differences of the energy
  // (step 1e-7 m) to 1e-6 of the largest force; and a flat face pressed in by d everywhere takes
  // G d A with energy G d^2 A / 2 (exact, round-off 1e-12).
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 2, 2, 2, ElementOrder::Quadratic);
  const auto triangles = surfaceTriangles(mesh, boundaryFaces(mesh));
  const HalfSpace floor{Vec3::Zero(), Vec3::UnitZ()};
  const double G = 1e11;
  const Mat3 R = Eigen::AngleAxisd(0.4, Vec3(1, 2, 0.5).normalized()).toRotationMatrix();
  std::vector<Vec3> x(mesh.nodeCount());
  double lowest = 1e9;
  for (std::size_t n = 0; n < x.size(); ++n) {
    x[n] = R * (mesh.nodes[n] - Vec3::Constant(0.5));
    lowest = std::min(lowest, x[n].z());
  }
  for (auto& p : x) {
    p.z() += -lowest - 0.15;
  }
  std::vector<Vec3> forces(x.size(), Vec3::Zero());
  addHalfSpaceContact(triangles, x, floor, G, forces);
  double largest = 0.0;
  for (const auto& f : forces) {
    largest = std::max(largest, f.norm());
  }
  ASSERT_GT(largest, 0.0);
  const auto energyAt = [&](const std::vector<Vec3>& positions) {
    std::vector<Vec3> scratch(positions.size(), Vec3::Zero());
    return addHalfSpaceContact(triangles, positions, floor, G, scratch);
  };
  double worst = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    for (int k = 0; k < 3; ++k) {
      auto plus = x;
      auto minus = x;
      plus[n][k] += 1e-7;
      minus[n][k] -= 1e-7;
      const double derivative = (energyAt(plus) - energyAt(minus)) / 2e-7;
      worst = std::max(worst, std::abs(derivative + forces[n][k]));
    }
  }
  std::cout << "largest contact force " << largest << " N, worst |dE/dx + f| " << worst << " N\n";
  EXPECT_LT(worst, 1e-6 * largest);
  // The undisturbed cube sunk flat by d = 0.01 m.
  std::vector<Vec3> flat(mesh.nodes);
  for (auto& p : flat) {
    p.z() -= 0.01;
  }
  std::vector<Vec3> flatForces(flat.size(), Vec3::Zero());
  const double energy = addHalfSpaceContact(triangles, flat, floor, G, flatForces);
  Vec3 total = Vec3::Zero();
  for (const auto& f : flatForces) {
    total += f;
  }
  EXPECT_NEAR(total.z(), G * 0.01 * 1.0, 1e-12 * G * 0.01);
  EXPECT_LT(total.head<2>().norm(), 1e-12 * G * 0.01);
  EXPECT_NEAR(energy, 0.5 * G * 0.01 * 0.01, 1e-12 * G * 0.01 * 0.01);
}

TEST(DeformableContact, BlockComesToRestOnAFloorCarryingItsWeight) {
  // A 1 x 1 x 1 m concrete block of tet10 set on the floor z = 0 under gravity, damped to rest
  // (mass damping 2 omega of its slowest mode, for 20 / omega): the floor carries the
  // weight, 22 955 N, within 1e-4 (the residual motion), with no sideways force (1e-9).
  DeformableSettings settings;
  settings.halfSpaces = {HalfSpace{Vec3::Zero(), Vec3::UnitZ()}};
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 2, 2, 2, ElementOrder::Quadratic);
  DeformableSettings probe = settings;
  const double G = DeformableBody(mesh, probe).contactGradient();
  // The slowest mode: the block bouncing on its contact layer, sqrt(G / (rho H)), or its own
  // first axial mode (free top, pressed base), pi c_bar / (2 H), whichever is lower.
  const double cBar = std::sqrt(settings.material.youngModulus / settings.material.density);
  const double omega = std::min(std::sqrt(G / (settings.material.density * 1.0)), 0.5 * std::numbers::pi * cBar);
  settings.massDamping = 2.0 * omega;
  DeformableBody body(mesh, settings, "block");
  const double dt = body.stableStep().dt;
  while (body.time() < 20.0 / omega) {
    body.step(dt);
  }
  const double weight = settings.material.density * 1.0 * 9.81;
  double deepest = 0.0;
  double shallowest = 1.0;
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    if (body.mesh().nodes[n].z() < 1e-9) {
      deepest = std::max(deepest, -body.positions()[n].z());
      shallowest = std::min(shallowest, -body.positions()[n].z());
    }
  }
  std::cout << "block on floor (G = " << G << " Pa/m, " << body.steps() << " steps of " << dt
            << " s): contact force " << body.contactForce().transpose() << " N vs weight " << weight
            << " N; base nodes sink " << shallowest << " to " << deepest << " m, mean pressure / G " << weight / G
            << " m\n";
  EXPECT_NEAR(body.contactForce().z(), weight, 1e-4 * weight);
  EXPECT_LT(body.contactForce().head<2>().norm(), 1e-9 * weight);
  // Not asserted: the base nodes sink unevenly (measured -2.6e-8 to +4.3e-8 m around the mean
  // 2.5e-8 m: corner nodes of the 6-node faces rise). The four linear sub-triangles per face give
  // the corners a third of their sub-triangles' load, where a uniform pressure on a quadratic face
  // gives them none (docs/theory.md section 19, "Contact with a static half-space").
}

TEST(DeformableContact, BarDroppedFlatOnAnAnvilCarriesRhoCVAndLeavesAtItsImpactSpeed) {
  // A 10 m bar of tet10 (0.125 m cells, 80 along it), sides held (uniaxial strain, as the wave
  // test), touching the rigid anvil z = 0 at 0.5 m/s (seed 002's impact speed), no gravity and no
  // viscosity. Targets: stress plateau at L/2 = -rho c v0 = -4.17 MPa within 2 %; contact ends
  // after 2 L / c = 5.61 ms within 3 % (the contact layer adds compliance, so the pulse is
  // slightly longer); the bar leaves at v0 within 2 %; kinetic + strain + contact energy
  // conserved within 1 %.
  constexpr double kLength = 10.0;
  constexpr double kSpeed = 0.5;
  const double h = kLength / 80;
  DeformableSettings settings;
  settings.gravity = Vec3::Zero();
  settings.halfSpaces = {HalfSpace{Vec3::Zero(), Vec3::UnitZ()}};
  DeformableBody body(test::boxMesh(Vec3(h, h, kLength), 1, 1, 80, ElementOrder::Quadratic), settings, "bar");
  body.setVelocities(std::vector<Vec3>(body.nodeCount(), Vec3(0.0, 0.0, -kSpeed)));
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    body.fixNode(n, Vec3(0.0, 0.0, 0.0), 3U);
  }
  std::vector<std::size_t> station;
  for (std::size_t e = 0; e < body.mesh().elementCount(); ++e) {
    double z = 0.0;
    for (int a = 0; a < 4; ++a) {
      z += 0.25 * body.mesh().nodes[body.mesh().element(e)[a]].z();
    }
    if (std::abs(z - 0.5 * kLength) < h) {
      station.push_back(e);
    }
  }
  const double c = dilatationalWaveSpeed(settings.material);
  const double sigma = settings.material.density * c * kSpeed;
  const double dt = body.stableStep().dt;
  const double energy0 = body.kineticEnergy();
  double plateau = 0.0;
  double plateauTime = 0.0;
  double drift = 0.0;
  double lastContact = 0.0;
  while (body.time() < 2.5 * kLength / c) {
    body.step(dt);
    const double t = body.time();
    if (t >= 0.7 * kLength / c && t <= 1.3 * kLength / c) {
      const auto stress = body.elementStresses();
      double s = 0.0;
      for (const auto e : station) {
        s += stress[e](2, 2) / static_cast<double>(station.size());
      }
      plateau += s * dt;
      plateauTime += dt;
    }
    if (body.contactForce().z() > 0.0) {
      lastContact = t;
    }
    drift = std::max(drift, std::abs(body.kineticEnergy() + body.strainEnergy() + body.contactEnergy() - energy0) /
                                energy0);
  }
  plateau /= plateauTime;
  double momentum = 0.0;
  double mass = 0.0;
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    momentum += body.masses()[n] * body.velocities()[n].z();
    mass += body.masses()[n];
  }
  const double speedAfter = momentum / mass;
  std::cout << "bar on anvil (G = " << body.contactGradient() << " Pa/m, dt " << dt << " s, stable step without contact "
            << 0.9 * body.stableStep().lengthMin / c << " s): plateau " << plateau << " Pa vs " << -sigma
            << "; contact ends at " << lastContact << " s vs 2L/c " << 2.0 * kLength / c << "; leaves at "
            << speedAfter << " m/s; energy drift " << 100.0 * drift << " %\n";
  EXPECT_NEAR(-plateau, sigma, 0.02 * sigma);
  EXPECT_NEAR(lastContact, 2.0 * kLength / c, 0.03 * 2.0 * kLength / c);
  EXPECT_NEAR(speedAfter, kSpeed, 0.02 * kSpeed);
  EXPECT_LT(drift, 0.01);
}

TEST(DeformableContact, BadHalfSpacesAreRefused) {
  DeformableSettings settings;
  settings.halfSpaces = {HalfSpace{Vec3::Zero(), Vec3(0.0, 0.0, 2.0)}};
  const auto mesh = test::boxMesh(Vec3(1, 1, 1), 1, 1, 1, ElementOrder::Linear);
  std::string message;
  try {
    DeformableBody body(mesh, settings, "anvil test");
  } catch (const core::InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("anvil test: half_spaces[0]: normal of length 2"), std::string::npos) << message;
  settings.halfSpaces[0].normal = Vec3::UnitZ();
  settings.contactGradient = -1.0;
  message.clear();
  try {
    DeformableBody body(mesh, settings, "anvil test");
  } catch (const core::InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("anvil test: contact_gradient: -1 Pa/m"), std::string::npos) << message;
}

} // namespace
} // namespace armour::deformable
