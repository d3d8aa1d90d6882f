// SPDX-License-Identifier: GPL-3.0-or-later
// Verification of the rigid solver (issue 3):
//  - tunnelling: a 1 m concrete cube thrown at 20 m/s at a wall is stopped by a thick wall, and by
//    a thin wall (a static convex piece or a thin fixed body) it is either stopped or the run is
//    refused with a message saying it would tunnel (a slab thinner than a level-set cell is refused
//    as input); it never ends up silently on the far side;
//  - contact detection: an overlap of two dolosse whose centroids lie outside each other's level-set
//    grid is found (it was missed by a cull, and units passed into each other in a pile);
//  - convergence: the block sliding down an incline against the closed-form solution of the
//    penalty model, for dt, dt/2 and dt/4, with the observed order of the error, and against the
//    rigid-body x(t) = g (sin a - mu cos a) t^2 / 2;
//  - fixed meshes (scene `static: type: mesh`) as obstacles: a cube comes to rest on top at the
//    height the contact stiffness predicts, on a plain and on a rotated and scaled mesh, and the
//    mesh body never moves.

#include "contact/ContactLaw.hpp"
#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "io/SceneReader.hpp"
#include "simulation/SceneBuilder.hpp"
#include "simulation/World.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

using namespace armour;
using namespace armour::simulation;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDensity = 2400.0; // kg/m^3, concrete
constexpr double kPenalty = 1.0e9;  // Pa, the default penalty modulus
constexpr double kG = 9.81;         // m/s^2

/// Four significant digits, for test properties and messages (std::to_string rounds 1e-9 to 0).
std::string sci(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

// ------------------------------------------------------------------------------------------------
// Tunnelling
// ------------------------------------------------------------------------------------------------

/// How the cube meets the wall.
enum class Leading { Face, Edge, Corner };

/// Which kind of wall.
enum class WallKind {
  Convex,    ///< a static convex piece (World::addConvex)
  FixedBody, ///< a box mesh as a fixed body (BodySpec::fixed)
};

/// What became of a thrown cube.
struct ThrowOutcome {
  bool refused = false;     ///< World::step threw SimulationError
  std::string message;      ///< its message
  double farFace = 0.0;     ///< x of the wall's far face (m)
  double maxLeading = -1e9; ///< largest x any corner of the cube reached during the run (m)
  double finalCentroid = 0.0; ///< centroid x at the end (or at the refusal) (m)
  double finalVelocity = 0.0; ///< centroid x velocity at the end (or at the refusal) (m/s)
  double maxOverlap = 0.0;  ///< deepest penetration seen in any step (m)
  double timeStep = 0.0;    ///< the automatic step (s)
};

Quat leadingOrientation(Leading leading) {
  switch (leading) {
  case Leading::Face:
    return Quat::Identity();
  case Leading::Edge: // a vertical edge in front
    return Quat(Eigen::AngleAxisd(kPi / 4.0, Vec3::UnitZ()));
  case Leading::Corner: // a body diagonal along x: Rz(45 deg) sends (1, -1, 1) to (sqrt 2, 0, 1), then
                        // Ry(atan(1 / sqrt 2)) to (sqrt 3, 0, 0)
    return Quat(Eigen::AngleAxisd(std::atan(std::sqrt(0.5)), Vec3::UnitY())) *
           Quat(Eigen::AngleAxisd(kPi / 4.0, Vec3::UnitZ()));
  }
  return Quat::Identity();
}

/// A 1 m concrete cube (2400 kg, penalty modulus 1e9 Pa, default restitution 0.05, automatic time
/// step) thrown along +x at `speed` from 1.5 m before a 4 m x 4 m wall whose near face is x = 0 and
/// far face x = thickness. No gravity: nothing but the wall acts on the cube. Runs 0.4 s (the cube
/// reaches the wall after 0.05 s) or until World::step refuses to go on.
ThrowOutcome throwCube(WallKind kind, double thickness, Leading leading, double speed = 20.0,
                       WorldSettings settings = {}) {
  settings.gravity = Vec3::Zero();
  settings.sleep.enabled = false;
  World world(settings);
  Material concrete;
  concrete.name = "concrete";
  concrete.density = kDensity;
  concrete.penaltyModulus = kPenalty;
  const MaterialId material = world.addMaterial(concrete);
  geometry::ShapeRequest unit;
  unit.volume = 1.0;
  const ShapeId cube = world.addShape("cube", geometry::makeShape("cube", unit));
  if (kind == WallKind::Convex) {
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) {
      corners.emplace_back((i & 1) ? thickness : 0.0, (i & 2) ? 2.0 : -2.0, (i & 4) ? 2.0 : -2.0);
    }
    world.addConvex("wall", corners, material);
  } else {
    ShapeId slab = 0;
    try {
      slab = world.addShape("wall", test::makeBox(thickness, 4.0, 4.0));
    } catch (const core::InputError& e) {
      // A wall thinner than its level set can hold is refused as input: the run is refused.
      ThrowOutcome refusedAtInput;
      refusedAtInput.refused = true;
      refusedAtInput.message = e.what();
      refusedAtInput.farFace = thickness;
      refusedAtInput.finalCentroid = -1.5;
      return refusedAtInput;
    }
    BodySpec wall;
    wall.name = "wall";
    wall.shape = slab;
    wall.material = material;
    wall.fixed = true;
    wall.position = Vec3(0.5 * thickness, 0.0, 0.0); // the centroid: the box spans x in [0, thickness]
    world.addBody(wall);
  }
  BodySpec spec;
  spec.name = "cube";
  spec.shape = cube;
  spec.material = material;
  spec.position = Vec3(-1.5, 0.0, 0.0);
  spec.orientation = leadingOrientation(leading);
  spec.velocity = Vec3(speed, 0.0, 0.0);
  const BodyId b = world.addBody(spec);

  ThrowOutcome out;
  out.farFace = thickness;
  out.timeStep = world.timeStep();
  const auto& corners = world.shape(cube).mesh.vertices; // body frame, scale 1
  const auto leadingX = [&] {
    double x = -1e9;
    for (const Vec3& v : corners) {
      x = std::max(x, world.bodies().toWorld(b, v).x());
    }
    return x;
  };
  try {
    while (world.time() < 0.4) {
      world.step();
      out.maxLeading = std::max(out.maxLeading, leadingX());
      out.maxOverlap = std::max(out.maxOverlap, world.lastStep().maxOverlap);
    }
  } catch (const SimulationError& e) {
    out.refused = true;
    out.message = e.what();
  }
  out.finalCentroid = world.bodies().position(b).x();
  out.finalVelocity = world.bodies().velocity(b).x();
  return out;
}

