// SPDX-License-Identifier: GPL-3.0-or-later
// Attitude of unit axes relative to the slope (analysis/Orientation.hpp; seed 000 Fig. 2c):
//  - the slope frame is orthonormal, right-handed, its normal points up and offshore;
//  - an axis along the normal dips 90 deg; one along the trunk axis dips 0 at azimuth 0; one along
//    the down-slope direction dips 0 at azimuth 90 deg (the header's convention); attitude() and
//    axisFromAttitude() are inverses (round-off, 1e-12);
//  - turning a whole pack about the slope normal by an angle adds the angle to every azimuth and
//    leaves the dips alone (1e-9: round-off of composed rotations);
//  - the least-squares slope through points on a known plane gives its tan(alpha) to 1e-12;
//  - the Schmidt projection preserves area: of N = 1e5 isotropic axes, the fraction plotted within
//    radius r is r^2, within 4 binomial standard deviations sqrt(p (1 - p) / N);
//  - body axes of the library shapes, and their errors.

#include "analysis/Orientation.hpp"
#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using armour::analysis::AxisAttitude;
using armour::analysis::SlopeFrame;
using armour::analysis::attitude;
using armour::analysis::axisFromAttitude;
using armour::analysis::stereonetPoint;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

Vector3d randomAxis(std::mt19937_64& rng) {
  const double z = 2.0 * uniform(rng) - 1.0;
  const double a = 2.0 * kPi * uniform(rng);
  const double r = std::sqrt(1.0 - z * z);
  return {r * std::cos(a), r * std::sin(a), z};
}

/// Uniformly random rotation (Shoemake's method).
Quaterniond randomRotation(std::mt19937_64& rng) {
  const double u1 = uniform(rng);
  const double u2 = 2.0 * kPi * uniform(rng);
  const double u3 = 2.0 * kPi * uniform(rng);
  const double a = std::sqrt(1.0 - u1);
  const double b = std::sqrt(u1);
  return Quaterniond(a * std::cos(u2), a * std::sin(u2), b * std::cos(u3), b * std::sin(u3));
}

/// Angle difference folded into (-pi, pi].
double wrap(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a > kPi) a -= 2.0 * kPi;
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

/// Seed 000's 4H:3V slope.
SlopeFrame seedSlope() { return SlopeFrame::fromTanAlpha(0.75, Vector3d(12.0, -3.0, 4.0)); }

} // namespace

TEST(Orientation, SlopeFrameIsRightHandedWithAnOutwardNormal) {
  const SlopeFrame f = seedSlope();
  EXPECT_NEAR(f.upSlope.norm(), 1.0, 1e-15);
  EXPECT_NEAR(f.normal.norm(), 1.0, 1e-15);
  EXPECT_NEAR(f.upSlope.dot(f.trunk), 0.0, 1e-15);
  EXPECT_NEAR((f.upSlope.cross(f.trunk) - f.normal).norm(), 0.0, 1e-15);
  EXPECT_GT(f.normal.z(), 0.0) << "the normal points up";
  EXPECT_LT(f.normal.x(), 0.0) << "and offshore (-x)";
  EXPECT_GT(f.upSlope.x(), 0.0);
  EXPECT_GT(f.upSlope.z(), 0.0);
  EXPECT_NEAR(f.tanAlpha(), 0.75, 1e-15);
  const Vector3d p(3.0, 7.0, -2.0);
  EXPECT_NEAR((f.toWorld(f.toLocal(p)) - p).norm(), 0.0, 1e-13);
  EXPECT_THROW((void)SlopeFrame::fromTanAlpha(INFINITY, Vector3d::Zero()), armour::core::InputError);
  EXPECT_THROW((void)SlopeFrame::fromTanAlpha(std::nan(""), Vector3d::Zero()), armour::core::InputError);
}

