// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchArmourLayer.hpp"

#include "benchmarks/SolverBenchDeposit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

namespace armour::bench {

CaseResult runLayer(const LayerOptions& o) {
  if (o.units < 1 || o.rocks < 0 || o.threads.empty() || !(o.slope > 0.0) || !(o.packing > 0.0)) {
    throw std::invalid_argument("armour-layer: --units, --threads, --slope and --packing must be positive");
  }
  CaseResult r;
  r.name = "armour layer";
  r.memBase = memoryNow();
  World world(baseSettings(o.sleep));
  const MaterialId concrete = addConcrete(world, o.friction, o.restitution);
  Material stone;
  stone.name = "rock";
  stone.density = 2650.0;
  stone.frictionStatic = stone.frictionDynamic = o.friction;
  stone.restitution = o.restitution;
  const MaterialId rock = world.addMaterial(stone);
  double t0 = wallNow();
  const ShapeSet units = addShapes(world, "coreloc", 1, o.seed);
  const ShapeSet rocks = addShapes(world, "rock", o.rockShapes, o.seed);
  r.buildShapes = wallNow() - t0;
  r.memShapes = memoryNow();

  const double dnUnit = std::cbrt(o.unitVolume), dnRock = std::cbrt(o.rockVolume);
  const double alpha = std::atan(1.0 / o.slope);
  const Vec3 up(-std::sin(alpha), 0.0, std::cos(alpha));   // out of the slope
  const Vec3 along(std::cos(alpha), 0.0, std::sin(alpha)); // up the slope
  // The profile by arc length s: the toe berm (z = 0) for s in [-toe, 0), then the slope.
  const auto surface = [&](double s) { return s < 0.0 ? Vec3(s, 0.0, 0.0) : Vec3(along * s); };
  const auto normalAt = [&](double s) { return s < 0.0 ? Vec3(Vec3::UnitZ()) : up; };

  // Rows as placed by crane (seed 000: 21 rows alternately of 12 and 11 units over 45 m): about
  // 2.2 Dn apart across the slope, staggered, rows spaced for the packing density up the slope.
  const int perRow = std::max(1, static_cast<int>(std::lround(o.width / (2.2 * dnUnit))));
  const double dx = o.width / perRow;
  const double dy = dnUnit * dnUnit / (o.packing * dx);
  int rows = 0;
  for (int placed = 0; placed < o.units; ++rows) {
    placed += perRow - (rows % 2 == 1 && perRow > 1 ? 1 : 0);
  }
  const double unitRadius = units.radius * dnUnit;
  const double arc = o.toe + rows * dy + unitRadius; // rock-covered profile length (m)

  // Rocks: two layers on a jittered grid over the profile, centres 0.35 and 1.0 Dn below the
  // surface, random orientation and size; fixed, so they may overlap each other.
  t0 = wallNow();
  const std::vector<Deposit::Plane> planes{{Vec3::Zero(), Vec3::UnitZ()},
                                           {Vec3::Zero(), up},
                                           {Vec3::Zero(), Vec3::UnitY()},
                                           {Vec3(0.0, o.width, 0.0), -Vec3::UnitY()},
                                           {Vec3(-o.toe - 2.0 * dnUnit, 0.0, 0.0), Vec3::UnitX()}};
  // The units are lowered along the slope normal, onto the rocks under them: the deposit works in
  // the slope frame (x up the slope, z out of it), slopeFrame: slope frame -> world.
  const Quat slopeFrame(Eigen::AngleAxisd(-alpha, Vec3::UnitY()));
  const Quat toSlope = slopeFrame.conjugate();
  std::vector<Deposit::Plane> slopePlanes;
  for (const auto& pl : planes) {
    slopePlanes.push_back({toSlope * pl.point, toSlope * pl.normal});
  }
  Deposit deposit(-o.toe - 2.0 * dnUnit, arc + 2.0 * unitRadius, 0.0, o.width, 2.0 * unitRadius, slopePlanes);
  std::mt19937_64 rng(o.seed);
  const int perLayer = (o.rocks + 1) / 2;
  const double spacing = perLayer > 0 ? std::sqrt(arc * o.width / perLayer) : 1.0;
  const int rockCols = std::max(1, static_cast<int>(std::round(o.width / spacing)));
  const int rockRows = std::max(1, (perLayer + rockCols - 1) / rockCols);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int i = 0; i < o.rocks; ++i) {
    const int layer = i / perLayer, k = i % perLayer;
    const double s = -o.toe + (k / rockCols + 0.5 + u(rng)) * (arc / rockRows);
    const double y = (k % rockCols + 0.5 + u(rng)) * (o.width / rockCols);
    BodySpec spec;
    spec.name = fmt::format("rock-{}", i);
    spec.shape = rocks.ids[rng() % rocks.ids.size()];
    spec.scale = drawScale("rock", dnRock, rng);
    spec.material = rock;
    spec.fixed = true;
    const double depth = (layer == 0 ? 0.35 : 1.0) * dnRock;
    spec.position = surface(s) + Vec3(0.0, y, 0.0) - depth * normalAt(s);
    spec.orientation = randomOrientation(rng);
    world.addBody(spec);
    const auto& model = world.shape(spec.shape);
    deposit.addObstacle(model, spec.scale, toSlope * spec.orientation * model.naturalToBody.conjugate(),
                        toSlope * spec.position);
  }
  r.fixed = static_cast<std::size_t>(o.rocks);
  // Units: row by row from the toe up, each lowered onto the rocks and the row below.
  std::uniform_real_distribution<double> jitter(-0.1 * dnUnit, 0.1 * dnUnit);
  const double clearance = o.clearance * dnUnit;
  const double placeStart = wallNow();
  for (int i = 0, row = 0; i < o.units; ++row) {
    const bool shortRow = row % 2 == 1 && perRow > 1;
    const int n = std::min(o.units - i, perRow - (shortRow ? 1 : 0));
    for (int c = 0; c < n; ++c, ++i) {
      const Vec3 plan((row + 0.5) * dy + jitter(rng), (c + (shortRow ? 1.0 : 0.5)) * dx + jitter(rng), 0.0);
      BodySpec spec;
      spec.name = fmt::format("coreloc-{}", i);
      spec.shape = units.ids[0];
      spec.scale = dnUnit;
      spec.material = concrete;
      const Deposit::Result d =
          deposit.place(world.shape(spec.shape), dnUnit, dnUnit, clearance, o.tries, o.moves, rng, &plan);
      spec.position = slopeFrame * d.position;
      spec.orientation = slopeFrame * d.orientation;
      world.addBody(spec);
    }
  }
  r.placement = wallNow() - placeStart;
  r.dynamic = static_cast<std::size_t>(o.units);
  // Floor and slope (their union is the solid), side walls, and an end wall beyond the berm.
  const char* names[] = {"floor", "slope", "side-y0", "side-y1", "toe-end"};
  for (std::size_t k = 0; k < planes.size(); ++k) {
    world.addPlane(StaticPlane{names[k], planes[k].point, planes[k].normal, k < 2 ? rock : concrete});
  }
  r.buildBodies = wallNow() - t0;
  r.memBodies = memoryNow();
  r.dt = world.timeStep();
  r.sampleListSlack = world.settings().sampleListSlackPerDn;
  r.landing = std::sqrt(2.0 * clearance / kGravity);
  const int settleThreads = *std::max_element(o.threads.begin(), o.threads.end());
  fmt::print(stderr, "armour layer: {} units placed in {:.1f} s on {} rocks, dt = {:.3g} s, settling {:.2f} s on {} "
             "thread(s) ...\n", o.units, r.placement, o.rocks, r.dt, o.settle, settleThreads);
  r.settle = settleWorld(world, settleThreads, o.settle, o.trace);
  r.memRunning = memoryNow();
  r.contacts = census(world, world.captureState());
  r.atStart = motion(world);
  // Validation: every unit between the side walls, not through the floor or slope.
  const auto check = [&](const std::string& when) {
    const auto& bodies = world.bodies();
    for (dyn::BodyId b = 0; b < bodies.size(); ++b) {
      if (bodies.motionType(b) == dyn::MotionType::Static) {
        continue;
      }
      const Vec3& x = bodies.position(b);
      // The solid is the union of the floor and slope half-spaces: inside when below either.
      const double height = std::min(x.z(), x.dot(up));
      if (!x.allFinite() || x.y() < -0.25 * dnUnit || x.y() > o.width + 0.25 * dnUnit || height < -0.25 * dnUnit) {
        throw InvalidCase(fmt::format("armour layer {}: {} left the section or went through the underlayer at "
                                      "({:.3f}, {:.3f}, {:.3f}) m",
                                      when, bodies.describe(b), x.x(), x.y(), x.z()));
      }
    }
  };
  check("after settling");
  if (r.contacts.touchingFraction < 2.0 / 3.0 || r.contacts.unitFixed == 0) {
    throw InvalidCase(fmt::format("armour layer: only {:.0f} % of the units touch anything, {} unit-rock contacts: "
                                  "settle longer",
                                  100.0 * r.contacts.touchingFraction, r.contacts.unitFixed));
  }
  measureWindows(world, r, 0, o.seconds, o.threads);
  check("after the window");
  r.notes +=
      fmt::format(" Slope {:.3g}H:1V, {:.0f} m wide, rock-covered profile {:.1f} m (toe berm {:.1f} m); units "
                  "in {} staggered rows of {}/{} ({:.2f} m apart across, {:.2f} m up the slope, packing {}), each "
                  "lowered along the slope normal onto the rocks and its neighbours (best of {} orientations, "
                  "then moves towards the slope until {} fail in a row) in {:.1f} s and released {:.2g} Dn "
                  "clear; rocks {}x{} per layer, {:.2f} m apart.",
                  o.slope, o.width, arc, o.toe, rows, perRow, perRow > 1 ? perRow - 1 : 1, dx, dy, o.packing, o.tries,
                  o.moves, r.placement, clearance / dnUnit, rockRows, rockCols, spacing);
  return r;
}

} // namespace armour::bench
