// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/SceneReader.hpp"

#include "core/TextFile.hpp"
#include "io/PlacementReader.hpp"
#include "io/SceneOverrides.hpp"
#include "io/SceneTables.hpp"
#include "io/ReadOrientation.hpp"
#include "io/YamlSchema.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"
#include "geometry/MeshFile.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string_view>

namespace armour::io {
namespace {

using namespace schema;

constexpr double kDeg = std::numbers::pi / 180.0;

/// Typos beyond this many bodies (e.g. count: [1000, 1000, 1000]) are refused rather than
/// allocated: a million rigid bodies is far beyond what one run of this solver is meant for.
constexpr std::size_t kMaxBodies = 1000000;
/// Height-field cells, same reasoning (1e7 cells of 1 m is a 3 km square).
constexpr std::size_t kMaxCells = 10000000;

// ---------------------------------------------------------------------------------------------
// Shared pieces
// ---------------------------------------------------------------------------------------------

/// Index of material `key` (required), listing the defined ones when unknown.
std::size_t readMaterialRef(const Block& b, const Scene& scene) {
  const std::string name = b.text("material", "the name of a material defined under 'materials'");
  const std::ptrdiff_t index = scene.findMaterial(name);
  if (index < 0) {
    std::vector<std::string_view> names;
    for (const Material& m : scene.materials) names.push_back(m.name);
    b.failValue("material", fmt::format("unknown material{}; defined materials are: {}", suggestion(name, names),
                                        fmt::join(names, ", ")));
  }
  return static_cast<std::size_t>(index);
}

/// Absolute path of a mesh file given relative to the scene folder; it must exist and have a
/// mesh extension.
std::filesystem::path readMeshPath(const Block& b, std::string_view key) {
  const std::string given = b.text(key, "a mesh file path (.stl, .obj or .vtp), relative to the scene file's folder");
  std::filesystem::path path(given);
  if (path.is_relative()) path = b.context().baseDir / path;
  path = std::filesystem::absolute(path).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    b.failValue(key, fmt::format("mesh file not found: {} (relative paths start from the scene file's folder {})",
                                 path.string(), b.context().baseDir.string()));
  try {
    (void)geometry::meshFormatFromPath(path);
  } catch (const core::InputError& e) {
    b.failValue(key, e.what());
  }
  return path;
}

std::vector<std::string_view> generatorNames() {
  std::vector<std::string_view> names;
  for (const auto& g : geometry::shapeGenerators()) names.push_back(g.name);
  return names;
}

// ---------------------------------------------------------------------------------------------
// materials
// ---------------------------------------------------------------------------------------------

const KeyList kFrictionKeys{"static", "dynamic"};

Material readMaterial(const Context& ctx, const std::string& name, const YAML::Node& node, const std::string& path) {
  const Block b(ctx, node, path, tables::materials());
  Material m;
  m.name = name;
  m.density = b.number("density");

  if (!b.has("friction")) b.failMissing("friction", "Coulomb coefficient (unit: -), e.g. friction: 0.75, or "
                                                    "friction: {static: 0.75, dynamic: 0.6}");
  const Num& friction = tables::materials().find("friction")->num;
  if (b.get("friction").IsMap()) {
    const Block f(ctx, b.get("friction"), b.path("friction"), kFrictionKeys);
    m.frictionStatic = f.number("static", friction);
    m.frictionDynamic = f.number("dynamic", friction);
    if (m.frictionDynamic > m.frictionStatic)
      fail(ctx, f.mark("dynamic"), f.path(),
           fmt::format("dynamic = {} exceeds static = {}: sliding friction cannot exceed the friction that starts "
                       "sliding; lower dynamic or raise static (unit: -)",
                       m.frictionDynamic, m.frictionStatic));
  } else {
    m.frictionStatic = m.frictionDynamic = b.number("friction", friction);
  }

  const int dissipation = b.oneOf({"restitution", "damping_ratio"}, false,
                                  "the energy lost in a collision: restitution in (0, 1], e.g. 0.05 (seed 001), or "
                                  "the contact's damping ratio");
  if (dissipation == 0) {
    // e = 0 is out: the contact law would need an infinite damping ratio to reach it.
    m.restitution = b.number("restitution");
  } else {
    m.restitution.reset();
    m.dampingRatio = b.number("damping_ratio");
  }

  m.penalty = b.number("penalty", m.penalty);
  // Outside this band the overlap or the time step becomes unreasonable for metre-sized units:
  // rho g Dn / p > 2e-3 (soft) or dt ~ sqrt(rho Dn^2 / p) below a tenth of a millisecond (stiff).
  if (m.penalty < 1e7 || m.penalty > 1e11)
    b.warnValue("penalty", "outside 1e7..1e11 Pa: expect large overlaps (soft) or a very small time step (stiff)");
  m.tangentialStiffnessRatio = b.number("tangential_stiffness_ratio", m.tangentialStiffnessRatio);
  return m;
}

void readMaterials(const Context& ctx, const YAML::Node& node, Scene& scene) {
  if (!node.IsDefined()) fail(ctx, YAML::Mark::null_mark(), "materials", "missing: define at least one material, e.g.\n"
                                                                         "materials:\n  concrete: {density: 2400, friction: 0.75, restitution: 0.05}");
  if (!node.IsMap() || node.size() == 0)
    fail(ctx, node.Mark(), "materials", "expected a mapping of material names to their properties, e.g. "
                                        "concrete: {density: 2400, friction: 0.75, restitution: 0.05}");
  std::set<std::string> seen;
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    if (!seen.insert(name).second) fail(ctx, kv.first.Mark(), child("materials", name), "material defined twice");
    scene.materials.push_back(readMaterial(ctx, name, kv.second, child("materials", name)));
  }
}

// ---------------------------------------------------------------------------------------------
// shapes
// ---------------------------------------------------------------------------------------------

const KeyList kShapeKeys{"generator", "params", "seed", "mesh"};

/// A shape mapping (named under `shapes:` or inline in a body).
ShapeSpec readShapeBlock(const Context& ctx, const YAML::Node& node, const std::string& path, const std::string& name) {
  const Block b(ctx, node, path, kShapeKeys);
  ShapeSpec s;
  s.name = name;
  const int which = b.oneOf({"generator", "mesh"}, false, "a shape-library name or a mesh file");
  if (which == 1) {
    b.refuse("params", "'params' applies to generators only; a mesh file is used as it is");
    b.refuse("seed", "'seed' applies to random generators only; a mesh file is used as it is");
    s.source = ShapeSource::MeshFile;
    s.meshFile = readMeshPath(b, "mesh");
    return s;
  }
  s.source = ShapeSource::Generator;
  s.generator = b.text("generator", "a shape-library name");
  const auto& generators = geometry::shapeGenerators();
  const auto found = std::find_if(generators.begin(), generators.end(),
                                  [&](const geometry::ShapeGenerator& g) { return g.name == s.generator; });
  if (found == generators.end()) {
    const auto names = generatorNames();
    b.failValue("generator", fmt::format("unknown generator{}; the shape library has: {}", suggestion(s.generator, names),
                                         fmt::join(names, ", ")));
  }
  if (b.has("params")) {
    KeyList paramNames;
    for (const auto& p : found->parameters) paramNames.push_back(p.name);
    const Block pb(ctx, b.get("params"), b.path("params"), paramNames);
    for (const auto& p : found->parameters) {
      if (!pb.has(p.name)) continue;
      const std::string example = fmt::format("{} (default; {})", p.defaultValue, p.description);
      s.params[p.name] = pb.number(p.name, {p.unit, Range{p.min, p.max}, example});
    }
  }
  s.seed = b.integer("seed", 0, "std::mt19937_64 seed of a random shape", ctx.seed);
  if (b.has("seed") && !found->random)
    b.warnValue("seed", fmt::format("'{}' is not a random shape: the seed has no effect", s.generator));
  return s;
}

void readShapes(const Context& ctx, const YAML::Node& node, Scene& scene) {
  if (!node.IsDefined() || node.IsNull()) return;
  if (!node.IsMap())
    fail(ctx, node.Mark(), "shapes", "expected a mapping of shape names to {generator: ..., params: ..., seed: ...} "
                                     "or {mesh: file.stl}");
  const auto generators = generatorNames();
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    const std::string path = child("shapes", name);
    if (std::find(generators.begin(), generators.end(), name) != generators.end())
      fail(ctx, kv.first.Mark(), path,
           fmt::format("'{}' is a shape-library name; give the named shape another name (e.g. {}_custom)", name, name));
    for (const ShapeSpec& s : scene.shapes)
      if (s.name == name) fail(ctx, kv.first.Mark(), path, "shape defined twice");
    scene.shapes.push_back(readShapeBlock(ctx, kv.second, path, name));
  }
}

