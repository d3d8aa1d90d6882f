// SPDX-License-Identifier: GPL-3.0-or-later
// Placement (issue 5): generated grids reproduce their analytic packing density; grid files are
// read or refused with the file and line; no unit starts overlapping anything (the pack as
// released has no engaged contact point); a placement is reproducible from its seed and
// independent of the thread count; a crane-placed pack at rest stays at rest (< 1 mm in 60 s)
// when its placed scene is run; a rock underlayer lies on the slope face; a placement stopped at
// a checkpoint and continued ends bit-identical to one not stopped.

#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "placement/PlacedScene.hpp"
#include "placement/PlacementGrid.hpp"
#include "placement/Placer.hpp"
#include "placement/PlacementProgress.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/SceneBuilder.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

using namespace armour;
namespace fs = std::filesystem;

namespace {

/// The lowest and highest point of body b's mesh along `normal` (world, m).
std::pair<double, double> spanAlong(const simulation::World& world, simulation::BodyId b, const Eigen::Vector3d& normal) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& v : world.shape(world.bodyShape(b)).mesh.vertices) {
    const double n = world.bodies().toWorld(b, world.bodyScale(b) * v).dot(normal);
    lo = std::min(lo, n);
    hi = std::max(hi, n);
  }
  return {lo, hi};
}

/// A 1:2 slope with the toe of seed 001 between walls 6.6 m apart: friction 0.75 > tan(alpha) =
/// 0.5, so single Antifer cubes rest on the face. Two rows of two 1 m^3 cubes (a few seconds).
std::string antiferScene(const std::string& method, const std::string& extra = "") {
  return R"(
description: placement test
duration: 1
seed: 5
materials:
  concrete: {density: 2350, friction: 0.75, restitution: 0.05}
static:
  - type: slope
    name: underlayer
    material: concrete
    origin: [0, 0]
    cot: 2
    crest_height: 6
    toe_height: 1.5
    toe_top_width: 2
    toe_base_width: 5
  - {type: wall, name: south, material: concrete, axis: y, position: 0, side: min}
  - {type: wall, name: north, material: concrete, axis: y, position: 4.4, side: max}
placement:
  shape: antifer
  material: concrete
  volume: 1.0
  method: )" + method + R"(
  grid: {rows: 2, units_per_row: 2, packing_density: 0.45, first_row: 0.7}
  orientation: {mode: perturbed, euler_deg: [0, -26.565, 0], max_angle_deg: 10}
  crane: {speed: 0.5, rest_speed: 0.01, max_time: 4}
  settle: {max_time: 10}
)" + extra;
}

io::Scene parse(const std::string& yaml) { return io::parseScene(yaml, fs::temp_directory_path(), "placement-test.yaml"); }

double maxDistance(const io::Scene& a, const io::Scene& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) d = std::max(d, (a.bodies[i].position - b.bodies[i].position).norm());
  return d;
}

} // namespace

TEST(PlacementGrid, StaggeredGridHasItsAnalyticPackingDensity) {
  // Seed 000's trunk: rows alternately of 12 and 11 units over 45 m, phi = 0.625, Dn = 1.71 m.
  placement::GridSettings g;
  g.rows = 21;
  g.unitsPerRow = {12, 11};
  g.packingDensity = 0.625;
  g.firstRow = 0.5;
  const double dn = std::cbrt(5.0);
  const placement::GridSlope slope{2.0, 1.0, 0.75};
  const auto points = placement::generateGrid(g, slope, dn, 45.0, 1, "test");
  ASSERT_EQ(points.size(), 242u); // 11 x 12 + 10 x 11
  const double dx = 45.0 / 12.0, dy = 11.5 * dn * dn / (0.625 * 45.0);
  // phi = n Dn^2 / (W dy) exactly as designed (1e-12: round-off only).
  EXPECT_NEAR(placement::gridSpacing(g, dn, 45.0, "test").packingDensity, 0.625, 1e-12);
  const double cosA = 0.8; // 4H:3V
  for (const auto& p : points) {
    EXPECT_NEAR(p.s, 0.5 * dn + p.row * dy, 1e-12);
    EXPECT_NEAR(p.plan.x(), 2.0 + p.s * cosA, 1e-12);
    const double expectY = (p.column + 0.5) * dx + (p.row % 2 == 1 ? 0.5 * dx : 0.0);
    EXPECT_NEAR(p.plan.y(), expectY, 1e-9) << "row " << p.row << " column " << p.column;
  }
  // Counting units in a window of whole cells of the slope plane gives phi (the issue's check):
  // rows 2..19 (18 rows, alternately 12 and 11 units) over 45 m x 18 dy.
  int n = 0;
  for (const auto& p : points) n += p.row >= 2 && p.row < 20 ? 1 : 0;
  EXPECT_EQ(n, 9 * 12 + 9 * 11);
  EXPECT_NEAR(n * dn * dn / (45.0 * 18.0 * dy), 0.625, 1e-12);
}

