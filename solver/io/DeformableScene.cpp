// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/DeformableScene.hpp"

#include "io/ReadOrientation.hpp"
#include "io/YamlSchema.hpp"

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace armour::io {
namespace {

using namespace schema;

const KeyList kTopKeys{"description", "material", "element", "f_bar", "gravity", "bodies", "half_spaces",
                       "contact",     "run",      "output"};
const KeyList kMaterialKeys{"density", "young_modulus", "poisson_ratio", "viscosity", "mass_damping"};
const KeyList kBodyKeys{"name", "shape", "volume", "tets", "box", "cells", "position", "orientation", "velocity"};
const KeyList kHalfSpaceKeys{"point", "normal"};
const KeyList kContactKeys{"friction", "gradient", "penalty", "damping"};
const KeyList kRunKeys{"duration", "step_safety", "frames_every", "stress_every", "checkpoint_every"};
const KeyList kOutputKeys{"folder"};

/// Largest tetrahedra asked of one shape: beyond this a size was probably given in the wrong unit.
constexpr std::uint64_t kMaxTets = 2'000'000;

DeformablePart readPart(const Block& b, std::size_t index) {
  DeformablePart p;
  p.name = b.text("name", "a name for the body, used in messages and outputs", fmt::format("body_{}", index));
  const int kind = b.oneOf({"shape", "box"}, false, "a library shape meshed by gmsh, or a box of Kuhn cells");
  if (kind == 0) {
    p.shape = b.text("shape", "a shape of the library (armour shape list), e.g. vcross");
    std::vector<std::string_view> valid;
    for (const auto& g : geometry::shapeGenerators()) valid.push_back(g.name);
    if (std::find(valid.begin(), valid.end(), p.shape) == valid.end()) {
      b.failValue("shape", fmt::format("unknown shape{}; the shapes are: {}", suggestion(p.shape, valid),
                                       fmt::join(valid, ", ")));
    }
    p.volume = b.number("volume", {"m^3", kPositive, "14 (seed 002's Vcross)"});
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
  }
  p.position = b.vec3("position", {"m", kAnyNumber, "[0, 0, 2]: the shape's centroid or the box's centre"});
  p.orientation = readOrientation(b, "orientation");
  p.velocity = b.vec3("velocity", {"m/s", kAnyNumber, "[0, 0, -0.5] (seed 002's drop)"}, Eigen::Vector3d::Zero());
  return p;
}

/// The block under `key`, or an empty node (all defaults) when it is absent.
YAML::Node blockOrEmpty(const Block& parent, std::string_view key) {
  return parent.has(key) ? parent.get(key) : YAML::Node();
}

} // namespace

DeformableScene readDeformableScene(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw core::InputError(fmt::format("{}: cannot open the deformable scene; check the path", file.string()));
  std::stringstream text;
  text << in.rdbuf();
  const std::string source = file.string();
  DeformableScene scene;
  scene.file = file;
  Context ctx{source, std::filesystem::absolute(file).parent_path(), 1, nullptr};
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
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
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    scene.parts.push_back(readPart(Block(ctx, bodies[i], indexed("bodies", i), kBodyKeys), i));
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
  scene.friction = c.number("friction", {"-", kNonNegative, "0.6; 0 frictionless (the half-spaces only)"}, 0.0);
  scene.contactGradient = c.number("gradient", {"Pa/m", kNonNegative, "0 = 10 E / h"}, 0.0);
  scene.contactPenalty = c.number("penalty", {"Pa", kNonNegative, "0 = 2 E"}, 0.0);
  scene.contactDamping = c.number("damping", {"-", kNonNegative, "0.2"}, 0.0);
  if (scene.friction > 0.0 && scene.halfSpaces.empty())
    c.failValue("friction", "acts on the half-spaces, and there are none; add half_spaces or remove friction");

  if (!top.has("run")) top.failMissing("run", "the run block, at least 'duration'");
  const Block r(ctx, top.get("run"), "run", kRunKeys);
  scene.duration = r.number("duration", {"s", kPositive, "0.008 (seed 002's drop)"});
  scene.stepSafety = r.number("step_safety", {"-", kFraction, "0.9"}, scene.stepSafety);
  scene.framesEvery = r.number("frames_every", {"s", kNonNegative, "0.001; 0 = the first and last frames only"}, 0.0);
  scene.stressEvery = r.integer("stress_every", 1, "steps between samples of the extreme stresses", 5);
  scene.checkpointEvery = r.number("checkpoint_every", {"s of wall time", kPositive, "600"}, scene.checkpointEvery);
  const Block o(ctx, blockOrEmpty(top, "output"), "output", kOutputKeys);
  const std::filesystem::path folder = o.text("folder", "a folder name", file.stem().string() + "-out");
  scene.output = folder.is_absolute() ? folder : ctx.baseDir / folder;
  return scene;
}

} // namespace armour::io
