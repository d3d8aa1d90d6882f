// SPDX-License-Identifier: GPL-3.0-or-later
// Convex hulls, half-space intersections and the two random rock generators.
#include "core/Error.hpp"
#include "geometry/ConvexHull.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <map>
#include <set>

namespace armour::geometry {
namespace {

/// Largest signed distance of any vertex in front of any face plane, relative to the bounding-box
/// diagonal: <= 0 (up to round-off) for a convex, outward mesh.
double convexityViolation(const TriangleMesh& mesh, const std::vector<Vec3>& points) {
  double worst = -std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = mesh.doubleAreaNormal(t).normalized();
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    for (const auto& p : points) {
      worst = std::max(worst, n.dot(p - a));
    }
  }
  return worst / mesh.bounds().size().norm();
}

/// Extents along the principal axes of inertia, longest first (m).
std::array<double, 3> principalExtents(const TriangleMesh& mesh) {
  const MassProperties mp = computeMassProperties(mesh);
  std::array<double, 3> extent{};
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis = mp.principalAxes.col(k);
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (const auto& v : mesh.vertices) {
      lo = std::min(lo, v.dot(axis));
      hi = std::max(hi, v.dot(axis));
    }
    extent[k] = hi - lo;
  }
  std::sort(extent.begin(), extent.end(), std::greater<>());
  return extent;
}

std::vector<Vec3> cubeCorners() {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? 1.0 : 0.0, (i & 2) ? 1.0 : 0.0, (i & 4) ? 1.0 : 0.0);
  }
  return corners;
}

// ---------------------------------------------------------------------------------------------
// Convex hull

TEST(ConvexHull, UnitCubeCornersGiveTwelveTrianglesAndUnitVolume) {
  TriangleMesh hull = convexHull(cubeCorners());
  EXPECT_EQ(hull.triangleCount(), 12u); // 6 square faces, 2 triangles each
  EXPECT_EQ(hull.vertexCount(), 8u);
  // Volume of a polyhedron with exact corner coordinates: round-off only.
  EXPECT_NEAR(signedVolume(hull), 1.0, 1e-12);
  EXPECT_TRUE(inspectMesh(hull).valid()); // closed, manifold, outward without any repair
}

TEST(ConvexHull, PointsOnEdgesAndFacesMakeNoSlivers) {
  // Cube corners plus edge midpoints, face centres and the body centre. Qhull's 'Qt' would fan the
  // merged faces and make zero-area triangles along the edges; the max-min-angle triangulation
  // must not. Every triangle keeps an angle >= 10 degrees (the best triangulation of a square with
  // edge midpoints has 45-degree-ish angles; 10 leaves room for another valid choice).
  std::vector<Vec3> points = cubeCorners();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        if (i == 1 || j == 1 || k == 1) {
          points.emplace_back(0.5 * i, 0.5 * j, 0.5 * k);
        }
      }
    }
  }
  TriangleMesh hull = convexHull(points);
  EXPECT_NEAR(signedVolume(hull), 1.0, 1e-12);
  EXPECT_TRUE(inspectMesh(hull).valid());
  for (std::size_t t = 0; t < hull.triangleCount(); ++t) {
    const auto c = hull.corners(t);
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = c[(k + 1) % 3] - c[k];
      const Vec3 v = c[(k + 2) % 3] - c[k];
      const double angle = std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / std::numbers::pi;
      EXPECT_GT(angle, 10.0) << "triangle " << t;
    }
  }
}

TEST(ConvexHull, RandomPointsLieInsideTheirHull) {
  std::mt19937_64 rng(7);
  std::vector<Vec3> points;
  for (int i = 0; i < 500; ++i) {
    const auto u = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    // Far from the origin on purpose: the hull must not lose precision there.
    points.emplace_back(1000.0 + u(), -2000.0 + 2.0 * u(), 500.0 + 0.5 * u());
  }
  const ConvexPolyhedron poly = convexHullPolyhedron(points);
  const TriangleMesh hull = triangulateFaces(poly);
  EXPECT_TRUE(inspectMesh(hull).valid());
  // Every input point on the inner side of every face, to round-off (1e-12 of the size).
  EXPECT_LT(convexityViolation(hull, points), 1e-12);
  // Hull vertices are input points, bit for bit.
  ASSERT_EQ(poly.vertexSource.size(), poly.vertices.size());
  for (std::size_t i = 0; i < poly.vertices.size(); ++i) {
    EXPECT_EQ(poly.vertices[i], points[poly.vertexSource[i]]);
  }
  // Volume of the hull is below that of the box the points were drawn in (1 x 2 x 0.5 = 1 m^3)
  // and, for 500 points, close to it: the expected missing volume is a few percent.
  const double volume = signedVolume(hull);
  EXPECT_LT(volume, 1.0);
  EXPECT_GT(volume, 0.85);
}