// ---------------------------------------------------------------------------------------------
// bodies
// ---------------------------------------------------------------------------------------------

const KeyList kBodyKeys{"name",     "shape",       "volume",   "dn",       "scale",    "material",
                        "position", "orientation", "velocity", "angular_velocity", "fixed", "grid"};
const KeyList kGridKeys{"count", "spacing", "rotation_jitter_deg"};

/// The shape of a body: a named shape, a library name, or an inline mapping. Returns its index
/// in scene.shapes (adding library and inline shapes as needed).
std::size_t readBodyShape(const Block& b, std::size_t namedShapes, Scene& scene) {
  const Context& ctx = b.context();
  if (!b.has("shape"))
    b.failMissing("shape", "a shape-library name (e.g. cube, dolos, rock), a name from 'shapes', or {mesh: file.stl}");
  const YAML::Node node = b.get("shape");
  if (node.IsMap()) {
    ShapeSpec s = readShapeBlock(ctx, node, b.path("shape"), b.path("shape"));
    // Bodies that name the same mesh file share one shape (one mesh read, one mass-property pass).
    if (s.source == ShapeSource::MeshFile) {
      s.name = "mesh:" + s.meshFile.string();
      for (std::size_t i = namedShapes; i < scene.shapes.size(); ++i)
        if (scene.shapes[i].name == s.name) return i;
    }
    scene.shapes.push_back(std::move(s));
    return scene.shapes.size() - 1;
  }
  const std::string name = b.text("shape", "a shape name");
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    if (scene.shapes[i].name == name) return i;
  const auto generators = generatorNames();
  if (std::find(generators.begin(), generators.end(), name) != generators.end()) {
    ShapeSpec s;
    s.name = name;
    s.generator = name;
    s.seed = ctx.seed;
    scene.shapes.push_back(s);
    return scene.shapes.size() - 1;
  }
  std::vector<std::string_view> all = generators;
  std::vector<std::string> named;
  for (std::size_t i = 0; i < namedShapes; ++i) {
    named.push_back(scene.shapes[i].name);
    all.push_back(scene.shapes[i].name);
  }
  b.failValue("shape", fmt::format("unknown shape{}; the shape library has: {}; named shapes: {}; or give "
                                   "{{mesh: file.stl}}",
                                   suggestion(name, all), fmt::join(generators, ", "),
                                   named.empty() ? std::string("(none)") : fmt::format("{}", fmt::join(named, ", "))));
}

struct NamedAt {
  std::string path;
  YAML::Mark mark;
};

