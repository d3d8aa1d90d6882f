// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/DeformableScene.hpp"

#include "core/TextFile.hpp"
#include "io/ReadOrientation.hpp"
#include "io/YamlSchema.hpp"

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

namespace armour::io {
namespace {

using namespace schema;

const KeyList kTopKeys{"description", "seed", "material", "element", "f_bar", "gravity", "bodies", "rigid_bodies",
                       "half_spaces", "contact", "run", "output"};
const KeyList kMaterialKeys{"density", "young_modulus", "poisson_ratio", "viscosity", "mass_damping"};
const KeyList kBodyKeys{"name",        "shape",    "mesh",   "volume", "tets", "shape_seed",        "params", "box",
                        "cells",       "position", "orientation", "velocity", "random_orientation", "grid"};
const KeyList kGridKeys{"counts", "spacing"};
const KeyList kRigidKeys{"name",        "shape", "volume", "shape_seed", "params", "position", "orientation",
                         "cells_per_dn", "fixed", "density", "velocity"};
const KeyList kHalfSpaceKeys{"point", "normal"};
const KeyList kContactKeys{"friction",          "body_friction",        "gradient", "penalty", "damping",
                           "rigid_penalty_modulus", "rigid_restitution"};
const KeyList kRunKeys{"duration", "step_safety", "mass_scaling", "frames_every", "stress_every", "checkpoint_every"};
const KeyList kOutputKeys{"folder"};

/// Largest tetrahedra asked of one shape: beyond this a size was probably given in the wrong unit.
constexpr std::uint64_t kMaxTets = 2'000'000;

/// The library shape of a body: shape, volume, shape_seed, params.
void readShape(const Block& b, DeformablePart& p) {
  p.shape = b.text("shape", "a shape of the library (armour shape list), e.g. vcross");
  std::vector<std::string_view> valid;
  for (const auto& g : geometry::shapeGenerators()) valid.push_back(g.name);
  if (std::find(valid.begin(), valid.end(), p.shape) == valid.end()) {
    b.failValue("shape", fmt::format("unknown shape{}; the shapes are: {}", suggestion(p.shape, valid),
                                     fmt::join(valid, ", ")));
  }
  p.volume = b.number("volume", {"m^3", kPositive, "14 (seed 002's Vcross)"});
  p.shapeSeed = b.integer("shape_seed", 0, "the seed of a random shape (rock, voronoi-rock)", 1);
  if (b.has("params")) {
    const YAML::Node params = b.get("params");
    if (!params.IsMap()) b.failValue("params", "expected a mapping of the generator's parameters, e.g. {points: 12}");
    for (const auto& kv : params) {
      double v = 0.0;
      if (!kv.second.IsScalar() || !YAML::convert<double>::decode(kv.second, v) || !std::isfinite(v))
        b.failValue("params", fmt::format("parameter '{}' = {}: expected a finite number", kv.first.Scalar(),
                                          valueText(kv.second)));
      p.params[kv.first.Scalar()] = v; // names and ranges are checked by the generator, which names them
    }
  }
}

DeformablePart readPart(const Block& b, std::size_t index) {
  DeformablePart p;
  p.name = b.text("name", "a name for the body, used in messages and outputs", fmt::format("body_{}", index));
  const int kind = b.oneOf({"shape", "box", "mesh"}, false,
                           "a library shape or a surface mesh file meshed by gmsh, or a box of Kuhn cells");
  if (kind == 0 || kind == 2) {
    if (kind == 0) {
      readShape(b, p);
    } else {
      const std::string file = b.text("mesh", "a closed surface mesh file (.stl, .obj, .vtp), relative to the scene file");
      p.meshFile = std::filesystem::absolute(b.context().baseDir / file).lexically_normal();
      if (!std::filesystem::exists(p.meshFile))
        b.failValue("mesh", fmt::format("no such file ({}); give the path relative to the scene file", p.meshFile.string()));
      p.volume = b.number("volume", {"m^3", kPositive, "5: the mesh scaled to this volume; absent: the file's own size"}, 0.0);
      b.refuse("shape_seed", "a mesh file is not random; remove shape_seed");
      b.refuse("params", "a mesh file has no shape parameters; remove params");
    }
    p.tets = b.integer("tets", 10, "tetrahedra wanted for the shape; gmsh gets within about 10 %", 2000);
    if (p.tets > kMaxTets) b.failValue("tets", fmt::format("more than {} tetrahedra; give fewer", kMaxTets));
    b.refuse("cells", "cells belong to a box; remove it, or give box: [x, y, z] instead of shape");
  } else {
    p.box = b.vec3("box", {"m", kPositive, "[8, 8, 4] (seed 002's anvil)"});
    const auto c = b.integers("cells", 3, 1, "Kuhn cells along x, y, z, 6 tetrahedra each");
    p.cells = {c[0], c[1], c[2]};
    if (c[0] * c[1] * c[2] * 6 > kMaxTets)
      b.failValue("cells", fmt::format("{} tetrahedra: more than {}; give fewer cells", 6 * c[0] * c[1] * c[2], kMaxTets));
    b.refuse("volume", "a box's volume is its size; remove volume");
    b.refuse("tets", "a box is meshed by its cells; remove tets");
    b.refuse("shape_seed", "a box is not random; remove shape_seed");
    b.refuse("params", "a box has no shape parameters; remove params");
  }
  p.position = b.vec3("position", {"m", kAnyNumber, "[0, 0, 2]: the shape's centroid or the box's centre"});
  p.orientation = readOrientation(b, "orientation");
  p.velocity = b.vec3("velocity", {"m/s", kAnyNumber, "[0, 0, -0.5] (seed 002's drop)"}, Eigen::Vector3d::Zero());
  return p;
}

/// A uniformly random rotation (Shoemake's method) from `rng`.
Eigen::Quaterniond randomRotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(rng), u2 = 2.0 * std::numbers::pi * u(rng), u3 = 2.0 * std::numbers::pi * u(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  return Eigen::Quaterniond(a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3)).normalized();
}

/// The body and its copies: `grid: {counts: [nx, ny, nz], spacing: [dx, dy, dz]}` places
/// nx ny nz copies from `position` (x fastest), named name_0, name_1, ...; with
/// `random_orientation: true` each copy (or the single body) is turned at random (from the scene's
/// seed and the copy's index in the file).
void readBody(const Block& b, std::size_t index, std::uint64_t seed, std::vector<DeformablePart>& out) {
  DeformablePart p = readPart(b, index);
  const bool random = b.flag("random_orientation", false);
  if (random) b.refuse("orientation", "random_orientation draws every orientation; remove one of the two");
  std::array<std::uint64_t, 3> counts{1, 1, 1};
  Eigen::Vector3d spacing = Eigen::Vector3d::Zero();
  const bool grid = b.has("grid");
  if (grid) {
    const Block g(b.context(), b.get("grid"), b.path("grid"), kGridKeys);
    const auto c = g.integers("counts", 3, 1, "copies along x, y, z");
    counts = {c[0], c[1], c[2]};
    spacing = g.vec3("spacing", {"m", kPositive, "[0.66, 0.88, 0.6]: centre to centre along x, y, z"});
    if (c[0] * c[1] * c[2] > 100000) g.failValue("counts", "more than 100000 copies; give fewer");
  }
  std::mt19937_64 rng(seed * 1000003ULL + index);
  std::size_t copy = 0;
  for (std::uint64_t k = 0; k < counts[2]; ++k) {
    for (std::uint64_t j = 0; j < counts[1]; ++j) {
      for (std::uint64_t i = 0; i < counts[0]; ++i, ++copy) {
        DeformablePart q = p;
        if (grid) q.name = fmt::format("{}_{}", p.name, copy);
        q.position += Eigen::Vector3d(static_cast<double>(i) * spacing.x(), static_cast<double>(j) * spacing.y(),
                                      static_cast<double>(k) * spacing.z());
        if (random) q.orientation = randomRotation(rng);
        out.push_back(std::move(q));
      }
    }
  }
}

/// A fixed rigid body of the scene (`rigid_bodies:`): a library shape at a pose.
RigidPart readRigid(const Block& b, std::size_t index) {
  RigidPart r;
  r.part.name = b.text("name", "a name for the rigid body, used in messages and outputs", fmt::format("rigid_{}", index));
  readShape(b, r.part);
  r.part.position = b.vec3("position", {"m", kAnyNumber, "[0, 0, -1]: the shape's centroid"});
  r.part.orientation = readOrientation(b, "orientation");
  r.cellsPerDn = b.number("cells_per_dn", {"-", kPositive, "24: level-set cells per Dn of the shape"}, r.cellsPerDn);
  if (r.cellsPerDn > 200.0) b.failValue("cells_per_dn", "more than 200 cells per Dn; give fewer (24 is usual)");
  r.fixed = b.flag("fixed", true);
  if (r.fixed) {
    for (const char* key : {"density", "velocity"}) {
      if (b.has(key)) b.failValue(key, "is for a moving rigid body; add 'fixed: false' or remove it");
    }
  } else {
    r.density = b.number("density", {"kg/m^3", kPositive, "2340; the material's density when absent"}, 0.0);
    r.part.velocity = b.vec3("velocity", {"m/s", kAnyNumber, "[0, 0, -1]"}, Eigen::Vector3d::Zero());
  }
  return r;
}

/// The block under `key`, or an empty node (all defaults) when it is absent.
YAML::Node blockOrEmpty(const Block& parent, std::string_view key) {
  return parent.has(key) ? parent.get(key) : YAML::Node();
}

} // namespace

