// SPDX-License-Identifier: GPL-3.0-or-later
// Surface samples: tributary areas that integrate the surface exactly, corners and sharp edges
// sampled, spacing and covering radius respected, samples on the surface, normals, scaling.
#include "contact/LevelSet.hpp"
#include "contact/SurfaceSamples.hpp"
#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"

#include "support/ShapeCache.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace armour::contact {
namespace {

using geometry::ShapeRequest;
using geometry::TriangleMesh;
using geometry::Vec3;

/// makeShape(name) at V = 1 m^3 (Dn = 1 m), built once per test program.
const TriangleMesh& shape(const std::string& name) { return test::unitShape(name); }

/// Default samples of shape(name), built once.
const SurfaceSamples& shapeSamples(const std::string& name) { return test::perUnitShape<SurfaceSamples>(name); }

/// Distance from x to the segment [a, b] and the parameter of the closest point.
double segmentDistance(const Vec3& x, const Vec3& a, const Vec3& b, double& t) {
  const Vec3 ab = b - a;
  t = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (x - (a + t * ab)).norm();
}

class SamplesOfShape : public ::testing::TestWithParam<std::string> {};

TEST_P(SamplesOfShape, AreasIntegrateTheSurfaceExactly) {
  const TriangleMesh& mesh = shape(GetParam());
  const SurfaceSamples& samples = shapeSamples(GetParam());
  double sum = 0.0;
  Vec3 moment = Vec3::Zero();
  Vec3 resultant = Vec3::Zero();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_GT(samples.areas()[i], 0.0);
    sum += samples.areas()[i];
    moment += samples.areas()[i] * samples.positions()[i];
    resultant += samples.areaVectors()[i];
  }
  // Every refined triangle hands out its area in three exact thirds, and bisection conserves area:
  // the sum is the surface area up to the round-off of a few thousand additions.
  const double area = mesh.surfaceArea();
  EXPECT_NEAR(sum, area, 1e-12 * area);
  EXPECT_NEAR(samples.totalArea(), area, 1e-12 * area);
  // A third of the area at each corner is exact for linear integrands (the centroid of a triangle
  // is the mean of its corners): the first moment equals int_S x dA of the mesh, so a uniform
  // pressure over a face acts at the face's centroid.
  Vec3 exactMoment = Vec3::Zero();
  Vec3 exactResultant = Vec3::Zero();
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto c = mesh.corners(t);
    exactMoment += mesh.area(t) * (c[0] + c[1] + c[2]) / 3.0;
    exactResultant += 0.5 * mesh.doubleAreaNormal(t);
  }
  EXPECT_NEAR((moment - exactMoment).norm(), 0.0, 1e-12 * area);
  // The area vectors sum to the closed surface's zero resultant (a uniform pressure pushes nowhere).
  EXPECT_NEAR(resultant.norm(), 0.0, 1e-12 * area);
  EXPECT_NEAR(exactResultant.norm(), 0.0, 1e-12 * area);
}

TEST_P(SamplesOfShape, EveryVertexAndEverySharpEdgeIsSampledAtTheSpacing) {
  const TriangleMesh& mesh = shape(GetParam());
  const SurfaceSamples& samples = shapeSamples(GetParam());
  const double s = samples.spacing();
  EXPECT_NEAR(s, 0.1, 1e-12); // default spacingOverDn x Dn (Dn = 1 m to the round-off of the volume)
  ASSERT_EQ(samples.meshVertexCount(), mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    EXPECT_EQ(samples.positions()[v], mesh.vertices[v]) << v;
  }
  // Along every mesh edge (sharp or not), the samples on it, sorted, are at most s apart and
  // include both ends: a cube edge landing on a face meets samples every s or closer.
  std::map<std::pair<int, int>, bool> edges;
  for (const auto& f : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      edges[std::minmax(f[k], f[(k + 1) % 3])] = true;
    }
  }
  double worstGap = 0.0;
  for (const auto& [e, unused] : edges) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(e.first)];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(e.second)];
    std::vector<double> along;
    for (const Vec3& p : samples.positions()) {
      double t = 0.0;
      // Bisection points of a straight edge are its midpoints: on it to round-off.
      if (segmentDistance(p, a, b, t) <= 1e-12) {
        along.push_back(t);
      }
    }
    std::sort(along.begin(), along.end());
    ASSERT_GE(along.size(), 2u);
    EXPECT_EQ(along.front(), 0.0);
    EXPECT_EQ(along.back(), 1.0);
    for (std::size_t i = 1; i < along.size(); ++i) {
      const double gap = (along[i] - along[i - 1]) * (b - a).norm();
      EXPECT_LE(gap, s * (1.0 + 1e-12));
      worstGap = std::max(worstGap, gap);
    }
  }
  EXPECT_GT(worstGap, 0.5 * s * (1.0 - 1e-12)); // bisection stops at the first length <= s
}

