// SPDX-License-Identifier: GPL-3.0-or-later
// Hydrodynamic pressure loads from a storm file (hydro/StormLoads, seed 000 section 2.3) against
// closed-form results: the surface elements, Archimedes on closed units, exact integration of a
// linear pressure field, the trunk (elements outside a bounded trunk carry no load; a file uniform
// along y has no bound), the cost rules (dry and out-of-grid units, a storm time outside the file)
// and the Weibull variability (draws, reproducible, zero net force when uniform, unbiased mean).
// Drag, added mass and restarts: test_hydro_flow.cpp.

#include "core/Error.hpp"
#include "hydro/StormLoads.hpp"
#include "hydro/SurfaceElements.hpp"
#include "hydro/Variability.hpp"
#include "simulation/World.hpp"
#include "storm/StormFile.hpp"
#include "storm/StormSampler.hpp"
#include "support/HydroFixtures.hpp"
#include "support/ShapeCache.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

using namespace armour;
using namespace armour::test;
using armour::hydro::StormLoads;
using armour::simulation::BodyId;
using armour::simulation::BodySpec;
using armour::simulation::Quat;
using armour::simulation::Vec3;
using armour::simulation::World;
using armour::simulation::WorldSettings;

// ================================================================================================
// Surface elements

TEST(SurfaceElements, ClosedSurfaceSumsAndOctantPatches) {
  const geometry::TriangleMesh cube = centredBox(2.0, 2.0, 2.0);
  const hydro::SurfaceElements e = hydro::buildSurfaceElements(cube, 0.1, 2);
  EXPECT_NEAR(e.totalArea, 24.0, 1e-12);
  EXPECT_NEAR(e.volume, 8.0, 1e-12);
  EXPECT_EQ(e.patchCount(), 8);
  // A closed surface: sum a n = 0 and sum a c x n = 0 (divergence theorem), to round-off.
  Vec3 vectorArea = Vec3::Zero(), moment = Vec3::Zero();
  std::vector<double> patchArea(8, 0.0);
  for (std::size_t i = 0; i < e.size(); ++i) {
    vectorArea += e.area[i] * e.normal[i];
    moment += e.momentArm[i];
    patchArea[e.patch[i]] += e.area[i];
    EXPECT_NEAR(e.normal[i].norm(), 1.0, 1e-14);
  }
  EXPECT_LT(vectorArea.norm(), 1e-12);
  EXPECT_LT(moment.norm(), 1e-12);
  // Every octant of a centred cube holds three quarter-faces: 24 / 8 = 3 m^2 (elements straddling
  // the mid-planes go whole to one side: their share is at most a strip one element wide).
  for (double a : patchArea) {
    EXPECT_NEAR(a, 3.0, 0.1 * 3.0);
  }
  EXPECT_EQ(hydro::patchIndex(Vec3(0.9, -0.9, 0.9), e.bounds, 2), 1 + 2 * (0 + 2 * 1));
  EXPECT_EQ(hydro::patchIndex(Vec3(5.0, 5.0, 5.0), e.bounds, 2), 7) << "outside the box: clamped";
}

TEST(SurfaceElements, CoreLocElementCounts) {
  // seed 000: "some 4000 surface elements for each of the 242 units". Longest-edge bisection makes
  // about 6.5 triangles per (area / h^2): a Core-Loc of Dn = 1 m (surface 7 m^2) gets ~4600 at
  // h = 0.1 Dn and ~18000 at h = 0.05 Dn (counts come in steps: bisection halves areas). The bounds
  // are those steps' neighbours.
  const auto& coreloc = test::unitShape("coreloc");
  const hydro::SurfaceElements coarse = hydro::buildSurfaceElements(coreloc, 0.1, 2);
  const hydro::SurfaceElements fine = hydro::buildSurfaceElements(coreloc, 0.05, 2);
  RecordProperty("coreloc_elements_h0.1", std::to_string(coarse.size()));
  RecordProperty("coreloc_elements_h0.05", std::to_string(fine.size()));
  EXPECT_GT(coarse.size(), 3000u);
  EXPECT_LT(coarse.size(), 6500u);
  EXPECT_GT(fine.size(), 12000u);
  EXPECT_LT(fine.size(), 26000u);
  // Every edge of the refined surface is at most h: the elements' areas are at most sqrt(3)/4 h^2.
  for (const double a : coarse.area) {
    ASSERT_LE(a, std::sqrt(3.0) / 4.0 * 0.01 * (1.0 + 1e-12));
  }
  EXPECT_NEAR(coarse.totalArea, coreloc.surfaceArea(), 1e-9 * coreloc.surfaceArea());
}

// ================================================================================================
// Variability draws