void readBodies(const Context& ctx, const YAML::Node& node, std::size_t namedShapes, Scene& scene, bool placing) {
  if (placing && (!node.IsDefined() || node.IsNull())) return; // `armour place` adds them
  if (!node.IsDefined() || node.IsNull())
    fail(ctx, YAML::Mark::null_mark(), "bodies", "missing: list at least one body, e.g.\nbodies:\n  - shape: cube\n"
                                                 "    volume: 1\n    material: concrete\n    position: [0, 0, 0.5]");
  if (!node.IsSequence() || node.size() == 0)
    fail(ctx, node.Mark(), "bodies", "expected a list of bodies (each item starts with '- ')");

  std::map<std::string, NamedAt> names;
  const auto addBody = [&](Body body, const std::string& path, const YAML::Mark& mark) {
    const auto [it, inserted] = names.emplace(body.name, NamedAt{path, mark});
    if (!inserted)
      fail(ctx, mark, fmt::format("{}.name = {}", path, body.name),
           fmt::format("duplicate body name (also {}); body names must be unique", it->second.path));
    if (scene.bodies.size() >= kMaxBodies)
      fail(ctx, mark, path, fmt::format("more than {} bodies; check the grid counts", kMaxBodies));
    scene.bodies.push_back(std::move(body));
  };

  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string path = indexed("bodies", i);
    const Block b(ctx, node[i], path, kBodyKeys);
    Body body;
    body.name = b.text("name", "a name", fmt::format("body{}", i));
    body.shape = readBodyShape(b, namedShapes, scene);
    body.material = readMaterialRef(b, scene);

    const bool mesh = scene.shapes[body.shape].source == ShapeSource::MeshFile;
    const Num volume{"m^3", kPositive, "volume: 5 (Dn = V^(1/3) = 1.71 m)"};
    const Num dn{"m", kPositive, "dn: 1.71 (volume Dn^3 = 5 m^3)"};
    if (mesh) {
      const int size = b.oneOf({"volume", "dn", "scale"}, true, "the size of a mesh: rescale it to a volume, or scale it");
      if (size == 0) body.volume = b.number("volume", volume);
      if (size == 1) body.volume = std::pow(b.number("dn", dn), 3);
      body.scale = b.number("scale", {"-", kPositive, "scale: 0.001 for a mesh drawn in mm"}, 1.0);
    } else {
      b.refuse("scale", "'scale' applies to mesh files only; size a library shape with 'volume' (m^3) or 'dn' (m)");
      const int size = b.oneOf({"volume", "dn"}, false, "the unit's size: volume in m^3 or nominal diameter Dn in m");
      body.volume = size == 0 ? b.number("volume", volume) : std::pow(b.number("dn", dn), 3);
    }

    body.position = b.vec3("position", {"m", kAnyNumber, "position: [0, 0, 1.5], the centroid [x, y, z]"});
    body.orientation = readOrientation(b, "orientation");
    body.velocity = b.vec3("velocity", {"m/s", kAnyNumber, "velocity: [0, 0, -0.5]"}, Vec3::Zero());
    body.angularVelocity = b.vec3("angular_velocity", {"rad/s", kAnyNumber, "angular_velocity: [0, 0, 1]"}, Vec3::Zero());
    body.fixed = b.flag("fixed", false);
    if (body.fixed && (b.has("velocity") || b.has("angular_velocity")))
      fail(ctx, b.mark(b.has("velocity") ? "velocity" : "angular_velocity"), path,
           "a fixed body does not move: remove 'velocity' and 'angular_velocity', or set fixed: false");

    if (!b.has("grid")) {
      addBody(body, path, b.mark());
      continue;
    }

    // A grid: the body above at `position` is cell (0, 0, 0); copies step by `spacing` along the
    // world axes, layer by layer from the bottom (iz outermost, then iy, then ix).
    const Block g(ctx, b.get("grid"), b.path("grid"), kGridKeys);
    const auto count = g.integers("count", 3, 1, "bodies along x, y, z");
    const Vec3 spacing = g.vec3("spacing", {"m", kNonNegative, "spacing: [2.5, 2.5, 2.0] between centroids along x, y, z"});
    for (int axis = 0; axis < 3; ++axis)
      if (count[static_cast<std::size_t>(axis)] > 1 && spacing[axis] <= 0.0)
        g.failValue("spacing", fmt::format("spacing along {} must be > 0 when count along it is {} (unit: m), "
                                           "or the bodies coincide",
                                           "xyz"[axis], count[static_cast<std::size_t>(axis)]));
    // In double: a product of three typos could overflow 64 bits.
    const double total = static_cast<double>(count[0]) * static_cast<double>(count[1]) * static_cast<double>(count[2]);
    if (total > static_cast<double>(kMaxBodies))
      g.failValue("count", fmt::format("{:g} bodies is more than the {} a scene may hold", total, kMaxBodies));
    const Vec3 jitter = g.vec3("rotation_jitter_deg", {"deg", Range{0.0, 180.0}, "[0, 20, 0]"}, Vec3::Zero());
    // Each grid draws from its own stream so adding a grid does not change the others.
    std::mt19937_64 rng(ctx.seed + 0x9E3779B97F4A7C15ULL * (i + 1));
    const auto symmetric = [&rng](double amplitude) {
      return amplitude * (2.0 * static_cast<double>(rng() >> 11) * 0x1.0p-53 - 1.0);
    };
    const Body base = body;
    for (std::uint64_t iz = 0; iz < count[2]; ++iz)
      for (std::uint64_t iy = 0; iy < count[1]; ++iy)
        for (std::uint64_t ix = 0; ix < count[0]; ++ix) {
          Body copy = base;
          copy.name = fmt::format("{}_{}_{}_{}", base.name, ix, iy, iz);
          copy.position = base.position + Vec3(static_cast<double>(ix) * spacing.x(), static_cast<double>(iy) * spacing.y(),
                                               static_cast<double>(iz) * spacing.z());
          if (jitter.any()) {
            const double dphi = symmetric(jitter.x()) * kDeg;
            const double dtheta = symmetric(jitter.y()) * kDeg;
            const double dpsi = symmetric(jitter.z()) * kDeg;
            copy.orientation = (base.orientation * quaternionFromTaitBryan(dphi, dtheta, dpsi)).normalized();
          }
          addBody(copy, path, b.mark());
        }
  }
}

// ---------------------------------------------------------------------------------------------
// static geometry
// ---------------------------------------------------------------------------------------------

const KeyList kPlaneKeys{"type", "name", "material", "point", "normal"};
const KeyList kSlopeKeys{"type",        "name",          "material",      "origin",         "angle_deg", "tan", "cot",
                         "crest_height", "toe_height", "toe_top_width", "toe_base_width", "roughness"};
const KeyList kRoughnessKeys{"cell_size", "max_depth", "seed", "y_range"};
const KeyList kHeightFieldKeys{"type", "name", "material", "origin", "angle_deg", "tan",
                               "cell_size", "extent", "max_depth", "seed"};