geometry::TriangleMesh librarySurface(const DeformablePart& part) {
  geometry::ShapeRequest request;
  request.volume = part.volume;
  request.seed = part.shapeSeed;
  request.params = part.params;
  return geometry::makeShape(part.shape, request);
}

DeformableScene readDeformableScene(const std::filesystem::path& file) {
  const std::string text = core::readTextFile(file, "the deformable scene");
  const std::string source = file.string();
  DeformableScene scene;
  scene.file = file;
  Context ctx{source, std::filesystem::absolute(file).parent_path(), 1, nullptr};
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw core::InputError(fmt::format("{}:{}:{}: YAML syntax error: {} (check the indentation, colons and brackets "
                                       "on this line or the one before)",
                                       source, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  if (!root.IsDefined() || root.IsNull())
    throw core::InputError(fmt::format("{}: the scene is empty; it needs at least 'bodies' and 'run: duration' "
                                       "(docs/deformable-file.md has an example)", source));
  const Block top(ctx, root, "", kTopKeys);
  (void)top.text("description", "a line of text", "");
  const Block m(ctx, blockOrEmpty(top, "material"), "material", kMaterialKeys);
  scene.density = m.number("density", {"kg/m^3", kPositive, "2340 (seed 002)"}, scene.density);
  scene.youngModulus = m.number("young_modulus", {"Pa", kPositive, "26.6e9 (seed 002)"}, scene.youngModulus);
  scene.poissonRatio = m.number("poisson_ratio", {"-", Range{-1.0, 0.5, true, true}, "0.205 (seed 002)"},
                                scene.poissonRatio);
  scene.viscosityFraction = m.number("viscosity", {"- (fraction of the critical 2 h sqrt(E rho))", kUnitInterval, "0.01"},
                                     scene.viscosityFraction);
  scene.massDamping = m.number("mass_damping", {"1/s", kNonNegative, "0 for dynamics"}, scene.massDamping);
  scene.quadratic = top.choice("element", {"tet4", "tet10"}, 1) == 1;
  scene.fBar = top.flag("f_bar", true);
  scene.gravity = top.vec3("gravity", {"m/s^2", kAnyNumber, "[0, 0, -9.81]"}, scene.gravity);

  if (!top.has("bodies")) top.failMissing("bodies", "a list of bodies (shape or box), e.g. the unit and its anvil");
  const YAML::Node bodies = top.get("bodies");
  if (!bodies.IsSequence() || bodies.size() == 0)
    top.failValue("bodies", "expected a list of one or more bodies, each with 'shape' or 'box' and 'position'");
  const std::uint64_t seed = top.integer("seed", 0, "the seed of random orientations", 1);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    readBody(Block(ctx, bodies[i], indexed("bodies", i), kBodyKeys), i, seed, scene.parts);
  }
  if (top.has("rigid_bodies")) {
    const YAML::Node list = top.get("rigid_bodies");
    if (!list.IsSequence()) top.failValue("rigid_bodies", "expected a list of {shape, volume, position}, fixed rigid bodies");
    for (std::size_t i = 0; i < list.size(); ++i)
      scene.rigidBodies.push_back(readRigid(Block(ctx, list[i], indexed("rigid_bodies", i), kRigidKeys), i));
  }
  if (top.has("half_spaces")) {
    const YAML::Node list = top.get("half_spaces");
    if (!list.IsSequence()) top.failValue("half_spaces", "expected a list of {point: [x, y, z], normal: [x, y, z]}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Block h(ctx, list[i], indexed("half_spaces", i), kHalfSpaceKeys);
      DeformableHalfSpace hs;
      hs.point = h.vec3("point", {"m", kAnyNumber, "[0, 0, 0]: a point of the bounding plane"});
      const Eigen::Vector3d n = h.vec3("normal", {"-", kAnyNumber, "[0, 0, 1]: out of the solid, into free space"});
      if (!(n.norm() > 1e-12)) h.failValue("normal", "a zero vector has no direction; give e.g. [0, 0, 1]");
      hs.normal = n.normalized();
      scene.halfSpaces.push_back(hs);
    }
  }
  const Block c(ctx, blockOrEmpty(top, "contact"), "contact", kContactKeys);
  scene.friction = c.number("friction", {"-", kNonNegative, "0.6; 0 frictionless (half-spaces and rigid bodies)"}, 0.0);
  scene.contactGradient = c.number("gradient", {"Pa/m", kNonNegative, "0 = 10 E / h"}, 0.0);
  scene.contactPenalty = c.number("penalty", {"Pa", kNonNegative, "0 = 2 E"}, 0.0);
  scene.contactDamping = c.number("damping", {"-", kNonNegative, "0.2"}, 0.0);
  scene.bodyFriction = c.number("body_friction", {"-", kNonNegative, "0.6; 0 frictionless (between the bodies)"}, 0.0);
  if (scene.bodyFriction > 0.0 && scene.parts.size() < 2)
    c.failValue("body_friction", "acts between the deformable bodies, and there is one; add bodies or remove it");
  const bool moving = std::any_of(scene.rigidBodies.begin(), scene.rigidBodies.end(), [](const RigidPart& r) { return !r.fixed; });
  for (const char* key : {"rigid_penalty_modulus", "rigid_restitution"}) {
    if (!moving && c.has(key))
      c.failValue(key, "sets the contact of moving rigid bodies, and every rigid body is fixed; give a rigid body "
                       "'fixed: false' or remove it");
  }
  scene.rigidPenaltyModulus =
      c.number("rigid_penalty_modulus", {"Pa", kPositive, "1e9 (as contact.penalty_modulus in scene files)"},
               scene.rigidPenaltyModulus);
  scene.rigidRestitution = c.number("rigid_restitution", {"-", Range{0.0, 1.0, true, false}, "0.05 (seed 001)"},
                                    scene.rigidRestitution);
  if (scene.friction > 0.0 && scene.halfSpaces.empty() && scene.rigidBodies.empty())
    c.failValue("friction", "acts on the half-spaces and the rigid bodies, and there are none; add half_spaces or "
                            "rigid_bodies, or remove friction");

  if (!top.has("run")) top.failMissing("run", "the run block, at least 'duration'");
  const Block r(ctx, top.get("run"), "run", kRunKeys);
  scene.duration = r.number("duration", {"s", kPositive, "0.008 (seed 002's drop)"});
  scene.stepSafety = r.number("step_safety", {"-", kFraction, "0.9"}, scene.stepSafety);
  scene.massScaling = r.number("mass_scaling", {"-", kNonNegative, "0.01 (at most 1 % of the mass added); 0 = off"}, 0.0);
  if (scene.massScaling > 0.1)
    r.failValue("mass_scaling", "adds more than a tenth of the unit's mass; give at most 0.1 (0.01 is usual)");
  scene.framesEvery = r.number("frames_every", {"s", kNonNegative, "0.001; 0 = the first and last frames only"}, 0.0);
  scene.stressEvery = r.integer("stress_every", 1, "steps between samples of the extreme stresses", 5);
  scene.checkpointEvery = r.number("checkpoint_every", {"s of wall time", kPositive, "600"}, scene.checkpointEvery);
  const Block o(ctx, blockOrEmpty(top, "output"), "output", kOutputKeys);
  const std::filesystem::path folder = o.text("folder", "a folder name", file.stem().string() + "-out");
  scene.output = folder.is_absolute() ? folder : ctx.baseDir / folder;
  return scene;
}

} // namespace armour::io
