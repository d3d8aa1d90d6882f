// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchPile.hpp"

#include "benchmarks/SolverBenchDeposit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace armour::bench {
namespace {

/// Validate the state at the measurement point; throws InvalidCase with the reason.
void requirePile(const World& world, const ContactCensus& c, double halfWidth, double dn, const std::string& what) {
  const auto& bodies = world.bodies();
  for (dyn::BodyId b = 0; b < bodies.size(); ++b) {
    if (bodies.motionType(b) == dyn::MotionType::Static) {
      continue;
    }
    const Vec3& x = bodies.position(b);
    if (!x.allFinite() || !bodies.velocity(b).allFinite()) {
      throw InvalidCase(fmt::format("{}: {} has a non-finite state", what, bodies.describe(b)));
    }
    // A centroid outside the walls or under the floor by more than the guard-rail overlap
    // means a unit went through the static geometry.
    if (std::abs(x.x()) > halfWidth + 0.25 * dn || std::abs(x.y()) > halfWidth + 0.25 * dn || x.z() < -0.25 * dn) {
      throw InvalidCase(fmt::format("{}: {} escaped the box: at ({:.3f}, {:.3f}, {:.3f}) m, walls at +-{:.3f} m",
                                    what, bodies.describe(b), x.x(), x.y(), x.z(), halfWidth));
    }
  }
  if (c.unitUnit == 0 || c.touchingFraction < 2.0 / 3.0) {
    const Motion m = motion(world);
    throw InvalidCase(fmt::format("{}: no pile formed at t = {:.3f} s: {} unit-unit contacts, {:.0f} % of the units "
                                  "touch anything (want >= 67 %), {} of {} awake, mean speed {:.3g} m/s: settle longer",
                                  what, world.time(), c.unitUnit, 100.0 * c.touchingFraction, m.awake, m.dynamic,
                                  m.mean));
  }
}

} // namespace

PileScene buildPile(World& world, const PileOptions& o) {
  if (o.shape != "cube" && o.shape != "rock" && o.shape != "coreloc") {
    throw std::invalid_argument(fmt::format("--shape {}: choose cube, rock or coreloc", o.shape));
  }
  if (o.count < 1 || o.layers < 1) {
    throw std::invalid_argument("--count and --layers must be positive");
  }
  PileScene p;
  p.name = fmt::format("{} {}", o.shape, o.count);
  p.concrete = addConcrete(world, o.friction, o.restitution);
  double t0 = wallNow();
  p.shapes = addShapes(world, o.shape, o.rockShapes, o.seed);
  p.buildShapes = wallNow() - t0;
  p.memShapes = memoryNow();

  // The box: a drop grid of bounding spheres (largest instance) a gap apart, side x side units
  // per layer. The drop places the units on that grid, jittered by up to gap/2 each way; the
  // deposit builds a loose random pile in the same box, so both give piles of the same height.
  std::mt19937_64 rng(o.seed);
  p.radius = p.shapes.radius * o.dn * (o.shape == "rock" ? kMaxScaleOverDn : 1.0);
  const double radius = p.radius;
  const double gap = o.gap * o.dn;
  p.cell = 2.0 * radius + 2.0 * gap;
  const double cell = p.cell;
  p.side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(o.count) / o.layers)));
  const int side = p.side;
  p.halfWidth = 0.5 * side * cell;
  const double halfWidth = p.halfWidth;
  const bool drop = o.placement == "drop";
  std::uniform_real_distribution<double> jitter(-0.5 * gap, 0.5 * gap);
  p.box = {{Vec3(0, 0, 0), Vec3::UnitZ()},
           {Vec3(-halfWidth, 0, 0), Vec3::UnitX()},
           {Vec3(halfWidth, 0, 0), -Vec3::UnitX()},
           {Vec3(0, -halfWidth, 0), Vec3::UnitY()},
           {Vec3(0, halfWidth, 0), -Vec3::UnitY()}};
  Deposit deposit(-halfWidth, halfWidth, -halfWidth, halfWidth, 2.0 * radius, p.box);
  const double clearance = o.clearance * o.dn; // deposit: gap left between units at release
  t0 = wallNow();
  for (int i = 0; i < o.count; ++i) {
    BodySpec spec;
    spec.name = fmt::format("{}-{}", o.shape, i);
    spec.shape = p.shapes.ids[rng() % p.shapes.ids.size()];
    spec.scale = drawScale(o.shape, o.dn, rng);
    spec.material = p.concrete;
    spec.orientation = randomOrientation(rng);
    if (drop) {
      const int layer = i / (side * side), ix = (i / side) % side, iy = i % side;
      spec.position = Vec3(-halfWidth + (ix + 0.5) * cell + jitter(rng), -halfWidth + (iy + 0.5) * cell + jitter(rng),
                           radius + gap + layer * cell + 0.5 * gap + jitter(rng));
    } else {
      const Deposit::Result d =
          deposit.place(world.shape(spec.shape), spec.scale, o.dn, clearance, o.tries, o.moves, rng);
      spec.position = d.position;
      spec.orientation = d.orientation;
    }
    world.addBody(spec);
    p.top = std::max(p.top, spec.position.z());
    p.meanZ += spec.position.z() / o.count;
  }
  p.placement = wallNow() - t0;
  fmt::print(stderr, "{}: placed in {:.2f} s, centroids up to z = {:.2f} m, mean {:.2f} m\n", p.name, p.placement,
             p.top, p.meanZ);
  const char* wallNames[] = {"floor", "wall-x0", "wall-x1", "wall-y0", "wall-y1"};
  for (std::size_t k = 0; k < p.box.size(); ++k) {
    world.addPlane(StaticPlane{wallNames[k], p.box[k].point, p.box[k].normal, p.concrete});
  }
  p.buildBodies = wallNow() - t0;
  return p;
}