const KeyList kWallKeys{"type", "name", "material", "axis", "position", "side"};
const KeyList kStaticMeshKeys{"type", "name", "material", "file", "position", "orientation", "scale"};

/// A gradient from `angle_deg`, `tan` or (slopes only) `cot`. Slopes need exactly one; a height
/// field's base plane is level unless one is given.
double readGradient(const Block& b, bool slope) {
  const KeyList keys = slope ? KeyList{"angle_deg", "tan", "cot"} : KeyList{"angle_deg", "tan"};
  const int which = b.oneOf(keys, !slope, slope ? "the slope: angle in degrees, tan = rise/run, or cot = run/rise "
                                                  "(1:2 is cot: 2)"
                                                : "the rise of the base plane along x: angle in degrees or tan");
  if (which == 0) return std::tan(b.number("angle_deg", {"deg", Range{0.0, 90.0, slope, true}, "26.57 (1:2)"}) * kDeg);
  if (which == 1) return b.number("tan", {"-", slope ? kPositive : kNonNegative, "0.5 (1:2)"});
  if (which == 2) return 1.0 / b.number("cot", {"-", kPositive, "2 (1:2), 1.5 (1:1.5)"});
  return 0.0;
}

/// Cells of size `cell` that fit in `length`; warns about a remainder.
int fitCells(const Block& b, std::string_view key, double length, double cell) {
  const double ratio = length / cell;
  // 1e-9 relative keeps 10 / 0.1 = 99.999999999 from losing a cell to round-off.
  const double n = std::floor(ratio * (1.0 + 1e-9));
  if (n < 1.0)
    b.failValue(key, fmt::format("{} m holds no cell of {} m; make it longer or the cells smaller (unit: m)", length, cell));
  if (n > static_cast<double>(kMaxCells)) b.failValue(key, fmt::format("{} cells is too many (at most {})", n, kMaxCells));
  if (ratio - n > 1e-6)
    b.warnValue(key, fmt::format("{} m is not a whole number of {} m cells: the field covers {} m", length, cell, n * cell));
  return static_cast<int>(n);
}

void checkCellCount(const Block& b, const HeightField& f) {
  if (static_cast<std::size_t>(f.cellsX) * static_cast<std::size_t>(f.cellsY) > kMaxCells)
    fail(b.context(), b.mark(), b.path(),
         fmt::format("{} x {} cells is more than {}; use larger cells", f.cellsX, f.cellsY, kMaxCells));
}

StaticSlope readSlope(const Block& b, const Scene& scene) {
  StaticSlope s;
  s.material = readMaterialRef(b, scene);
  const auto origin = b.numbers("origin", 2, {"m", kAnyNumber, "origin: [0, 0], the slope foot (x, z)"}, std::vector<double>{0.0, 0.0});
  s.origin = Vec2(origin[0], origin[1]);
  s.tanAlpha = readGradient(b, true);
  s.crestHeight = b.number("crest_height", {"m", kPositive, "crest_height: 20, above the origin"});
  s.toeHeight = b.number("toe_height", {"m", kNonNegative, "toe_height: 1.8 (seed 001)"}, 0.0);
  s.toeTopWidth = b.number("toe_top_width", {"m", kNonNegative, "toe_top_width: 2 (seed 001)"}, 0.0);
  s.toeBaseWidth = b.number("toe_base_width", {"m", kNonNegative, "toe_base_width: 10 (seed 001)"}, s.toeTopWidth);
  if (s.toeBaseWidth < s.toeTopWidth)
    b.failValue("toe_base_width", fmt::format("must be >= toe_top_width = {} m: the toe's foot lies offshore of its "
                                              "top edge (equal widths give a vertical front face)",
                                              s.toeTopWidth));
  if (s.toeHeight == 0.0 && (b.has("toe_top_width") || b.has("toe_base_width")))
    b.warnValue(b.has("toe_top_width") ? "toe_top_width" : "toe_base_width", "toe_height is 0: there is no toe, the width is unused");

  if (b.has("roughness")) {
    const Block r(b.context(), b.get("roughness"), b.path("roughness"), kRoughnessKeys);
    HeightField f;
    f.cellSize = r.number("cell_size", {"m", kPositive, "cell_size: 1 (seed 001)"}, 1.0);
    f.maxDepth = r.number("max_depth", {"m", kNonNegative, "max_depth: 0.4, the deepest hollow h"});
    f.seed = r.integer("seed", 0, "std::mt19937_64 seed of the depths", b.context().seed);
    const auto y = r.numbers("y_range", 2, {"m", kAnyNumber, "y_range: [-10, 10], the field's extent along y"});
    if (!(y[1] > y[0])) r.failValue("y_range", "expected [y_min, y_max] with y_max > y_min (unit: m)");
    const double faceLength = s.crestHeight * std::sqrt(1.0 + s.tanAlpha * s.tanAlpha) / s.tanAlpha;
    f.origin = Vec3(s.origin.x(), y[0], s.origin.y());
    f.tanAlpha = s.tanAlpha;
    f.cellsX = fitCells(r, "cell_size", faceLength, f.cellSize);
    f.cellsY = fitCells(r, "y_range", y[1] - y[0], f.cellSize);
    checkCellCount(r, f);
    generateDepths(f);
    s.roughness = std::move(f);
  }
  return s;
}

StaticHeightField readHeightField(const Block& b, const Scene& scene) {
  StaticHeightField h;
  h.material = readMaterialRef(b, scene);
  HeightField& f = h.field;
  f.origin = b.vec3("origin", {"m", kAnyNumber, "origin: [0, -10, 0], the corner of cell (0, 0)"});
  f.tanAlpha = readGradient(b, false);
  f.cellSize = b.number("cell_size", {"m", kPositive, "cell_size: 1 (seed 001)"}, 1.0);
  const auto extent = b.numbers("extent", 2, {"m", kPositive, "extent: [20, 20], along the plane's x and along y"});
  f.maxDepth = b.number("max_depth", {"m", kNonNegative, "max_depth: 0.4, the deepest hollow h"});
  f.seed = b.integer("seed", 0, "std::mt19937_64 seed of the depths", b.context().seed);
  f.cellsX = fitCells(b, "extent", extent[0], f.cellSize);
  f.cellsY = fitCells(b, "extent", extent[1], f.cellSize);
  checkCellCount(b, f);
  generateDepths(f);
  return h;
}

