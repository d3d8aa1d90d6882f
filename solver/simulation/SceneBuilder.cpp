// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/SceneBuilder.hpp"

#include "contact/ContactLaw.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"
#include "geometry/MeshFile.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace armour::simulation {
namespace {

using Vec2 = Eigen::Vector2d;

/// A prism: the top points (world) and the same points dropped to z = base.
ConvexPiece prism(std::string name, const std::vector<Vec3>& top, double base, MaterialId material) {
  ConvexPiece piece{std::move(name), {}, material};
  piece.corners.reserve(2 * top.size());
  for (const Vec3& p : top) {
    piece.corners.push_back(p);
  }
  for (const Vec3& p : top) {
    piece.corners.emplace_back(p.x(), p.y(), base);
  }
  return piece;
}

/// Split an (x, z) polyline (x non-decreasing) into maximal runs over which it is concave (its
/// direction turns clockwise or goes straight), and make each run's region down to `base`,
/// extruded over y in [y0, y1], a convex prism. A vertical segment (a vertical toe face) has the
/// steepest direction, so it starts a run rather than ending one.
void addProfilePieces(const std::vector<Vec2>& points, double y0, double y1, double base, const std::string& name,
                      MaterialId material, std::vector<ConvexPiece>& out) {
  if (points.size() < 2 || !(y1 > y0)) {
    return;
  }
  const auto angle = [&](std::size_t i) {
    const Vec2 d = points[i + 1] - points[i];
    return std::atan2(d.y(), d.x());
  };
  std::size_t start = 0;
  int part = 0;
  const auto emit = [&](std::size_t first, std::size_t last) {
    if (!(points[last].x() > points[first].x())) {
      return; // no width: nothing to extrude
    }
    std::vector<Vec3> top;
    for (std::size_t i = first; i <= last; ++i) {
      top.emplace_back(points[i].x(), y0, points[i].y());
      top.emplace_back(points[i].x(), y1, points[i].y());
    }
    out.push_back(prism(fmt::format("{}/{}", name, part++), top, base, material));
  };
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    // A turn upwards (counter-clockwise) makes a valley: the region below is not convex there.
    if (angle(i) > angle(i - 1) + 1e-12) {
      emit(start, i);
      start = i;
    }
  }
  emit(start, points.size() - 1);
}

/// The cells of a height field as convex prisms down to `base`: one per cell edge. The two
/// triangles that share an interior edge (one in each cell, each from the edge to its cell's
/// lowered centre) form a ridge, so the region below them is convex; border edges have one.
void addCellPieces(const io::HeightField& f, double base, const std::string& name, MaterialId material,
                   std::vector<ConvexPiece>& out) {
  // Edges along y (constant ix), between cells (ix - 1, iy) and (ix, iy).
  for (int iy = 0; iy < f.cellsY; ++iy) {
    for (int ix = 0; ix <= f.cellsX; ++ix) {
      std::vector<Vec3> top{f.corner(ix, iy)};
      if (ix < f.cellsX) top.push_back(f.lowCentre(ix, iy));
      top.push_back(f.corner(ix, iy + 1));
      if (ix > 0) top.push_back(f.lowCentre(ix - 1, iy));
      out.push_back(prism(fmt::format("{}/edge-y({},{})", name, ix, iy), top, base, material));
    }
  }
  // Edges along x (constant iy), between cells (ix, iy - 1) and (ix, iy).
  for (int iy = 0; iy <= f.cellsY; ++iy) {
    for (int ix = 0; ix < f.cellsX; ++ix) {
      std::vector<Vec3> top{f.corner(ix, iy)};
      if (iy > 0) top.push_back(f.lowCentre(ix, iy - 1));
      top.push_back(f.corner(ix + 1, iy));
      if (iy < f.cellsY) top.push_back(f.lowCentre(ix, iy));
      out.push_back(prism(fmt::format("{}/edge-x({},{})", name, ix, iy), top, base, material));
    }
  }
}

double lowestPoint(const io::HeightField& f) {
  double z = std::numeric_limits<double>::infinity();
  for (int iy = 0; iy < f.cellsY; ++iy) {
    for (int ix = 0; ix < f.cellsX; ++ix) {
      z = std::min(z, f.lowCentre(ix, iy).z());
    }
  }
  for (int iy = 0; iy <= f.cellsY; iy += f.cellsY) {
    for (int ix = 0; ix <= f.cellsX; ix += f.cellsX) {
      z = std::min(z, f.corner(ix, iy).z());
    }
  }
  return z;
}

