// SPDX-License-Identifier: GPL-3.0-or-later
// The scene builder: scene files (tests/data/scenes) turned into a World. Bodies (count, mass =
// density x volume, placement), materials (damping ratio -> restitution round trip), static
// geometry (the convex pieces of slopes and height fields reproduce the solid: points known below
// the surface are inside their union, points above are outside, and no two pieces overlap),
// errors naming the scene and the item, and a smoke run: cubes dropped on a floor come to rest.

#include "contact/ContactLaw.hpp"
#include "core/Error.hpp"
#include "geometry/ConvexHull.hpp"
#include "io/SceneReader.hpp"
#include "simulation/SceneBuilder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

using namespace armour;
using namespace armour::simulation;
namespace fs = std::filesystem;

namespace {

const fs::path kScenes = fs::path(ARMOUR_TEST_DATA) / "scenes";

/// The solid of the static geometry as the builder made it: half-spaces and convex pieces.
struct StaticSolid {
  std::vector<StaticPlane> planes;
  std::vector<geometry::ConvexPolyhedron> pieces;

  StaticSolid(const std::vector<StaticPlane>& p, const std::vector<ConvexPiece>& convex) : planes(p) {
    for (const ConvexPiece& c : convex) {
      pieces.push_back(geometry::convexHullPolyhedron(c.corners, c.name));
    }
  }
  /// Largest signed face distance: < 0 strictly inside the piece (m).
  static double pieceDistance(const geometry::ConvexPolyhedron& p, const Vec3& x) {
    double d = -std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < p.normals.size(); ++f) {
      d = std::max(d, p.normals[f].dot(x) - p.offsets[f]);
    }
    return d;
  }
  /// Number of convex pieces strictly containing x (deeper than tol).
  int piecesContaining(const Vec3& x, double tol) const {
    int n = 0;
    for (const auto& p : pieces) {
      n += pieceDistance(p, x) < -tol ? 1 : 0;
    }
    return n;
  }
  bool inside(const Vec3& x, double tol) const {
    for (const auto& pl : planes) {
      if ((x - pl.point).dot(pl.normal) < -tol) return true;
    }
    return piecesContaining(x, tol) > 0;
  }
};

/// Height of a height field's cell surface above (x, y), from the definition in Scene.hpp (four
/// triangles from the cell's corners to its lowered centre), independently of the builder's
/// decomposition. False outside the field.
bool fieldSurface(const io::HeightField& f, double x, double y, double& z) {
  const Vec3 ax = f.alongX();
  const double u = (x - f.origin.x()) / (f.cellSize * ax.x());
  const double v = (y - f.origin.y()) / f.cellSize;
  const int ix = static_cast<int>(std::floor(u));
  const int iy = static_cast<int>(std::floor(v));
  if (ix < 0 || iy < 0 || ix >= f.cellsX || iy >= f.cellsY) return false;
  const Vec3 c[4] = {f.corner(ix, iy), f.corner(ix + 1, iy), f.corner(ix + 1, iy + 1), f.corner(ix, iy + 1)};
  const Vec3 low = f.lowCentre(ix, iy);
  for (int k = 0; k < 4; ++k) {
    const Vec3& a = c[k];
    const Vec3& b = c[(k + 1) % 4];
    // Barycentric coordinates of (x, y) in the projected triangle (a, b, low).
    const Eigen::Matrix2d m{{b.x() - a.x(), low.x() - a.x()}, {b.y() - a.y(), low.y() - a.y()}};
    const Eigen::Vector2d w = m.inverse() * Eigen::Vector2d(x - a.x(), y - a.y());
    if (w.x() >= -1e-12 && w.y() >= -1e-12 && w.sum() <= 1.0 + 1e-12) {
      z = a.z() + w.x() * (b.z() - a.z()) + w.y() * (low.z() - a.z());
      return true;
    }
  }
  return false;
}

io::Scene readTestScene(const std::string& name) { return io::readScene(kScenes / name); }

