// SPDX-License-Identifier: GPL-3.0-or-later
// Pack geometry (analysis/PackGeometry.hpp):
//  - the verification: a regular grid of N cubes of side a at spacing Dx x Dy on a flat
//    slope reproduces phi = Dn^2 / (Dx Dy) (Dn = a) exactly (round-off, 1e-12), through a window
//    of whole grid cells; the convex hull of the centroids gives N a^2 / ((nx-1) Dx (ny-1) Dy);
//  - cubes lying on the underlayer plane: slope-normal extent [0, a], layer thickness a, layer
//    coefficient 1 (round-off);
//  - porosity by Halton sampling: cubes face to face fill their slab (porosity 0; the only misses
//    are points exactly on shared faces, where the winding number is 1/2: at most a few in 4000);
//    cubes at spacing 2a leave 3/4 of their slab empty (within 4 binomial standard deviations of
//    4000 points, 0.027, a conservative bound for Halton points), the slab above them is empty;
//  - the winding number of a closed mesh is 1 inside, 0 outside;
//  - contact numbers from a handmade contact list.

#include "analysis/PackGeometry.hpp"
#include "core/Error.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace armour::analysis;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

/// A cube of side a centred on the origin.
armour::geometry::TriangleMesh centredCube(double a) {
  auto m = armour::test::makeBox(a, a, a);
  armour::geometry::translate(m, Vector3d::Constant(-0.5 * a));
  return m;
}

/// Rotation taking the body z axis to the slope normal, then turned by `spin` about the normal.
Quaterniond onSlope(const SlopeFrame& f, double spin) {
  const Quaterniond tilt = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), f.normal);
  return Quaterniond(Eigen::AngleAxisd(spin, f.normal)) * tilt;
}

struct Grid {
  std::vector<Vector3d> positions;
  std::vector<Quaterniond> orientations;
};

/// nx x ny cubes of side a resting on the slope plane with cell centres at ((i + 1/2) dx, (j + 1/2) dy).
Grid cubeGrid(const SlopeFrame& f, int nx, int ny, double dx, double dy, double a) {
  Grid g;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      g.positions.push_back(f.toWorld(Vector3d((i + 0.5) * dx, (j + 0.5) * dy, 0.5 * a)));
      g.orientations.push_back(onSlope(f, 0.0));
    }
  }
  return g;
}

} // namespace

TEST(PackGeometry, RegularGridReproducesItsAnalyticPackingDensity) {
  const SlopeFrame f = SlopeFrame::fromTanAlpha(0.5, Vector3d(3.0, -2.0, 1.0));
  const double a = 1.2, dx = 1.5, dy = 1.7;
  const int nx = 7, ny = 9;
  const Grid g = cubeGrid(f, nx, ny, dx, dy, a);
  const PackingDensity w = packingDensityInWindow(g.positions, {a}, f, {0.0, nx * dx, 0.0, ny * dy});
  EXPECT_EQ(w.count, static_cast<std::size_t>(nx * ny));
  EXPECT_NEAR(w.area, nx * dx * ny * dy, 1e-12);
  EXPECT_NEAR(w.phi, a * a / (dx * dy), 1e-12);
  EXPECT_NEAR(packingDensity(w.count, a, w.area), a * a / (dx * dy), 1e-12);
  // Any window of whole cells gives the same phi, and windows split on a cell boundary tile.
  const PackingDensity lower = packingDensityInWindow(g.positions, {a}, f, {0.0, 3 * dx, 2 * dy, 6 * dy});
  const PackingDensity upper = packingDensityInWindow(g.positions, {a}, f, {3 * dx, nx * dx, 2 * dy, 6 * dy});
  EXPECT_NEAR(lower.phi, a * a / (dx * dy), 1e-12);
  EXPECT_EQ(lower.count + upper.count, static_cast<std::size_t>(nx * 4));
  // The hull joins the outer centres: area (nx - 1) dx (ny - 1) dy.
  const PackingDensity hull = packingDensityHull(g.positions, {a}, f);
  EXPECT_NEAR(hull.area, (nx - 1) * dx * (ny - 1) * dy, 1e-10);
  EXPECT_NEAR(hull.phi, nx * ny * a * a / ((nx - 1) * dx * (ny - 1) * dy), 1e-12);
  EXPECT_THROW((void)packingDensityInWindow(g.positions, {a}, f, {1.0, 1.0, 0.0, 2.0}), armour::core::InputError);
  EXPECT_THROW((void)packingDensityHull({Vector3d(0, 0, 0), Vector3d(1, 0, 0.5)}, {a}, f), armour::core::InputError);
}

