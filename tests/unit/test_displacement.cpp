// SPDX-License-Identifier: GPL-3.0-or-later
// Displacement measures between two states (analysis/Displacement.hpp) against analytic values
// (round-off tolerances, 1e-12 relative, unless stated):
//  - a rigid translation d of every unit: delta_rms = D = |d| (seed 001 eq. 3, seed 003 eq. 3),
//    D_z = d_x, D'_z = |d_x| (seed 003 eqs. 4-5, its z our x), every count by |d| / Dn;
//  - no motion: every measure 0;
//  - a rigid rotation of the pack by theta about an axis: every unit turns by theta and moves by
//    2 r_i sin(theta / 2), r_i its distance from the axis;
//  - seed 003's middle half: units outside it do not change D, D_z, D'_z;
//  - the counts of units moved more than 0.2 / 0.5 / 1 Dn use each unit's own Dn;
//  - rotation angles are in [0, pi] and see q and -q as the same;
//  - bad input (sizes, NaN, Dn <= 0, zero quaternion) is refused naming the unit.

#include "analysis/Displacement.hpp"
#include "core/Error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using armour::analysis::DisplacementSettings;
using armour::analysis::measureDisplacement;
using armour::analysis::SlopeFrame;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

constexpr double kPi = std::numbers::pi;

double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

struct Pack {
  std::vector<Vector3d> positions;
  std::vector<Quaterniond> orientations;
};

/// n units spread over a 20 m x 30 m x 5 m box, random orientations.
Pack randomPack(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Pack p;
  for (std::size_t i = 0; i < n; ++i) {
    p.positions.emplace_back(20.0 * uniform(rng), 30.0 * uniform(rng), 5.0 * uniform(rng));
    p.orientations.push_back(Quaterniond(uniform(rng) - 0.5, uniform(rng) - 0.5, uniform(rng) - 0.5, uniform(rng) - 0.5)
                                 .normalized());
  }
  return p;
}

SlopeFrame slope() { return SlopeFrame::fromTanAlpha(0.5, Vector3d(0.0, 0.0, 0.0)); }

} // namespace

TEST(Displacement, RigidTranslation) {
  const Pack before = randomPack(40, 1);
  Pack after = before;
  const Vector3d d(-0.3, 0.2, -0.6); // |d| = 0.7 m
  for (auto& p : after.positions) p += d;
  const double dn = 1.5;
  const auto r = measureDisplacement(before.positions, after.positions, before.orientations, after.orientations, {dn},
                                     slope());
  EXPECT_EQ(r.count, 40u);
  EXPECT_NEAR(r.deltaRms, 0.7, 1e-12);
  EXPECT_NEAR(r.deltaRmsHorizontal, std::hypot(0.3, 0.2), 1e-12);
  EXPECT_NEAR(r.deltaRmsOverDn, 0.7 / dn, 1e-12);
  EXPECT_NEAR(r.meanDn, 0.7 / dn, 1e-12);
  EXPECT_NEAR(r.maxDn, 0.7 / dn, 1e-12);
  EXPECT_NEAR(r.total, 40 * 0.7, 1e-11);
  // Seed 003 over the middle half: every unit moved alike, so the means are the unit's values.
  EXPECT_GT(r.middleCount, 0u);
  EXPECT_LT(r.middleCount, 40u);
  EXPECT_NEAR(r.D, 0.7, 1e-12);
  EXPECT_NEAR(r.x.mean, -0.3, 1e-12) << "seed 003's D_z: negative for units moving seaward";
  EXPECT_NEAR(r.x.meanAbsolute, 0.3, 1e-12);
  EXPECT_NEAR(r.y.mean, 0.2, 1e-12);
  EXPECT_NEAR(r.z.meanAbsolute, 0.6, 1e-12);
  const SlopeFrame f = slope();
  EXPECT_NEAR(r.s.mean, d.dot(f.upSlope), 1e-12);
  EXPECT_NEAR(r.n.mean, d.dot(f.normal), 1e-12);
  // 0.7 / 1.5 = 0.47 Dn: above 0.2, below 0.5 and 1.
  ASSERT_EQ(r.movedCounts.size(), 3u);
  EXPECT_EQ(r.movedCounts[0], 40u);
  EXPECT_EQ(r.movedCounts[1], 0u);
  EXPECT_EQ(r.movedCounts[2], 0u);
  EXPECT_EQ(r.rockingCount, 0u);
  EXPECT_EQ(r.maxRotation, 0.0);
}