/// Count mismatches of the union against a reference surface z = surface(x, y) over random
/// points of the domain at the given heights above (+) or below (-) the surface.
struct UnionCheck {
  int checkedInside = 0, checkedOutside = 0, wrongInside = 0, wrongOutside = 0, doubled = 0;
};
template <typename Surface>
UnionCheck checkUnion(const StaticSolid& solid, const StaticDomain& d, Surface&& surface, int samples) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> ux(d.xMin + 1e-3, d.xMax - 1e-3), uy(d.yMin + 1e-3, d.yMax - 1e-3);
  UnionCheck out;
  // 1e-4 m: far above the round-off of coordinates of order 10 m (1e-15 relative), far below
  // the features (cell depths of 0.1 m, toe of 1.5 m). 0.5 m: a deep point inside the pieces.
  const double offsets[] = {-0.5, -1e-4, 1e-4, 0.5};
  for (int i = 0; i < samples; ++i) {
    const double x = ux(rng), y = uy(rng);
    const double z0 = surface(x, y);
    for (double dz : offsets) {
      const Vec3 p(x, y, z0 + dz);
      if (dz < 0.0) {
        ++out.checkedInside;
        out.wrongInside += solid.inside(p, 1e-9) ? 0 : 1;
        out.doubled += solid.piecesContaining(p, 1e-9) > 1 ? 1 : 0;
      } else {
        ++out.checkedOutside;
        out.wrongOutside += solid.inside(p, -1e-9) ? 1 : 0;
      }
    }
  }
  return out;
}

} // namespace

TEST(SceneBuilder, BlockOnSlopeBodiesAndStatics) {
  const io::Scene scene = readTestScene("block-on-slope.yaml");
  const BuiltScene built = buildWorld(scene);
  const World& world = *built.world;
  ASSERT_EQ(built.bodyIndexOfSceneBody.size(), 1u);
  const BodyId b = built.bodyIndexOfSceneBody[0];
  // makeShape meets the volume to round-off, and the scale (1 / V)^(1/3) restores it: 1e-9.
  EXPECT_NEAR(world.bodies().info(b).mass, 2400.0 * 1.0, 2400.0 * 1e-9);
  EXPECT_LT((world.bodies().position(b) - Vec3(3.774, 0, 2.452)).norm(), 1e-12);
  // The natural frame comes back through naturalToBody: round-off only.
  EXPECT_LT(world.naturalOrientation(b).angularDistance(scene.bodies[0].orientation), 1e-9);
  // Two walls and the seabed; the toe (front face + top) and the face with the crest.
  EXPECT_EQ(built.planes.size(), 3u);
  ASSERT_EQ(built.convexPieces.size(), 2u);
  EXPECT_EQ(built.staticPieceCount(), 5u);
  EXPECT_EQ(world.staticConvexCount(), 2u);
  // The slope is cut in y at the walls (+-3 m) plus the margin: it must reach beyond them.
  EXPECT_LT(built.domain.yMin, -3.0);
  EXPECT_GT(built.domain.yMax, 3.0);
  // auto: the used step is exactly safety x the stable step.
  ASSERT_GT(built.stableTimeStep, 0.0);
  EXPECT_DOUBLE_EQ(built.timeStep, 0.2 * built.stableTimeStep);
  EXPECT_DOUBLE_EQ(world.timeStep(), built.timeStep);
}