TEST(PackGeometry, ConvexHullArea) {
  // A unit square with interior and edge points, and a triangle.
  EXPECT_NEAR(convexHullArea({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.5, 0}, {0.2, 0.7}}), 1.0, 1e-15);
  EXPECT_NEAR(convexHullArea({{0, 0}, {4, 0}, {0, 3}}), 6.0, 1e-15);
  EXPECT_EQ(convexHullArea({{0, 0}, {1, 1}, {2, 2}}), 0.0);
}

TEST(PackGeometry, CubesOnTheUnderlayerGiveThicknessA) {
  const SlopeFrame f = SlopeFrame::fromTanAlpha(2.0 / 3.0, Vector3d(10.0, 0.0, -4.0));
  const double a = 2.0;
  const auto cube = centredCube(a);
  Grid g = cubeGrid(f, 4, 5, 2.5, 2.5, a);
  std::vector<double> tops;
  for (std::size_t i = 0; i < g.positions.size(); ++i) {
    g.orientations[i] = onSlope(f, 0.3 * static_cast<double>(i)); // spun about n: same extent
    const Eigen::Vector2d e = normalExtent(cube, g.positions[i], g.orientations[i], f);
    EXPECT_NEAR(e.x(), 0.0, 1e-12);
    EXPECT_NEAR(e.y(), a, 1e-12);
    tops.push_back(e.y());
  }
  const LayerThickness t = layerThickness(g.positions, tops, {a}, f, {0.0, 10.0, 0.0, 12.5});
  EXPECT_EQ(t.count, 20u);
  EXPECT_NEAR(t.thickness, a, 1e-12);
  EXPECT_NEAR(t.layerCoefficient, 1.0, 1e-12);
  // SPM/CEM: phi = n k (1 - P) inverts porosityFromPackingDensity.
  EXPECT_NEAR(layerCoefficient(2.0 * 1.02 * 1.5, 2, 1.5), 1.02, 1e-15);
  EXPECT_NEAR(porosityFromPackingDensity(2 * 1.02 * (1 - 0.37), 2, 1.02), 0.37, 1e-15);
  EXPECT_THROW((void)layerThickness(g.positions, tops, {a}, f, {100.0, 110.0, 0.0, 1.0}), armour::core::InputError);
}

TEST(PackGeometry, HaltonSequence) {
  EXPECT_EQ(halton(1, 2), 0.5);
  EXPECT_EQ(halton(2, 2), 0.25);
  EXPECT_EQ(halton(3, 2), 0.75);
  EXPECT_NEAR(halton(1, 3), 1.0 / 3.0, 1e-16);
  EXPECT_NEAR(halton(5, 3), 2.0 / 3.0 + 1.0 / 9.0, 1e-16); // 5 = 12 in base 3
  EXPECT_NEAR(halton(7, 5), 2.0 / 5.0 + 1.0 / 25.0, 1e-16); // 7 = 12 in base 5
}

TEST(PackGeometry, WindingNumberOfAClosedMesh) {
  const auto cube = centredCube(2.0);
  EXPECT_NEAR(windingNumber(cube, Vector3d::Zero()), 1.0, 1e-12);
  EXPECT_NEAR(windingNumber(cube, Vector3d(0.999, -0.999, 0.5)), 1.0, 1e-9);
  EXPECT_NEAR(windingNumber(cube, Vector3d(1.001, 0.0, 0.0)), 0.0, 1e-9);
  EXPECT_NEAR(windingNumber(cube, Vector3d(30.0, -7.0, 2.0)), 0.0, 1e-12);
  const auto tet =
      armour::test::makeTetrahedron(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1));
  EXPECT_TRUE(insideMesh(tet, Vector3d(0.2, 0.2, 0.2)));
  EXPECT_FALSE(insideMesh(tet, Vector3d(0.4, 0.4, 0.4)));
}

