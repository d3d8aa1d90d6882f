// SPDX-License-Identifier: GPL-3.0-or-later
// Tetrahedral meshes of closed surfaces (gmsh Delaunay, seeded interior): they fill the solid
// exactly, tets are positive, the surface is kept, and the element count follows the request.
#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "geometry/SurfaceRefinement.hpp"
#include "geometry/Tetrahedralizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace armour::geometry {
namespace {

/// Closed surface of a union of unit voxels (integer cell coordinates): every face between a
/// filled and an empty cell, two triangles each, outward. Voxels must touch face to face (no
/// edge-only contact), which keeps the surface manifold. Shared grid points are shared vertices.
TriangleMesh voxelSolid(const std::set<std::array<int, 3>>& cells) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::int32_t> index;
  const auto vertex = [&](const std::array<int, 3>& p) {
    auto [it, inserted] = index.try_emplace(p, static_cast<std::int32_t>(mesh.vertices.size()));
    if (inserted) {
      mesh.vertices.emplace_back(p[0], p[1], p[2]);
    }
    return it->second;
  };
  for (const auto& c : cells) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        std::array<int, 3> neighbour = c;
        neighbour[axis] += side == 0 ? -1 : 1;
        if (cells.count(neighbour) != 0) {
          continue;
        }
        // The face's corners, counter-clockwise seen from outside (u x v = outward normal).
        const int u = (axis + 1) % 3;
        const int v = (axis + 2) % 3;
        std::array<int, 3> o = c;
        o[axis] += side;
        std::array<std::array<int, 3>, 4> q{o, o, o, o};
        q[1][u] += 1;
        q[2][u] += 1;
        q[2][v] += 1;
        q[3][v] += 1;
        std::array<std::int32_t, 4> id{vertex(q[0]), vertex(q[1]), vertex(q[2]), vertex(q[3])};
        if (side == 0) {
          std::swap(id[1], id[3]); // the low face looks along -axis: reverse the walk
        }
        mesh.triangles.push_back({id[0], id[1], id[2]});
        mesh.triangles.push_back({id[0], id[2], id[3]});
      }
    }
  }
  return mesh;
}

/// A 3-d cross: centre cell plus one arm cell on each of its six faces (volume 7 m^3, non-convex).
TriangleMesh crossSolid() {
  return voxelSolid({{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}});
}

/// An L-shaped prism of three cells (volume 3 m^3, one re-entrant edge).
TriangleMesh lSolid() { return voxelSolid({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}); }

std::set<std::array<std::int32_t, 3>> sortedTriangles(const TriangleMesh& mesh) {
  std::set<std::array<std::int32_t, 3>> out;
  for (auto f : mesh.triangles) {
    std::sort(f.begin(), f.end());
    out.insert(f);
  }
  return out;
}

/// The checks every tet mesh must pass: positive tets that fill the solid, and no dihedral angle
/// below `minDihedralDeg` (degree).
void expectFills(const TetMesh& tets, const TriangleMesh& surface, const std::string& what, double minDihedralDeg) {
  ASSERT_FALSE(tets.tets.empty()) << what;
  // The requirement is 0.5 %; both volumes are exact for the same polyhedron, so in
  // practice they agree to round-off (the mesher itself checks 1e-6).
  EXPECT_NEAR(tets.totalVolume() / signedVolume(surface), 1.0, 0.005) << what;
  for (std::size_t t = 0; t < tets.tets.size(); ++t) {
    ASSERT_GT(tets.volume(t), 0.0) << what << ": tet " << t;
  }
  const TetMeshQuality q = tetMeshQuality(tets);
  EXPECT_GT(q.minVolume, 0.0) << what;
  EXPECT_GT(q.minDihedralDeg, minDihedralDeg) << what;
  // Mean radius ratio 3 r_in / r_circ: 0.6-0.8 measured where the BCC lattice (0.95 for its
  // Sommerville tetrahedra) fills most of the solid, about 0.43 for meshes of a coarse rock's
  // surface points alone; 0.3 flags a mesh made mostly of flat tets.
  EXPECT_GT(q.meanRadiusRatio, 0.3) << what;
}