void readPlane(const Block& b, const std::string& name, Scene& scene) {
  StaticPlane p;
  p.name = name;
  p.material = readMaterialRef(b, scene);
  p.point = b.vec3("point", {"m", kAnyNumber, "point: [0, 0, 0]"}, Vec3::Zero());
  const Vec3 n = b.vec3("normal", {"-", kAnyNumber, "normal: [0, 0, 1], out of the solid"}, Vec3::UnitZ());
  if (!(n.norm() > 1e-300)) b.failValue("normal", "a zero normal has no direction; e.g. [0, 0, 1] for a floor");
  p.normal = n.normalized();
  scene.statics.planes.push_back(p);
}

void readSlopeItem(const Block& b, const std::string& name, Scene& scene) {
  StaticSlope s = readSlope(b, scene);
  s.name = name;
  scene.statics.slopes.push_back(std::move(s));
}

void readHeightFieldItem(const Block& b, const std::string& name, Scene& scene) {
  StaticHeightField h = readHeightField(b, scene);
  h.name = name;
  scene.statics.heightFields.push_back(std::move(h));
}

void readWall(const Block& b, const std::string& name, Scene& scene) {
  StaticWall w;
  w.name = name;
  w.material = readMaterialRef(b, scene);
  w.axis = static_cast<int>(b.choice("axis", {"x", "y"}));
  w.position = b.number("position", {"m", kAnyNumber, "position: -10, the wall's coordinate on its axis"});
  w.atMinimum = b.choice("side", {"min", "max"}) == 0;
  scene.statics.walls.push_back(w);
}

void readStaticMesh(const Block& b, const std::string& name, Scene& scene) {
  StaticMesh m;
  m.name = name;
  m.material = readMaterialRef(b, scene);
  m.file = readMeshPath(b, "file");
  m.position = b.vec3("position", {"m", kAnyNumber, "position: [0, 0, 0]"}, Vec3::Zero());
  m.orientation = readOrientation(b, "orientation");
  m.scale = b.number("scale", {"-", kPositive, "scale: 0.001 for a mesh drawn in mm"}, 1.0);
  scene.statics.meshes.push_back(m);
}

/// The static item types: a new type is one row here, its key list above and its reader.
struct StaticType {
  std::string_view name;
  const KeyList* keys;
  void (*read)(const Block&, const std::string& name, Scene&);
};
const std::array<StaticType, 5> kStaticTypeTable{{{"plane", &kPlaneKeys, readPlane},
                                                  {"slope", &kSlopeKeys, readSlopeItem},
                                                  {"heightfield", &kHeightFieldKeys, readHeightFieldItem},
                                                  {"wall", &kWallKeys, readWall},
                                                  {"mesh", &kStaticMeshKeys, readStaticMesh}}};

void readStatic(const Context& ctx, const YAML::Node& node, Scene& scene) {
  if (!node.IsDefined() || node.IsNull()) return;
  KeyList typeNames;
  for (const StaticType& t : kStaticTypeTable) typeNames.push_back(t.name);
  if (!node.IsSequence())
    fail(ctx, node.Mark(), "static", fmt::format("expected a list of static items, each starting with '- type: ' and one "
                                                 "of {}",
                                                 fmt::join(typeNames, ", ")));
  std::map<std::string, NamedAt> names;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string path = indexed("static", i);
    const YAML::Node item = node[i];
    if (!item.IsMap() || !item["type"].IsDefined())
      fail(ctx, item.Mark(), path, fmt::format("missing key 'type': one of {}", fmt::join(typeNames, ", ")));
    // The type decides which keys are valid, so it is read before the Block checks them.
    const std::string type = item["type"].IsScalar() ? item["type"].Scalar() : "";
    const auto found = std::find_if(kStaticTypeTable.begin(), kStaticTypeTable.end(),
                                    [&](const StaticType& t) { return t.name == type; });
    if (found == kStaticTypeTable.end())
      fail(ctx, item["type"].Mark(), fmt::format("{}.type = {}", path, valueText(item["type"])),
           fmt::format("unknown static type{}; valid types are: {}", suggestion(type, typeNames),
                       fmt::join(typeNames, ", ")));
    const Block b(ctx, item, path, *found->keys);
    const std::string name = b.text("name", "a name", fmt::format("{}{}", type, i));
    const auto [it, inserted] = names.emplace(name, NamedAt{path, b.mark()});
    if (!inserted)
      fail(ctx, b.mark("name"), fmt::format("{}.name = {}", path, name),
           fmt::format("duplicate static name (also {}); names must be unique", it->second.path));
    found->read(b, name, scene);
  }
}

// ---------------------------------------------------------------------------------------------
// run settings and the whole file
// ---------------------------------------------------------------------------------------------

/// contact.constraint (the constraint solver's settings); warned about under the penalty solver.
void readConstraintSettings(const Block& c, Scene& scene) {
  const Block k(c.context(), c.has("constraint") ? c.get("constraint") : YAML::Node(), tables::contactConstraint());
  if (c.has("constraint") && scene.contact.solver != ContactSolver::Constraint)
    c.warnValue("constraint", "applies to contact.solver: constraint only; the penalty solver ignores it");
  if (scene.contact.solver == ContactSolver::Constraint && scene.contact.model == ContactModel::Fdem)
    c.failValue("solver", "the constraint solver runs on the level-set narrow phase; use contact.model: levelset, "
                          "or contact.solver: penalty with fdem");
  simulation::ConstraintSettings& s = scene.contact.constraint;
  s.timeStep = k.number("time_step", s.timeStep);
  s.substeps = static_cast<int>(k.integer("substeps", static_cast<std::uint64_t>(s.substeps)));
  s.dampingRatio = k.number("damping_ratio", s.dampingRatio);
  s.pushSpeed = k.number("push_speed", s.pushSpeed);
  s.restitutionThreshold = k.number("restitution_threshold", s.restitutionThreshold);
  s.speculativeMargin = k.number("speculative_margin", s.speculativeMargin);
  s.patchAngle = k.number("patch_angle", s.patchAngle);
  s.frictionAnchors = k.flag("friction_anchors", s.frictionAnchors);
  // Below the speculative margin, so that no contact can appear unseen while a pair's patches are reused.
  const Range kReuse{0.0, std::min(0.5 * s.speculativeMargin, 0.05), false, false};
  s.reuseDistance = k.number("reuse_distance", {"Dn", kReuse, "0.001; 0 = off; at most half the speculative margin"},
                             s.reuseDistance);
  if (!k.has("reuse_distance")) s.reuseDistance = std::min(s.reuseDistance, 0.5 * s.speculativeMargin);
}