/// "<scene>: <item>: <message>", without repeating the item when the message starts with it
/// (World's own messages name the body or material).
[[noreturn]] void failItem(const io::Scene& scene, const std::string& item, const std::exception& e) {
  const std::string message = e.what();
  if (message.rfind(item, 0) == 0) {
    throw core::InputError(scene.sourceName + ": " + message);
  }
  throw core::InputError(scene.sourceName + ": " + item + ": " + message);
}

std::string shapeItem(const io::ShapeSpec& spec) {
  if (spec.source == io::ShapeSource::MeshFile) {
    return fmt::format("shape '{}' (mesh {})", spec.name, spec.meshFile.string());
  }
  return fmt::format("shape '{}' (generator {})", spec.name, spec.generator);
}

} // namespace

// The closed surface of a shape in its natural frame: a generator at V = 1 m^3, or a mesh file
// at its own size, validated (orientation repaired where unambiguous).
geometry::TriangleMesh shapeMesh(const io::ShapeSpec& spec) {
  if (spec.source == io::ShapeSource::Generator) {
    geometry::ShapeRequest request;
    request.volume = 1.0;
    request.params = spec.params;
    request.seed = spec.seed;
    return geometry::makeShape(spec.generator, request);
  }
  return geometry::readValidMesh(spec.meshFile, "scene");
}

WorldSettings worldSettings(const io::Scene& scene) {
  WorldSettings w;
  w.gravity = scene.gravity;
  w.timeStep = scene.timeStep.automatic ? 0.0 : scene.timeStep.value;
  w.timeStepSafety = scene.timeStep.safety;
  w.levelSet.cellsPerDn = scene.contact.levelSetCellsPerDn;
  w.samples.spacingOverDn = scene.contact.sampleSpacing;
  w.maxOverlapPerDn = scene.contact.maxOverlap;
  w.sampleListSlackPerDn = scene.contact.sampleListSlack;
  w.contactModel = scene.contact.model == io::ContactModel::Fdem ? ContactModel::Fdem : ContactModel::LevelSet;
  w.fdem.elementsPerUnit = scene.contact.fdemElementsPerUnit;
  w.solver = scene.contact.solver == io::ContactSolver::Constraint ? ContactSolverKind::Constraint
                                                                   : ContactSolverKind::Penalty;
  w.dashpot = scene.contact.dashpot == io::ContactDashpot::Implicit ? DashpotIntegration::Implicit
                                                                     : DashpotIntegration::Explicit;
  w.constraint = scene.contact.constraint;
  w.sleep = scene.sleep;
  w.bodyDamping = scene.bodyDamping;
  w.recordContacts = scene.output.contacts;
  return w;
}

Material worldMaterial(const io::Material& in, const std::string& where) {
  Material m;
  m.name = in.name;
  m.density = in.density;
  m.frictionStatic = in.frictionStatic;
  m.frictionDynamic = in.frictionDynamic;
  m.penaltyModulus = in.penalty;
  m.tangentialStiffnessRatio = in.tangentialStiffnessRatio;
  if (in.restitution) {
    m.restitution = *in.restitution;
  } else {
    const double zeta = in.dampingRatio.value_or(0.0);
    // World turns the restitution back into zeta by bisection on [0, 1000] (ContactLaw.cpp).
    if (!(zeta >= 0.0 && zeta <= 1.0e3)) {
      core::failInput(where, "damping_ratio = {}: the contact law takes 0 to 1000 (a restitution of about "
                             "2.5e-7 at 1000); give a smaller damping ratio or a restitution",
                      zeta);
    }
    m.restitution = contact::restitutionOfClampedDashpot(zeta);
  }
  return m;
}