std::string name(Leading leading) {
  return leading == Leading::Face ? "face first" : leading == Leading::Edge ? "edge first" : "corner first";
}

std::string describe(const ThrowOutcome& o) {
  return "max leading x " + sci(o.maxLeading) + " m (far face " + sci(o.farFace) + " m), final centroid x " +
         sci(o.finalCentroid) + " m, final vx " + sci(o.finalVelocity) + " m/s, max overlap " + sci(o.maxOverlap) + " m" +
         (o.refused ? ", refused: " + o.message : ", not refused");
}

/// The assertion of issue 3 for a thin wall: either the cube is stopped (no corner ever passes the
/// far face, and it ends moving back or at rest, on the near side) or the run is refused with a
/// message that says it would tunnel, before any corner has passed the far face.
void expectStoppedOrRefused(const ThrowOutcome& o, const std::string& what) {
  EXPECT_LT(o.maxLeading, o.farFace) << what << ": a corner passed the far face; " << describe(o);
  EXPECT_LT(o.finalCentroid, 0.0) << what << ": the centroid is not on the near side; " << describe(o);
  if (o.refused) {
    // Refused at the contact (it would tunnel) or at input (too thin for its level set).
    EXPECT_TRUE(o.message.find("tunnel") != std::string::npos || o.message.find("too thin") != std::string::npos)
        << what << ": refused for another reason; " << describe(o);
  } else {
    // Stopped: the rebound speed of a restitution of 0.05 is about 1 m/s; 0 would mean stuck in the wall.
    EXPECT_LT(o.finalVelocity, 0.0) << what << ": not sent back; " << describe(o);
  }
}

} // namespace

TEST(Tunnelling, ThickConvexWallStopsTheCubeFaceEdgeOrCornerFirst) {
  // A 0.5 m wall (inner depth 0.25 m). Face first the whole face engages at once: the overlap is
  // about v sqrt(m / K) = 0.031 m undamped, less with the damping of e = 0.05 (measured 6.7 mm).
  // Edge first (measured 33 mm) and corner first (88 mm) fewer samples carry the impact, so the
  // cube goes deeper, but every overlap stays below the guard rails (0.25 Dn = 0.25 m and half the
  // wall's inner depth, 0.125 m): the cube must come back, not be refused.
  for (Leading leading : {Leading::Face, Leading::Edge, Leading::Corner}) {
    const std::string what = name(leading);
    const ThrowOutcome o = throwCube(WallKind::Convex, 0.5, leading);
    EXPECT_FALSE(o.refused) << what << ": " << describe(o);
    EXPECT_LT(o.maxLeading, 0.25) << what << ": the cube must not reach the middle of the wall; " << describe(o);
    EXPECT_LT(o.finalVelocity, -0.3) << what << ": the cube must rebound; " << describe(o);
    EXPECT_LT(o.finalCentroid, -0.5) << what << ": " << describe(o);
    RecordProperty("thick_wall_overlap_m_" + std::to_string(static_cast<int>(leading)), sci(o.maxOverlap));
  }
}