TEST_P(SamplesOfShape, EverySurfacePointIsWithinSpacingOverSqrt3OfASample) {
  // The refined triangles have every edge <= s. In a triangle, the point farthest from all three
  // corners is the circumcentre when the triangle is acute (R = a / (2 sin A) <= s / sqrt 3, the
  // largest angle A being >= 60 degrees), and otherwise a point of the longest edge, within s / 2
  // of one of its ends. So the covering radius is s / sqrt(3).
  const TriangleMesh& mesh = shape(GetParam());
  const SurfaceSamples& samples = shapeSamples(GetParam());
  const double bound = samples.spacing() / std::sqrt(3.0);
  std::vector<double> cumulative;
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    total += mesh.area(t);
    cumulative.push_back(total);
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    const auto t = static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) -
                                            cumulative.begin());
    const auto c = mesh.corners(std::min(t, mesh.triangleCount() - 1));
    double b1 = u(rng);
    double b2 = u(rng);
    if (b1 + b2 > 1.0) {
      b1 = 1.0 - b1;
      b2 = 1.0 - b2;
    }
    const Vec3 x = c[0] + b1 * (c[1] - c[0]) + b2 * (c[2] - c[0]);
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& p : samples.positions()) {
      nearest = std::min(nearest, (p - x).squaredNorm());
    }
    worst = std::max(worst, std::sqrt(nearest));
  }
  EXPECT_LE(worst, bound * (1.0 + 1e-12));
  std::printf("[ %s ] %zu samples at spacing %.3g Dn: farthest surface point from a sample %.3f s (bound %.3f s)\n",
              GetParam().c_str(), samples.size(), samples.spacing(), worst / samples.spacing(), 1.0 / std::sqrt(3.0));
}

TEST_P(SamplesOfShape, SamplesLieOnTheSurfaceOfTheMeshAndOfItsLevelSet) {
  const TriangleMesh& mesh = shape(GetParam());
  const SurfaceSamples& samples = shapeSamples(GetParam());
  const MeshDistance exact(mesh);
  const LevelSet ls(mesh);
  const double h = ls.cellSize();
  double worst = 0.0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3& p = samples.positions()[i];
    // Midpoints of straight edges: on the surface to round-off.
    EXPECT_LE(std::abs(exact.signedDistance(p)), 1e-12) << i;
    EXPECT_NEAR(samples.normals()[i].norm(), 1.0, 1e-12);
    // On the grid, within the trilinear interpolation error of a 1-Lipschitz function
    // (test_level_set: <= sqrt(3) h / 2; float rounding of O(h) node values is 1e-7 h).
    const double phi = ls.distance(p);
    EXPECT_LE(std::abs(phi), std::sqrt(3.0) / 2.0 * h + 1e-7 * h) << i;
    worst = std::max(worst, std::abs(phi) / h);
  }
  std::printf("[ %s ] max |phi(sample)| = %.3f h\n", GetParam().c_str(), worst);
}

INSTANTIATE_TEST_SUITE_P(Units, SamplesOfShape, ::testing::Values("cube", "dolos", "coreloc", "rock", "antifer"));

TEST(SurfaceSamplesCube, NormalsAtFacesEdgesAndCornersAndFlatContactArea) {
  const SurfaceSamples& samples = shapeSamples("cube");
  double bottomArea = 0.0;
  double bottomProjected = 0.0;
  int counts[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3& p = samples.positions()[i];
    // Coordinates of the unit cube's faces are +-0.5, and midpoints of such points keep them
    // exactly: the number of coordinates at +-0.5 tells face (1), edge (2) or corner (3).
    Vec3 expected = Vec3::Zero();
    int onFaces = 0;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(p[k]) == 0.5) {
        expected[k] = p[k] > 0 ? 1.0 : -1.0;
        ++onFaces;
      }
    }
    ASSERT_GE(onFaces, 1);
    ++counts[onFaces];
    // Angle-weighted: each face meeting at the sample contributes the same angle (pi at an edge
    // point, pi / 2 at a corner), so the normal is the face normal, the edge bisector or the
    // cube diagonal, to round-off.
    EXPECT_NEAR((samples.normals()[i] - expected.normalized()).norm(), 0.0, 1e-12) << p.transpose();
    if (p.z() == -0.5) {
      bottomArea += samples.areas()[i];
      bottomProjected += std::max(0.0, -samples.areaVectors()[i].z());
    }
  }
  EXPECT_EQ(counts[3], 8);
  EXPECT_GT(counts[2], 12 * 8); // edges of length 1 at spacing <= 0.1: at least 9 points inside each
  // A cube pressed flat into a floor engages the samples of its bottom face. Projected on the
  // floor normal their area vectors give exactly the face area; their scalar areas also carry
  // a third of the side triangles along the edges.
  EXPECT_NEAR(bottomProjected, 1.0, 1e-12);
  EXPECT_GT(bottomArea, 1.0);
  std::printf("[ cube ] %d face, %d edge, 8 corner samples; bottom face: scalar area %.4f, projected %.4f m^2\n",
              counts[1], counts[2], bottomArea, bottomProjected);
}