TEST(SceneBuilder, SlopePiecesUnionIsTheSlope) {
  const io::Scene scene = readTestScene("block-on-slope.yaml");
  const io::StaticSlope& slope = scene.statics.slopes.at(0);
  StaticDomain d;
  d.xMin = -20, d.xMax = 30, d.yMin = -4, d.yMax = 4, d.depth = 2;
  const std::vector<ConvexPiece> pieces = slopePieces(slope, d, 0);
  ASSERT_EQ(pieces.size(), 2u);
  const StaticSolid solid({slopeSeabed(slope, 0)}, pieces);
  // Seabed at -1.8 m (the toe's foot).
  EXPECT_DOUBLE_EQ(solid.planes[0].point.z(), -1.8);
  const UnionCheck c = checkUnion(solid, d, [&](double x, double) { return io::slopeHeight(slope, x); }, 2000);
  EXPECT_EQ(c.checkedInside, 4000);
  EXPECT_EQ(c.wrongInside, 0);
  EXPECT_EQ(c.wrongOutside, 0);
  EXPECT_EQ(c.doubled, 0); // pieces meet face to face: no point is pushed by two of them
  // Points known by hand: under the toe top, in front of the toe, on the crest, above the face.
  // Toe front face from (-10, -1.8) to (-2, 0): z = -0.675 m at x = -5.
  EXPECT_TRUE(solid.inside({-5.0, 0.0, -0.685}, 1e-9));
  EXPECT_FALSE(solid.inside({-5.0, 0.0, -0.665}, -1e-9));
  EXPECT_TRUE(solid.inside({-1.0, 0.0, -0.01}, 1e-9)); // 1 cm under the toe top
  EXPECT_FALSE(solid.inside({-1.0, 0.0, 0.01}, -1e-9));
  EXPECT_FALSE(solid.inside({-11.0, 0.0, -1.79}, -1e-9)); // 1 cm above the seabed, offshore of the toe
  EXPECT_TRUE(solid.inside({25.0, 3.9, 9.99}, 1e-9));     // under the crest (z = 10 beyond x = 20)
  EXPECT_FALSE(solid.inside({4.0, 0.0, 2.01}, -1e-9));    // 1 cm above the face at x = 4 (z = 2)
  EXPECT_TRUE(solid.inside({4.0, 0.0, 1.99}, 1e-9));
}

TEST(SceneBuilder, RoughSlopeAndHeightFieldPiecesUnion) {
  const io::Scene scene = readTestScene("every-feature.yaml");
  const io::StaticSlope& slope = scene.statics.slopes.at(0);
  ASSERT_TRUE(slope.roughness.has_value());
  const io::HeightField& rough = *slope.roughness;
  ASSERT_EQ(rough.cellsX, 20); // face 5 m / sin 30 deg = 10 m of 0.5 m cells
  ASSERT_EQ(rough.cellsY, 16); // y_range [-4, 4]
  StaticDomain d;
  d.xMin = 5, d.xMax = 45, d.yMin = -7, d.yMax = 7, d.depth = 1.5;
  const std::vector<ConvexPiece> pieces = slopePieces(slope, d, 0);
  // One prism per cell edge, (cx + 1) cy + cx (cy + 1), plus the toe, the smooth face south and
  // north of the field and the crest above it (the 20 cells cover the face exactly).
  EXPECT_EQ(pieces.size(), 21u * 16u + 20u * 17u + 4u);
  const StaticSolid solid({slopeSeabed(slope, 0)}, pieces);
  const auto surface = [&](double x, double y) {
    double z = 0.0;
    return fieldSurface(rough, x, y, z) ? z : io::slopeHeight(slope, x);
  };
  const UnionCheck c = checkUnion(solid, d, surface, 2000);
  EXPECT_EQ(c.wrongInside, 0);
  EXPECT_EQ(c.wrongOutside, 0);
  EXPECT_EQ(c.doubled, 0);
  // The deepest hollow, 1 mm from its lowered centre (the centre itself lies on the seams of
  // four pieces): 0.1 mm below the surface is solid, 0.1 mm above is not.
  const auto deepest = std::max_element(rough.depths.begin(), rough.depths.end()) - rough.depths.begin();
  const Vec3 low = rough.lowCentre(static_cast<int>(deepest) % rough.cellsX, static_cast<int>(deepest) / rough.cellsX);
  EXPECT_GT(rough.depths[static_cast<std::size_t>(deepest)], 0.15); // h = 0.2 m, 320 cells
  double zLow = 0.0;
  ASSERT_TRUE(fieldSurface(rough, low.x() + 1e-3, low.y() + 0.5e-3, zLow));
  // 1.1 mm off the centre on a 30 deg face (0.58 rise per run) with hollow faces rising at most
  // h / (cell / 2) = 0.8: the surface there is within 2 mm of the centre's height.
  EXPECT_NEAR(zLow, low.z(), 2e-3);
  EXPECT_TRUE(solid.inside(Vec3(low.x() + 1e-3, low.y() + 0.5e-3, zLow - 1e-4), 1e-9));
  EXPECT_FALSE(solid.inside(Vec3(low.x() + 1e-3, low.y() + 0.5e-3, zLow + 1e-4), -1e-9));

  const io::StaticHeightField& bed = scene.statics.heightFields.at(0);
  StaticDomain db;
  db.xMin = -14, db.xMax = 0, db.yMin = -8, db.yMax = 3, db.depth = 2;
  const std::vector<ConvexPiece> bedPieces = heightFieldPieces(bed, db, 0);
  EXPECT_EQ(bedPieces.size(), 7u * 4u + 6u * 5u + 4u); // 6 x 4 cells, four plain strips around
  const StaticSolid bedSolid({}, bedPieces);
  const auto bedSurface = [&](double x, double y) {
    double z = 0.0;
    return fieldSurface(bed.field, x, y, z) ? z : bed.field.origin.z() + bed.field.tanAlpha * (x - bed.field.origin.x());
  };
  const UnionCheck cb = checkUnion(bedSolid, db, bedSurface, 2000);
  EXPECT_EQ(cb.wrongInside, 0);
  EXPECT_EQ(cb.wrongOutside, 0);
  EXPECT_EQ(cb.doubled, 0);
}