TEST(Variability, DrawsAreReproducibleAndFollowTheWeibullModel) {
  storm::Variability model;
  model.present = true;
  model.probabilityAbove = {0.7, 0.3};
  model.classes[0] = {2.0, 0.4, -1.0, 0}; // crest above: shape 2, scale 0.4
  model.classes[1] = {1.0, 0.1, -1.0, 0}; // crest below: exponential, mean 0.1
  model.classes[2] = {1.5, 0.2, -1.0, 0};
  model.classes[3] = {1.5, 0.2, -1.0, 0};
  model.normalisationPressure = kRho * kG * 2.0;
  model.normalisationElevation = 2.0;
  hydro::VariabilitySettings settings;
  settings.seed = 42;
  const hydro::VariabilityModel v(model, settings);
  ASSERT_TRUE(v.active());
  EXPECT_EQ(v.normalisedDeviation(3, 5, 17, true), v.normalisedDeviation(3, 5, 17, true));
  // Crest draws over 40000 keys: P(above) = 0.7 and the class means lambda Gamma(1 + 1/k)
  // (0.4 Gamma(1.5) = 0.3545 above, 0.1 below). Standard errors: sqrt(0.21/40000) = 0.0023 for the
  // fraction, < 0.002 for the means: 4 sigma bounds, deterministic for this seed.
  int above = 0;
  double sumAbove = 0.0, sumBelow = 0.0;
  const int n = 40000;
  for (int i = 0; i < n; ++i) {
    const double d = v.normalisedDeviation(static_cast<std::uint64_t>(i % 200), i / 200 % 8, i / 1600, true);
    if (d > 0.0) {
      ++above;
      sumAbove += d;
    } else {
      sumBelow -= d;
    }
  }
  EXPECT_NEAR(above / static_cast<double>(n), 0.7, 4 * 0.0023);
  EXPECT_NEAR(sumAbove / above, 0.4 * std::tgamma(1.5), 4 * 0.002);
  EXPECT_NEAR(sumBelow / (n - above), 0.1, 4 * 0.002);
  // The pressure deviation scales with |eta| / a_n and vanishes at a zero crossing.
  storm::WavePhase phase{true, 17, 1.0};
  EXPECT_DOUBLE_EQ(v.pressureDeviation(3, 5, phase), v.normalisedDeviation(3, 5, 17, true) * kRho * kG * 2.0 * 0.5);
  phase.elevation = 0.0;
  EXPECT_EQ(v.pressureDeviation(3, 5, phase), 0.0);
}

// ================================================================================================
// Pressure integration

TEST_F(HydroTest, ArchimedesOnSubmergedClosedUnits) {
  // Hydrostatic still water: F = rho g V up, no horizontal force, no moment about the centre of
  // buoyancy (the centroid, fully submerged). The midpoint rule integrates the linear field exactly
  // on flat triangles, so the error is round-off plus the double-stored field; 0.5 % (seed-level
  // accuracy) and 1e-3 rho g V (Dn) are the bounds asked for, the measured errors are printed.
  const std::string path = stillWater();
  Scene scene;
  const std::vector<std::string> shapes = {"cube", "coreloc", "rock"};
  std::vector<double> scales = {1.0, 1.3, 0.8};
  std::vector<BodyId> ids;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    ids.push_back(scene.add(shapes[k], Vec3(-5.0 + 5.0 * k, 0.3 * k, -5.0 - k), someOrientation(static_cast<int>(k)),
                            scales[k]));
  }
  StormLoads stage(scene.world, settingsFor(path), "all", path);
  const Loads l = applyAt(stage, scene.world, 0.0);
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const double volume = std::pow(scales[k], 3); // unit shapes are 1 m^3
    const double buoyancy = kRho * kG * volume;
    const double dn = scales[k];
    const Vec3& f = l.force[ids[k]];
    const Vec3& m = l.torque[ids[k]];
    RecordProperty(shapes[k] + "_buoyancy_relative_error", fmt::format("{:.3e}", f.z() / buoyancy - 1.0));
    EXPECT_NEAR(f.z(), buoyancy, 5e-3 * buoyancy) << shapes[k];
    EXPECT_LT(std::hypot(f.x(), f.y()), 1e-3 * buoyancy) << shapes[k];
    EXPECT_LT(m.norm(), 1e-3 * buoyancy * dn) << shapes[k];
    EXPECT_NEAR(stage.applied(ids[k]).pressureForce.z(), f.z(), 1e-12 * buoyancy);
    EXPECT_DOUBLE_EQ(stage.held(ids[k]).wetFraction, 1.0);
  }
}

TEST_F(HydroTest, HalfSubmergedCubeFeelsHalfTheBuoyancy) {
  // A 1 m cube with its centroid on the still water level and its faces aligned: the bottom face
  // at 0.5 m depth carries rho g 0.5 L^2 and the wet halves of the side faces cancel. The side
  // faces' elements straddling the surface get all or nothing, and the interpolated pressure
  // within half a voxel of the surface is not hydrostatic (it is on the sides only, where it
  // cancels): 1 % bound.
  const std::string path = stillWater();
  Scene scene;
  const BodyId b = scene.add("cube", Vec3(0.1, 0.0, 0.0));
  StormLoads stage(scene.world, settingsFor(path), "all", path);
  const Loads l = applyAt(stage, scene.world, 0.0);
  const double half = 0.5 * kRho * kG;
  RecordProperty("relative_error", fmt::format("{:.3e}", l.force[b].z() / half - 1.0));
  EXPECT_NEAR(l.force[b].z(), half, 0.01 * half);
  EXPECT_LT(std::hypot(l.force[b].x(), l.force[b].y()), 0.01 * half);
  EXPECT_NEAR(stage.held(b).wetFraction, 0.5, 0.02);
}