TEST(Displacement, NoMotionGivesZeros) {
  const Pack p = randomPack(10, 2);
  const auto r = measureDisplacement(p.positions, p.positions, p.orientations, p.orientations, {1.0}, slope());
  EXPECT_EQ(r.deltaRms, 0.0);
  EXPECT_EQ(r.D, 0.0);
  EXPECT_EQ(r.x.mean, 0.0);
  EXPECT_EQ(r.total, 0.0);
  EXPECT_EQ(r.maxDn, 0.0);
  EXPECT_LE(r.maxRotation, 1e-15);
  for (const auto c : r.movedCounts) EXPECT_EQ(c, 0u);
  EXPECT_EQ(r.rockingCount, 0u);
}

TEST(Displacement, RigidRotationOfThePack) {
  const Pack before = randomPack(30, 3);
  const Vector3d axisPoint(10.0, 15.0, 2.0);
  const Vector3d axis = Vector3d(0.2, -0.4, 1.0).normalized();
  for (const double theta : {0.05, 0.5, 2.5}) {
    const Quaterniond r(Eigen::AngleAxisd(theta, axis));
    Pack after;
    for (std::size_t i = 0; i < before.positions.size(); ++i) {
      after.positions.push_back(axisPoint + r * (before.positions[i] - axisPoint));
      after.orientations.push_back(r * before.orientations[i]);
    }
    const auto m =
        measureDisplacement(before.positions, after.positions, before.orientations, after.orientations, {2.0}, slope());
    double sumSq = 0.0;
    for (std::size_t i = 0; i < before.positions.size(); ++i) {
      const Vector3d rel = before.positions[i] - axisPoint;
      const double radius = (rel - rel.dot(axis) * axis).norm();
      const double chord = 2.0 * radius * std::sin(0.5 * theta);
      EXPECT_NEAR(m.units[i].distance, chord, 1e-12 * (1.0 + chord));
      EXPECT_NEAR(m.units[i].rotation, theta, 1e-12);
      EXPECT_EQ(m.units[i].rocking, theta > 5.0 * kPi / 180.0);
      sumSq += chord * chord;
    }
    EXPECT_NEAR(m.deltaRms, std::sqrt(sumSq / 30.0), 1e-12 * (1.0 + m.deltaRms));
    EXPECT_NEAR(m.meanRotation, theta, 1e-12);
  }
}

TEST(Displacement, OnlyTheMiddleHalfCountsForSeed003) {
  // Ten units at y = 0 .. 9 m: the trunk extent is [0, 9], its middle half [2.25, 6.75] holds
  // y = 3, 4, 5, 6.
  std::vector<Vector3d> before;
  for (int i = 0; i < 10; ++i) before.emplace_back(1.0, i, 0.5);
  const std::vector<Quaterniond> q(10, Quaterniond::Identity());
  auto after = before;
  after[3].x() -= 0.4; // middle units slide seaward
  after[5].x() -= 0.2;
  after[6].y() += 0.3;
  const auto a = measureDisplacement(before, after, q, q, {1.0}, slope());
  EXPECT_EQ(a.middleCount, 4u);
  EXPECT_NEAR(a.middleTrunkMin, 2.25, 1e-12);
  EXPECT_NEAR(a.middleTrunkMax, 6.75, 1e-12);
  EXPECT_NEAR(a.D, (0.4 + 0.2 + 0.3) / 4.0, 1e-12);
  EXPECT_NEAR(a.x.mean, -0.6 / 4.0, 1e-12);
  EXPECT_NEAR(a.y.meanAbsolute, 0.3 / 4.0, 1e-12);
  // Units at the sides falling off change delta_rms but not D.
  auto wild = after;
  wild[0] += Vector3d(-5.0, 1.0, -3.0);
  wild[9] += Vector3d(-2.0, 0.0, -1.0);
  wild[2] += Vector3d(-1.0, 0.0, 0.0);
  const auto b = measureDisplacement(before, wild, q, q, {1.0}, slope());
  EXPECT_EQ(b.D, a.D);
  EXPECT_EQ(b.x.mean, a.x.mean);
  EXPECT_EQ(b.x.meanAbsolute, a.x.meanAbsolute);
  EXPECT_GT(b.deltaRms, a.deltaRms);
  // An explicit structure extent moves the middle: [0, 20] keeps y in [5, 15].
  DisplacementSettings s;
  s.trunkMin = 0.0;
  s.trunkMax = 20.0;
  const auto c = measureDisplacement(before, after, q, q, {1.0}, slope(), s);
  EXPECT_EQ(c.middleCount, 5u);
  EXPECT_NEAR(c.D, (0.2 + 0.3) / 5.0, 1e-12);
  // A middle with no unit gives NaN, not a division by zero.
  s.trunkMin = 100.0;
  s.trunkMax = 200.0;
  const auto none = measureDisplacement(before, after, q, q, {1.0}, slope(), s);
  EXPECT_EQ(none.middleCount, 0u);
  EXPECT_TRUE(std::isnan(none.D));
}