TEST(SceneBuilder, DolosPileOnHeightField) {
  const io::Scene scene = readTestScene("dolos-pile.yaml");
  const BuiltScene built = buildWorld(scene);
  const World& world = *built.world;
  ASSERT_EQ(built.bodyIndexOfSceneBody.size(), 12u);
  // One World shape for the twelve units.
  std::size_t shapes = 0;
  for (const auto& s : built.shapeOfSceneShape) shapes += s ? 1 : 0;
  EXPECT_EQ(shapes, 1u);
  for (std::size_t i = 0; i < 12; ++i) {
    const BodyId b = built.bodyIndexOfSceneBody[i];
    EXPECT_EQ(world.bodyShape(b), *built.shapeOfSceneShape[scene.bodies[i].shape]);
    EXPECT_NEAR(world.bodies().info(b).mass, 2350.0, 2350.0 * 1e-9); // density x 1 m^3, round-off
    EXPECT_LT((world.bodies().position(b) - scene.bodies[i].position).norm(), 1e-12);
    EXPECT_EQ(world.bodies().info(b).name, scene.bodies[i].name);
  }
  EXPECT_EQ(scene.bodies[11].name, "dolos_2_1_1");
  EXPECT_LT((world.bodies().position(built.bodyIndexOfSceneBody[11]) - Vec3(2 + 2 * 2.7, -1.35 + 2.7, 1.6 + 2.7)).norm(),
            1e-12);
  // 10 x 10 cells: 11 x 10 + 10 x 11 edge prisms and four plain strips; four walls.
  EXPECT_EQ(built.convexPieces.size(), 224u);
  EXPECT_EQ(world.staticConvexCount(), 224u);
  EXPECT_EQ(built.planes.size(), 4u);
}