TEST(ConvexHull, RefusesTooFewCoplanarAndCollinearPoints) {
  const auto expectError = [](const std::vector<Vec3>& points, const std::string& phrase) {
    try {
      (void)convexHull(points, "test points");
      ADD_FAILURE() << "no error for " << phrase;
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test points"), std::string::npos) << e.what();
    }
  };
  expectError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, "at least 4");
  expectError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(0.3, 0.2, 0)}, "one plane");
  expectError({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3)}, "one line");
  expectError({Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)}, "coincide");
}

// ---------------------------------------------------------------------------------------------
// Half-space intersection

TEST(HalfspaceIntersection, CubeFromSixPlanesIgnoresARedundantSeventh) {
  std::vector<Halfspace> planes;
  for (int k = 0; k < 3; ++k) {
    planes.push_back({Vec3::Unit(k), 1.0});   // x_k <= 1
    planes.push_back({-Vec3::Unit(k), 0.0});  // x_k >= 0
  }
  planes.push_back({Vec3(1, 1, 1), 5.0}); // far outside the cube: touches nothing
  const ConvexPolyhedron cube = convexHalfspaceIntersection(planes, Vec3(0.3, 0.4, 0.5));
  EXPECT_EQ(cube.faces.size(), 6u);
  EXPECT_EQ(cube.vertices.size(), 8u);
  std::set<std::int32_t> sources(cube.faceSource.begin(), cube.faceSource.end());
  EXPECT_EQ(sources, (std::set<std::int32_t>{0, 1, 2, 3, 4, 5}));
  const TriangleMesh mesh = triangulateFaces(cube);
  EXPECT_TRUE(inspectMesh(mesh).valid());
  EXPECT_NEAR(signedVolume(mesh), 1.0, 1e-12);
}

TEST(HalfspaceIntersection, RefusesUnboundedAndBadInteriorPoint) {
  const auto expectUnbounded = [](const std::vector<Halfspace>& planes) {
    try {
      (void)convexHalfspaceIntersection(planes, Vec3::Constant(0.5));
      ADD_FAILURE() << "no error";
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("unbounded"), std::string::npos) << e.what();
    }
  };
  std::vector<Halfspace> planes;
  for (int k = 0; k < 3; ++k) {
    planes.push_back({-Vec3::Unit(k), 0.0});
  }
  planes.push_back({Vec3(1, 0, 0), 1.0});
  planes.push_back({Vec3(0, 1, 0), 1.0});
  expectUnbounded(planes); // nothing limits +z
  // A square prism: normals all in the x-y plane, open along z both ways.
  expectUnbounded({{Vec3(1, 0, 0), 1.0}, {Vec3(-1, 0, 0), 0.0}, {Vec3(0, 1, 0), 1.0}, {Vec3(0, -1, 0), 0.0}});
  planes.push_back({Vec3(0, 0, 1), 1.0});
  EXPECT_NO_THROW((void)convexHalfspaceIntersection(planes, Vec3::Constant(0.5)));
  EXPECT_THROW((void)convexHalfspaceIntersection(planes, Vec3(2.0, 0.5, 0.5)), core::InputError);
}

// ---------------------------------------------------------------------------------------------
// Rock generators

class RockGenerator : public ::testing::TestWithParam<std::string> {};

TEST_P(RockGenerator, SameSeedSameRockOtherSeedOtherRock) {
  ShapeRequest request;
  request.volume = 2.0;
  request.seed = 42;
  const TriangleMesh a = makeShape(GetParam(), request);
  const TriangleMesh b = makeShape(GetParam(), request);
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  ASSERT_EQ(a.triangles, b.triangles);
  for (std::size_t i = 0; i < a.vertexCount(); ++i) {
    EXPECT_EQ(a.vertices[i], b.vertices[i]); // bitwise: the construction has no hidden state
  }
  request.seed = 43;
  const TriangleMesh c = makeShape(GetParam(), request);
  bool differs = c.vertexCount() != a.vertexCount();
  for (std::size_t i = 0; !differs && i < a.vertexCount(); ++i) {
    differs = (a.vertices[i] - c.vertices[i]).norm() > 1e-3;
  }
  EXPECT_TRUE(differs);
}

TEST_P(RockGenerator, ManySeedsGiveValidConvexRocksOfTheRequestedVolume) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    ShapeRequest request;
    request.volume = 0.7;
    request.seed = seed;
    const TriangleMesh rock = makeShape(GetParam(), request);
    EXPECT_TRUE(inspectMesh(rock).valid()) << "seed " << seed;
    // makeShape scales to the volume: round-off only.
    EXPECT_NEAR(signedVolume(rock), 0.7, 1e-12) << "seed " << seed;
    // Convex: no vertex in front of any face plane by more than 1e-9 of the size.
    EXPECT_LT(convexityViolation(rock, rock.vertices), 1e-9) << "seed " << seed;
    // Longest dimension along x, shortest along z (the documented orientation).
    const Vec3 size = rock.bounds().size();
    EXPECT_GT(size.x(), size.y()) << "seed " << seed;
    EXPECT_GT(size.y(), size.z()) << "seed " << seed;
    // Moderate triangle count: tens to a few hundred for the defaults.
    EXPECT_GE(rock.triangleCount(), 30u) << "seed " << seed;
    EXPECT_LE(rock.triangleCount(), 300u) << "seed " << seed;
  }
}