TEST(Orientation, AxisNormalToTheSlopeDipsNinetyDegrees) {
  const SlopeFrame f = seedSlope();
  for (const Vector3d& u : {Vector3d(-f.normal), Vector3d(f.normal), Vector3d(-3.0 * f.normal)}) {
    const AxisAttitude a = attitude(u, f);
    EXPECT_NEAR(a.dip, kPi / 2.0, 1e-12);
    EXPECT_EQ(a.dipAzimuth, 0.0) << "no azimuth for a vertical pole: set to 0";
    EXPECT_NEAR(stereonetPoint(a).norm(), 0.0, 1e-12) << "plots at the centre";
  }
}

TEST(Orientation, AxesInTheSlopePlane) {
  const SlopeFrame f = seedSlope();
  const Vector3d down = -f.upSlope;
  // Along the trunk: dip 0, azimuth 0, both signs (an in-plane axis takes the azimuth in [0, pi)).
  for (const Vector3d& u : {Vector3d(f.trunk), Vector3d(-f.trunk)}) {
    const AxisAttitude a = attitude(u, f);
    EXPECT_NEAR(a.dip, 0.0, 1e-12);
    EXPECT_NEAR(a.dipAzimuth, 0.0, 1e-12);
    EXPECT_NEAR((stereonetPoint(a) - Eigen::Vector2d(-1.0, 0.0)).norm(), 0.0, 1e-12) << "t is on the left";
  }
  // Down-slope: azimuth 90 deg; up-slope is the same line.
  for (const Vector3d& u : {down, Vector3d(f.upSlope)}) {
    const AxisAttitude a = attitude(u, f);
    EXPECT_NEAR(a.dip, 0.0, 1e-12);
    EXPECT_NEAR(a.dipAzimuth, kPi / 2.0, 1e-12);
    EXPECT_NEAR((stereonetPoint(a) - Eigen::Vector2d(0.0, -1.0)).norm(), 0.0, 1e-12) << "down-slope at the bottom";
  }
  // Half-way between t and down-slope, 30 deg into the slope: azimuth 45 deg, dip 30 deg.
  const Vector3d u = std::cos(30 * kDeg) * (f.trunk + down).normalized() - std::sin(30 * kDeg) * f.normal;
  EXPECT_NEAR(attitude(u, f).dip, 30 * kDeg, 1e-12);
  EXPECT_NEAR(attitude(u, f).dipAzimuth, 45 * kDeg, 1e-12);
  EXPECT_NEAR(attitude(-u, f).dipAzimuth, 45 * kDeg, 1e-12) << "the other end of the same axis";
  // Into the slope and up-slope: azimuth 270 deg.
  const Vector3d v = std::cos(20 * kDeg) * f.upSlope - std::sin(20 * kDeg) * f.normal;
  EXPECT_NEAR(attitude(v, f).dipAzimuth, 270 * kDeg, 1e-12);
}

TEST(Orientation, AttitudeAndAxisFromAttitudeAreInverses) {
  const SlopeFrame f = SlopeFrame::fromTanAlpha(0.5, Vector3d(1.0, 2.0, 3.0));
  std::mt19937_64 rng(5);
  for (int k = 0; k < 1000; ++k) {
    const Vector3d u = randomAxis(rng);
    const AxisAttitude a = attitude(u, f);
    ASSERT_GE(a.dip, 0.0);
    ASSERT_LE(a.dip, kPi / 2.0);
    ASSERT_GE(a.dipAzimuth, 0.0);
    ASSERT_LT(a.dipAzimuth, 2.0 * kPi);
    const Vector3d back = axisFromAttitude(a, f);
    EXPECT_NEAR(std::abs(back.dot(u)), 1.0, 1e-12) << "the same line";
    EXPECT_LE(back.dot(f.normal), 1e-15) << "pointing into the slope";
  }
}