TEST(SceneBuilder, MeshBodiesDampingRatioAndStaticMesh) {
  const std::string yaml = R"(
duration: 1
time_step_safety: 0.3
gravity: [0, 0, -9.8]
contact: {sample_spacing: 0.08, level_set_cells_per_dn: 20, max_overlap: 0.1}
sleep: {enabled: false, linear_speed: 0.002, angular_speed: 0.004, time: 0.25}
materials:
  concrete: {density: 2400, friction: 0.75, restitution: 0.05}
  rock: {density: 2650, friction: 0.6, damping_ratio: 0.3}
shapes:
  block: {mesh: meshes/block.stl}
  unused: {generator: tetrapod}
bodies:
  - {name: c, shape: block, scale: 2, material: concrete, position: [0, 5, 1]}
  - {name: d, shape: block, volume: 8, material: rock, position: [0, -5, 1]}
static:
  - {type: mesh, name: crown, material: concrete, file: meshes/block.stl, position: [30, 0, 4],
     orientation: {euler_deg: [0, 0, 90]}, scale: 1.5}
)";
  const io::Scene scene = io::parseScene(yaml, kScenes, "inline.yaml");
  const BuiltScene built = buildWorld(scene);
  const World& world = *built.world;
  // Settings carried over one to one.
  const WorldSettings& w = world.settings();
  EXPECT_EQ(w.timeStep, 0.0); // auto
  EXPECT_EQ(w.timeStepSafety, 0.3);
  EXPECT_EQ(w.gravity, Vec3(0, 0, -9.8));
  EXPECT_EQ(w.samples.spacingOverDn, 0.08);
  EXPECT_EQ(w.levelSet.cellsPerDn, 20.0);
  EXPECT_EQ(w.maxOverlapPerDn, 0.1);
  EXPECT_FALSE(w.sleep.enabled);
  EXPECT_EQ(w.sleep.linearSpeed, 0.002);
  EXPECT_EQ(w.sleep.angularSpeed, 0.004);
  EXPECT_EQ(w.sleep.time, 0.25);
  EXPECT_DOUBLE_EQ(built.timeStep, 0.3 * built.stableTimeStep);
  // block.stl is the unit cube [0, 1]^3: scale 2 gives 8 m^3; volume 8 gives the same size.
  EXPECT_NEAR(world.bodies().info(built.bodyIndexOfSceneBody[0]).mass, 2400.0 * 8.0, 1e-9 * 2400.0 * 8.0);
  EXPECT_NEAR(world.bodies().info(built.bodyIndexOfSceneBody[1]).mass, 2650.0 * 8.0, 1e-9 * 2650.0 * 8.0);
  EXPECT_NEAR(world.bodyScale(built.bodyIndexOfSceneBody[1]), 2.0, 1e-12);
  // Both bodies share the one World shape; the unused shape is not built and is warned about.
  EXPECT_EQ(world.bodyShape(built.bodyIndexOfSceneBody[0]), world.bodyShape(built.bodyIndexOfSceneBody[1]));
  const auto unused = static_cast<std::size_t>(std::find_if(scene.shapes.begin(), scene.shapes.end(),
                                                            [](const auto& s) { return s.name == "unused"; }) -
                                               scene.shapes.begin());
  ASSERT_LT(unused, scene.shapes.size());
  EXPECT_FALSE(built.shapeOfSceneShape[unused].has_value());
  ASSERT_FALSE(built.warnings.empty());
  EXPECT_NE(built.warnings[0].find("'unused'"), std::string::npos);

  // Damping ratio 0.3 -> restitution -> World's damping ratio: the round trip is the bisection
  // of ContactLaw.cpp, exact to round-off (1e-9 is generous).
  const double e = built.materials[1].restitution;
  EXPECT_NEAR(contact::dampingRatioFromRestitution(e), 0.3, 1e-9);
  // The clamped dashpot lets go before the half period, so it keeps more energy than the linear
  // dashpot's e = exp(-pi zeta / sqrt(1 - zeta^2)) = 0.372; Schwager and Poschel's t* gives 0.451.
  EXPECT_GT(e, std::exp(-std::numbers::pi * 0.3 / std::sqrt(1.0 - 0.09)));
  EXPECT_NEAR(e, 0.451, 1e-3);

  // Static mesh: file vertex p goes to R (1.5 p) + (30, 0, 4) with R = 90 deg about z; its
  // centroid (0.5, 0.5, 0.5) to (30 - 0.75, 0.75, 4.75).
  ASSERT_EQ(built.staticMeshBodies.size(), 1u);
  const BodyId crown = built.staticMeshBodies[0];
  EXPECT_LT((world.bodies().position(crown) - Vec3(29.25, 0.75, 4.75)).norm(), 1e-12);
  EXPECT_EQ(world.bodies().motionType(crown), dynamics::MotionType::Static);
  // World corner of the file's vertex (1, 0, 0): R (1.5, 0, 0) + t = (30, 1.5, 4).
  const Vec3 corner = world.bodies().position(crown) +
                      world.naturalOrientation(crown) * (1.5 * (Vec3(1, 0, 0) - Vec3(0.5, 0.5, 0.5)));
  EXPECT_LT((corner - Vec3(30, 1.5, 4)).norm(), 1e-12);
}