void readRunSettings(const Block& top, Scene& scene) {
  const Context& ctx = top.context();
  scene.description = top.text("description", "text", std::string());
  if (top.has("initial_state"))
    scene.initialState = std::filesystem::absolute(
                             ctx.baseDir / top.text("initial_state", "the placed state file (.nc) armour place wrote "
                                                                    "beside the placed scene"))
                             .lexically_normal();
  scene.gravity = top.vec3("gravity", {"m/s^2", kAnyNumber, "gravity: [0, 0, -9.81]"}, scene.gravity);
  scene.duration = top.number("duration");

  if (top.has("time_step")) {
    const YAML::Node dt = top.get("time_step");
    if (dt.IsScalar() && dt.Scalar() == "auto") {
      scene.timeStep.automatic = true;
    } else {
      scene.timeStep.automatic = false;
      scene.timeStep.value = top.number("time_step", {"s", kPositive, "time_step: 1e-4, or time_step: auto"});
    }
  }
  scene.timeStep.safety = top.number("time_step_safety", scene.timeStep.safety);
  if (!scene.timeStep.automatic && top.has("time_step_safety"))
    top.warnValue("time_step_safety", "applies to time_step: auto only; the fixed time step is used as given");
  if (!scene.timeStep.automatic && scene.timeStep.value > scene.duration)
    top.warnValue("time_step", fmt::format("longer than the duration {} s: the run takes a single step", scene.duration));

  const Block c(ctx, top.has("contact") ? top.get("contact") : YAML::Node(), tables::contact());
  scene.contact.sampleSpacing = c.number("sample_spacing", scene.contact.sampleSpacing);
  scene.contact.levelSetCellsPerDn = c.number("level_set_cells_per_dn", scene.contact.levelSetCellsPerDn);
  scene.contact.maxOverlap = c.number("max_overlap", scene.contact.maxOverlap);
  scene.contact.sampleListSlack = c.number("sample_list_slack", scene.contact.sampleListSlack);
  scene.contact.model = static_cast<ContactModel>(c.choice("model", static_cast<std::size_t>(scene.contact.model)));
  scene.contact.solver = static_cast<ContactSolver>(c.choice("solver", static_cast<std::size_t>(scene.contact.solver)));
  scene.contact.dashpot = static_cast<ContactDashpot>(c.choice("dashpot", static_cast<std::size_t>(scene.contact.dashpot)));
  if (c.has("dashpot") && scene.contact.solver == ContactSolver::Constraint)
    c.warnValue("dashpot", "applies to contact.solver: penalty only; the constraint solver's contacts are soft "
                           "constraints (contact.constraint.damping_ratio)");
  readConstraintSettings(c, scene);
  const Block fd(ctx, c.has("fdem") ? c.get("fdem") : YAML::Node(), tables::contactFdem());
  if (c.has("fdem") && scene.contact.model != ContactModel::Fdem)
    c.warnValue("fdem", "applies to contact.model: fdem only; the level-set model ignores it");
  scene.contact.fdemElementsPerUnit = fd.integer("elements_per_unit", scene.contact.fdemElementsPerUnit);

  const Block o(ctx, top.has("output") ? top.get("output") : YAML::Node(), tables::output());
  const std::string folder = o.text("folder", "a folder path, relative to the scene file's folder", scene.name + "-out");
  scene.output.folder = std::filesystem::absolute(ctx.baseDir / folder).lexically_normal();
  scene.output.folderGiven = o.has("folder");
  scene.output.vtkInterval = o.number("vtk_interval", scene.output.vtkInterval);
  scene.output.seriesInterval = o.number("series_interval", scene.output.seriesInterval);
  scene.output.checkpointInterval = o.number("checkpoint_interval", scene.output.checkpointInterval);
  scene.output.checkpointWallMinutes = o.number("checkpoint_wall_minutes", scene.output.checkpointWallMinutes);
  scene.output.contacts = o.flag("contacts", scene.output.contacts);
  if (o.has("unit_loads")) {
    const YAML::Node list = o.get("unit_loads");
    if (list.IsScalar()) {
      scene.output.unitLoads.push_back(list.Scalar());
    } else if (list.IsSequence()) {
      for (const auto& item : list) {
        if (!item.IsScalar() || item.Scalar().empty())
          o.failValue("unit_loads", "expected body names or prefixes ending in '*', e.g. [unit_3, unit_7] or 'unit_*'");
        scene.output.unitLoads.push_back(item.Scalar());
      }
    } else {
      o.failValue("unit_loads", "expected body names or prefixes ending in '*', e.g. [unit_3, unit_7] or 'unit_*'");
    }
  }
  scene.output.unitLoadsInterval = o.number("unit_loads_interval", scene.output.unitLoadsInterval);
  scene.output.unitLoadsCluster = o.number("unit_loads_cluster", scene.output.unitLoadsCluster);

  const Block s(ctx, top.has("sleep") ? top.get("sleep") : YAML::Node(), tables::sleep());
  scene.sleep.enabled = s.flag("enabled", scene.sleep.enabled);
  scene.sleep.scope = static_cast<simulation::SleepScope>(s.choice("scope", static_cast<std::size_t>(scene.sleep.scope)));
  scene.sleep.linearSpeed = s.number("linear_speed", scene.sleep.linearSpeed);
  scene.sleep.angularSpeed = s.number("angular_speed", scene.sleep.angularSpeed);
  scene.sleep.time = s.number("time", scene.sleep.time);
  scene.sleep.wakeLoadFraction = s.number("wake_load_fraction", scene.sleep.wakeLoadFraction);

  const Block d(ctx, top.has("body_damping") ? top.get("body_damping") : YAML::Node(), tables::bodyDamping());
  scene.bodyDamping.linear = d.number("linear", scene.bodyDamping.linear);
  scene.bodyDamping.angular = d.number("angular", scene.bodyDamping.angular);
}