TEST(Tunnelling, ThinConvexWallStopsTheCubeOrRefusesTheRun) {
  // 0.1, 0.05 and 0.02 m static convex walls, face, edge and corner first. A sample point inside a
  // convex piece is pushed out through the nearest face; past the middle of the wall that is the far
  // face, so a deep overlap would carry the cube through. The guard rail stops the run when an
  // overlap exceeds half the wall's inner depth (half its thickness). Measured at 20 m/s: the face
  // impact (6.7 mm) is stopped by the 0.1 and 0.05 m walls and refused at 0.02 m; edge and corner
  // first are refused for all three.
  for (double thickness : {0.1, 0.05, 0.02}) {
    for (Leading leading : {Leading::Face, Leading::Edge, Leading::Corner}) {
      expectStoppedOrRefused(throwCube(WallKind::Convex, thickness, leading),
                             "convex wall " + sci(thickness) + " m, " + name(leading));
    }
  }
}

TEST(Tunnelling, ThinFixedBodyStopsTheCubeOrRefusesTheRun) {
  // The same with the wall a fixed body (a box mesh with its level set and samples): the contact
  // is then found both ways (the cube's samples in the wall's level set and the wall's samples in
  // the cube's). Measured: the 0.1 m body stops the face-first cube (overlap 6.8 mm) and refuses
  // the corner-first one (13 mm, more than half the inner depth its level-set nodes give, 0.026 m;
  // the true half thickness is 0.05 m); the 0.02 m slab is refused as input, being thinner than a
  // level-set cell (0.0285 m).
  for (double thickness : {0.1, 0.02}) {
    for (Leading leading : {Leading::Face, Leading::Corner}) {
      expectStoppedOrRefused(throwCube(WallKind::FixedBody, thickness, leading),
                             "fixed body " + sci(thickness) + " m, " + name(leading));
    }
  }
}

TEST(Tunnelling, ConstraintSolverStopsTheCubeOrRefusesTheRun) {
  // The same throws at 20 m/s under the constraint solver (issue 22: "stopped or refused"), whose
  // step (1/200 s) carries the cube 0.1 m: more than the 0.05 Dn speculative margin and five times
  // the thinnest wall. The margin grows with a pair's approach over the step, so the wall is found
  // before the cube reaches it. Either the cube is sent back from the near side, or the run is
  // refused by the tunnelling guard. Measured: face and corner first are stopped at every wall; edge
  // first is refused at all three convex walls (the speculative contact does not catch a leading
  // edge at 20 m/s; at the 0.05 m wall the edge is 13 mm past the far face when the guard refuses
  // the run; docs/theory.md section 18).
  WorldSettings settings;
  settings.solver = ContactSolverKind::Constraint;
  const auto check = [](const ThrowOutcome& o, const std::string& what) {
    if (o.refused) {
      EXPECT_NE(o.message.find("tunnel"), std::string::npos) << what << ": refused for another reason; " << describe(o);
      return;
    }
    EXPECT_LT(o.maxLeading, o.farFace) << what << ": a corner passed the far face; " << describe(o);
    EXPECT_LT(o.finalCentroid, 0.0) << what << ": not on the near side; " << describe(o);
    EXPECT_LT(o.finalVelocity, 0.0) << what << ": not sent back; " << describe(o);
  };
  int stopped = 0;
  for (double thickness : {0.1, 0.05, 0.02}) {
    for (Leading leading : {Leading::Face, Leading::Edge, Leading::Corner}) {
      const ThrowOutcome o = throwCube(WallKind::Convex, thickness, leading, 20.0, settings);
      check(o, "constraint solver, convex wall " + sci(thickness) + " m, " + name(leading));
      stopped += o.refused ? 0 : 1;
    }
  }
  for (Leading leading : {Leading::Face, Leading::Corner}) {
    const ThrowOutcome o = throwCube(WallKind::FixedBody, 0.1, leading, 20.0, settings);
    check(o, "constraint solver, fixed body 0.1 m, " + name(leading));
    stopped += o.refused ? 0 : 1;
  }
  EXPECT_GE(stopped, 8) << "the speculative margin stopped 8 of the 11 throws when this was written";
}

TEST(Tunnelling, WithoutTheGuardRailAThinWallIsPassed) {
  // The assertion above is not vacuous: switch the tunnelling guard off and a face-first cube at
  // 20 m/s goes deeper (6.7 mm) than half of a 0.01 m wall, every bottom sample is then pushed out
  // through the far face, and the cube ends up beyond the wall. (If this ever fails because the
  // solver stops the cube by itself, e.g. by continuous collision detection, delete it.)
  WorldSettings settings;
  settings.maxOverlapPerInnerDepth = 1e9;
  const ThrowOutcome o = throwCube(WallKind::Convex, 0.01, Leading::Face, 20.0, settings);
  EXPECT_FALSE(o.refused) << describe(o);
  EXPECT_GT(o.finalCentroid, o.farFace + 0.5) << "expected the cube on the far side; " << describe(o);
}