TEST_F(HydroTest, LinearPressureFieldIsIntegratedExactly) {
  // p = p0 + a x + c z + e t with alpha = 1: bilinear-in-space, linear-in-time sampling reproduces
  // it exactly and the midpoint rule integrates it exactly on flat triangles, so F = -grad p V to
  // round-off: 1e-9 relative. The moment's integrand (r - x_c) x n p is quadratic on a triangle,
  // which the one-point rule integrates with an O(h^2) error (the exact value is 0: the first
  // moment of the volume about its centroid vanishes); measured 1e-6 of |grad p| V Dn at
  // h = 0.05 Dn: bound 1e-5.
  const double p0 = 2.0e4, a = -1500.0, c = 4000.0, e = 900.0;
  const std::string path = file("linear.nc");
  writeStorm(path, gridHeader(-6.0, 6.0, -6.0, 6.0, 0.4, 10.0), {0.0, 0.25, 0.5, 0.75, 1.0},
             [&](double t, double x, double z) {
               Flow f;
               f.p = p0 + a * x + c * z + e * t;
               f.alpha = 1.0;
               return f;
             },
             flat());
  Scene scene;
  const BodyId b = scene.add("coreloc", Vec3(0.7, 0.2, -0.4), someOrientation(3), 1.4);
  hydro::StormLoadSettings s = settingsFor(path);
  s.updateInterval = 0.05;
  s.timeOffset = 0.02; // storm time 0.37 s at t = 0.35 s: between records
  StormLoads stage(scene.world, s, "all", path);
  const Loads l = applyAt(stage, scene.world, 0.35);
  const double volume = std::pow(1.4, 3);
  const Vec3 expected = -Vec3(a, 0.0, c) * volume;
  const double scale = Vec3(a, 0.0, c).norm() * volume;
  RecordProperty("relative_error", fmt::format("{:.3e}", (l.force[b] - expected).norm() / scale));
  EXPECT_LT((l.force[b] - expected).norm(), 1e-9 * scale);
  RecordProperty("moment_relative_error", fmt::format("{:.3e}", l.torque[b].norm() / (scale * 1.4)));
  EXPECT_LT(l.torque[b].norm(), 1e-5 * scale * 1.4);
}

TEST_F(HydroTest, UnitsReachingOutOfTheSamplingBoxKeepArchimedes) {
  // The water does not end where the storm file's box does. Units in still water reaching out of
  // the grid or lying wholly beyond it take the edge column's flow along x, the edge row's pressure
  // continued hydrostatically along z, and a bounded trunk's section flow along y: Archimedes (rho
  // g V up, no horizontal force) to the bounds of ArchimedesOnSubmergedClosedUnits (0.5 %, 1e-3
  // rho g V). Leaving the outer elements unloaded pushed the units out of the box with the pressure
  // of the rest (3.7 to 5.2 rho g V horizontally, measured); holding the bottom row instead of
  // continuing it, or skipping a unit wholly outside (the loose trunk's units fallen off the toe in
  // front of the tank file's window), took their buoyancy.
  const std::string open = stillWater();
  const std::string trunk = file("short_trunk.nc");
  writeStorm(trunk, gridHeader(-5.0, 5.0, -10.0, 2.0, 0.5, 0.0, -5.0, 10.0), {0.0, 10.0}, hydrostatic(0.0), flat());
  const std::string shallow = file("shallow.nc"); // rows from z = -6 m up: the seabed lies deeper
  writeStorm(shallow, gridHeader(-10.0, 10.0, -6.0, 2.0, 0.5, 0.0), {0.0, 10.0}, hydrostatic(0.0), flat());
  const std::string window = file("window.nc");   // rows up to z = -3 m only: the surface lies above
  writeStorm(window, gridHeader(-10.0, 10.0, -12.0, -3.0, 0.5, 0.0), {0.0, 10.0}, hydrostatic(0.0), flat());
  struct Case {
    std::string storm, shape;
    Vec3 position;
    double scale;
    double buoyancyFraction = 1.0;
  };
  const std::vector<Case> cases = {{open, "coreloc", Vec3(10.0, 0.3, -5.0), 1.3},   // across the x edge
                                   {open, "cube", Vec3(10.3, 0.0, -4.0), 1.0},      // half beyond it
                                   {open, "coreloc", Vec3(14.0, 0.0, -5.0), 1.0},   // wholly beyond it
                                   {trunk, "cube", Vec3(0.0, 5.0, -4.0), 1.0},      // across a trunk end
                                   {shallow, "cube", Vec3(0.0, 0.0, -6.0), 1.0},    // across the bottom
                                   {shallow, "dolos", Vec3(-2.0, 0.0, -9.0), 1.0},  // wholly below it
                                   {window, "cube", Vec3(0.0, 0.0, -1.5), 1.0},     // above the top, wet
                                   {window, "cube", Vec3(3.0, 0.0, 0.0), 1.0, 0.5}, // half out of the water
                                   {window, "cube", Vec3(0.0, 0.0, 3.0), 1.0, 0.0}}; // dry
  for (const Case& c : cases) {
    Scene scene;
    const BodyId b = scene.add(c.shape, c.position, c.buoyancyFraction == 0.5 ? Quat::Identity() : someOrientation(2),
                               c.scale);
    StormLoads stage(scene.world, settingsFor(c.storm), "all", c.storm);
    const Loads l = applyAt(stage, scene.world, 0.0);
    const double buoyancy = kRho * kG * std::pow(c.scale, 3);
    const std::string what = c.shape + " at " + fmt::format("({}, {}, {}) in {}", c.position.x(), c.position.y(),
                                                             c.position.z(), fs::path(c.storm).filename().string());
    RecordProperty(fmt::format("{}_{}_{}_horizontal_over_buoyancy", c.shape, c.position.x(), c.position.z()),
                   fmt::format("{:.3e}", std::hypot(l.force[b].x(), l.force[b].y()) / buoyancy));
    EXPECT_NEAR(l.force[b].z(), c.buoyancyFraction * buoyancy, 5e-3 * buoyancy) << what;
    EXPECT_LT(std::hypot(l.force[b].x(), l.force[b].y()), 1e-3 * buoyancy) << what;
    EXPECT_LT(l.torque[b].norm(), 1e-3 * buoyancy * c.scale) << what;
    EXPECT_EQ(stage.counters().skippedBodies, c.buoyancyFraction == 0.0 ? 1u : 0u) << what;
  }
}

