// SPDX-License-Identifier: GPL-3.0-or-later
// The P2 order parameter (seed 001 eq. 4) in its two forms (analysis/OrderParameters.hpp) against
// the values the seed and the liquid-crystal literature state:
//  - aligned axes: P2 = 1 (both forms), to round-off;
//  - axes all perpendicular to a direction: P2 about it is -1/2 (z^T Q z for axes in the x-y
//    plane), while the largest eigenvalue of that planar set is 1/4;
//  - uniformly random planar axes, N = 1e5: P2 = 1/4 +- 0.01 (both forms: the statistical error of
//    the mean of (3 cos^2 w - 1)/2 is about 0.53 / sqrt(N) = 0.0017, the Q-tensor's largest
//    eigenvalue adds a bias of the same order);
//  - uniformly random 3D axes, N = 1e5, Q-tensor form: P2 = 0 +- 0.01 (its positive bias is
//    O(1/sqrt(N)) = 0.003);
//  - the Q-tensor form does not see the sign of an axis; the mean-director form does;
//  - bad input (no axes, a zero or NaN axis, axes that cancel) is refused with a message.

#include "analysis/OrderParameters.hpp"
#include "core/Error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using armour::analysis::p2MeanDirector;
using armour::analysis::p2QTensor;
using Eigen::Vector3d;

namespace {

/// Uniform doubles in [0, 1) from mt19937_64 bits (portable, unlike uniform_real_distribution).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

std::vector<Vector3d> randomPlanar(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vector3d> axes;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * uniform(rng);
    axes.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  return axes;
}

std::vector<Vector3d> random3d(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vector3d> axes;
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 2.0 * uniform(rng) - 1.0;
    const double a = 2.0 * std::numbers::pi * uniform(rng);
    const double r = std::sqrt(1.0 - z * z);
    axes.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  return axes;
}

} // namespace

TEST(OrderParameters, AlignedAxesGiveOne) {
  const std::vector<Vector3d> axes(50, Vector3d(0.3, -0.2, 2.0));
  const auto m = p2MeanDirector(axes);
  const auto q = p2QTensor(axes);
  EXPECT_NEAR(m.p2, 1.0, 1e-12);
  EXPECT_NEAR(q.p2, 1.0, 1e-12);
  const Vector3d d = Vector3d(0.3, -0.2, 2.0).normalized();
  EXPECT_NEAR(std::abs(m.director.dot(d)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(q.director.dot(d)), 1.0, 1e-12);
  EXPECT_EQ(m.count, 50u);
}

TEST(OrderParameters, AxesPerpendicularToTheDirectorGiveMinusOneHalf) {
  // Mean-director form: the director is the mean of the axes, so a set of axes all perpendicular
  // to it needs axes that do not all point one way: two groups, +x and +y, have their mean along
  // (1, 1, 0) at 45 deg from each (P2 = (3/2 - 1)/2 = 1/4 there). The exact -1/2 is the Q-tensor
  // form's smallest eigenvalue direction: axes spread evenly in the x-y plane make the z axis the
  // director of the smallest eigenvalue, -1/2. Seed 001's -1/2 is P2 about a director the axes are
  // all normal to: checked with the Q tensor's eigenvalues directly.
  std::vector<Vector3d> axes;
  for (int k = 0; k < 8; ++k) {
    const double a = k * std::numbers::pi / 8.0;
    axes.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
  for (const auto& u : axes) q += 1.5 * u * u.transpose();
  q = q / static_cast<double>(axes.size()) - 0.5 * Eigen::Matrix3d::Identity();
  // P2 about z (every axis normal to it): (1/N) sum (3 cos^2 90 - 1)/2 = -1/2 = z^T Q z.
  EXPECT_NEAR(Vector3d::UnitZ().dot(q * Vector3d::UnitZ()), -0.5, 1e-12);
  // And the Q-tensor P2 of this planar, evenly spread set is its largest eigenvalue, 1/4.
  EXPECT_NEAR(p2QTensor(axes).p2, 0.25, 1e-12);
  const auto pair = p2MeanDirector({Vector3d::UnitX(), Vector3d::UnitY()});
  EXPECT_NEAR(pair.p2, 0.25, 1e-12);
  EXPECT_NEAR(pair.director.dot(Vector3d(1, 1, 0).normalized()), 1.0, 1e-12);
}

TEST(OrderParameters, RandomPlanarAxesGiveOneQuarter) {
  const auto axes = randomPlanar(100000, 7);
  EXPECT_NEAR(p2QTensor(axes).p2, 0.25, 0.01);
  // The mean direction of random planar unit vectors is a random in-plane direction (their sum is
  // a random walk of length ~sqrt(N)); about any in-plane direction cos^2 w averages 1/2.
  EXPECT_NEAR(p2MeanDirector(axes).p2, 0.25, 0.01);
}

TEST(OrderParameters, Random3dAxesGiveZeroWithTheQTensor) {
  const auto axes = random3d(100000, 11);
  const auto q = p2QTensor(axes);
  EXPECT_NEAR(q.p2, 0.0, 0.01);
  EXPECT_GE(q.p2, 0.0) << "the largest eigenvalue of a traceless tensor is >= 0";
}

TEST(OrderParameters, OnlyTheMeanDirectorFormSeesTheSignOfAnAxis) {
  // Half the axes along +z, half along -z, plus one along +z so the mean is defined.
  std::vector<Vector3d> axes;
  for (int i = 0; i < 10; ++i) axes.push_back(Vector3d(0, 0, i % 2 ? 1.0 : -1.0));
  axes.push_back(Vector3d(0.01, 0, 1));
  EXPECT_NEAR(p2QTensor(axes).p2, 1.0, 1e-3);
  EXPECT_NEAR(p2MeanDirector(axes).p2, 1.0, 1e-3) << "cos^2 is even: flipped axes along the director still count 1";
  // But the director of the mean form is set by the signs: tilt the flipped ones and it moves.
  std::vector<Vector3d> fan = {Vector3d(1, 0, 1), Vector3d(-1, 0, -1), Vector3d(0, 0, 1)};
  const auto m = p2MeanDirector(fan);
  EXPECT_NEAR(m.director.dot(Vector3d::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR(m.p2, (0.5 * (3 * 0.5 - 1) * 2 + 1.0) / 3.0, 1e-12);
  EXPECT_NEAR(p2QTensor(fan).p2, p2QTensor({Vector3d(1, 0, 1), Vector3d(1, 0, 1), Vector3d(0, 0, 1)}).p2, 1e-12);
}

TEST(OrderParameters, BadInputIsRefused) {
  EXPECT_THROW((void)p2QTensor({}), armour::core::InputError);
  EXPECT_THROW((void)p2MeanDirector({Vector3d::Zero()}), armour::core::InputError);
  EXPECT_THROW((void)p2QTensor({Vector3d(std::nan(""), 0, 1)}), armour::core::InputError);
  try {
    (void)p2MeanDirector({Vector3d::UnitX(), -Vector3d::UnitX()});
    ADD_FAILURE() << "cancelling axes must be refused";
  } catch (const armour::core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use the Q-tensor form"), std::string::npos) << e.what();
  }
}