TEST(PlacementGrid, ParallelogramGridWrapsAlongTheTrunk) {
  // Seed 003: 4.011 m along the trunk, 2.754 m up the slope, rows shifted for a 60 degree line.
  placement::GridSettings g;
  g.rows = 4;
  g.unitsPerRow = {5};
  g.dx = 4.011 / std::cbrt(16.0);
  g.dy = 2.754 / std::cbrt(16.0);
  g.stagger = 2.754 / std::tan(60.0 * std::numbers::pi / 180.0) / 4.011;
  const auto points = placement::generateGrid(g, {0.0, 0.0, 0.5}, std::cbrt(16.0), 5 * 4.011, 1, "test");
  for (const auto& p : points) {
    EXPECT_GE(p.plan.y(), 0.0);
    EXPECT_LT(p.plan.y(), 5 * 4.011);
  }
  // Row 1 is shifted by 2.754 / tan 60 = 1.590 m.
  EXPECT_NEAR(points[5].plan.y() - points[0].plan.y(), 1.5900, 1e-3);
}

TEST(PlacementGrid, RefusesImpossibleGridsAndBadFiles) {
  placement::GridSettings g;
  g.rows = 2;
  g.unitsPerRow = {13};
  g.dx = 2.0;
  g.dy = 1.0;
  try {
    (void)placement::generateGrid(g, {}, 1.0, 20.0, 1, "trunk.yaml");
    FAIL() << "13 units of 2 Dn in 20 m accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("more than the width"), std::string::npos) << e.what();
  }
  const fs::path file = fs::temp_directory_path() / "armour-grid-test.csv";
  std::ofstream(file) << "x,y,z\n1,2,3\n4,five,6\n";
  try {
    (void)placement::readGridFile(file.string());
    FAIL() << "a bad line accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":3"), std::string::npos) << e.what(); // the line number
  }
  std::ofstream(file) << "# centres\n1.5,2\n3,4,5\n";
  const auto points = placement::readGridFile(file.string());
  ASSERT_EQ(points.size(), 2u);
  EXPECT_FALSE(points[0].startZ.has_value());
  EXPECT_DOUBLE_EQ(*points[1].startZ, 5.0);
  fs::remove(file);
}