TEST(Tunnelling, ThinFixedBodyIsNotRefusedAtAGentleTouch) {
  // A cube pushed at 1 m/s against a 0.02 m fixed slab overlaps it by about 1 mm at most
  // (v sqrt(m / K)), a tenth of the slab's half thickness: it must simply be stopped. Once the
  // tunnelling guard took the slab's inner depth from its level-set nodes (-min phi) and, with no
  // node inside the slab, refused the run at the first touch. Two checks, at the default 24 cells
  // per Dn:
  //  1. A 0.02 x 4 x 4 m slab (Dn 0.68 m, cells 0.028 m, no node inside) is refused when it is
  //     added, naming the shape and the resolution that would hold it.
  //  2. A 0.02 x 1.2 x 1.2 m slab (Dn 0.31 m, cells 0.013 m: nodes inside) is accepted; the run
  //     goes on and the cube is sent back.
  WorldSettings settings;
  settings.gravity = Vec3::Zero();
  settings.sleep.enabled = false;
  {
    World refusing(settings);
    try {
      refusing.addShape("slab", test::makeBox(0.02, 4.0, 4.0));
      ADD_FAILURE() << "a 0.02 m slab with cells of 0.028 m must be refused as input";
    } catch (const core::InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("shape 'slab'"), std::string::npos) << what;
      EXPECT_NE(what.find("too thin for its level set"), std::string::npos) << what;
      EXPECT_NE(what.find("raise contact.level_set_cells_per_dn to at least"), std::string::npos) << what;
    }
  }
  auto world = std::make_unique<World>(settings);
  const MaterialId material = world->addMaterial(Material{});
  geometry::ShapeRequest unit;
  unit.volume = 1.0;
  const ShapeId cube = world->addShape("cube", geometry::makeShape("cube", unit));
  BodySpec wall;
  wall.name = "slab";
  wall.shape = world->addShape("slab", test::makeBox(0.02, 1.2, 1.2));
  wall.material = material;
  wall.fixed = true;
  wall.position = Vec3(0.01, 0.0, 0.0);
  world->addBody(wall);
  BodySpec spec;
  spec.name = "cube";
  spec.shape = cube;
  spec.material = material;
  spec.position = Vec3(-0.52, 0.0, 0.0);
  spec.velocity = Vec3(1.0, 0.0, 0.0);
  const BodyId b = world->addBody(spec);
  try {
    world->advanceTo(0.2);
  } catch (const SimulationError& e) {
    ADD_FAILURE() << "a 1 m/s touch was refused: " << e.what();
  }
  EXPECT_LT(world->bodies().velocity(b).x(), 0.0) << "the cube must be sent back";
  EXPECT_LT(world->bodies().position(b).x(), 0.0) << "the cube must stay on its side of the slab";
}

TEST(ContactDetection, OverlappingDolosseAreFoundWhenACentroidLiesOutsideTheOtherLevelSet) {
  // Not a thrown body but the same failure: an overlap the contact stage does not see lets bodies
  // pass into each other. Two dolosse (V = 1 m^3) posed so that A's surface samples reach 1 cm into
  // B (by B's level set, evaluated here where it is accurate, inside B's grid), their centroids
  // 2.17 m apart: A's centroid lies outside B's level-set grid and B's outside A's. The contact
  // must be found. (Found in the pile of test_dolos_pile: the lattice collapse tripped the energy
  // guard after contacts 0.13 m deep appeared from one step to the next. A pose from a random
  // search in which 3 of 32 such overlaps were missed: the near-miss test before the sample loops
  // took LevelSet::value at the other centroid as a lower bound of the distance, but outside the
  // grid value() is phi at the clamped point plus the distance to it, which can exceed the true
  // distance.)
  WorldSettings settings;
  settings.gravity = Vec3::Zero();
  settings.sleep.enabled = false;
  World world(settings);
  const MaterialId material = world.addMaterial(Material{});
  geometry::ShapeRequest unit;
  unit.volume = 1.0;
  const ShapeId dolos = world.addShape("dolos", geometry::makeShape("dolos", unit));
  BodySpec a;
  a.name = "a";
  a.shape = dolos;
  a.material = material;
  a.orientation = Quat(-0.65617102368304014, 0.37048971721434304, -0.46336548635867975, 0.466336126810664);
  BodySpec b = a;
  b.name = "b";
  b.position = Vec3(-1.4227891200691118, 0.68483767708071108, -1.4811797581197683);
  b.orientation = Quat(0.21012247681780349, -0.784018618627081, 0.28635174286844584, -0.50908351941330665);
  const BodyId ia = world.addBody(a);
  const BodyId ib = world.addBody(b);
  // The overlap, from B's level set at A's samples (body frames: the World's, principal axes).
  const ShapeModel& shape = world.shape(dolos);
  const contact::LevelSet& ls = *shape.levelSet;
  const auto inGrid = [&](const Vec3& x) {
    return (x.array() >= ls.gridBounds().min.array()).all() && (x.array() <= ls.gridBounds().max.array()).all();
  };
  double depth = 0.0;
  for (const Vec3& p : shape.samples->positions()) {
    const Vec3 local = world.bodies().orientation(ib).conjugate() * (world.bodies().toWorld(ia, p) - world.bodies().position(ib));
    if (inGrid(local)) {
      depth = std::max(depth, -ls.value(local));
    }
  }
  ASSERT_GT(depth, 0.005) << "the pose must overlap (measured 0.010 m)";
  EXPECT_FALSE(inGrid(world.bodies().orientation(ib).conjugate() * (world.bodies().position(ia) - world.bodies().position(ib))))
      << "the case is about a centroid outside the other grid";
  world.step();
  EXPECT_GT(world.lastStep().contactPoints, 0u) << "A's samples are " << depth << " m inside B but no contact was found";
}