TEST_F(HydroTest, UnitsReachingIntoVoxelsWithoutDataKeepArchimedes) {
  // A storm file sampled on the units' surfaces (seed 000's 3D tanks) has data only in the armour
  // layer: here still water whose voxels hold data only in a band x < 0, z > -8 m (the layer; in
  // front of it, x > 0, and below it, samples = 0). Units straddling the band's front or its
  // bottom, or wholly outside it, take the gap fill (still water under the free surface) on their
  // elements in the empty voxels: Archimedes to the bounds of ArchimedesOnSubmergedClosedUnits
  // (0.5 %, 1e-3 rho g V). Leaving those elements atmospheric (as before) pushed the units out of
  // the band with the pressure of the rest and took the buoyancy of the part outside.
  const std::string path = file("band.nc");
  storm::StormHeader h = gridHeader(-10.0, 10.0, -12.0, 2.0, 0.5, 0.0);
  for (std::size_t k = 0; k < h.nz(); ++k) {
    for (std::size_t i = 0; i < h.nx(); ++i) {
      h.samples[k * h.nx() + i] = (h.x[i] < 0.0 && h.z[k] > -8.0) ? 17 : 0;
    }
  }
  writeStorm(path, h, {0.0, 10.0}, hydrostatic(0.0), flat());
  struct Case {
    std::string shape;
    Vec3 position;
    double scale;
  };
  const std::vector<Case> cases = {{"cube", Vec3(0.0, 0.0, -4.0), 1.0},       // half in front of the band
                                   {"coreloc", Vec3(0.2, 0.3, -5.0), 1.3},    // across the band's front
                                   {"cube", Vec3(-3.0, 0.0, -8.0), 1.0},      // half below the band
                                   {"dolos", Vec3(4.0, 0.0, -6.0), 1.0}};     // wholly in front of it
  for (const Case& c : cases) {
    Scene scene;
    const BodyId b = scene.add(c.shape, c.position, someOrientation(3), c.scale);
    StormLoads stage(scene.world, settingsFor(path), "all", path);
    const Loads l = applyAt(stage, scene.world, 0.0);
    const double buoyancy = kRho * kG * std::pow(c.scale, 3);
    const std::string what = c.shape + " at " + fmt::format("({}, {}, {})", c.position.x(), c.position.y(),
                                                             c.position.z());
    RecordProperty(c.shape + "_" + fmt::format("{}", c.position.x()) + "_horizontal_over_buoyancy",
                   fmt::format("{:.3e}", std::hypot(l.force[b].x(), l.force[b].y()) / buoyancy));
    EXPECT_NEAR(l.force[b].z(), buoyancy, 5e-3 * buoyancy) << what;
    EXPECT_LT(std::hypot(l.force[b].x(), l.force[b].y()), 1e-3 * buoyancy) << what;
    EXPECT_LT(l.torque[b].norm(), 1e-3 * buoyancy * c.scale) << what;
    EXPECT_GT(stage.counters().filledElements, 0u) << what;
    EXPECT_LE(stage.counters().filledElements, stage.counters().wetElements) << what;
    EXPECT_NE(stage.summary().find("took the gap fill"), std::string::npos) << stage.summary();
  }
}