TEST(Orientation, TurningThePackAboutTheNormalShiftsEveryAzimuth) {
  const SlopeFrame f = seedSlope();
  std::mt19937_64 rng(9);
  std::vector<Quaterniond> pack;
  for (int k = 0; k < 200; ++k) pack.push_back(randomRotation(rng));
  const Vector3d nose = armour::analysis::noseAxisOf("coreloc");
  const auto before = armour::analysis::noseAxesWorld(pack, nose);
  for (const double turn : {10 * kDeg, 95 * kDeg, -140 * kDeg}) {
    const Quaterniond r(Eigen::AngleAxisd(turn, f.normal));
    std::vector<Quaterniond> turned;
    for (const auto& q : pack) turned.push_back(r * q);
    const auto after = armour::analysis::noseAxesWorld(turned, nose);
    for (std::size_t i = 0; i < pack.size(); ++i) {
      const AxisAttitude a = attitude(before[i], f);
      const AxisAttitude b = attitude(after[i], f);
      EXPECT_NEAR(b.dip, a.dip, 1e-9);
      if (a.dip < 89 * kDeg) { // the azimuth of a near-vertical pole is ill-conditioned
        EXPECT_NEAR(wrap(b.dipAzimuth - a.dipAzimuth - turn), 0.0, 1e-9) << "unit " << i;
      }
    }
  }
}

TEST(Orientation, FittedPlaneRecoversTheSlope) {
  // Points on z = 4 + (x - 30) tan(alpha), spread along the trunk, far from the origin, and pairs
  // offset by +-e along z at the same x (zero-mean residuals at every x leave the fit exact).
  for (const double tanAlpha : {0.0, 0.5, 0.75, 2.0 / 3.0}) {
    std::mt19937_64 rng(3);
    std::vector<Vector3d> points;
    for (int k = 0; k < 100; ++k) {
      const double x = 30.0 + 20.0 * uniform(rng);
      const double y = 1000.0 + 40.0 * uniform(rng);
      const double z = 4.0 + (x - 30.0) * tanAlpha;
      const double e = 0.5 * uniform(rng);
      points.emplace_back(x, y, z + e);
      points.emplace_back(x, y + 1.0, z - e);
    }
    const SlopeFrame f = armour::analysis::fitSlopeFrame(points);
    EXPECT_NEAR(f.tanAlpha(), tanAlpha, 1e-12);
    EXPECT_NEAR(f.toLocal(Vector3d(30.0, 0.0, 4.0)).z(), 0.0, 1e-11) << "the plane passes through the known line";
  }
  EXPECT_THROW((void)armour::analysis::fitSlopeFrame({Vector3d(1, 2, 3)}), armour::core::InputError);
  EXPECT_THROW((void)armour::analysis::fitSlopeFrame({Vector3d(1, 2, 3), Vector3d(1, 5, 6)}), armour::core::InputError)
      << "all at the same x";
  EXPECT_THROW((void)armour::analysis::fitSlopeFrame({Vector3d(0, 0, 0), Vector3d(1, std::nan(""), 0)}),
               armour::core::InputError);
}

TEST(Orientation, SchmidtProjectionPreservesArea) {
  const SlopeFrame f = seedSlope();
  std::mt19937_64 rng(17);
  constexpr int n = 100000;
  std::vector<Eigen::Vector2d> points;
  points.reserve(n);
  for (int k = 0; k < n; ++k) points.push_back(stereonetPoint(attitude(randomAxis(rng), f)));
  for (const auto& p : points) ASSERT_LE(p.norm(), 1.0 + 1e-12);
  for (const double r : {0.2, 0.4, 0.6, 0.8, 0.95}) {
    int inside = 0;
    for (const auto& p : points) inside += p.norm() < r ? 1 : 0;
    const double expected = r * r;
    const double sigma = std::sqrt(expected * (1.0 - expected) / n);
    EXPECT_NEAR(static_cast<double>(inside) / n, expected, 4.0 * sigma) << "radius " << r;
  }
  // And uniform in angle: each quadrant holds a quarter.
  int quadrant[4] = {0, 0, 0, 0};
  for (const auto& p : points) quadrant[(p.x() >= 0 ? 1 : 0) + (p.y() >= 0 ? 2 : 0)]++;
  const double sigma = std::sqrt(0.25 * 0.75 / n);
  for (int q = 0; q < 4; ++q) EXPECT_NEAR(quadrant[q] / static_cast<double>(n), 0.25, 4.0 * sigma);
}