StaticDomain staticDomain(const io::Scene& scene, const std::vector<double>& bodyRadius) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double lo[2] = {inf, inf}, hi[2] = {-inf, -inf};
  const auto include = [&](int axis, double value) {
    lo[axis] = std::min(lo[axis], value);
    hi[axis] = std::max(hi[axis], value);
  };
  double largest = 0.0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const double r = i < bodyRadius.size() ? bodyRadius[i] : 0.0;
    largest = std::max(largest, r);
    for (int a = 0; a < 2; ++a) {
      include(a, scene.bodies[i].position[a] - r);
      include(a, scene.bodies[i].position[a] + r);
    }
  }
  double cell = 0.0;
  const auto includeField = [&](const io::HeightField& f) {
    for (int a = 0; a < 2; ++a) {
      include(a, f.corner(0, 0)[a]);
      include(a, f.corner(f.cellsX, f.cellsY)[a]);
    }
    cell = std::max(cell, f.cellSize);
  };
  for (const io::StaticSlope& s : scene.statics.slopes) {
    const std::vector<Vec2> profile = io::slopeProfile(s);
    include(0, profile.front().x());
    include(0, profile.back().x());
    if (s.roughness) includeField(*s.roughness);
  }
  for (const io::StaticHeightField& h : scene.statics.heightFields) includeField(h.field);
  for (const io::StaticMesh& m : scene.statics.meshes) {
    include(0, m.position.x());
    include(1, m.position.y());
  }
  for (const io::StaticWall& w : scene.statics.walls) include(w.axis, w.position);
  for (int a = 0; a < 2; ++a) {
    if (!std::isfinite(lo[a])) lo[a] = hi[a] = 0.0;
  }
  // Room for a body to roll a couple of diameters beyond the outermost one before it meets an edge.
  const double margin = std::max(1.0, 4.0 * largest);
  StaticDomain d;
  d.xMin = lo[0] - margin;
  d.xMax = hi[0] + margin;
  d.yMin = lo[1] - margin;
  d.yMax = hi[1] + margin;
  // "A few cell sizes" and several body sizes below the surface: far beyond any overlap the guard
  // rail lets through (a quarter of Dn by default).
  d.depth = std::max({1.0, 4.0 * largest, 2.0 * cell});
  if (!scene.statics.slopes.empty()) d.edge[1] = d.edge[2] = d.edge[3] = true;
  if (!scene.statics.heightFields.empty()) d.edge[0] = d.edge[1] = d.edge[2] = d.edge[3] = true;
  return d;
}

StaticPlane slopeSeabed(const io::StaticSlope& slope, MaterialId material) {
  const std::vector<Vec2> profile = io::slopeProfile(slope);
  StaticPlane p;
  p.name = slope.name + "/seabed";
  p.point = Vec3(profile.front().x(), 0.0, profile.front().y());
  p.normal = Vec3::UnitZ();
  p.material = material;
  return p;
}

std::vector<ConvexPiece> slopePieces(const io::StaticSlope& slope, const StaticDomain& domain, MaterialId material) {
  const std::vector<Vec2> profile = io::slopeProfile(slope);
  const Vec2 crest = profile.back();
  const double base = profile.front().y() - domain.depth;
  std::vector<ConvexPiece> out;
  // The toe (offshore of the origin) over the whole y extent; then the face, whose level crest
  // continues onshore to the domain's end.
  std::vector<Vec2> toe, face;
  for (const Vec2& p : profile) {
    if (p.x() <= slope.origin.x()) toe.push_back(p);
    if (p.x() >= slope.origin.x()) face.push_back(p);
  }
  if (domain.xMax > crest.x()) face.emplace_back(domain.xMax, crest.y());
  addProfilePieces(toe, domain.yMin, domain.yMax, base, slope.name + "/toe", material, out);
  if (!slope.roughness) {
    addProfilePieces(face, domain.yMin, domain.yMax, base, slope.name + "/face", material, out);
    return out;
  }
  // Rough face: smooth south and north of the field's y band; inside it the cells, and the
  // smooth strip above the cells (a remainder shorter than a cell) with the crest.
  const io::HeightField& f = *slope.roughness;
  const double fy0 = f.corner(0, 0).y();
  const double fy1 = f.corner(0, f.cellsY).y();
  addProfilePieces(face, domain.yMin, fy0, base, slope.name + "/face-south", material, out);
  addProfilePieces(face, fy1, domain.yMax, base, slope.name + "/face-north", material, out);
  const Vec3 top = f.corner(f.cellsX, 0);
  std::vector<Vec2> upper{Vec2(top.x(), top.z())};
  if (crest.x() > top.x() + 1e-9 * std::max(1.0, std::abs(crest.x()))) upper.push_back(crest);
  if (domain.xMax > upper.back().x()) upper.emplace_back(domain.xMax, crest.y());
  addProfilePieces(upper, fy0, fy1, base, slope.name + "/crest", material, out);
  addCellPieces(f, base, slope.name, material, out);
  return out;
}

