// SPDX-License-Identifier: GPL-3.0-or-later
// Numerical stability at the extremes: mass ratios of 100 (a light unit on a heavy one and a heavy
// one on a light one), soft and very stiff contacts, and a tiny fixed time step. Each case must
// come to the analytic resting overlap d = W L / (E_p A) (weight W carried over the face area A,
// length scale L = the smaller Dn of the pair) and stay there.

#include "geometry/ShapeLibrary.hpp"
#include "simulation/World.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace armour;
using namespace armour::simulation;

namespace {

constexpr double kG = 9.81;
constexpr double kRho = 2400.0;

struct Scene {
  World world;
  MaterialId material = 0;
  ShapeId cube = 0;

  Scene(double penaltyModulus, double timeStep = 0.0) : world(settings(timeStep)) {
    Material m;
    m.name = "concrete";
    m.restitution = 0.3; // settles in a few tenths of a second
    m.frictionStatic = m.frictionDynamic = 0.6;
    m.penaltyModulus = penaltyModulus;
    material = world.addMaterial(m);
    geometry::ShapeRequest r;
    r.volume = 1.0;
    cube = world.addShape("cube", geometry::makeShape("cube", r));
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  }
  static WorldSettings settings(double timeStep) {
    WorldSettings s;
    s.sleep.enabled = false; // the overlaps are measured on awake bodies
    s.timeStep = timeStep;
    return s;
  }
  BodyId addCube(double side, const Vec3& position) {
    BodySpec b;
    b.shape = cube;
    b.scale = side;
    b.material = material;
    b.position = position;
    return world.addBody(b);
  }
  double tilt(BodyId b) const { return Eigen::AngleAxisd(world.naturalOrientation(b)).angle(); }
};

/// Resting overlap of a face of area a carrying weight w at length scale l (unit: m).
double restingOverlap(double weight, double length, double modulus, double area) {
  return weight * length / (modulus * area);
}

} // namespace

TEST(Extremes, LightUnitOnAHeavyOneMassRatio100) {
  // A 1 m cube (2400 kg) on a 4.64 m cube (100 x the mass) on the floor. Floor: d = 101 m g L / (E A)
  // with L = A^(1/2) = 4.64 m, A = 21.5 m^2: 5.12e-4 m. Between the cubes: L = 1 m (the smaller Dn),
  // A = 1 m^2 (the small face): 2.354e-5 m. Both within 2 % after 1.5 s; no tilt (1e-6 rad).
  const double big = std::cbrt(100.0);
  Scene s(1e9);
  const BodyId heavy = s.addCube(big, Vec3(0, 0, 0.5 * big));
  const BodyId light = s.addCube(1.0, Vec3(0, 0, big + 0.5));
  s.world.advanceTo(1.5);
  const double m = kRho;
  const double floorOverlap = 0.5 * big - s.world.bodies().position(heavy).z();
  const double pairOverlap = s.world.bodies().position(heavy).z() + 0.5 * big + 0.5 - s.world.bodies().position(light).z();
  const double floorExpected = restingOverlap(101.0 * m * kG, big, 1e9, big * big);
  const double pairExpected = restingOverlap(m * kG, 1.0, 1e9, 1.0);
  EXPECT_NEAR(floorOverlap, floorExpected, 0.02 * floorExpected);
  EXPECT_NEAR(pairOverlap, pairExpected, 0.02 * pairExpected);
  EXPECT_LT(s.tilt(light), 1e-6);
  EXPECT_LT(s.world.bodies().velocity(light).norm(), 1e-4) << "the light unit has settled";
}

TEST(Extremes, HeavyUnitOnALightOneMassRatio100) {
  // The 4.64 m cube balanced on the 1 m cube: the light unit carries 100 x its weight. Floor:
  // d = 101 m g (1 m) / (E 1 m^2) = 2.378e-3 m; between the cubes (L = 1 m, A = 1 m^2):
  // 100 m g / E = 2.354e-3 m. Within 2 %; the stack stays upright (rotational stiffness of a
  // 1 m^2 patch E/(12 L) = 8.3e7 N m/rad against m g h = 7.8e6 N m/rad: stable).
  // It settles slowly: each contact's dashpot is set from the pair's reduced mass (about the light
  // unit's), so the heavy unit's bounce on it is damped about sqrt(100) = 10 times less than the
  // restitution says (damping ratio 0.04 instead of 0.36, e-folding time 0.6 s): hence 5 s here.
  const double big = std::cbrt(100.0);
  Scene s(1e9);
  const BodyId light = s.addCube(1.0, Vec3(0, 0, 0.5));
  const BodyId heavy = s.addCube(big, Vec3(0, 0, 1.0 + 0.5 * big));
  s.world.advanceTo(5.0);
  const double m = kRho;
  const double floorOverlap = 0.5 - s.world.bodies().position(light).z();
  const double pairOverlap = s.world.bodies().position(light).z() + 0.5 + 0.5 * big - s.world.bodies().position(heavy).z();
  const double floorExpected = restingOverlap(101.0 * m * kG, 1.0, 1e9, 1.0);
  const double pairExpected = restingOverlap(100.0 * m * kG, 1.0, 1e9, 1.0);
  EXPECT_NEAR(floorOverlap, floorExpected, 0.02 * floorExpected);
  EXPECT_NEAR(pairOverlap, pairExpected, 0.02 * pairExpected);
  EXPECT_LT(s.tilt(heavy), 1e-6);
  EXPECT_LT(s.world.bodies().velocity(heavy).norm(), 2e-4) << "the heavy unit has settled";
}

TEST(Extremes, SoftAndVeryStiffContactsRestAtTheirOverlap) {
  // E_p from 1e7 Pa (d = 2.354e-3 m) to 1e11 Pa (d = 2.354e-7 m): the auto time step follows the
  // stiffness (dt ~ E_p^-1/2), and the resting overlap is W L / (E_p A) within 1 % at both ends.
  for (const double modulus : {1e7, 1e11}) {
    Scene s(modulus);
    const BodyId b = s.addCube(1.0, Vec3(0, 0, 0.5));
    s.world.advanceTo(0.6);
    const double expected = restingOverlap(kRho * kG, 1.0, modulus, 1.0);
    EXPECT_NEAR(0.5 - s.world.bodies().position(b).z(), expected, 0.01 * expected) << "E_p = " << modulus << " Pa";
  }
}

TEST(Extremes, TinyFixedTimeStepHoldsTheRestingState) {
  // dt = 1e-7 s, 1000 x below the stable step: a cube placed at its resting overlap stays within
  // 1e-9 m of it over 2e5 steps (0.02 s), and the step count and time agree to round-off.
  const double dt = 1e-7;
  Scene s(1e9, dt);
  const double d = restingOverlap(kRho * kG, 1.0, 1e9, 1.0);
  const BodyId b = s.addCube(1.0, Vec3(0, 0, 0.5 - d));
  for (int i = 0; i < 200000; ++i) {
    s.world.step();
  }
  EXPECT_NEAR(s.world.bodies().position(b).z(), 0.5 - d, 1e-9);
  EXPECT_EQ(s.world.stepCount(), 200000u);
  EXPECT_NEAR(s.world.time(), 0.02, 1e-12);
}