TEST_F(HydroTest, OffsetPutsTheSceneIntoTheFilesCoordinates) {
  // A storm file in a tank's coordinates (still water with its surface at z = 0 over x in
  // [-10, 10] m, a linear-in-x pressure added so that the position along x matters) and two
  // scenes: one placed in the tank's coordinates, one whose origin lies at the tank's
  // (x, z) = (-104, -3). With hydro.storm.offset = [-104, -3] the second unit, at scene (104 + x,
  // z + 3), takes the first one's load exactly (same samples, same arithmetic: 1e-12); without
  // it, it lies beyond the grid's x edge and takes the edge column's flow: buoyancy, but none of
  // the horizontal pressure gradient.
  const std::string path = file("tank.nc");
  writeStorm(path, gridHeader(-10.0, 10.0, -12.0, 2.0, 0.5, 0.0), {0.0, 10.0},
             [](double, double x, double z) {
               Flow f = hydrostatic(0.0)(0.0, x, z);
               if (z < 0.0) f.p += 300.0 * x;
               return f;
             },
             flat());
  const Vec3 inTank(2.3, 0.4, -4.1);
  Scene tank;
  const BodyId a = tank.add("coreloc", inTank, someOrientation(1));
  StormLoads tankStage(tank.world, settingsFor(path), "all", path);
  const Loads expected = applyAt(tankStage, tank.world, 0.0);
  ASSERT_GT(expected.force[a].z(), 0.5 * kRho * kG);
  ASSERT_GT(std::abs(expected.force[a].x()), 100.0);

  const Vec3 inScene = inTank + Vec3(104.0, 0.0, 3.0);
  Scene scene;
  const BodyId b = scene.add("coreloc", inScene, someOrientation(1));
  hydro::StormLoadSettings shifted = settingsFor(path);
  shifted.offsetX = -104.0;
  shifted.offsetZ = -3.0;
  StormLoads stage(scene.world, shifted, "all", path);
  const Loads l = applyAt(stage, scene.world, 0.0);
  EXPECT_NEAR((l.force[b] - expected.force[a]).norm(), 0.0, 1e-12 * expected.force[a].norm());
  EXPECT_NEAR((l.torque[b] - expected.torque[a]).norm(), 0.0, 1e-12 * expected.force[a].norm());
  EXPECT_EQ(stage.evaluatedElements(b), tankStage.evaluatedElements(a));

  StormLoads unshifted(scene.world, settingsFor(path), "all", path);
  const Loads held = applyAt(unshifted, scene.world, 0.0);
  EXPECT_NEAR(held.force[b].z(), expected.force[a].z(), 5e-3 * expected.force[a].z());
  EXPECT_LT(std::abs(held.force[b].x()), 1e-3 * std::abs(expected.force[a].x()));
  EXPECT_EQ(unshifted.counters().skippedBodies, 0u);
}

