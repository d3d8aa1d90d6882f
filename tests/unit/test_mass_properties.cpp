// SPDX-License-Identifier: GPL-3.0-or-later
// Mass properties of closed polyhedra against closed forms. Tolerance 1e-10 relative: the
// divergence-theorem sums are exact polynomials, so only round-off (~1e-15 per term) remains.

#include "geometry/MassProperties.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

using namespace armour::geometry;
using namespace armour::test;

namespace {
constexpr double kRel = 1e-10;

void expectMatrixNear(const Mat3& actual, const Mat3& expected, double scale) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(actual(r, c), expected(r, c), kRel * scale) << "entry (" << r << ", " << c << ")";
    }
  }
}
} // namespace

TEST(MassProperties, UnitCube) {
  const auto mp = computeMassProperties(makeBox(1.0, 1.0, 1.0));
  EXPECT_NEAR(mp.volume, 1.0, kRel);
  EXPECT_NEAR((mp.centroid - Vec3(0.5, 0.5, 0.5)).norm(), 0.0, kRel);
  expectMatrixNear(mp.inertia, Mat3::Identity() / 6.0, 1.0 / 6.0); // m a^2 / 6 with m = 1
  EXPECT_NEAR(mp.nominalDiameter(), 1.0, kRel);
}

TEST(MassProperties, BoxClosedForm) {
  const double a = 2.0, b = 0.7, c = 3.3;
  const auto mp = computeMassProperties(makeBox(a, b, c));
  const double m = a * b * c;
  EXPECT_NEAR(mp.volume, m, kRel * m);
  EXPECT_NEAR((mp.centroid - Vec3(a, b, c) / 2).norm(), 0.0, kRel * c);
  const Mat3 expected = Vec3(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12).asDiagonal();
  expectMatrixNear(mp.inertia, expected, expected.norm());
  // Principal moments ascending, axes right-handed.
  EXPECT_LE(mp.principalMoments[0], mp.principalMoments[1]);
  EXPECT_LE(mp.principalMoments[1], mp.principalMoments[2]);
  EXPECT_NEAR(mp.principalAxes.determinant(), 1.0, 1e-12);
}

TEST(MassProperties, RightTetrahedronClosedForm) {
  // Legs a, b, c on the axes: V = abc/6, centroid (a, b, c)/4,
  // about the centroid Ixx = 3 m (b^2 + c^2) / 80 and Ixy = + m a b / 80 (products of inertia
  // int xy dm = m ab / 20 about the origin, minus m ab / 16 for the shift).
  const double a = 1.5, b = 2.0, c = 0.8;
  const auto mp = computeMassProperties(makeTetrahedron(Vec3::Zero(), Vec3(a, 0, 0), Vec3(0, b, 0), Vec3(0, 0, c)));
  const double m = a * b * c / 6.0;
  EXPECT_NEAR(mp.volume, m, kRel * m);
  EXPECT_NEAR((mp.centroid - Vec3(a, b, c) / 4).norm(), 0.0, kRel * b);
  Mat3 expected;
  expected << 3 * m * (b * b + c * c) / 80, m * a * b / 80, m * a * c / 80, //
      m * a * b / 80, 3 * m * (a * a + c * c) / 80, m * b * c / 80,         //
      m * a * c / 80, m * b * c / 80, 3 * m * (a * a + b * b) / 80;
  expectMatrixNear(mp.inertia, expected, expected.norm());
}

TEST(MassProperties, RigidTransformInvariance) {
  // Volume is invariant, the centroid moves with the body and the inertia rotates as R I R^T,
  // also far from the origin (1 km away) thanks to the local reference point.
  const auto base = makeTetrahedron(Vec3(0.1, 0.2, 0.3), Vec3(1.7, 0.1, -0.2), Vec3(0.4, 2.1, 0.5), Vec3(0.2, 0.6, 1.9));
  const auto mp0 = computeMassProperties(base);
  const Mat3 R = someRotation();
  const Vec3 t(1000.0, -2000.0, 500.0);
  auto moved = base;
  transform(moved, R, t);
  const auto mp1 = computeMassProperties(moved);
  EXPECT_NEAR(mp1.volume, mp0.volume, kRel * mp0.volume);
  EXPECT_NEAR((mp1.centroid - (R * mp0.centroid + t)).norm(), 0.0, 1e-12 * t.norm());
  expectMatrixNear(mp1.inertia, R * mp0.inertia * R.transpose(), mp0.inertia.norm());
}

TEST(MassProperties, InwardMeshHasNegativeVolume) {
  auto box = makeBox(1.0, 2.0, 3.0);
  flipOrientation(box);
  EXPECT_NEAR(signedVolume(box), -6.0, kRel * 6.0);
}

TEST(MassProperties, ScaleToVolumeIsExactAndKeepsCentroid) {
  auto box = makeBox(1.0, 2.0, 3.0);
  translate(box, Vec3(5, 5, 5));
  scaleToVolume(box, 14.0);
  const auto mp = computeMassProperties(box);
  EXPECT_NEAR(mp.volume, 14.0, 1e-12 * 14.0);
  EXPECT_NEAR((mp.centroid - Vec3(5.5, 6.0, 6.5)).norm(), 0.0, 1e-12);
}