// Minimum dihedral angles asserted below (degree), from the measured values with margin:
//  - box-like solids with a refined surface: 14-17 measured, 10 asserted;
//  - rocks with a refined surface: 1.2 (rock) and 3.0 (voronoi-rock) worst over 5 seeds; slivers
//    at nearly flat ridges and thin surface triangles, asserted > 0.5;
//  - any surface kept as given (coarse, thin triangles): only positive volume is promised.
constexpr double kBoxMinDihedral = 10.0;
constexpr double kRockMinDihedral = 0.5;
constexpr double kCoarseMinDihedral = 0.0;

TEST(TetMeshQuality, RegularTetrahedron) {
  TetMesh m;
  m.vertices = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
  m.tets = {{0, 1, 2, 3}};
  if (m.volume(0) < 0.0) {
    std::swap(m.tets[0][2], m.tets[0][3]);
  }
  const TetMeshQuality q = tetMeshQuality(m);
  EXPECT_NEAR(q.minDihedralDeg, std::acos(1.0 / 3.0) * 180.0 / std::numbers::pi, 1e-9); // 70.53 degrees
  EXPECT_NEAR(q.maxDihedralDeg, q.minDihedralDeg, 1e-9);
  EXPECT_NEAR(q.minRadiusRatio, 1.0, 1e-12);
  EXPECT_NEAR(m.totalVolume(), 8.0 / 3.0, 1e-12); // a cube of side 2 minus four corner tets of 4/3
  EXPECT_EQ(tetMeshBoundary(m).triangleCount(), 4u);
  EXPECT_TRUE(inspectMesh(tetMeshBoundary(m)).valid()); // the boundary faces are outward
}

TEST(Tetrahedralizer, CubeFillsExactlyAndKeepsItsSurface) {
  const TriangleMesh cube = makeShape("cube", ShapeRequest{});
  TetrahedralizeOptions options;
  options.maxEdge = 0.25;
  const TetMesh tets = tetrahedralize(cube, options);
  expectFills(tets, cube, "cube", kCoarseMinDihedral);
  // Interior points were used: without them the 8 corners give 5-6 tets. (A full BCC fill of
  // spacing 0.25 has 12 / 0.25^3 = 768 tets per m^3; the lattice keeps 0.9 spacing off the
  // surface, so the coarse surface's layer takes a large share: 228 measured.)
  EXPECT_GT(tets.tets.size(), 100u);
  // The surface vertices come first, unchanged, and the boundary of the tets is the input surface.
  for (std::size_t i = 0; i < cube.vertexCount(); ++i) {
    EXPECT_EQ(tets.vertices[i], cube.vertices[i]);
  }
  EXPECT_EQ(sortedTriangles(tetMeshBoundary(tets)), sortedTriangles(cube));
}

TEST(Tetrahedralizer, NonConvexSolidsFillExactly) {
  for (const auto& [name, solid] : {std::pair{"L", lSolid()}, std::pair{"cross", crossSolid()}}) {
    ASSERT_TRUE(inspectMesh(solid).valid()) << name; // the test fixture itself
    // Surface refined first so the elements are about uniform (0.3 m edges).
    TetrahedralizeOptions options;
    options.maxEdge = 0.3;
    options.keepSurface = false;
    const TetMesh tets = tetrahedralize(solid, options);
    expectFills(tets, solid, name, kBoxMinDihedral);
    EXPECT_NEAR(tets.totalVolume(), name == std::string("L") ? 3.0 : 7.0, 1e-9) << name;
    // The boundary is the refined surface: watertight, outward, same area, no edge above h.
    const TriangleMesh boundary = tetMeshBoundary(tets);
    EXPECT_TRUE(inspectMesh(boundary).valid()) << name;
    EXPECT_NEAR(boundary.surfaceArea(), solid.surfaceArea(), 1e-9) << name;
    EXPECT_LE(surfaceMeshStats(boundary).maxEdge, 0.3 + 1e-12) << name;
  }
}