TEST_F(HydroTest, ImpermeableBedTakesNoPressureUnderAUnitRestingOnIt) {
  // A 1 m cube (Dn = 1 m, faces along the axes) resting on a bed at z = -5 m in still water whose
  // surface is at z = 0 (h = 5 m over the bed, the box H = 1 m high, A = 1 m^2). Porous bed (the
  // default): the bottom face carries rho g h A up, F_z = rho g V (Archimedes). Impermeable: the
  // bottom face carries nothing and the top face, h - H down, pushes down: F_z = -rho g (h - H) A
  // = -4 rho g; the side faces cancel in both. The midpoint rule integrates the linear field
  // exactly on flat faces, so the bounds are Archimedes' (5e-3 of the force; measured round-off).
  const std::string path = stillWater();
  const double bedLevel = -5.0;
  const double weightOfWater = kRho * kG; // rho g times 1 m^3 (N)
  const auto loadsOf = [&](const Vec3& position, const Quat& q, hydro::BedKind kind, double offsetZ = 0.0) {
    Scene scene;
    const BodyId b = scene.add("cube", position, q);
    hydro::StormLoadSettings s = settingsFor(path);
    s.bed.kind = kind;
    s.bed.level = bedLevel;
    s.offsetZ = offsetZ;
    StormLoads stage(scene.world, s, "all", path);
    // The bottom face is what the switch drops: 1 m^2 of elements facing straight down.
    double down = 0.0;
    const hydro::SurfaceElements& el = stage.elements(scene.world.bodyShape(b));
    for (std::size_t e = 0; e < el.size(); ++e) {
      down += el.normal[e].z() < -0.99 ? el.area[e] : 0.0;
    }
    EXPECT_NEAR(down, 1.0, 1e-12) << "the cube's body frame has its faces along the axes";
    const Loads l = applyAt(stage, scene.world, 0.0);
    return std::make_pair(l.force[b], l.torque[b]);
  };
  const Vec3 resting(0.3, 0.0, bedLevel + 0.5);

  const auto [porous, porousTorque] = loadsOf(resting, Quat::Identity(), hydro::BedKind::Porous);
  EXPECT_NEAR(porous.z(), weightOfWater, 5e-3 * weightOfWater) << "porous: Archimedes";

  const auto [sealed, sealedTorque] = loadsOf(resting, Quat::Identity(), hydro::BedKind::Impermeable);
  const double expected = -kRho * kG * (5.0 - 1.0) * 1.0;
  RecordProperty("impermeable_fz_relative_error", fmt::format("{:.3e}", sealed.z() / expected - 1.0));
  EXPECT_NEAR(sealed.z(), expected, 5e-3 * std::abs(expected)) << "impermeable: only the top face, pushing down";
  EXPECT_LT(std::hypot(sealed.x(), sealed.y()), 1e-3 * weightOfWater);
  EXPECT_LT(sealedTorque.norm(), 1e-3 * weightOfWater * 1.0) << "a uniform top pressure has no moment";
  // The difference is the bottom face's rho g h A, to round-off.
  EXPECT_NEAR(porous.z() - sealed.z(), kRho * kG * 5.0, 1e-9 * kRho * kG * 5.0);

  // Lifted 2 cm (2 % of Dn, beyond the 1 % band): water under it, the porous result.
  const auto [lifted, liftedTorque] =
      loadsOf(resting + Vec3(0.0, 0.0, 0.02), Quat::Identity(), hydro::BedKind::Impermeable);
  EXPECT_NEAR(lifted.z(), weightOfWater, 5e-3 * weightOfWater) << "2 cm above the bed: loaded from below";

  // Resting on an edge (turned 45 degrees about x): no face points within 26 degrees of straight
  // down, so nothing is dropped and the impermeable bed gives the porous result exactly.
  const Quat edge(Eigen::AngleAxisd(std::numbers::pi / 4.0, Vec3::UnitX()));
  const Vec3 onEdge(0.3, 0.0, bedLevel + std::sqrt(0.5));
  const auto [edgePorous, edgePorousTorque] = loadsOf(onEdge, edge, hydro::BedKind::Porous);
  const auto [edgeSealed, edgeSealedTorque] = loadsOf(onEdge, edge, hydro::BedKind::Impermeable);
  EXPECT_EQ(edgeSealed.z(), edgePorous.z());
  EXPECT_NEAR(edgeSealed.z(), weightOfWater, 5e-3 * weightOfWater);

  // The bed level is in the scene's coordinates: with hydro.storm.offset z = +1 m the scene's bed
  // at -5 m lies at the file's -4 m, 4 m under the surface, and the top face 3 m: F_z = -3 rho g.
  const auto [shifted, shiftedTorque] = loadsOf(resting, Quat::Identity(), hydro::BedKind::Impermeable, 1.0);
  EXPECT_NEAR(shifted.z(), -3.0 * weightOfWater, 5e-3 * 3.0 * weightOfWater);
}

TEST_F(HydroTest, BadBedSettingsNameTheKey) {
  const std::string path = stillWater();
  Scene scene;
  scene.add("cube", Vec3(0.0, 0.0, -3.0));
  hydro::StormLoadSettings s = settingsFor(path);
  s.bed.kind = hydro::BedKind::Impermeable;
  s.bed.toleranceDn = 1.5;
  try {
    StormLoads stage(scene.world, s, "all", path);
    ADD_FAILURE() << "a bed tolerance of 1.5 Dn was accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hydro.storm.bed_tolerance: = 1.5 Dn: must lie in [0, 1]"), std::string::npos)
        << e.what();
  }
}

TEST_F(HydroTest, FileUniformAlongYLoadsUnitsBeyondItsTrunkRange) {
  // The same still water twice, averaged over y in [-5, 5] m: bounded (a 3D tank's section) and
  // uniform along y (a 2D tank, which holds at every y). A unit at y = 20 m, outside the range,
  // gets nothing from the bounded file (skipped, no element sampled) and from the uniform file the
  // load of the identical unit at y = 0: the fields do not depend on y and both units sit at the
  // same (x, z) with the same orientation, so their elements sample the same points: equal to
  // round-off (1e-12 relative), and Archimedes to the 0.5 % of ArchimedesOnSubmergedClosedUnits.
  storm::StormHeader h = gridHeader(-5.0, 5.0, -10.0, 2.0, 0.5, 0.0, -5.0, 10.0);
  const std::string bounded = file("bounded.nc");
  writeStorm(bounded, h, {0.0, 10.0}, hydrostatic(0.0), flat());
  h.uniformAlongY = true;
  const std::string uniform = file("uniform.nc");
  writeStorm(uniform, h, {0.0, 10.0}, hydrostatic(0.0), flat());
  const double buoyancy = kRho * kG; // library shapes are 1 m^3

  Scene scene;
  const BodyId inside = scene.add("coreloc", Vec3(0.5, 0.0, -4.0), someOrientation(1));
  const BodyId beyond = scene.add("coreloc", Vec3(0.5, 20.0, -4.0), someOrientation(1));
  {
    StormLoads stage(scene.world, settingsFor(bounded), "all", bounded);
    const Loads l = applyAt(stage, scene.world, 0.0);
    EXPECT_NEAR(l.force[inside].z(), buoyancy, 5e-3 * buoyancy);
    EXPECT_EQ(l.force[beyond], Vec3::Zero());
    EXPECT_EQ(l.torque[beyond], Vec3::Zero());
    EXPECT_EQ(stage.evaluatedElements(beyond), 0u);
    EXPECT_EQ(stage.counters().skippedBodies, 1u) << "outside a bounded file's trunk counts as skipped";
    EXPECT_EQ(stage.counters().evaluatedBodies, 1u);
  }
  {
    StormLoads stage(scene.world, settingsFor(uniform), "all", uniform);
    const Loads l = applyAt(stage, scene.world, 0.0);
    EXPECT_NEAR(l.force[inside].z(), buoyancy, 5e-3 * buoyancy);
    EXPECT_LT((l.force[beyond] - l.force[inside]).norm(), 1e-12 * buoyancy);
    EXPECT_LT((l.torque[beyond] - l.torque[inside]).norm(), 1e-12 * buoyancy);
    EXPECT_EQ(stage.evaluatedElements(beyond), stage.evaluatedElements(inside));
    EXPECT_GT(stage.evaluatedElements(beyond), 1000u);
    EXPECT_EQ(stage.counters().skippedBodies, 0u);
    EXPECT_EQ(stage.counters().evaluatedBodies, 2u);
  }
}