TEST(PlacementReader, ErrorsNameTheKeyAndTheFix) {
  const auto refuses = [](const std::string& yaml, const std::string& expect) {
    try {
      (void)parse(yaml);
      ADD_FAILURE() << "accepted: " << expect;
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  std::string s = antiferScene("crane");
  refuses(std::string(s).replace(s.find("method: crane"), 13, "method: sling"), "expected one of crane, grid");
  refuses(std::string(s).replace(s.find("packing_density"), 15, "packing_densty"), "did you mean 'packing_density'");
  refuses(std::string(s).replace(s.find("mode: perturbed"), 15, "mode: random"), "remove euler_deg");
  refuses(std::string(s).replace(s.find("material: concrete\n  volume"), 18, "material: steel"), "no such material");
  refuses(std::string(s).replace(s.find("mode: perturbed"), 15, "mode: perturbed, frame: face"), "expected one of world, slope");
  refuses(s + "  nest: {tilt_deg: 120}\n", "placement.nest.tilt_deg");
  refuses(s + "  nest: {max_drift: -1}\n", "placement.nest.max_drift");
  refuses(s + "  nest: {moves: 0}\n", "placement.nest.moves");
  refuses(s + "  lowering: sideways\n", "expected one of vertical, slope_normal");
  const auto orient = [&](const std::string& keys) {
    return std::string(s).replace(s.find("mode: perturbed"), 15, "mode: perturbed, " + keys);
  };
  refuses(orient("select: best"), "expected one of lowest, keyed, interlocked");
  refuses(orient("layer_thickness: 1.5"), "target of select: keyed or interlocked");
  refuses(orient("unkeyed_cost: 0.5"), "add select: keyed");
  refuses(orient("select: interlocked, unkeyed_cost: 0.5"), "add select: keyed");
  refuses(orient("offsets: 4"), "add select: interlocked");
  refuses(orient("select: keyed, envelope_reward: 1"), "placement.orientation.envelope_reward");
  refuses(orient("select: interlocked, offset_radius: -0.1"), "placement.orientation.offset_radius");
  refuses(orient("select: interlocked, stacked_cost: -1"), "placement.orientation.stacked_cost");
  refuses(orient("select: interlocked, offsets: -2"), "placement.orientation.offsets");
  refuses(orient("select: interlocked, drift_cst: 1"), "did you mean 'drift_cost'");
  refuses(orient("select: interlocked, settle_candidates: 4"), "add settle_each: {}");
  refuses(orient("select: interlocked, settle_candidates: 0"), "placement.orientation.settle_candidates");
  refuses(orient("select: keyed, layer_thickness: 0"), "placement.orientation.layer_thickness");
  refuses(orient("select: keyed, off_underlayer_cost: -1"), "placement.orientation.off_underlayer_cost");
  refuses(s + "  settle_each: {damping: -1}\n", "placement.settle_each.damping");
  refuses(s + "  settle_each: {rest_speed: 0}\n", "placement.settle_each.rest_speed");
  refuses(s + "  settle_each: {max_time: 0}\n", "placement.settle_each.max_time");
  refuses(s + "  settle_each: {rest_time: 2, max_time: 1}\n", "not shorter than max_time");
  refuses(s + "  settle_each: {max_drift: 0}\n", "placement.settle_each.max_drift");
  refuses(s + "  settle_each: {hold_at_max_drift: maybe}\n", "expected true or false");
  refuses(s + "  settle_each: {rest_sped: 0.1}\n", "did you mean 'rest_speed'");
  refuses(s + "  toe_berm: {count: 10, dn50: 1, length: 3}\n", "add placement.rocks");
  const std::string rocks = s + "  rocks: {count: 10, dn50: 0.4}\n";
  refuses(rocks + "  toe_berm: {count: 10, dn50: 1}\n", "placement.toe_berm: missing key 'length'");
  refuses(rocks + "  toe_berm: {count: 10, dn50: 1, length: 0}\n", "placement.toe_berm.length");
  refuses(rocks + "  toe_berm: {count: 10, dn50: 1, length: 3, lenght: 3}\n", "did you mean 'length'");
  const io::Scene berm = parse(rocks + "  toe_berm: {count: 12, dn50: 1.1, length: 3}\n");
  EXPECT_TRUE(berm.placement.toeBerm.enabled);
  EXPECT_EQ(berm.placement.toeBerm.count, 12);
  EXPECT_DOUBLE_EQ(berm.placement.toeBerm.toeLength, 3.0);
  EXPECT_DOUBLE_EQ(berm.placement.toeBerm.sEnd, 0.0);
  // And the defaults, when the block is given empty.
  const io::Scene on = parse(s + "  settle_each: {}\n");
  EXPECT_TRUE(on.placement.settleEach.enabled);
  EXPECT_DOUBLE_EQ(on.placement.settleEach.damping, 2.0);
  EXPECT_DOUBLE_EQ(on.placement.settleEach.maxTime, 6.0);
  EXPECT_FALSE(parse(s).placement.settleEach.enabled);
}

TEST(Placement, AToeBermLiesInFrontOfTheFootOnTheSameUnderlayer) {
  // A berm of 12 rocks of Dn50 0.6 m on an underlayer of 40 rocks of 0.3 m, from 2 m offshore of
  // the foot (the toe top) to 0.5 m up the face. Geometric placement (no dynamics): the underlayer
  // is the one laid without a berm, stone for stone (the berm's random streams are its own); the
  // berm's rocks lie in its band (their centroids' s within a rock's size of it, in the slope frame)
  // and on top of the underlayer there (no berm rock below the face).
  const std::string rocks = antiferScene("grid") + "  rocks: {count: 40, dn50: 0.3, toe_length: 2}\n";
  placement::PlaceOptions options;
  options.dynamics = false;
  const placement::PlacementResult plain = placement::place(parse(rocks), {}, options);
  const placement::PlacementResult berm =
      placement::place(parse(rocks + "  toe_berm: {count: 12, dn50: 0.6, length: 2, s_end: 0.5}\n"), {}, options);
  ASSERT_EQ(plain.summary.rocks, 40);
  ASSERT_GE(berm.summary.rocks, 40 + 10) << "fewer than 10 of the 12 berm rocks found a place";
  const auto rockNamed = [](const io::Scene& sc, const std::string& name) -> const io::Body* {
    for (const auto& b : sc.bodies)
      if (b.name == name) return &b;
    return nullptr;
  };
  const double a = std::atan(0.5);
  const Eigen::Vector3d up(std::cos(a), 0.0, std::sin(a)), normal(-std::sin(a), 0.0, std::cos(a));
  for (int k = 0; k < berm.summary.rocks; ++k) {
    const std::string name = fmt::format("rock_{:04d}", k);
    const io::Body* b = rockNamed(berm.scene, name);
    ASSERT_NE(b, nullptr) << name;
    if (k < 40) {
      const io::Body* p = rockNamed(plain.scene, name);
      ASSERT_NE(p, nullptr) << name;
      EXPECT_EQ(b->position, p->position) << name << ": the underlayer changed with the berm";
      continue;
    }
    const double s = b->position.dot(up), n = b->position.dot(normal);
    EXPECT_GT(s, -2.0 - 0.6) << name;
    EXPECT_LT(s, 0.5 + 0.6) << name;
    EXPECT_GT(b->position.z(), 0.0) << name << ": a berm rock below the toe top";
    EXPECT_GT(n, -0.6) << name;
  }
}

TEST(Placement, SlopeFrameOrientationsLieOnTheFace) {
  // frame: slope with the base orientation the identity and no perturbation: every unit's natural
  // z axis is the face normal (-sin a, 0, cos a), to round-off.
  std::string s = antiferScene("grid");
  s.replace(s.find("orientation: {mode: perturbed, euler_deg: [0, -26.565, 0], max_angle_deg: 10}"), 77,
            "orientation: {mode: perturbed, frame: slope, max_angle_deg: 0}");
  placement::PlaceOptions options;
  options.dynamics = false;
  const placement::PlacementResult r = placement::place(parse(s), {}, options);
  const double a = std::atan(0.5);
  for (const auto& u : r.units)
    EXPECT_NEAR((u.releaseOrientation * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(-std::sin(a), 0.0, std::cos(a))).norm(),
                0.0, 1e-12) << u.name;
}

TEST(Placement, NoUnitStartsOverlapping) {
  // Every unit lowered geometrically onto the slope and those before it: the pack as released has
  // no engaged contact point at all (the clearance is 0.002 Dn), so no unit starts inside another
  // or inside the underlayer.
  const io::Scene scene = parse(antiferScene("grid"));
  placement::PlaceOptions options;
  options.dynamics = false;
  placement::PlacementResult r = placement::place(scene, {}, options);
  ASSERT_EQ(r.units.size(), 4u);
  auto& world = *r.built.world;
  world.evaluateContacts();
  EXPECT_EQ(world.lastStep().contactPoints, 0u);
  EXPECT_EQ(world.lastStep().maxOverlap, 0.0);
  // And each one is close to what it landed on: within the clearance plus one bisection step
  // (0.05 Dn / 32) of the underlayer or another unit, i.e. not left hanging above it.
  for (const auto& u : r.units) {
    EXPECT_LT(u.gridPoint.z(), 3.0) << u.name; // well below the 6 m crest: it came down
  }
}

TEST(Placement, NestingWorksUnitsIntoTheHolesOfADenseGrid) {
  // Four staggered rows of 1 m cubes lying on a 1:2 face, 0.76 m apart up the slope (phi = 0.6):
  // lowered straight down, a unit lands on the cubes below and the rows stack (the highest
  // centroid 2.3 Dn above the face; such a stack slumps when released). With `nest:` each unit is
  // worked into the hole among the units below: every unit lies on the face (centroid less than
  // 0.8 Dn above it; 0.63 seen), within max_drift of its grid point, and none overlaps anything.
  std::string s = antiferScene("grid");
  s.replace(s.find("rows: 2, units_per_row: 2, packing_density: 0.45"), 48, "rows: 4, units_per_row: 2, packing_density: 0.6");
  const double a = std::atan(0.5);
  const Eigen::Vector3d normal(-std::sin(a), 0.0, std::cos(a));
  placement::PlaceOptions options;
  options.dynamics = false;
  const auto highest = [&](const placement::PlacementResult& r) {
    double h = 0.0;
    for (const auto& u : r.units) h = std::max(h, u.gridPoint.dot(normal));
    return h;
  };
  const placement::PlacementResult stacked = placement::place(parse(s), {}, options);
  EXPECT_GT(highest(stacked), 1.0) << "the test needs a grid whose rows stack without nesting";
  const placement::PlacementResult nested = placement::place(parse(s + "  nest: {max_drift: 0.75}\n"), {}, options);
  ASSERT_EQ(nested.units.size(), 8u);
  EXPECT_LT(highest(nested), 0.8);
  // Drift in plan from where the unit was lowered (the grid point, moved inside the walls).
  for (std::size_t i = 0; i < nested.units.size(); ++i)
    EXPECT_LE((nested.units[i].gridPoint.head<2>() - stacked.units[i].gridPoint.head<2>()).norm(), 0.75 + 1e-9)
        << nested.units[i].name;
  auto& world = *nested.built.world;
  world.evaluateContacts();
  EXPECT_EQ(world.lastStep().contactPoints, 0u);
}

TEST(Placement, SlopeNormalLoweringLandsUnitsAtTheirGridPoints) {
  // Lowered vertically onto a 1:2 face, a unit whose centroid ends h above the face lies
  // h tan(alpha) up-slope of its grid point (0.27 m for these 1 m cubes); lowered along the slope
  // normal it keeps its grid point's up-slope distance s (and its trunk position y), to round-off.
  const std::string s = antiferScene("grid");
  const io::Scene scene = parse(s);
  const auto grid = placement::generateGrid(scene.placement.grid, placement::GridSlope{0.0, 0.0, 0.5}, 1.0, 4.4, 5, "test");
  placement::PlaceOptions options;
  options.dynamics = false;
  const double a = std::atan(0.5);
  const Eigen::Vector3d along(std::cos(a), 0.0, std::sin(a));
  const placement::PlacementResult vertical = placement::place(scene, {}, options);
  const placement::PlacementResult normal = placement::place(parse(s + "  lowering: slope_normal\n"), {}, options);
  ASSERT_EQ(normal.units.size(), grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    EXPECT_NEAR(normal.units[i].gridPoint.dot(along), grid[i].s, 1e-9) << normal.units[i].name;
    EXPECT_NEAR(normal.units[i].gridPoint.y(), vertical.units[i].gridPoint.y(), 1e-9) << normal.units[i].name;
    EXPECT_GT(vertical.units[i].gridPoint.dot(along) - grid[i].s, 0.2) << vertical.units[i].name;
  }
  auto& world = *normal.built.world;
  world.evaluateContacts();
  EXPECT_EQ(world.lastStep().contactPoints, 0u);
}

TEST(Placement, ReproducibleFromItsSeedOnAnyThreadCount) {
  const io::Scene scene = parse(antiferScene("crane"));
  omp_set_num_threads(1);
  const placement::PlacementResult a = placement::place(scene);
  omp_set_num_threads(2);
  const placement::PlacementResult b = placement::place(scene);
  omp_set_num_threads(1);
  ASSERT_EQ(a.scene.bodies.size(), b.scene.bodies.size());
  for (std::size_t i = 0; i < a.scene.bodies.size(); ++i) {
    EXPECT_EQ(a.scene.bodies[i].position, b.scene.bodies[i].position) << a.scene.bodies[i].name;
    EXPECT_EQ(a.scene.bodies[i].orientation.coeffs(), b.scene.bodies[i].orientation.coeffs());
  }
  // A different seed gives a different pack.
  const placement::PlacementResult c = placement::place(parse(antiferScene("crane", "  seed: 6\n")));
  EXPECT_GT(maxDistance(a.scene, c.scene), 1e-3);
}

TEST(Placement, CranePlacedPackAtRestStaysAtRest) {
  // The issue's check: the placed scene, run for 60 s with no loads, moves no unit by 1 mm.
  const std::string input = antiferScene("crane");
  const io::Scene scene = parse(input);
  const placement::PlacementResult r = placement::place(scene);
  EXPECT_TRUE(r.summary.moving.empty());
  const io::Scene placed = parse(placement::placedSceneYaml(input, r));
  ASSERT_EQ(placed.bodies.size(), 4u);
  // The written scene reproduces the pack: positions to the last bit (shortest round-trip text).
  for (std::size_t i = 0; i < placed.bodies.size(); ++i) EXPECT_EQ(placed.bodies[i].position, r.scene.bodies[i].position);
  simulation::BuiltScene built = simulation::buildWorld(placed);
  built.world->advanceTo(60.0);
  double drift = 0.0;
  for (std::size_t i = 0; i < placed.bodies.size(); ++i)
    drift = std::max(drift, (built.world->bodies().position(built.bodyIndexOfSceneBody[i]) - placed.bodies[i].position).norm());
  EXPECT_LT(drift, 1e-3) << "largest drift in 60 s";
}

TEST(Placement, RockUnderlayerLiesOnTheFace) {
  // 40 rocks of Dn50 0.4 m dropped on the face: every one rests on the slope or on other rocks,
  // with its centroid between 0 and 2.5 Dn50 above the face along its normal (a loose double
  // layer), none below it, and none outside the walls.
  const std::string rocks = "  rocks: {count: 40, dn50: 0.4, grading: 1.3, shapes: 4, s_end: 3, toe_length: 1}\n";
  const io::Scene scene = parse(antiferScene("grid", rocks));
  placement::PlaceOptions options;
  options.dynamics = false;
  const placement::PlacementResult r = placement::place(scene, {}, options);
  EXPECT_EQ(r.summary.rocks, 40);
  const double a = std::atan(0.5);
  const Eigen::Vector3d normal(-std::sin(a), 0.0, std::cos(a));
  int onFace = 0;
  for (const io::Body& b : r.scene.bodies) {
    if (b.name.rfind("rock_", 0) != 0) continue;
    EXPECT_TRUE(b.fixed);
    EXPECT_GT(b.position.y(), 0.0);
    EXPECT_LT(b.position.y(), 4.4);
    if (b.position.x() < 0.3) continue; // on the toe
    ++onFace;
    const double height = b.position.dot(normal);
    EXPECT_GT(height, 0.0) << b.name;
    EXPECT_LT(height, 2.5 * 0.4) << b.name;
  }
  EXPECT_GT(onFace, 15);
  // The units then land on the rocks, not through them.
  auto& world = *r.built.world;
  world.evaluateContacts();
  EXPECT_EQ(world.lastStep().contactPoints, 0u);
}

namespace {

/// Centroid height above a face through the origin with outward normal n, and the angle between
/// n and the nearest face normal of a cube turned by q (natural frame: faces along its axes).
double cubeTiltDeg(const Eigen::Quaterniond& q, const Eigen::Vector3d& n) {
  double best = 0.0;
  for (int k = 0; k < 3; ++k) best = std::max(best, std::abs((q * Eigen::Vector3d::Unit(k)).dot(n)));
  return std::acos(std::min(1.0, best)) * 180.0 / std::numbers::pi;
}

} // namespace

TEST(Placement, SettleEachLaysATiltedCubeFlatAtRest) {
  // One 1 m^3 cube turned 20-40 degrees off lying flat on a 1:2 face (friction 0.75 >
  // tan(alpha) = 0.5: a cube lying on a face rests there, and it tips only at 45 degrees). At its
  // first touch it stands on an edge or a corner, which is not a rest. With settle_each it is
  // simulated alone until it rests: it must then lie on a face -- tilt below 0.5 degree (0.004
  // seen, from 12.8 at its first touch), centroid 0.5 m above the face to 5 mm (the penalty
  // penetration under its weight is 2e-5 m; 5 mm allows for the level-set cell; 2e-5 m seen) --
  // and after the final release move less than 1 mm (the creep bound of
  // CranePlacedPackAtRestStaysAtRest; 1e-9 m seen). Released from its first touch instead it
  // falls over onto a face: more than 5 cm (0.32 m seen).
  std::string s = antiferScene("grid");
  const auto edit = [&s](const std::string& from, const std::string& to) {
    ASSERT_NE(s.find(from), std::string::npos) << from;
    s.replace(s.find(from), from.size(), to);
  };
  edit("shape: antifer", "shape: cube");
  edit("rows: 2, units_per_row: 2", "rows: 1, units_per_row: 1");
  edit("mode: perturbed, euler_deg: [0, -26.565, 0], max_angle_deg: 10",
       "mode: tilted, euler_deg: [0, -26.565, 0], max_angle_deg: 40");
  s += "  seed: 3\n";
  const double a = std::atan(0.5);
  const Eigen::Vector3d normal(-std::sin(a), 0.0, std::cos(a));
  placement::PlaceOptions geometric;
  geometric.dynamics = false;
  const placement::PlacementResult touch = placement::place(parse(s), {}, geometric);
  ASSERT_EQ(touch.units.size(), 1u);
  ASSERT_GT(cubeTiltDeg(touch.units[0].releaseOrientation, normal), 10.0) << "the test needs a cube on an edge";

  const placement::PlacementResult settled = placement::place(parse(s + "  settle_each: {}\n"));
  const placement::UnitRecord& u = settled.units[0];
  EXPECT_FALSE(u.capped) << "its own settle reached the time cap";
  EXPECT_LT(u.restTime, 1.5); // well before the 6 s cap: 0.70 s seen
  EXPECT_LT(cubeTiltDeg(u.releaseOrientation, normal), 0.5);
  EXPECT_NEAR(u.gridPoint.dot(normal), 0.5, 0.005);
  EXPECT_LT(settled.summary.maxDisplacementDn, 1e-3) << "moved after the final release";
  EXPECT_TRUE(settled.summary.moving.empty());

  const placement::PlacementResult released = placement::place(parse(s));
  EXPECT_GT(released.summary.maxDisplacementDn, 0.05) << "released from its first touch, it should fall over";

  // Held at a drift of 0.1 Dn (its free settle drifts 0.26 Dn): stopped in the step it crosses
  // it (at most ~1 m/s x 1e-4 s further; 0.01 Dn allows a hundred times that), counted as not at
  // rest and named as drifted.
  const placement::PlacementResult held =
      placement::place(parse(s + "  settle_each: {max_drift: 0.1, hold_at_max_drift: true}\n"));
  EXPECT_TRUE(held.units[0].capped);
  EXPECT_NEAR(held.units[0].settleDrift, 0.1, 0.01);
  EXPECT_EQ(held.summary.settleCappedUnits, 1);
  EXPECT_EQ(held.summary.drifted.size(), 1u);
}

TEST(Placement, SettleEachHoldsADenseGridAfterTheRelease) {
  // The nesting test's grid (four staggered rows of 1 m^3 Antifer cubes 0.76 m apart on a 1:2
  // face, nested): released together from their first touches the units drop onto their
  // supports and the rows ride down on each other (largest move 0.085 Dn, median 0.05 Dn seen);
  // settled one by one first, each rests where the pack will hold it, so the final release moves
  // no unit by more than 0.01 Dn (0.001 seen; 0.01 Dn is ten times that, and a third of the
  // smallest move seen without). Without settle_each the largest move must exceed 0.03 Dn, or
  // the grid does not show what the settle is for.
  std::string s = antiferScene("grid");
  s.replace(s.find("rows: 2, units_per_row: 2, packing_density: 0.45"), 48, "rows: 4, units_per_row: 2, packing_density: 0.6");
  s += "  nest: {max_drift: 0.75}\n";
  const placement::PlacementResult together = placement::place(parse(s));
  EXPECT_GT(together.summary.maxDisplacementDn, 0.03) << "the test needs a grid that moves when released at first touch";
  const placement::PlacementResult settled = placement::place(parse(s + "  settle_each: {}\n"));
  ASSERT_EQ(settled.units.size(), 8u);
  EXPECT_EQ(settled.summary.settleCappedUnits, 0);
  EXPECT_LT(settled.summary.maxDisplacementDn, 0.01);
  EXPECT_TRUE(settled.summary.moving.empty());
  EXPECT_TRUE(settled.summary.drifted.empty());
}

namespace {

/// Place `scene`, stop at safe point `stopAt` (counted from 1) through a checkpoint file, continue
/// from that file, and require the continued placement to equal `reference` bit for bit: every
/// body's position and orientation, and every unit's record. Returns whether the stop was in the
/// final settle.
bool stopAndContinue(const io::Scene& scene, const placement::PlacementResult& reference, int stopAt) {
  const fs::path file = fs::temp_directory_path() / fmt::format("armour-place-checkpoint-{}.nc", ::getpid());
  int calls = 0;
  bool inSettle = false;
  placement::PlaceOptions stopping;
  stopping.safePoint = [&](const std::function<placement::PlacementProgress()>& capture) {
    if (++calls < stopAt) return false;
    placement::PlacementProgress p = capture();
    inSettle = p.finalSettle;
    simulation::Checkpoint c;
    c.sceneFingerprint = "test";
    c.applicationState = placement::encodeProgress(p);
    c.state = std::move(p.world);
    simulation::writeCheckpoint(file, c);
    return true;
  };
  EXPECT_THROW((void)placement::place(scene, {}, stopping), placement::PlacementStopped);
  const simulation::Checkpoint c = simulation::readCheckpoint(file, {"test", "", 0});
  placement::PlacementProgress resume = placement::decodeProgress(c.applicationState, file.string());
  resume.world = c.state;
  fs::remove(file);
  placement::PlaceOptions continuing;
  continuing.resume = &resume;
  const placement::PlacementResult r = placement::place(scene, {}, continuing);
  EXPECT_EQ(r.scene.bodies.size(), reference.scene.bodies.size());
  for (std::size_t i = 0; i < std::min(r.scene.bodies.size(), reference.scene.bodies.size()); ++i) {
    EXPECT_EQ(r.scene.bodies[i].name, reference.scene.bodies[i].name);
    EXPECT_EQ(r.scene.bodies[i].position, reference.scene.bodies[i].position) << r.scene.bodies[i].name;
    EXPECT_EQ(r.scene.bodies[i].orientation.coeffs(), reference.scene.bodies[i].orientation.coeffs());
  }
  EXPECT_EQ(r.units.size(), reference.units.size());
  for (std::size_t i = 0; i < std::min(r.units.size(), reference.units.size()); ++i) {
    EXPECT_EQ(r.units[i].gridPoint, reference.units[i].gridPoint);
    EXPECT_EQ(r.units[i].restTime, reference.units[i].restTime);
    EXPECT_EQ(r.units[i].releaseTime, reference.units[i].releaseTime);
  }
  EXPECT_EQ(r.summary.simulatedTime, reference.summary.simulatedTime);
  EXPECT_EQ(r.summary.rocks, reference.summary.rocks);
  EXPECT_EQ(r.summary.settleCappedUnits, reference.summary.settleCappedUnits);
  return inSettle;
}

} // namespace

TEST(Placement, StoppedAndContinuedEndsBitIdentical) {
  // A placement stopped at a safe point (as SIGINT does: checkpoint, stop) and continued from
  // its checkpoint file ends exactly where the uninterrupted one does: the World's state and the
  // placement's progress (records, stage, settle clock) restore everything it depends on.
  // settle_each on rocks: stopped after the second unit (the rocks are added again from the
  // record, not dropped anew) and in the final settle; crane: after the third unit.
  const io::Scene settleEach = parse(antiferScene(
      "grid", "  rocks: {count: 12, dn50: 0.4, grading: 1.3, shapes: 3, s_end: 3, toe_length: 1}\n  settle_each: {}\n"));
  int safePoints = 0;
  placement::PlaceOptions counting;
  counting.safePoint = [&](const auto&) { return ++safePoints, false; };
  const placement::PlacementResult reference = placement::place(settleEach, {}, counting);
  ASSERT_GT(safePoints, 10) << "too short a final settle to stop in";
  EXPECT_FALSE(stopAndContinue(settleEach, reference, 2));
  EXPECT_TRUE(stopAndContinue(settleEach, reference, safePoints - 3));

  const io::Scene crane = parse(antiferScene("crane"));
  EXPECT_FALSE(stopAndContinue(crane, placement::place(crane), 3));
}

TEST(Placement, ProgressRecordsAreRefusedWhenDamaged) {
  placement::PlacementProgress p;
  p.unitsDone = 1;
  placement::UnitRecord u;
  u.name = "unit 0 with spaces";
  u.gridPoint = {0.1, -2.0 / 3.0, 1e-300};
  p.units.push_back(u);
  p.bodies.push_back({"rock_0000", 2, 0.123456789, 0, 0.027, true});
  p.stillSince = 0.1;
  const std::string text = placement::encodeProgress(p);
  const placement::PlacementProgress q = placement::decodeProgress(text, "c.nc");
  EXPECT_EQ(q.units.at(0).name, u.name);
  EXPECT_EQ(q.units.at(0).gridPoint, u.gridPoint); // hexadecimal floats: exact
  EXPECT_EQ(q.bodies.at(0).scale, 0.123456789);
  EXPECT_EQ(q.stillSince, 0.1);
  const auto refused = [](const std::string& t, const std::string& words) {
    try {
      (void)placement::decodeProgress(t, "c.nc");
      ADD_FAILURE() << "accepted: " << t;
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("c.nc"), std::string::npos) << e.what();
    }
  };
  refused("something else\n", "does not start with");
  refused(text.substr(0, text.size() - 4), "ends before its 'end' line");
  std::string bad = text;
  bad.replace(bad.find("units_done 1"), 12, "units_done 2");
  refused(bad, "units_done 2 but 1 unit records");
  bad = text;
  bad.replace(bad.find("still_since "), 12, "still_since x");
  refused(bad, "is not a number");
}

TEST(Placement, InterlockedSearchKeysUnitsIntoTheRowBelowInsteadOfStackingThem) {
  // Session 28: four staggered rows of 1 m^3 Core-Locs on a bare 4H:3V face (the face is the
  // underlayer) at seed 000's packing density 0.625 (rows 0.70 Dn apart while a unit is 1.66 Dn
  // long), each unit settled alone (settle_each), then all released and settled. The lowest
  // centroid of 8 random attitudes (`select: lowest`, nested) against `select: interlocked`
  // (8 attitudes, each at the grid point and 8 shifts within 0.35 Dn, the cost of theory.md 15,
  // the best 8 nested, settled alone and judged again at rest). Interlocked must leave no more
  // units stacked (no contact with the face, centroid more than 1 Dn above it), put no fewer on
  // the face, and end with a mean top lower by at least 0.05 Dn (a tenth of the spread between
  // rules on the strip of docs/placement.md, "Session 28", is 0.03 Dn: the margin is above it).
  const std::string scene = R"(
description: interlocked placement test
duration: 1
seed: 11
materials:
  concrete: {density: 2400, friction: 0.6, restitution: 0.1}
static:
  - {type: slope, name: core, material: concrete, origin: [0, 0], cot: 1.3333333333333333, crest_height: 8,
     toe_height: 1, toe_top_width: 2, toe_base_width: 4}
  - {type: wall, name: south, material: concrete, axis: y, position: 0, side: min}
  - {type: wall, name: north, material: concrete, axis: y, position: 5.6, side: max}
placement:
  shape: coreloc
  material: concrete
  volume: 1.0
  method: grid
  grid: {rows: 4, units_per_row: [3, 2], packing_density: 0.625, first_row: 0.5}
  lowering: slope_normal
  nest: {}
  settle_each: {}
  settle: {max_time: 3}
)";
  const double a = std::atan(0.75);
  const Eigen::Vector3d normal(-std::sin(a), 0.0, std::cos(a));
  placement::PlaceOptions options;
  struct Measure {
    double meanTop = 0.0; ///< above the face (unit: m = Dn)
    int onFace = 0;       ///< units whose lowest point lies within 0.02 Dn of the face (the clearance is 0.002)
    int stacked = 0;      ///< units off the face with the centroid more than 1 Dn above it
  };
  const auto measure = [&](const placement::PlacementResult& r) {
    Measure m;
    const auto& world = *r.built.world;
    for (const auto& u : r.units) {
      const auto [lo, hi] = spanAlong(world, u.body, normal);
      m.meanTop += hi / static_cast<double>(r.units.size());
      const bool on = lo < 0.02;
      if (on) ++m.onFace;
      if (!on && world.bodies().position(u.body).dot(normal) > 1.0) ++m.stacked;
    }
    return m;
  };
  const auto lowest = placement::place(parse(scene + "  orientation: {mode: random, tries: 8}\n"), {}, options);
  const auto inter = placement::place(
      parse(scene + "  orientation: {mode: random, tries: 8, select: interlocked, settle_candidates: 8}\n"), {}, options);
  ASSERT_EQ(inter.units.size(), 10u);
  const Measure l = measure(lowest), k = measure(inter);
  fmt::print("lowest: mean top {:.3f} Dn, on the face {}, stacked {}; interlocked: {:.3f}, {}, {}\n", l.meanTop,
              l.onFace, l.stacked, k.meanTop, k.onFace, k.stacked);
  EXPECT_LE(k.stacked, l.stacked);
  EXPECT_GE(k.onFace, l.onFace);
  EXPECT_LT(k.meanTop, l.meanTop - 0.05) << "a lower layer by at least 0.05 Dn";
}