// ------------------------------------------------------------------------------------------------
// Convergence: the block sliding down an incline
// ------------------------------------------------------------------------------------------------

namespace {

/// A 1 m cube laid on a slope of angle theta (the slope descends towards +x) with zero overlap and
/// at rest, friction mu (static = dynamic), restitution e, a fixed time step dt, run for T.
struct Slide {
  double along = 0.0; ///< centroid displacement down the slope (m)
  double depth = 0.0; ///< centroid displacement into the slope: the overlap of the face (m)
};

Slide slide(double theta, double mu, double restitution, double dt, double duration,
            DashpotIntegration dashpot = DashpotIntegration::Explicit) {
  WorldSettings settings;
  settings.sleep.enabled = false;
  settings.timeStep = dt;
  settings.dashpot = dashpot;
  World world(settings);
  Material m;
  m.name = "concrete";
  m.density = kDensity;
  m.penaltyModulus = kPenalty;
  m.restitution = restitution;
  m.frictionStatic = m.frictionDynamic = mu;
  const MaterialId material = world.addMaterial(m);
  geometry::ShapeRequest unit;
  unit.volume = 1.0;
  const ShapeId cube = world.addShape("cube", geometry::makeShape("cube", unit));
  const Vec3 normal(std::sin(theta), 0.0, std::cos(theta));
  const Vec3 downhill(std::cos(theta), 0.0, -std::sin(theta));
  world.addPlane({"slope", Vec3::Zero(), normal, material});
  BodySpec spec;
  spec.shape = cube;
  spec.material = material;
  spec.position = 0.5 * normal;
  spec.orientation = Quat(Eigen::AngleAxisd(theta, Vec3::UnitY()));
  const BodyId b = world.addBody(spec);
  const auto steps = static_cast<long>(std::llround(duration / dt));
  for (long i = 0; i < steps; ++i) {
    world.step();
  }
  return {world.bodies().position(b).dot(downhill), 0.5 - world.bodies().position(b).dot(normal)};
}

/// The penalty model's own solution. A face pressed flat is one linear spring-dashpot: stiffness
/// K = E_p A / L (A = 1 m^2, L = Dn = 1 m) and damping 2 zeta sqrt(m K), zeta from the restitution;
/// starting at zero overlap and at rest, its overlap is that of a damped oscillator under m g cos a:
///   d(t) = d_eq [1 - exp(-zeta w t) (cos(w_d t) + zeta / sqrt(1 - zeta^2) sin(w_d t))],
///   d_eq = m g cos a / K, w = sqrt(K / m), w_d = w sqrt(1 - zeta^2).
/// Every engaged point slides from the first step (the damped normal force starts from zero), so
/// the friction is mu times the normal force N(t) = m g cos a - m d''(t), and integrating
/// m x'' = m g sin a - mu N twice gives x(t) = g (sin a - mu cos a) t^2 / 2 + mu d(t).
/// (The friction torque tilts the cube; the tilt leaves the sums of the point forces, and so the
/// centroid's motion, unchanged as long as every bottom point stays engaged, which holds while the
/// friction's lever arm mu x 0.5 m stays inside the face's core, a sixth of the side: mu < 1/3.
/// At mu = 0.1 all 289 bottom samples stay engaged.)
struct PenaltySolution {
  double along = 0.0, depth = 0.0;
};
PenaltySolution penaltySolution(double theta, double mu, double restitution, double t) {
  const double m = kDensity * 1.0;
  const double k = kPenalty * 1.0 / 1.0;
  const double zeta = contact::dampingRatioFromRestitution(restitution);
  const double w = std::sqrt(k / m);
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  const double dEq = m * kG * std::cos(theta) / k;
  const double d =
      dEq * (1.0 - std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t)));
  return {0.5 * kG * (std::sin(theta) - mu * std::cos(theta)) * t * t + mu * d, d};
}

} // namespace