std::vector<ConvexPiece> heightFieldPieces(const io::StaticHeightField& item, const StaticDomain& domain,
                                           MaterialId material) {
  const io::HeightField& f = item.field;
  const auto planeZ = [&](double x) { return f.origin.z() + f.tanAlpha * (x - f.origin.x()); };
  const double base = std::min({lowestPoint(f), planeZ(domain.xMin), planeZ(domain.xMax)}) - domain.depth;
  std::vector<ConvexPiece> out;
  addCellPieces(f, base, item.name, material, out);
  // The plain base plane around the field, as four prisms within the domain.
  const double fx0 = f.corner(0, 0).x(), fx1 = f.corner(f.cellsX, 0).x();
  const double fy0 = f.corner(0, 0).y(), fy1 = f.corner(0, f.cellsY).y();
  const auto rect = [&](const char* part, double x0, double x1, double y0, double y1) {
    if (!(x1 > x0) || !(y1 > y0)) return;
    const std::vector<Vec3> top{{x0, y0, planeZ(x0)}, {x1, y0, planeZ(x1)}, {x1, y1, planeZ(x1)}, {x0, y1, planeZ(x0)}};
    out.push_back(prism(item.name + "/" + part, top, base, material));
  };
  rect("offshore", domain.xMin, fx0, domain.yMin, domain.yMax);
  rect("onshore", fx1, domain.xMax, domain.yMin, domain.yMax);
  rect("south", fx0, fx1, domain.yMin, fy0);
  rect("north", fx0, fx1, fy1, domain.yMax);
  return out;
}