// ---------------------------------------------------------------------------------------------
// hydro: loads on units (docs/scene-file.md, "Hydrodynamic loads")
// ---------------------------------------------------------------------------------------------

const KeyList kHydroKeys{"model", "bodies", "storm", "oscillating", "shallow_wave"};
const KeyList kHydroModels{"storm", "oscillating", "shallow_wave"};
const KeyList kStormLoadKeys{"file",         "time_offset", "offset",   "update_interval", "ramp_time",
                             "between_updates", "wet_alpha", "element_size", "pressure", "variability",
                             "drag",         "added_mass", "bed",      "bed_level",       "bed_tolerance"};
const KeyList kVariabilityKeys{"enabled", "seed", "patches_per_axis"};
const KeyList kDragKeys{"enabled", "coefficient"};
const KeyList kOscillatingKeys{"amplitude", "period", "wave_number", "z_min", "z_swl", "z_max", "waves"};
const KeyList kShallowWaveKeys{"amplitude", "angular_frequency", "angle_deg", "tan", "cot", "toe_x", "depth_at_toe",
                               "ray_spacing", "exposure_interval"};

/// hydro.storm.bed, bed_level, bed_tolerance: what lies under units resting on the bed
/// (docs/foam-bridge.md, "A unit on an impermeable bed"). The level defaults to the scene's one
/// horizontal static plane.
void readBed(const Block& s, const Scene& scene, hydro::BedSettings& bed) {
  bed.kind = static_cast<hydro::BedKind>(s.choice("bed", {"porous", "impermeable"}, 0));
  if (bed.kind == hydro::BedKind::Porous) {
    const std::string why = "used only with bed: impermeable (a porous bed loads every surface element); remove it or "
                            "set hydro.storm.bed: impermeable";
    s.refuse("bed_level", why);
    s.refuse("bed_tolerance", why);
    return;
  }
  bed.toleranceDn = s.number("bed_tolerance", {"Dn", kUnitInterval, "0.01 (elements within 0.01 Dn of the bed)"},
                             bed.toleranceDn);
  if (s.has("bed_level")) {
    bed.level = s.number("bed_level", {"m", kAnyNumber, "0: the z of the bed the units rest on"});
    return;
  }
  std::vector<const StaticPlane*> level;
  for (const StaticPlane& p : scene.statics.planes) {
    if (p.normal.z() > 1.0 - 1e-9) level.push_back(&p);
  }
  if (level.size() != 1)
    s.failMissing("bed_level", fmt::format("the z of the impermeable bed (m); it is taken from the scene's horizontal "
                                           "static plane when there is exactly one, and the scene has {}",
                                           level.size()));
  bed.level = level.front()->point.z();
}