TEST(Convergence, SlidingBlockErrorFallsAtTheOrderOfTheIntegrator) {
  // theta = 35 deg, mu = 0.1: sliding from the start. Compared at T = 4 ms, inside the contact
  // transient (period 2 pi / w = 9.7 ms), where the solution still changes on the time scale of
  // the contact; dt = 0.2, 0.1 and 0.05 ms (w dt = 0.13 to 0.03), all below the stability limit.
  //
  // Expected orders, measured and explained:
  //  - e = 1 (no damping): velocity Verlet is second order; measured 2.00 and 2.00 (errors 1.8e-9,
  //    4.6e-10, 1.1e-10 m against an overlap of 3.6e-5 m). Asserted within 0.15.
  //  - e = 0.3 (damping ratio 0.36): first order; measured 0.96 and 0.99 (errors 1.1e-8, 5.7e-9,
  //    2.9e-9 m). The step computes the forces after the drift, with the half-step velocity
  //    v(n+1/2) (kick, drift, forces, kick); the dashpot and the friction springs then see a
  //    velocity dt/2 old, an O(dt) error in the damping force, so the scheme is first order
  //    whenever the contact damping matters. The error is small (2.9e-4 of the overlap at the
  //    automatic step of 0.13 ms). Asserted within 0.15 of 1.
  //  - e = 0.3 with contact.dashpot: implicit: first order as well, with a larger constant: the
  //    dashpot sees v(n+1/2) / (1 + zeta omega dt), 6.4 % less than the explicit one at the
  //    coarsest step (zeta = 0.497, omega dt = 0.129), so the transient's overlap and the
  //    friction it carries are off by up to that fraction there (measured in session 21: errors
  //    6.6e-8, 3.4e-8, 1.7e-8 m, overlap 3.3 % off; explicit 0.55 %). Asserted: order within 0.15 of 1, overlap
  //    and displacement error within 6.4 % of the overlap.
  // After the transient there is nothing left to converge: see the next test.
  const double theta = 35.0 * kPi / 180.0;
  const double mu = 0.1;
  const double T = 4.0e-3;
  const double dt = 2.0e-4;
  struct Case {
    double restitution, order;
    DashpotIntegration dashpot = DashpotIntegration::Explicit;
    double depthTolerance = 0.02; ///< of the overlap, at every step
    double errorTolerance = 0.01; ///< of mu x the overlap, at the coarsest step
  };
  for (const Case c : {Case{1.0, 2.0}, Case{0.3, 1.0}, Case{0.3, 1.0, DashpotIntegration::Implicit, 0.064, 0.064}}) {
    const PenaltySolution exact = penaltySolution(theta, mu, c.restitution, T);
    double error[3];
    for (int k = 0; k < 3; ++k) {
      const Slide s = slide(theta, mu, c.restitution, dt / (1 << k), T, c.dashpot);
      error[k] = std::abs(s.along - exact.along);
      // The sliding block's displacement and its overlap differ from the model by the same
      // amount (times mu): check the overlap too, to 2 % at the coarsest step.
      EXPECT_NEAR(s.depth, exact.depth, c.depthTolerance * exact.depth)
          << "e = " << c.restitution << ", dt = " << dt / (1 << k);
      if (k == 0) {
        RecordProperty(std::string(c.dashpot == DashpotIntegration::Implicit ? "implicit_" : "") + "depth_error_e" +
                           std::to_string(static_cast<int>(100 * c.restitution)),
                       sci(s.depth / exact.depth - 1.0));
      }
    }
    const double order1 = std::log2(error[0] / error[1]);
    const double order2 = std::log2(error[1] / error[2]);
    const std::string tag = std::string(c.dashpot == DashpotIntegration::Implicit ? "implicit_" : "") + "e" +
                            std::to_string(static_cast<int>(100 * c.restitution));
    RecordProperty("order_" + tag, sci(order1) + " " + sci(order2));
    RecordProperty("error_m_" + tag, sci(error[0]) + " " + sci(error[1]) + " " + sci(error[2]));
    EXPECT_NEAR(order1, c.order, 0.15) << "e = " << c.restitution << ": errors " << error[0] << ", " << error[1] << " m";
    EXPECT_NEAR(order2, c.order, 0.15) << "e = " << c.restitution << ": errors " << error[1] << ", " << error[2] << " m";
    EXPECT_LT(error[0], c.errorTolerance * mu * exact.depth) << "e = " << c.restitution;
  }
}