TEST(PackGeometry, PorosityOfSlabsOfCubes) {
  const SlopeFrame f = SlopeFrame::fromTanAlpha(0.5, Vector3d(1.0, 2.0, 3.0));
  const double a = 1.0;
  const std::vector<armour::geometry::TriangleMesh> shapes = {centredCube(a)};
  constexpr std::size_t samples = 4000;
  // Face to face: a 4 x 4 block of cubes fills the slab [0, a) over the window [0, 4a)^2.
  {
    const Grid g = cubeGrid(f, 4, 4, a, a, a);
    const std::vector<std::size_t> shapeOf(g.positions.size(), 0);
    const auto inside = insideAnyUnit(shapes, shapeOf, g.positions, g.orientations);
    const auto slabs = porosityProfile(inside, f, {0.0, 4 * a, 0.0, 4 * a}, 0.0, a, 1, samples);
    ASSERT_EQ(slabs.size(), 1u);
    EXPECT_LE(slabs[0].porosity, 0.005) << slabs[0].samples - slabs[0].solid << " misses";
    EXPECT_NEAR(slabs[0].volume, 16.0 * a * a * a, 1e-12);
  }
  // Spacing 2a: a quarter of the slab is solid; the slab above the cubes is empty.
  {
    const Grid g = cubeGrid(f, 4, 4, 2 * a, 2 * a, a);
    const std::vector<std::size_t> shapeOf(g.positions.size(), 0);
    const auto inside = insideAnyUnit(shapes, shapeOf, g.positions, g.orientations);
    const auto slabs = porosityProfile(inside, f, {0.0, 8 * a, 0.0, 8 * a}, 0.0, 2 * a, 2, samples);
    ASSERT_EQ(slabs.size(), 2u);
    const double expected = porosityFromCount(16, a * a * a, 64 * a * a * a);
    EXPECT_EQ(expected, 0.75);
    const double sigma = std::sqrt(0.75 * 0.25 / samples);
    EXPECT_NEAR(slabs[0].porosity, expected, 4.0 * sigma);
    EXPECT_NEAR(slabs[0].standardError, sigma, 0.1 * sigma);
    EXPECT_EQ(slabs[1].porosity, 1.0);
    EXPECT_NEAR(slabs[1].n0, a, 1e-15);
  }
  EXPECT_THROW((void)porosityProfile([](const Vector3d&) { return false; }, f, {0, 1, 0, 1}, 1.0, 0.5, 1, 10),
               armour::core::InputError);
}

TEST(PackGeometry, ContactNumbersFromAPairList) {
  // Units 0-3, supports 4 and 5 (e.g. underlayer rocks).
  const std::vector<BodyRole> roles = {BodyRole::unit,    BodyRole::unit,    BodyRole::unit,
                                       BodyRole::unit,    BodyRole::support, BodyRole::support};
  const std::vector<Contact> contacts = {
      {0, 1, 100.0}, {1, 0, 50.0}, // one pair, two contact points: 150 N
      {1, 2, 30.0},  {2, 3, 10.0}, {3, 2, 5.0}, // 2-3: 15 N
      {0, 4, 500.0}, {0, 5, 20.0}, {4, 5, 1000.0}, // support-support: ignored
  };
  const PackContacts r = contactNumbers(contacts, roles);
  EXPECT_EQ(r.unitCount, 4u);
  EXPECT_EQ(r.unitUnitPairs, 3u);
  EXPECT_EQ(r.unitSupportPairs, 2u);
  EXPECT_DOUBLE_EQ(r.coordinationNumber, 1.5);
  EXPECT_DOUBLE_EQ(r.meanContactNumber, (3 + 2 + 2 + 1) / 4.0);
  EXPECT_EQ(r.minContactNumber, 1u);
  EXPECT_EQ(r.maxContactNumber, 3u);
  EXPECT_EQ(r.maxForce, 500.0);
  EXPECT_EQ(r.bodies[0].unitNeighbours, 1u);
  EXPECT_EQ(r.bodies[0].supportNeighbours, 2u);
  EXPECT_EQ(r.bodies[0].contactNumber, 3u);
  EXPECT_EQ(r.bodies[0].maxForce, 500.0);
  EXPECT_EQ(r.bodies[1].contactNumber, 2u);
  EXPECT_EQ(r.bodies[1].maxForce, 150.0);
  EXPECT_EQ(r.bodies[2].maxForce, 30.0);
  EXPECT_EQ(r.bodies[3].contactNumber, 1u);
  EXPECT_EQ(r.bodies[3].maxForce, 15.0);
  EXPECT_EQ(r.bodies[4].contactNumber, 0u) << "supports are not analysed";
  // A force floor of 20 N drops the 15 N pair 2-3 and keeps the 20 N one.
  const PackContacts strong = contactNumbers(contacts, roles, 20.0);
  EXPECT_EQ(strong.unitUnitPairs, 2u);
  EXPECT_EQ(strong.bodies[3].contactNumber, 0u);
  EXPECT_EQ(strong.minContactNumber, 0u);
  EXPECT_EQ(strong.bodies[0].supportNeighbours, 2u);
  EXPECT_THROW((void)contactNumbers({{0, 0, 1.0}}, roles), armour::core::InputError);
  EXPECT_THROW((void)contactNumbers({{0, 6, 1.0}}, roles), armour::core::InputError);
  EXPECT_THROW((void)contactNumbers({{0, 1, -1.0}}, roles), armour::core::InputError);
}