TEST(Displacement, CountsUseEachUnitsNominalDiameter) {
  // Moves of 0.1, 0.3, 0.6, 1.2 Dn with Dn = 1, 2, 3, 4 m.
  std::vector<Vector3d> before(4, Vector3d::Zero());
  const std::vector<double> dn = {1.0, 2.0, 3.0, 4.0};
  const std::vector<double> moved = {0.1, 0.3, 0.6, 1.2};
  std::vector<Vector3d> after;
  for (int i = 0; i < 4; ++i) {
    before[i].y() = i;
    after.push_back(before[i] + Vector3d(0.0, 0.0, -moved[i] * dn[i]));
  }
  const std::vector<Quaterniond> q(4, Quaterniond::Identity());
  const auto r = measureDisplacement(before, after, q, q, dn, slope());
  EXPECT_EQ(r.movedCounts, (std::vector<std::size_t>{3, 2, 1}));
  EXPECT_NEAR(r.maxDn, 1.2, 1e-12);
  EXPECT_EQ(r.maxUnit, 3u);
  EXPECT_NEAR(r.meanDn, (0.1 + 0.3 + 0.6 + 1.2) / 4.0, 1e-12);
  DisplacementSettings s;
  s.thresholdsDn = {0.05, 2.0};
  EXPECT_EQ(measureDisplacement(before, after, q, q, dn, slope(), s).movedCounts, (std::vector<std::size_t>{4, 0}));
}

TEST(Displacement, RotationAngleIsTheShorterWay) {
  using armour::analysis::rotationAngle;
  const Quaterniond a(Eigen::AngleAxisd(0.3, Vector3d(1, 2, 3).normalized()));
  const Quaterniond turn(Eigen::AngleAxisd(190.0 * kPi / 180.0, Vector3d::UnitX()));
  EXPECT_NEAR(rotationAngle(a, turn * a), 170.0 * kPi / 180.0, 1e-12);
  const Quaterniond minus(-a.w(), -a.x(), -a.y(), -a.z());
  EXPECT_NEAR(rotationAngle(a, minus), 0.0, 1e-12) << "q and -q are the same orientation";
  const Quaterniond tiny(Eigen::AngleAxisd(1e-9, Vector3d::UnitZ()));
  EXPECT_NEAR(rotationAngle(a, tiny * a), 1e-9, 1e-17) << "small angles keep their digits";
}

TEST(Displacement, BadInputIsRefusedNamingTheUnit) {
  const Pack p = randomPack(5, 4);
  auto expectMessage = [](auto&& call, const std::string& needle) {
    try {
      call();
      ADD_FAILURE() << "expected an InputError mentioning '" << needle << "'";
    } catch (const armour::core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  auto shorter = p.positions;
  shorter.pop_back();
  expectMessage(
      [&] { (void)measureDisplacement(p.positions, shorter, p.orientations, p.orientations, {1.0}, slope()); },
      "4 final positions");
  auto nan = p.positions;
  nan[3].z() = std::nan("");
  expectMessage([&] { (void)measureDisplacement(p.positions, nan, p.orientations, p.orientations, {1.0}, slope()); },
                "unit 3");
  expectMessage(
      [&] {
        (void)measureDisplacement(p.positions, p.positions, p.orientations, p.orientations, {1, 1, -1, 1, 1}, slope());
      },
      "unit 2");
  auto zeroQ = p.orientations;
  zeroQ[4] = Quaterniond(0, 0, 0, 0);
  expectMessage([&] { (void)measureDisplacement(p.positions, p.positions, p.orientations, zeroQ, {1.0}, slope()); },
                "unit 4");
  expectMessage([&] { (void)measureDisplacement({}, {}, {}, {}, {1.0}, slope()); }, "empty");
  DisplacementSettings s;
  s.middleFraction = 0.0;
  expectMessage(
      [&] { (void)measureDisplacement(p.positions, p.positions, p.orientations, p.orientations, {1.0}, slope(), s); },
      "middle fraction");
}