void readHydro(const Block& top, Scene& scene) {
  if (!top.has("hydro")) return;
  const Context& ctx = top.context();
  const Block h(ctx, top.get("hydro"), "hydro", kHydroKeys);
  hydro::HydroSettings& out = scene.hydro;
  out.enabled = true;
  out.model = static_cast<hydro::HydroModel>(h.choice("model", kHydroModels, 0));
  out.bodies = h.text("bodies", "'all' or a body-name prefix such as unit_", std::string("all"));
  const std::string_view wanted = kHydroModels[static_cast<std::size_t>(out.model)];
  for (std::string_view other : kHydroModels) {
    if (other != wanted)
      h.refuse(other, fmt::format("settings of model '{}', but hydro.model is '{}'; remove the block or change the "
                                  "model", other, wanted));
  }
  if (out.model == hydro::HydroModel::Storm) {
    if (!h.has("storm")) h.failMissing("storm", "the storm block, e.g. storm: {file: storm.nc}");
    const Block s(ctx, h.get("storm"), "hydro.storm", kStormLoadKeys);
    hydro::StormLoadSettings& st = out.storm;
    st.file = std::filesystem::absolute(ctx.baseDir / s.text("file", "the storm file (netCDF), relative to the scene "
                                                                    "file's folder"))
                  .lexically_normal()
                  .string();
    st.timeOffset = s.number("time_offset", {"s", kNonNegative, "0: storm time at simulation time 0"}, st.timeOffset);
    const auto offset = s.numbers("offset", 2, {"m", kAnyNumber, "offset: [104, 3], the storm file's (x, z) of the "
                                                              "scene's origin"},
                                  std::vector<double>{st.offsetX, st.offsetZ});
    st.offsetX = offset[0];
    st.offsetZ = offset[1];
    st.updateInterval = s.number("update_interval", {"s", kPositive, "0.1 (seed 000)"}, st.updateInterval);
    st.rampTime = s.number("ramp_time", {"s", kNonNegative, "2 (the loads rise from zero over the first 2 s)"},
                           st.rampTime);
    st.betweenUpdates = static_cast<hydro::BetweenUpdates>(s.choice("between_updates", {"hold", "interpolate"}, 0));
    st.wetAlpha = s.number("wet_alpha", {"-", Range{0.0, 1.0, true, true}, "0.5"}, st.wetAlpha);
    st.elementSizePerDn = s.number("element_size", {"Dn", Range{0.0, 1.0, true, false}, "0.1 (4640 elements on a "
                                                                                         "Core-Loc)"},
                                   st.elementSizePerDn);
    st.pressure = s.flag("pressure", st.pressure);
    readBed(s, scene, st.bed);
    const Block v(ctx, s.has("variability") ? s.get("variability") : YAML::Node(), "hydro.storm.variability",
                  kVariabilityKeys);
    st.variability.enabled = v.flag("enabled", st.variability.enabled);
    st.variability.seed = v.integer("seed", 0, "seed of the variability draws", scene.seed);
    st.variability.patchesPerAxis = static_cast<int>(
        v.integer("patches_per_axis", 1, "patches per body axis, each with its own deviation", 2));
    if (st.variability.patchesPerAxis > 8) v.failValue("patches_per_axis", "must be <= 8 (512 patches per unit)");
    const Block d(ctx, s.has("drag") ? s.get("drag") : YAML::Node(), "hydro.storm.drag", kDragKeys);
    st.drag.enabled = d.flag("enabled", st.drag.enabled);
    st.drag.coefficient = d.number("coefficient", {"-", kNonNegative, "1.0 (C_d)"}, st.drag.coefficient);
    const Block a(ctx, s.has("added_mass") ? s.get("added_mass") : YAML::Node(), "hydro.storm.added_mass", kDragKeys);
    st.addedMass.enabled = a.flag("enabled", st.addedMass.enabled);
    st.addedMass.coefficient = a.number("coefficient", {"-", kNonNegative, "1.0 (C_a)"}, st.addedMass.coefficient);
    // The equivalent force F_x reads the contact forces of the same evaluation, which the
    // constraint solver only knows after its solve: not yet supported there.
    if (st.addedMass.enabled && scene.contact.solver == ContactSolver::Constraint)
      a.failValue("enabled", "added mass is not yet supported with contact.solver: constraint; switch it off or use "
                             "contact.solver: penalty");
  } else if (out.model == hydro::HydroModel::Oscillating) {
    if (!h.has("oscillating")) h.failMissing("oscillating", "the force model's block (seed 001 eq. 1-2)");
    const Block o(ctx, h.get("oscillating"), "hydro.oscillating", kOscillatingKeys);
    hydro::OscillatingForceSettings& os = out.oscillating;
    os.amplitude = o.number("amplitude", {"N", kNonNegative, "5e4 (F0)"});
    os.period = o.number("period", {"s", kPositive, "10"});
    os.waveNumber = o.number("wave_number", {"1/m", kAnyNumber, "0.06 (2 pi / wave length)"}, 0.0);
    os.zMin = o.number("z_min", {"m", kAnyNumber, "5.658 (seed 001)"});
    os.zSwl = o.number("z_swl", {"m", kAnyNumber, "15.568 (seed 001)"});
    os.zMax = o.number("z_max", {"m", kAnyNumber, "23.568 (seed 001)"});
    os.waves = o.number("waves", {"-", kNonNegative, "10; 0 = the whole run"}, 0.0);
    if (!(os.zMin < os.zSwl && os.zSwl < os.zMax))
      o.failValue("z_swl", fmt::format("needs z_min < z_swl < z_max; got {} < {} < {} (unit: m)", os.zMin, os.zSwl,
                                       os.zMax));
  } else {
    if (!h.has("shallow_wave")) h.failMissing("shallow_wave", "the force model's block (seed 003 eq. 2)");
    const Block w(ctx, h.get("shallow_wave"), "hydro.shallow_wave", kShallowWaveKeys);
    hydro::ShallowWaveForceSettings& sw = out.shallowWave;
    sw.amplitude = w.number("amplitude", {"N", kNonNegative, "2e4 (F)"});
    sw.angularFrequency = w.number("angular_frequency", {"rad/s", kPositive, "3.1416 (seed 003: 1/2 Hz)"},
                                   sw.angularFrequency);
    sw.slopeAngle = std::atan(readGradient(w, true));
    sw.toeX = w.number("toe_x", {"m", kAnyNumber, "0: x of the slope's toe"});
    sw.depthAtToe = w.number("depth_at_toe", {"m", kPositive, "12: still water depth d0 above the toe"});
    sw.raySpacing = w.number("ray_spacing", {"m", kNonNegative, "0.25; 0 = Dn / 4 of the smallest unit"}, sw.raySpacing);
    sw.exposureInterval = w.number("exposure_interval", {"s", kPositive, "0.5"}, sw.exposureInterval);
  }
}


} // namespace

Scene parseScene(const std::string& yaml, const std::filesystem::path& baseDir, const std::string& sourceName,
                 const std::vector<std::string>& overrides) {
  Scene scene;
  scene.sourceName = sourceName;
  scene.name = std::filesystem::path(sourceName).stem().string();
  scene.baseDir = std::filesystem::absolute(baseDir).lexically_normal();
  Context ctx{sourceName, scene.baseDir, 1, &scene.warnings};

  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw core::InputError(fmt::format("{}:{}:{}: YAML syntax error: {} (check the indentation, colons and brackets "
                                       "on this line or the one before)",
                                       sourceName, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  applyOverrides(root, overrides);
  if (!root.IsDefined() || root.IsNull())
    throw core::InputError(fmt::format("{}: the scene is empty; it needs at least 'materials', 'bodies' and 'duration' "
                                       "(docs/scene-file.md has an example)",
                                       sourceName));
  const Block top(ctx, root, "", tables::top());
  scene.seed = top.integer("seed", scene.seed);
  ctx.seed = scene.seed;

  readRunSettings(top, scene);
  readMaterials(ctx, top.get("materials"), scene);
  readShapes(ctx, top.get("shapes"), scene);
  const std::size_t namedShapes = scene.shapes.size();
  readBodies(ctx, top.get("bodies"), namedShapes, scene, top.has("placement"));
  readStatic(ctx, top.get("static"), scene);
  readHydro(top, scene);
  detail::readPlacement(top, scene);
  // Unit names are checked here when the bodies are given; a placement scene's come with `armour place`.
  if (!top.has("placement") && !scene.output.unitLoads.empty()) {
    if (const UnitLoadSelection units = selectUnitLoadBodies(scene); !units.problem.empty())
      Block(ctx, top.get("output"), tables::output()).failValue("unit_loads", units.problem);
  }

  const bool anyFixed = std::any_of(scene.bodies.begin(), scene.bodies.end(), [](const Body& b) { return b.fixed; });
  if (scene.statics.size() == 0 && !anyFixed && scene.gravity.norm() > 0.0)
    warn(ctx, YAML::Mark::null_mark(), "static", "no static geometry and no fixed body: every body falls freely");
  return scene;
}

Scene readScene(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  const std::string text = core::readTextFile(path, "the scene file");
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  return parseScene(text, folder, path.string(), overrides);
}

} // namespace armour::io