// ================================================================================================
// The cost rules

TEST_F(HydroTest, DryUnitsCostNothingAndUnitsBeyondTheGridAreLoaded) {
  const std::string path = stillWater();
  Scene scene;
  const BodyId wet = scene.add("coreloc", Vec3(0.0, 0.0, -5.0));
  const BodyId dry = scene.add("coreloc", Vec3(3.0, 0.0, 5.0));
  const BodyId outside = scene.add("coreloc", Vec3(30.0, 0.0, -5.0));
  const BodyId filtered = scene.add("coreloc", Vec3(-3.0, 0.0, -5.0), Quat::Identity(), 1.0, 2400.0, "rock_1");
  BodySpec fixedSpec;
  fixedSpec.name = "unit_fixed";
  fixedSpec.shape = scene.shape("coreloc");
  fixedSpec.material = scene.material(2400.0);
  fixedSpec.position = Vec3(-6.0, 0.0, -5.0);
  fixedSpec.fixed = true;
  const BodyId fixed = scene.world.addBody(fixedSpec);
  StormLoads stage(scene.world, settingsFor(path), "unit", path);
  const Loads l = applyAt(stage, scene.world, 0.0);
  EXPECT_TRUE(stage.loaded(wet));
  EXPECT_FALSE(stage.loaded(filtered)) << "name filter 'unit'";
  EXPECT_FALSE(stage.loaded(fixed)) << "fixed bodies never take loads";
  EXPECT_GT(stage.evaluatedElements(wet), 1000u);
  EXPECT_NEAR(l.force[wet].z(), kRho * kG, 0.005 * kRho * kG);
  for (const BodyId b : {dry, filtered, fixed}) {
    EXPECT_EQ(stage.evaluatedElements(b), 0u) << b;
    EXPECT_EQ(l.force[b], Vec3::Zero()) << b;
    EXPECT_EQ(l.torque[b], Vec3::Zero()) << b;
  }
  // 20 m beyond the grid's x edge the water goes on: the edge column's still water.
  EXPECT_EQ(stage.evaluatedElements(outside), stage.evaluatedElements(wet));
  EXPECT_NEAR(l.force[outside].z(), kRho * kG, 0.005 * kRho * kG);
  const auto& c = stage.counters();
  EXPECT_EQ(c.loadedBodies, 3u);
  EXPECT_EQ(c.skippedBodies, 1u);
  EXPECT_EQ(c.evaluatedBodies, 2u);
  EXPECT_EQ(c.evaluatedElements, stage.evaluatedElements(wet) + stage.evaluatedElements(outside));
}

TEST_F(HydroTest, StormTimeOutsideTheFileIsAnInputErrorNamingFileAndRange) {
  const std::string path = stillWater(10.0);
  Scene scene;
  scene.add("cube", Vec3(0.0, 0.0, -5.0));
  hydro::StormLoadSettings s = settingsFor(path);
  s.timeOffset = 4.0;
  for (const auto mode : {hydro::BetweenUpdates::Hold, hydro::BetweenUpdates::Interpolate}) {
    s.betweenUpdates = mode;
    StormLoads stage(scene.world, s, "all", path);
    applyAt(stage, scene.world, 5.9);
    applyAt(stage, scene.world, 6.0); // storm time 10 s: the last record (Interpolate holds it ahead)
    try {
      applyAt(stage, scene.world, 6.1);
      ADD_FAILURE() << "storm time 10.1 s is past the last record";
    } catch (const core::InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find("10.1"), std::string::npos) << what;
      EXPECT_NE(what.find("0 .. 10 s"), std::string::npos) << what;
    }
  }
}