TEST(Convergence, SlidingBlockAfterTheTransientMatchesTheRigidSolutionForEveryStep) {
  // theta = 35 deg, mu = 0.4 (the sliding test of test_contact_physics): after 1 s the block has
  // slid 1.21 m. While every engaged point slides, the friction is mu times the normal force and
  // the discrete equations of the centroid along and into the slope are linear with constant
  // coefficients: velocity Verlet then integrates x - mu d exactly, for any step, so
  //   x(T) = g (sin a - mu cos a) T^2 / 2 + mu (d(T) - d(0)),  d(0) = 0,
  // holds to round-off (measured 1e-16 to 6e-14 m), and the only difference from the rigid-body
  // solution is mu times the resting overlap, 0.4 x 1.9e-5 m = 7.6e-6 m, the same for every step
  // (here the friction's lever arm lifts the uphill edge of the face, the rest is unaffected).
  // So the error against the rigid analytic solution does not converge with dt: it is the model's
  // (the penalty spring's) and is bounded by mu x the overlap under the weight.
  const double theta = 35.0 * kPi / 180.0;
  const double mu = 0.4;
  const double T = 1.0;
  const double rigid = 0.5 * kG * (std::sin(theta) - mu * std::cos(theta)) * T * T;
  const double restingOverlap = kDensity * kG * std::cos(theta) / kPenalty; // m g cos a L / (E_p A)
  double first = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double dt = 4.0e-4 / (1 << k);
    const Slide s = slide(theta, mu, 0.3, dt, T);
    EXPECT_NEAR(s.along - mu * s.depth, rigid, 1e-12) << "dt = " << dt;
    EXPECT_NEAR(s.along - rigid, mu * restingOverlap, 0.05 * mu * restingOverlap) << "dt = " << dt;
    if (k == 0) {
      first = s.along;
      RecordProperty("error_against_rigid_m", sci(s.along - rigid));
    } else {
      EXPECT_NEAR(s.along, first, 1e-12) << "dt = " << dt << ": the same for every step";
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Fixed meshes as static obstacles
// ------------------------------------------------------------------------------------------------

namespace {

const std::filesystem::path kScenes = std::filesystem::path(ARMOUR_TEST_DATA) / "scenes";

/// Resting overlap of a 1 m concrete cube on a face, m g cos a L / (E_p A), A = 1 m^2, L = 1 m.
double restingOverlap(double cosTilt) { return kDensity * kG * cosTilt * 1.0 / (kPenalty * 1.0); }

/// Full precision in a scene file (std::to_string keeps 6 decimals only).
std::string full(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

/// Everything about the static mesh body that must not change (bit for bit).
struct Frozen {
  Vec3 position;
  Quat orientation;
  bool same(const World& w, BodyId b) const {
    const Quat& q = w.bodies().orientation(b);
    return w.bodies().position(b) == position && q.coeffs() == orientation.coeffs() &&
           w.bodies().velocity(b) == Vec3::Zero() && w.bodies().worldAngularVelocity(b) == Vec3::Zero();
  }
};

} // namespace

TEST(FixedMesh, CubeComesToRestOnTopOfAFixedMesh) {
  // block.stl is the unit cube [0, 1]^3; scaled by 2 and moved by (-1, -1, 0) it is a fixed 2 m
  // block with its top at z = 2 and centred on the z axis. A 1 m cube dropped from 5 cm above it
  // must rest at z = 2 + 0.5 - d. Body-body contacts are found both ways, each direction's
  // tributary areas weighted by w = Dn_other^2 / (Dn_A^2 + Dn_B^2) (0.8 for the cube's samples in
  // the block's level set, area 1 m^2; 0.2 for the block's top samples, spacing 0.1 Dn = 0.2 m,
  // inside the cube's footprint, whose projected areas A2 make 1 m^2 give or take a row of samples
  // on each side: 0 < A2 < 1.44 m^2). With L = min Dn = 1 m, d = d0 / (0.8 + 0.2 A2) lies between
  // d0 / 1.09 and 1.25 d0, d0 = m g L / (E_p 1 m^2) = 2.35e-5 m; measured 2.47e-5 m = 1.05 d0.
  // Asserted more loosely, d0 / 1.25 < d < 2 d0 (what any split of the penalty between the two
  // directions allows: half each gives d0 / 1.22 to 2 d0), i.e. the cube rests on the top face to
  // within 5e-5 m, neither sunk into the block nor floating.
  const std::string yaml = R"(
duration: 1
materials:
  concrete: {density: 2400, friction: 0.6, restitution: 0.3}
bodies:
  - {name: cube, shape: cube, dn: 1.0, material: concrete, position: [0, 0, 2.55]}
static:
  - {type: mesh, name: block, material: concrete, file: meshes/block.stl, position: [-1, -1, 0], scale: 2}
)";
  const BuiltScene built = buildWorld(io::parseScene(yaml, kScenes, "fixed-mesh.yaml"));
  World& world = *built.world;
  ASSERT_EQ(built.staticMeshBodies.size(), 1u);
  const BodyId block = built.staticMeshBodies[0];
  const BodyId cube = built.bodyIndexOfSceneBody[0];
  EXPECT_EQ(world.bodies().motionType(block), dynamics::MotionType::Static);
  EXPECT_LT((world.bodies().position(block) - Vec3(0, 0, 1)).norm(), 1e-12) << "centroid of the 2 m block";
  const Frozen frozen{world.bodies().position(block), world.bodies().orientation(block)};
  world.advanceTo(1.0);
  const double d = 2.5 - world.bodies().position(cube).z();
  RecordProperty("resting_overlap_m", sci(d));
  EXPECT_GT(d, restingOverlap(1.0) / 1.25);
  EXPECT_LT(d, 2.0 * restingOverlap(1.0));
  EXPECT_LT(std::hypot(world.bodies().position(cube).x(), world.bodies().position(cube).y()), 1e-6)
      << "a flat landing on a level face does not drift sideways";
  EXPECT_LT(world.bodies().velocity(cube).norm(), 1e-3) << "at rest";
  EXPECT_TRUE(frozen.same(world, block)) << "the fixed mesh body moved";
}

TEST(FixedMesh, CubeRestsOnARotatedScaledFixedMesh) {
  // The block file scaled by 2.5 and turned by 10 deg about x (euler_deg [10, 0, 0]) about the
  // file's origin: its top face is a 10 deg incline with outward normal n = (0, -sin 10, cos 10)
  // through the top face's centre c = R (1.25, 1.25, 2.5). A cube turned the same way is laid flat
  // on it, touching (centroid at c + 0.5 n, at rest); friction 0.6 > tan 10 deg = 0.18, so it must stay put: after settling its
  // centroid is 0.5 - d above the face, d about m g cos 10 L / (E_p 1 m^2) (between d0 cos 10 / 1.25
  // and 2 d0 cos 10 as above; measured 2.31e-5 m = 1.00 d0 cos 10), and it
  // does not creep down the face: less than 1e-4 m in 1 s once settled (the friction springs hold
  // a constant stretch, test_contact_physics; measured: 0 to round-off, the speed is 2e-13 m/s).
  // The block never moves.
  const double a = 10.0 * kPi / 180.0;
  const Quat R(Eigen::AngleAxisd(a, Vec3::UnitX()));
  const Vec3 n = R * Vec3::UnitZ();
  const Vec3 topCentre = R * Vec3(1.25, 1.25, 2.5);
  const Vec3 start = topCentre + 0.5 * n;
  const std::string yaml = R"(
duration: 3
sleep: {enabled: false}         # the creep check needs the cube integrated throughout
materials:
  concrete: {density: 2400, friction: 0.6, restitution: 0.3}
bodies:
  - name: cube
    shape: cube
    dn: 1.0
    material: concrete
    position: [)" + full(start.x()) + ", " + full(start.y()) + ", " + full(start.z()) + R"(]
    orientation: {euler_deg: [10, 0, 0]}
static:
  - {type: mesh, name: block, material: concrete, file: meshes/block.stl, orientation: {euler_deg: [10, 0, 0]}, scale: 2.5}
)";
  const BuiltScene built = buildWorld(io::parseScene(yaml, kScenes, "rotated-mesh.yaml"));
  World& world = *built.world;
  ASSERT_EQ(built.staticMeshBodies.size(), 1u);
  const BodyId block = built.staticMeshBodies[0];
  const BodyId cube = built.bodyIndexOfSceneBody[0];
  EXPECT_LT((world.bodies().position(block) - R * Vec3(1.25, 1.25, 1.25)).norm(), 1e-9) << "block centroid";
  const Frozen frozen{world.bodies().position(block), world.bodies().orientation(block)};
  const Vec3 downhill = (n.z() * n - Vec3::UnitZ()).normalized(); // in the face, pointing down it
  world.advanceTo(1.0);
  const Vec3 settled = world.bodies().position(cube);
  world.advanceTo(2.0);
  const Vec3 p = world.bodies().position(cube);
  const double height = (p - topCentre).dot(n);
  const double d = 0.5 - height;
  RecordProperty("resting_overlap_m", sci(d));
  RecordProperty("creep_m", sci((p - settled).norm()));
  EXPECT_GT(d, restingOverlap(std::cos(a)) / 1.25);
  EXPECT_LT(d, 2.0 * restingOverlap(std::cos(a)));
  EXPECT_LT((p - settled).norm(), 1e-4) << "creeps down the face";
  EXPECT_EQ(world.lastStep().awakeBodies, 1u) << "integrated throughout (sleeping off)";
  EXPECT_LT(std::abs((p - start).dot(downhill)), 1e-3) << "slid down the face: elastic stretch only";
  EXPECT_LT(world.naturalOrientation(cube).angularDistance(R), 1e-3) << "lies flat on the face";
  EXPECT_TRUE(frozen.same(world, block)) << "the fixed mesh body moved";
}