TEST(Tetrahedralizer, TargetCountIsMetWithinAFactorOfTwo) {
  struct Case {
    const char* name;
    TriangleMesh surface;
    std::size_t target;
    bool keepSurface;
    double minDihedral;
  };
  // Coarse surfaces kept as given (the surface does not force the count) and surfaces refined to
  // the lattice spacing.
  const std::vector<Case> cases{
      {"cube", makeShape("cube", ShapeRequest{}), 2000, true, kCoarseMinDihedral},
      {"cube", makeShape("cube", ShapeRequest{}), 20000, false, kBoxMinDihedral},
      {"cross", crossSolid(), 5000, false, kBoxMinDihedral},
      {"voronoi-rock", makeShape("voronoi-rock", ShapeRequest{}), 3000, true, kCoarseMinDihedral},
      {"voronoi-rock", makeShape("voronoi-rock", ShapeRequest{}), 3000, false, kRockMinDihedral},
      {"rock", makeShape("rock", ShapeRequest{}), 3000, true, kCoarseMinDihedral},
      {"rock", makeShape("rock", ShapeRequest{}), 3000, false, kRockMinDihedral}};
  for (const auto& c : cases) {
    TetrahedralizeOptions options;
    options.targetTetCount = c.target;
    options.keepSurface = c.keepSurface;
    const TetMesh tets = tetrahedralize(c.surface, options);
    const std::string what = std::string(c.name) + (c.keepSurface ? " (surface kept)" : " (surface refined)");
    expectFills(tets, c.surface, what, c.minDihedral);
    // Up to three corrections of the spacing land within 10 % here (measured 0-8 %); the
    // interface promises 0.5x-2x, which is what is asserted.
    const double ratio = static_cast<double>(tets.tets.size()) / static_cast<double>(c.target);
    EXPECT_GT(ratio, 0.5) << what << " target " << c.target << " got " << tets.tets.size();
    EXPECT_LT(ratio, 2.0) << what << " target " << c.target << " got " << tets.tets.size();
  }
}

TEST(Tetrahedralizer, IsRepeatable) {
  // gmsh's Delaunay with the points given: the same input gives the same mesh, also after other
  // meshes were made in the same process (gmsh 4.8's HXT mesher failed this).
  TetrahedralizeOptions options;
  options.targetTetCount = 1500;
  options.keepSurface = false;
  const TriangleMesh rock = makeShape("rock", ShapeRequest{});
  const TetMesh a = tetrahedralize(rock, options);
  (void)tetrahedralize(crossSolid(), options);
  const TetMesh b = tetrahedralize(rock, options);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.vertices, b.vertices);
}

TEST(Tetrahedralizer, RefusesTooManyTets) {
  TetrahedralizeOptions options;
  options.maxEdge = 1e-3; // ~1.2e10 tets in a unit cube: a size given in mm by mistake
  try {
    (void)tetrahedralize(makeShape("cube", ShapeRequest{}), options);
    ADD_FAILURE() << "no error";
  } catch (const core::InputError& e) {
    // Smallest allowed size for 1 m^3 and 5e6 tets: (12 / 5e6)^(1/3) = 0.01339 m.
    EXPECT_NE(std::string(e.what()).find(">= 0.01339"), std::string::npos) << e.what();
  }
}

TEST(Tetrahedralizer, RocksWithSurfaceAsGiven) {
  for (const char* shape : {"rock", "voronoi-rock"}) {
    ShapeRequest request;
    request.volume = 2.0;
    const TriangleMesh rock = makeShape(shape, request);
    const TetMesh tets = tetrahedralize(rock); // size follows the surface triangles
    expectFills(tets, rock, shape, kCoarseMinDihedral);
    EXPECT_EQ(sortedTriangles(tetMeshBoundary(tets)), sortedTriangles(rock)) << shape;
  }
}

TEST(Tetrahedralizer, RefusesOpenAndInvertedSurfaces) {
  TriangleMesh open = makeShape("cube", ShapeRequest{});
  open.triangles.pop_back();
  EXPECT_THROW((void)tetrahedralize(open), core::InputError);
  TriangleMesh inverted = makeShape("cube", ShapeRequest{});
  flipOrientation(inverted);
  EXPECT_THROW((void)tetrahedralize(inverted), core::InputError);
  TetrahedralizeOptions bad;
  bad.maxEdge = -1.0;
  EXPECT_THROW((void)tetrahedralize(makeShape("cube", ShapeRequest{}), bad), core::InputError);
}

} // namespace
} // namespace armour::geometry