CaseResult runPile(const PileOptions& o) {
  if (o.shape != "cube" && o.shape != "rock" && o.shape != "coreloc") {
    throw std::invalid_argument(fmt::format("--shape {}: choose cube, rock or coreloc", o.shape));
  }
  if (o.count < 1 || o.layers < 1 || o.threads.empty()) {
    throw std::invalid_argument("--count, --layers and --threads must be positive");
  }
  CaseResult r;
  r.memBase = memoryNow();
  World world(baseSettings(o.sleep));
  const PileScene p = buildPile(world, o);
  r.name = p.name;
  r.buildShapes = p.buildShapes;
  r.memShapes = p.memShapes;
  r.placement = p.placement;
  r.buildBodies = p.buildBodies;
  const double radius = p.radius, halfWidth = p.halfWidth, top = p.top, meanZ = p.meanZ;
  const int side = p.side;
  const bool drop = o.placement == "drop";
  const double clearance = o.clearance * o.dn;
  r.memBodies = memoryNow();
  r.dynamic = static_cast<std::size_t>(o.count);
  r.dt = world.timeStep();
  r.sampleListSlack = world.settings().sampleListSlackPerDn;
  // Drop: the top layer's free fall to the floor (the last unit cannot have landed before).
  // Deposit: the fall through the clearance.
  r.landing = drop ? std::sqrt(2.0 * (top - radius) / kGravity) : std::sqrt(2.0 * clearance / kGravity);
  const double settle = o.settle >= 0.0 ? o.settle : drop ? r.landing + 0.3 : 0.1;
  const int settleThreads = *std::max_element(o.threads.begin(), o.threads.end());
  fmt::print(stderr, "{}: dt = {:.3g} s, settling {:.2f} s ({} steps) on {} thread(s) ...\n", r.name, r.dt, settle,
             static_cast<long>(std::ceil(settle / r.dt)), settleThreads);
  r.settle = settleWorld(world, settleThreads, settle, o.trace);
  r.memRunning = memoryNow();
  const WorldState state = world.captureState();
  r.contacts = census(world, state);
  r.atStart = motion(world);
  requirePile(world, r.contacts, halfWidth, o.dn, r.name);
  if (r.atStart.awake == 0) {
    r.notes += " All units asleep: the window times an idle pile.";
  }
  measureWindows(world, r, o.steps, 0.0, o.threads);
  requirePile(world, census(world, world.captureState()), halfWidth, o.dn, r.name + " (after the window)");
  if (drop) {
    r.notes += fmt::format(" Dropped: box {:.1f} m x {:.1f} m, {} layers of {}x{}; released at rest, top layer at z = "
                           "{:.2f} m (free fall {:.2f} s).",
                           2 * halfWidth, 2 * halfWidth, (o.count + side * side - 1) / (side * side), side, side, top,
                           r.landing);
  } else {
    r.notes += fmt::format(" Deposited: box {:.1f} m x {:.1f} m, loose random pile built in place in {:.2f} s "
                           "(centroids up to z = {:.2f} Dn, mean {:.2f} Dn), released at rest {:.2g} Dn apart.",
                           2 * halfWidth, 2 * halfWidth, r.placement, top / o.dn, meanZ / o.dn, clearance / o.dn);
  }
  return r;
}

} // namespace armour::bench