TEST(SurfaceSamplesScale, ScaledSamplesEqualSamplesOfTheScaledMesh) {
  const TriangleMesh& mesh = shape("dolos");
  const SurfaceSamples& base = shapeSamples("dolos");
  // s = 2 is exact in binary and bisection compares squared lengths with s^2 h^2, so sampling the
  // scaled mesh reproduces the scaled samples bit for bit.
  TriangleMesh big = mesh;
  geometry::scale(big, 2.0);
  const SurfaceSamples direct(big);
  const SurfaceSamples scaled = base.scaled(2.0);
  ASSERT_EQ(direct.size(), scaled.size());
  EXPECT_EQ(direct.positions(), scaled.positions());
  EXPECT_DOUBLE_EQ(direct.spacing(), scaled.spacing());
  for (std::size_t i = 0; i < direct.size(); ++i) {
    EXPECT_NEAR(direct.areas()[i], scaled.areas()[i], 1e-15 * direct.totalArea());
    EXPECT_NEAR((direct.normals()[i] - scaled.normals()[i]).norm(), 0.0, 1e-14);
  }
  // Any factor: positions x s, areas x s^2, normals unchanged.
  const double s = 0.37;
  const SurfaceSamples small = base.scaled(s);
  EXPECT_NEAR(small.totalArea(), s * s * base.totalArea(), 1e-14);
  EXPECT_NEAR(small.boundingRadius(), s * base.boundingRadius(), 1e-15);
  for (std::size_t i = 0; i < base.size(); ++i) {
    EXPECT_EQ(small.positions()[i], s * base.positions()[i]);
    EXPECT_EQ(small.normals()[i], base.normals()[i]);
  }
}

TEST(SurfaceSamplesOrder, RepeatableAndSpacingControlsTheCount) {
  const SurfaceSamples& a = shapeSamples("coreloc");
  const SurfaceSamples b(shape("coreloc"));
  EXPECT_EQ(a.positions(), b.positions());
  EXPECT_EQ(a.areas(), b.areas());
  // Halving the spacing roughly quadruples the samples (a surface, refined by bisection: about
  // 2 to 4.2 area / s^2 vertices, docs/theory.md section 3).
  SurfaceSampleSettings finer;
  finer.spacingOverDn = 0.05;
  const SurfaceSamples c(shape("coreloc"), finer);
  const double ratio = static_cast<double>(c.size()) / static_cast<double>(a.size());
  EXPECT_GT(ratio, 2.5);
  EXPECT_LT(ratio, 5.0);
  std::printf("[ report ] samples at spacing Dn/10:");
  for (const std::string name : {"cube", "dolos", "coreloc", "rock", "antifer"}) {
    std::printf(" %s %zu", name.c_str(), shapeSamples(name).size());
  }
  std::printf("; coreloc at Dn/20: %zu\n", c.size());
}

TEST(SurfaceSamplesInput, BadSettingsAreRefused) {
  const TriangleMesh& cube = shape("cube");
  SurfaceSampleSettings bad;
  bad.spacingOverDn = 0.0;
  EXPECT_THROW(SurfaceSamples(cube, bad, "cube"), core::InputError);
  SurfaceSampleSettings tiny;
  tiny.spacing = 1e-6; // 2.5e13 samples: a spacing in the wrong unit
  try {
    SurfaceSamples s(cube, tiny, "cube");
    FAIL() << "expected InputError";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("maxSamples"), std::string::npos) << e.what();
  }
  TriangleMesh inverted = cube;
  geometry::flipOrientation(inverted);
  EXPECT_THROW(SurfaceSamples(inverted, {}, "cube"), core::InputError);
}

} // namespace
} // namespace armour::contact