namespace {

/// A warning of the build: logged and kept in the BuiltScene.
void warnBuild(BuiltScene& b, const std::string& text) {
  core::logger("scene")->warn("{}", text);
  b.warnings.push_back(text);
}

/// One World shape per scene shape that a body uses (its bodies share the level set and samples).
void buildShapes(const io::Scene& scene, BuiltScene& built) {
  auto log = core::logger("scene");
  World& world = *built.world;
  std::vector<bool> used(scene.shapes.size(), false);
  for (const io::Body& b : scene.bodies) used[b.shape] = true;
  built.shapeOfSceneShape.assign(scene.shapes.size(), std::nullopt);
  for (std::size_t i = 0; i < scene.shapes.size(); ++i) {
    const io::ShapeSpec& spec = scene.shapes[i];
    if (!used[i]) {
      // The units of a placement use it once `armour place` adds them.
      if (scene.placement.enabled && spec.name == scene.placement.shape) continue;
      warnBuild(built, fmt::format("{}: {} is used by no body; not built", scene.sourceName, shapeItem(spec)));
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    try {
      built.shapeOfSceneShape[i] = world.addShape(spec.name, shapeMesh(spec));
    } catch (const core::InputError& e) {
      failItem(scene, shapeItem(spec), e);
    }
    const ShapeModel& model = world.shape(*built.shapeOfSceneShape[i]);
    log->info("{}: {} triangles, {} surface samples, level set {}x{}x{} nodes ({:.2f} s)", shapeItem(spec),
              model.mesh.triangleCount(), model.samples->size(), model.levelSet->nodeCounts()[0],
              model.levelSet->nodeCounts()[1], model.levelSet->nodeCounts()[2],
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (model.fdem) {
      log->info("{}: fdem contact elements: {} of {} tetrahedra within reach of the surface, {} contactor faces, "
                "potential peaks {:.3g} Dn below the surface (median)",
                shapeItem(spec), model.fdem->elements().size(), model.fdem->totalTetCount(), model.fdem->faces().size(),
                model.fdem->reach() / std::cbrt(model.unitMass.volume));
    }
  }
}

/// The scene's bodies; returns each body's radius (unit: m) for the static domain.
std::vector<double> buildBodies(const io::Scene& scene, BuiltScene& built) {
  World& world = *built.world;
  std::vector<double> bodyRadius;
  bodyRadius.reserve(scene.bodies.size());
  for (const io::Body& b : scene.bodies) {
    const std::string item = "body '" + b.name + "'";
    const ShapeId shape = *built.shapeOfSceneShape[b.shape];
    const ShapeModel& model = world.shape(shape);
    BodySpec spec;
    spec.name = b.name;
    spec.shape = shape;
    // Uniform scale from the shape as built (V = 1 m^3 for generators, the file's own volume for
    // meshes) to the body's volume.
    spec.scale = b.volume ? std::cbrt(*b.volume / model.unitMass.volume) : b.scale;
    spec.material = static_cast<MaterialId>(b.material);
    spec.fixed = b.fixed;
    spec.position = b.position;
    spec.orientation = b.orientation;
    spec.velocity = b.velocity;
    spec.angularVelocity = b.angularVelocity;
    try {
      built.bodyIndexOfSceneBody.push_back(world.addBody(spec));
    } catch (const core::InputError& e) {
      failItem(scene, item, e);
    }
    bodyRadius.push_back(model.radius * spec.scale);
  }
  return bodyRadius;
}

/// The static planes, walls, slopes and height fields, over the static domain.
void buildStatics(const io::Scene& scene, BuiltScene& built, const std::vector<double>& bodyRadius) {
  World& world = *built.world;
  built.domain = staticDomain(scene, bodyRadius);
  const StaticDomain& domain = built.domain;
  const auto addPlane = [&](const StaticPlane& p, const std::string& item) {
    try {
      world.addPlane(p);
    } catch (const core::InputError& e) {
      failItem(scene, item, e);
    }
    built.planes.push_back(p);
  };
  for (const io::StaticPlane& p : scene.statics.planes) {
    addPlane({p.name, p.point, p.normal, static_cast<MaterialId>(p.material)}, "plane '" + p.name + "'");
  }
  for (const io::StaticWall& w : scene.statics.walls) {
    Vec3 point = Vec3::Zero();
    point[w.axis] = w.position;
    addPlane({w.name, point, w.normal(), static_cast<MaterialId>(w.material)}, "wall '" + w.name + "'");
  }
  const auto hasWalls = [&](int axis) {
    bool lo = false, hi = false;
    for (const io::StaticWall& w : scene.statics.walls) {
      if (w.axis == axis) (w.atMinimum ? lo : hi) = true;
    }
    return lo && hi;
  };
  for (const io::StaticSlope& s : scene.statics.slopes) {
    const auto material = static_cast<MaterialId>(s.material);
    addPlane(slopeSeabed(s, material), "slope '" + s.name + "'");
    for (ConvexPiece& piece : slopePieces(s, domain, material)) built.convexPieces.push_back(std::move(piece));
    if (!hasWalls(1)) {
      warnBuild(built, fmt::format("{}: slope '{}' is unbounded along y and is built over y in [{:.4g}, {:.4g}] m: a body "
                              "beyond falls off its edge; bound the domain with walls on axis y",
                              scene.sourceName, s.name, domain.yMin, domain.yMax));
    }
  }
  for (const io::StaticHeightField& h : scene.statics.heightFields) {
    for (ConvexPiece& piece : heightFieldPieces(h, domain, static_cast<MaterialId>(h.material))) {
      built.convexPieces.push_back(std::move(piece));
    }
    if (!hasWalls(0) || !hasWalls(1)) {
      warnBuild(built, fmt::format("{}: the plane around heightfield '{}' is built over x in [{:.4g}, {:.4g}] m, y in "
                              "[{:.4g}, {:.4g}] m: a body beyond falls off its edge; bound the domain with walls",
                              scene.sourceName, h.name, domain.xMin, domain.xMax, domain.yMin, domain.yMax));
    }
  }
  for (const ConvexPiece& piece : built.convexPieces) {
    try {
      world.addConvex(piece.name, piece.corners, piece.material);
    } catch (const core::InputError& e) {
      failItem(scene, "static piece '" + piece.name + "'", e);
    }
  }
}

/// The static meshes: fixed bodies of their own shapes.
void buildStaticMeshes(const io::Scene& scene, BuiltScene& built) {
  World& world = *built.world;
  for (const io::StaticMesh& m : scene.statics.meshes) {
    const std::string item = fmt::format("static mesh '{}' ({})", m.name, m.file.string());
    try {
      io::ShapeSpec spec;
      spec.name = m.name;
      spec.source = io::ShapeSource::MeshFile;
      spec.meshFile = m.file;
      const geometry::TriangleMesh mesh = shapeMesh(spec);
      const ShapeId shape = world.addShape(m.name, mesh);
      // World places a body by its centroid c (natural frame): vertex p of the file must land at
      // R (s p) + t, so the centroid goes to R (s c) + t.
      const Vec3 centroid = geometry::computeMassProperties(mesh).centroid;
      BodySpec spec2;
      spec2.name = m.name;
      spec2.shape = shape;
      spec2.scale = m.scale;
      spec2.material = static_cast<MaterialId>(m.material);
      spec2.fixed = true;
      spec2.orientation = m.orientation;
      spec2.position = m.position + m.orientation * (m.scale * centroid);
      built.staticMeshBodies.push_back(world.addBody(spec2));
    } catch (const core::InputError& e) {
      failItem(scene, item, e);
    }
  }
}

} // namespace

BuiltScene buildWorld(const io::Scene& scene) {
  BuiltScene built;
  built.world = std::make_unique<World>(worldSettings(scene));
  World& world = *built.world;

  for (const io::Material& m : scene.materials) {
    const std::string item = "material '" + m.name + "'";
    try {
      built.materials.push_back(worldMaterial(m, item));
      world.addMaterial(built.materials.back());
    } catch (const core::InputError& e) {
      failItem(scene, item, e);
    }
  }

  buildShapes(scene, built);
  const std::vector<double> bodyRadius = buildBodies(scene, built);
  buildStatics(scene, built, bodyRadius);
  buildStaticMeshes(scene, built);
  try {
    built.stableTimeStep = world.stableTimeStep();
    built.timeStep = world.timeStep();
  } catch (const core::InputError& e) {
    failItem(scene, "time_step", e);
  }
  return built;
}

std::string describeBuild(const io::Scene& scene, const BuiltScene& built) {
  const World& world = *built.world;
  std::size_t fixed = 0;
  for (const BodyId b : built.bodyIndexOfSceneBody) {
    if (world.bodies().motionType(b) == dynamics::MotionType::Static) ++fixed;
  }
  std::size_t shapes = 0;
  for (const auto& s : built.shapeOfSceneShape) shapes += s ? 1 : 0;
  std::string out;
  out += fmt::format("bodies: {} ({} dynamic, {} fixed)\n", built.bodyIndexOfSceneBody.size(),
                     built.bodyIndexOfSceneBody.size() - fixed, fixed);
  out += fmt::format("shapes: {} built ({} in the scene)\n", shapes, scene.shapes.size());
  out += fmt::format("static pieces: {} ({} half-spaces, {} convex pieces, {} fixed meshes)\n",
                     built.staticPieceCount(), built.planes.size(), built.convexPieces.size(),
                     built.staticMeshBodies.size());
  if (!built.convexPieces.empty()) {
    out += fmt::format("static domain: unbounded items cut to x in [{:.6g}, {:.6g}] m, y in [{:.6g}, {:.6g}] m; "
                       "pieces reach {:.4g} m below their lowest surface point\n",
                       built.domain.xMin, built.domain.xMax, built.domain.yMin, built.domain.yMax, built.domain.depth);
  }
  if (std::isfinite(built.stableTimeStep)) {
    out += fmt::format("stable time step: {:.6g} s (stiffest contact of each dynamic body, with damping)\n",
                       built.stableTimeStep);
  } else {
    out += "stable time step: none (no dynamic body)\n";
  }
  if (scene.contact.solver == io::ContactSolver::Constraint) {
    // The stable step above is the penalty solver's; the constraint solver has its own step.
    out += fmt::format("time step: {:.6g} s (constraint solver, {}; {} substeps; the stable step above is the "
                       "penalty solver's)\n",
                       built.timeStep, scene.timeStep.automatic ? "contact.constraint.time_step" : "time_step",
                       scene.contact.constraint.substeps);
  } else if (scene.timeStep.automatic) {
    out += fmt::format("time step: {:.6g} s (auto: {} x the stable step)\n", built.timeStep, scene.timeStep.safety);
  } else {
    out += fmt::format("time step: {:.6g} s (fixed: {:.3g} x the stable step)\n", built.timeStep,
                       built.timeStep / built.stableTimeStep);
  }
  out += fmt::format("steps to the duration {} s: {:.0f}\n", scene.duration, std::ceil(scene.duration / built.timeStep));
  return out;
}

} // namespace armour::simulation