TEST(Orientation, BodyAxesOfTheLibraryShapes) {
  using armour::analysis::noseAxisOf;
  using armour::analysis::unitAxisOf;
  EXPECT_EQ(noseAxisOf("coreloc"), Vector3d::UnitX());
  EXPECT_EQ(noseAxisOf("xbloc"), Vector3d::UnitY());
  EXPECT_EQ(noseAxisOf("antifer"), Vector3d::UnitZ());
  EXPECT_EQ(unitAxisOf("dolos", "upper-fluke"), Vector3d::UnitX());
  EXPECT_EQ(unitAxisOf("dolos", "lower-fluke"), Vector3d::UnitY());
  // Every shape but the rocks has a stereonet axis.
  for (const auto& g : armour::geometry::shapeGenerators()) {
    if (g.random) {
      EXPECT_TRUE(armour::analysis::unitAxesOf(g.name).empty()) << g.name;
    } else {
      EXPECT_NEAR(noseAxisOf(g.name).norm(), 1.0, 1e-15) << g.name;
    }
  }
  try {
    (void)noseAxisOf("rock");
    ADD_FAILURE() << "a rock has no nose";
  } catch (const armour::core::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'rock'"), std::string::npos) << m;
    EXPECT_NE(m.find("coreloc"), std::string::npos) << "lists the shapes that have one: " << m;
  }
  try {
    (void)unitAxisOf("dolos", "nose2");
    ADD_FAILURE();
  } catch (const armour::core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("upper-fluke"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)noseAxisOf("no-such-shape"), armour::core::InputError);
}

TEST(Orientation, AntiferNoseRunsFromTheBaseToTheNarrowerTop) {
  // The Antifer is built without gmsh: check the frame makeShape leaves (centroid at the origin,
  // taper along +z) against the axis the table gives.
  const auto mesh = armour::geometry::makeShape("antifer", {});
  const Vector3d nose = armour::analysis::noseAxisOf("antifer");
  double lo = 1e300, hi = -1e300;
  for (const auto& v : mesh.vertices) {
    lo = std::min(lo, v.dot(nose));
    hi = std::max(hi, v.dot(nose));
  }
  double baseWidth = 0.0, topWidth = 0.0;
  for (const auto& v : mesh.vertices) {
    const double w = std::abs(v.x());
    if (std::abs(v.dot(nose) - lo) < 1e-9) baseWidth = std::max(baseWidth, w);
    if (std::abs(v.dot(nose) - hi) < 1e-9) topWidth = std::max(topWidth, w);
  }
  EXPECT_LT(topWidth, baseWidth);
  EXPECT_LT(std::abs(hi + lo), hi - lo) << "the centroid lies between base and top";
}

TEST(Orientation, NoseAxesFollowTheOrientations) {
  const std::vector<Quaterniond> q = {Quaterniond::Identity(),
                                      Quaterniond(Eigen::AngleAxisd(kPi / 2, Vector3d::UnitZ())),
                                      Quaterniond(2.0, 0.0, 0.0, 0.0)}; // not normalised: still the identity
  const auto axes = armour::analysis::noseAxesWorld(q, Vector3d(3.0, 0.0, 0.0));
  EXPECT_NEAR((axes[0] - Vector3d::UnitX()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((axes[1] - Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((axes[2] - Vector3d::UnitX()).norm(), 0.0, 1e-15);
  try {
    (void)armour::analysis::noseAxesWorld({Quaterniond::Identity(), Quaterniond(0, 0, 0, 0)}, Vector3d::UnitX());
    ADD_FAILURE();
  } catch (const armour::core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unit 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)attitude(Vector3d::Zero(), seedSlope()), armour::core::InputError);
}