TEST(Placement, KeyedAttitudesKeepUnitsOnTheFaceAndTheLayerAtItsDesignThickness) {
  // Three staggered rows of 1 m^3 Core-Locs on a 4H:3V face (no rocks: the face is the
  // underlayer) at seed 000's packing density 0.625 (rows 0.70 Dn apart while a unit is 1.65 Dn
  // long), 8 random attitudes per unit, lowered along the face normal and nested; no simulation.
  // Kept by the lowest centroid (`select: lowest`), units land on the rows below: 2 or more stand
  // more than 0.3 Dn off the face. Kept by `select: keyed` with the Core-Loc's design thickness
  // 1.52 Dn (the candidate whose top lies nearest 1.52 Dn above the face, touching the underlayer
  // and a unit placed before), at most one does (a unit of the first row may rest on the toe
  // instead), and the mean top lies within 0.15 Dn of 1.52 (1.61 seen; the lowest centroid gives
  // 1.37 with units lying flat and stacked).
  const std::string scene = R"(
description: keyed placement test
duration: 1
seed: 7
materials:
  concrete: {density: 2400, friction: 0.6, restitution: 0.1}
static:
  - {type: slope, name: core, material: concrete, origin: [0, 0], cot: 1.3333333333333333, crest_height: 8,
     toe_height: 1, toe_top_width: 2, toe_base_width: 4}
  - {type: wall, name: south, material: concrete, axis: y, position: 0, side: min}
  - {type: wall, name: north, material: concrete, axis: y, position: 5.6, side: max}
placement:
  shape: coreloc
  material: concrete
  volume: 1.0
  method: grid
  grid: {rows: 3, units_per_row: [3, 2], packing_density: 0.625, first_row: 0.5}
  lowering: slope_normal
  nest: {}
)";
  const double a = std::atan(0.75);
  const Eigen::Vector3d normal(-std::sin(a), 0.0, std::cos(a));
  placement::PlaceOptions options;
  options.dynamics = false;
  struct Measure {
    double meanTop = 0.0; ///< above the face (unit: m = Dn)
    int offFace = 0;      ///< units whose lowest point is more than 0.3 Dn above the face
  };
  const auto measure = [&](const placement::PlacementResult& r) {
    Measure m;
    const auto& world = *r.built.world;
    for (const auto& u : r.units) {
      const auto [lo, hi] = spanAlong(world, u.body, normal);
      m.meanTop += hi / static_cast<double>(r.units.size());
      if (lo > 0.3) ++m.offFace;
    }
    return m;
  };
  const auto lowest = placement::place(parse(scene + "  orientation: {mode: random, tries: 8}\n"), {}, options);
  const auto keyed = placement::place(
      parse(scene + "  orientation: {mode: random, tries: 8, select: keyed, layer_thickness: 1.52}\n"), {}, options);
  ASSERT_EQ(keyed.units.size(), 8u);
  const Measure l = measure(lowest), k = measure(keyed);
  EXPECT_GE(l.offFace, 2) << "the test needs a grid where the lowest centroid leaves units off the face";
  EXPECT_LE(k.offFace, 1);
  EXPECT_NEAR(k.meanTop, 1.52, 0.15);
  auto& world = *keyed.built.world;
  world.evaluateContacts();
  EXPECT_EQ(world.lastStep().contactPoints, 0u) << "no unit starts overlapping";
}