// ================================================================================================
// Variability

TEST_F(HydroTest, VariabilityIsReproducibleAndSeedDependent) {
  const std::string path = file("waves.nc");
  writeVariabilityStorm(path, 8);
  auto forces = [&](std::uint64_t seed) {
    Scene scene;
    scene.add("coreloc", Vec3(0.0, 0.0, -5.0), someOrientation(1));
    scene.add("cube", Vec3(1.0, 1.0, -5.0));
    hydro::StormLoadSettings s = settingsFor(path);
    s.variability.enabled = true;
    s.variability.seed = seed;
    StormLoads stage(scene.world, s, "all", path);
    std::vector<Vec3> out;
    for (double t : {0.5, 1.5, 2.5}) {
      const Loads l = applyAt(stage, scene.world, t);
      out.insert(out.end(), l.force.begin(), l.force.end());
      out.insert(out.end(), l.torque.begin(), l.torque.end());
    }
    return out;
  };
  const auto a = forces(7), b = forces(7), c = forces(8);
  ASSERT_EQ(a.size(), c.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], b[i]) << i;   // bit-identical
    EXPECT_NE(a[i], c[i]) << i;   // every load differs with another seed
  }
}

TEST_F(HydroTest, UniformDeviationGivesNoNetForce) {
  // patchesPerAxis = 1: one deviation dp over the whole closed surface; -dp sum a n = 0 and
  // -dp sum a c x n = 0, so the loads equal those without variability to round-off (1e-9 of
  // dp A, A the surface area, i.e. of the largest partial sum).
  const std::string path = file("waves.nc");
  writeVariabilityStorm(path, 8);
  Scene scene;
  const BodyId b = scene.add("coreloc", Vec3(0.0, 0.0, -5.0), someOrientation(2));
  hydro::StormLoadSettings s = settingsFor(path);
  StormLoads plain(scene.world, s, "all", path);
  s.variability.enabled = true;
  s.variability.patchesPerAxis = 1;
  StormLoads varied(scene.world, s, "all", path);
  const double area = varied.elements(scene.world.bodyShape(b)).totalArea;
  // The deviation at t = 0.5 s (storm time 0.5 s: a crest, eta = 0.92 m).
  const storm::StormReader reader(path);
  storm::StormSampler sampler(reader);
  sampler.setTime(0.5);
  const hydro::VariabilityModel model(reader.header().variability, s.variability);
  const double dp = model.pressureDeviation(b, 0, sampler.phase(0.0));
  ASSERT_GT(std::abs(dp), 10.0) << "the test needs a deviation";
  const Loads l0 = applyAt(plain, scene.world, 0.5);
  const Loads l1 = applyAt(varied, scene.world, 0.5);
  EXPECT_LT((l1.force[b] - l0.force[b]).norm(), 1e-9 * std::abs(dp) * area);
  EXPECT_LT((l1.torque[b] - l0.torque[b]).norm(), 1e-9 * std::abs(dp) * area);
}

TEST_F(HydroTest, OctantDeviationsAverageToTheMeanForce) {
  // Octants: independent deviations per patch give a net force and moment each half wave, of zero
  // mean for this symmetric model. Over N = 200 half waves the mean force must lie within 4
  // standard errors (sample standard deviation / sqrt(N)) of the force without variability, per
  // component; and the spread must be real (the variability does load the unit).
  const int halfWaves = 200;
  const std::string path = file("waves.nc");
  writeVariabilityStorm(path, halfWaves);
  // (A Core-Loc: a cube's octant forces all pass through its centre and make no moment.)
  Scene scene;
  const BodyId b = scene.add("coreloc", Vec3(0.0, 0.0, -5.0), someOrientation(4));
  hydro::StormLoadSettings s = settingsFor(path);
  s.elementSizePerDn = 0.1;
  s.updateInterval = kWavePeriod / 2.0;
  s.timeOffset = kWavePeriod / 4.0; // update j at storm time (j + 1/2) T/2: a crest or a trough
  StormLoads plain(scene.world, s, "all", path);
  const Vec3 reference = applyAt(plain, scene.world, 0.0).force[b];
  s.variability.enabled = true;
  StormLoads varied(scene.world, s, "all", path);
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
  double torqueSum = 0.0;
  for (int j = 0; j < halfWaves; ++j) {
    const Loads l = applyAt(varied, scene.world, j * s.updateInterval);
    const Vec3 d = l.force[b] - reference;
    sum += d;
    sum2 += d.cwiseProduct(d);
    torqueSum += l.torque[b].norm();
  }
  const Vec3 mean = sum / halfWaves;
  const Vec3 sd = (sum2 / halfWaves - mean.cwiseProduct(mean)).cwiseSqrt();
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(sd[a], 100.0) << "axis " << a << ": octant deviations must give a net force";
    EXPECT_LT(std::abs(mean[a]), 4.0 * sd[a] / std::sqrt(halfWaves)) << "axis " << a;
  }
  EXPECT_GT(torqueSum / halfWaves, 10.0) << "and a moment";
}