TEST_P(RockGenerator, PrincipalExtentsFollowTheAspectRatios) {
  struct Case {
    double b, c;
  };
  for (const Case k : {Case{0.75, 0.55}, Case{0.5, 0.3}, Case{0.9, 0.8}}) {
    double sumB = 0.0;
    double sumC = 0.0;
    const int seeds = 10;
    for (int seed = 1; seed <= seeds; ++seed) {
      ShapeRequest request;
      request.seed = static_cast<std::uint64_t>(seed);
      request.params = {{"aspect_b", k.b}, {"aspect_c", k.c}};
      const TriangleMesh rock = makeShape(GetParam(), request);
      // The generators stretch the rock so that its bounding box has the requested proportions:
      // exact up to round-off (makeShape only centres and scales uniformly afterwards).
      const Vec3 box = rock.bounds().size();
      EXPECT_NEAR(box.y() / box.x(), k.b, 1e-12);
      EXPECT_NEAR(box.z() / box.x(), k.c, 1e-12);
      const auto e = principalExtents(rock);
      sumB += e[1] / e[0];
      sumC += e[2] / e[0];
    }
    // Extents along the principal axes of inertia (the orientation-free measure) differ from the
    // box because a random rock's principal axes tilt away from x, y, z: by up to 20 % for one
    // nearly isotropic rock (b = 0.9, c = 0.8), by a few percent on average. Seed-averaged ratios
    // must be within 10 % of the request.
    EXPECT_NEAR(sumB / seeds / k.b, 1.0, 0.10) << "b/a requested " << k.b;
    EXPECT_NEAR(sumC / seeds / k.c, 1.0, 0.10) << "c/a requested " << k.c;
  }
}

INSTANTIATE_TEST_SUITE_P(Rocks, RockGenerator, ::testing::Values("rock", "voronoi-rock"),
                         [](const auto& info) { return info.param == "rock" ? "Rock" : "VoronoiRock"; });

TEST(Rock, PointCountSetsTheFacetCount) {
  // Without jitter every sample point is on the ellipsoid and so a hull vertex: V points give
  // 2 V - 4 triangles (Euler, all faces triangles for points in general position).
  ShapeRequest request;
  request.params = {{"points", 100.0}, {"roughness", 0.0}};
  const TriangleMesh rock = makeShape("rock", request);
  EXPECT_EQ(rock.vertexCount(), 100u);
  EXPECT_EQ(rock.triangleCount(), 196u);
}

TEST(VoronoiRock, FacetEdgesAreNotTiny) {
  // The generator drops facets that make edges shorter than 0.2 x sqrt(area / neighbours), the
  // mean facet size. Facet edges are the mesh edges whose two triangles are not coplanar
  // (diagonals inside a facet are not checked: a sharp facet corner can make a short diagonal).
  // The final stretch to the exact box proportions changes lengths and area by a few percent,
  // hence 0.17 here.
  std::map<double, double> meanFacets;
  for (const double neighbours : {30.0, 100.0}) {
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      ShapeRequest request;
      request.seed = seed;
      request.params = {{"neighbours", neighbours}};
      const TriangleMesh rock = makeShape("voronoi-rock", request);
      const double minEdge = 0.17 * std::sqrt(rock.surfaceArea() / neighbours);
      std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::size_t>> edges;
      for (std::size_t t = 0; t < rock.triangleCount(); ++t) {
        const auto& f = rock.triangles[t];
        for (int k = 0; k < 3; ++k) {
          edges[{std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])}].push_back(t);
        }
      }
      std::size_t facetEdges = 0;
      for (const auto& [edge, faces] : edges) {
        ASSERT_EQ(faces.size(), 2u);
        const Vec3 n0 = rock.doubleAreaNormal(faces[0]).normalized();
        const Vec3 n1 = rock.doubleAreaNormal(faces[1]).normalized();
        if (n0.dot(n1) < 1.0 - 1e-9) {
          ++facetEdges;
          EXPECT_GE((rock.vertices[edge.first] - rock.vertices[edge.second]).norm(), minEdge)
              << "seed " << seed << ", " << neighbours << " neighbours";
        }
      }
      // Facets by Euler's formula for the polyhedron (every mesh vertex is a facet corner):
      // F = E - V + 2. The pruning stops at 10 facets.
      const auto facets = static_cast<double>(facetEdges) - static_cast<double>(rock.vertexCount()) + 2.0;
      EXPECT_GE(facets, 10.0) << "seed " << seed;
      meanFacets[neighbours] += facets / 10.0;
    }
  }
  // More neighbours, more (smaller) facets, though far fewer than the neighbours: most of them are
  // shadowed by nearer ones, as in a random Voronoi tessellation (about 15.5 faces per cell).
  // Measured about 16 and 28.
  EXPECT_GT(meanFacets[100.0], 1.3 * meanFacets[30.0]);
  EXPECT_GT(meanFacets[30.0], 12.0);
}

} // namespace
} // namespace armour::geometry