TEST(SceneBuilder, ErrorsNameTheSceneAndTheItem) {
  // An open mesh (a cube missing a face) used as a body's shape.
  const fs::path dir = fs::temp_directory_path() / ("armour_test_scene_builder_" + std::to_string(std::random_device{}()));
  fs::create_directories(dir);
  {
    std::ofstream obj(dir / "open.obj");
    obj << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
           "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n";
  }
  const std::string open = R"(
duration: 1
materials: {concrete: {density: 2400, friction: 0.75, restitution: 0.05}}
bodies:
  - {name: u, shape: {mesh: open.obj}, material: concrete, position: [0, 0, 1]}
)";
  try {
    (void)buildWorld(io::parseScene(open, dir, "open-mesh.yaml"));
    FAIL() << "an open mesh was accepted";
  } catch (const core::InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("open-mesh.yaml: shape '", 0), 0u) << m;
    EXPECT_NE(m.find("open.obj"), std::string::npos) << m;
    EXPECT_NE(m.find("open edges"), std::string::npos) << m;
  }
  // A fixed time step far above the stability limit of a 1 m cube (about 3 ms).
  const std::string tooLong = R"(
duration: 1
time_step: 0.1
materials: {concrete: {density: 2400, friction: 0.75, restitution: 0.05}}
bodies:
  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 1]}
)";
  try {
    (void)buildWorld(io::parseScene(tooLong, dir, "long-step.yaml"));
    FAIL() << "a time step of 0.1 s was accepted";
  } catch (const core::InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("long-step.yaml: time_step", 0), 0u) << m;
    EXPECT_NE(m.find("stability limit"), std::string::npos) << m;
  }
  fs::remove_all(dir);
}

TEST(SceneBuilder, RunSmokeCubesComeToRest) {
  io::Scene scene = readTestScene("run-smoke.yaml");
  // Awake to the end, so that "at rest" is the contact's damping at work, not sleep's zeroing.
  scene.sleep.enabled = false;
  BuiltScene built = buildWorld(scene);
  World& world = *built.world;
  // The scene's 0.3 s is for the command-line test; rest needs longer: the cubes land after 0.14
  // and 0.2 s and e = 0.05 leaves a bounce of a few mm/s that the contact damps within ~0.1 s.
  world.advanceTo(1.0);
  for (std::size_t i = 0; i < 2; ++i) {
    const BodyId b = built.bodyIndexOfSceneBody[i];
    const Vec3 x = world.bodies().position(b);
    // z = 0.5 m less the overlap under self-weight, rho g Dn / p = 2.4e-5 m: 1e-3 m is the
    // brief's tolerance, 40 times that overlap.
    EXPECT_NEAR(x.z(), 0.5, 1e-3) << scene.bodies[i].name;
    // Sharper: at rest the floor carries the weight, p d A / L = m g with A = 1 m^2 (projected
    // sample areas of a flat face sum to the face), L = Dn = 1 m: d = rho g Dn / p exactly, up to
    // the round-off of summing ~200 sample areas (1e-9 m is 4e-5 of d).
    EXPECT_NEAR(0.5 - x.z(), 2400.0 * 9.81 * 1.0 / 1.0e9, 1e-9) << scene.bodies[i].name;
    // At rest: 1 mm/s is far below the 1.4 and 2.0 m/s impact speeds.
    EXPECT_LT(world.bodies().velocity(b).norm(), 1e-3) << scene.bodies[i].name;
    // A flat landing pushes straight up: no sideways drift or tilt beyond round-off-level effects.
    EXPECT_LT((x.head<2>() - scene.bodies[i].position.head<2>()).norm(), 1e-6) << scene.bodies[i].name;
    EXPECT_LT(world.naturalOrientation(b).angularDistance(scene.bodies[i].orientation), 1e-6) << scene.bodies[i].name;
  }
}
