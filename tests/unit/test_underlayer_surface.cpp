// SPDX-License-Identifier: GPL-3.0-or-later
// The underlayer's surface stones (analysis/UnderlayerSurface.hpp), the base of the armour layer's
// thickness:
//  - a 5 x 5 bed of "diamond" cubes (a unit cube turned so that a body diagonal is the slope
//    normal: one top vertex, sqrt(3)/2 above the centroid) under a slab covering the middle 3 x 3:
//    exactly the 16 outer diamonds and the slab are surface stones, and the mean top of the
//    surface stones is their mean top (round-off, 1e-12); over every stone it is lower;
//  - a higher stone beside a top does not cover it; a stone on another does;
//  - the same bed on a 4H:3V slope frame (the bed turned with the frame): the same stones;
//  - a stone without a mesh or with a non-positive scale: an input error naming the body.

#include "analysis/UnderlayerSurface.hpp"
#include "core/Error.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace armour::analysis;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

/// A box of sides a x b x c centred on the origin.
armour::geometry::TriangleMesh centredBox(double a, double b, double c) {
  auto m = armour::test::makeBox(a, b, c);
  for (auto& v : m.vertices) v -= Vector3d(a / 2, b / 2, c / 2);
  return m;
}

/// The rotation taking the cube's body diagonal (1, 1, 1) to +z: a single highest vertex.
Quaterniond diamond() { return Quaterniond::FromTwoVectors(Vector3d(1, 1, 1).normalized(), Vector3d::UnitZ()); }

struct Bed {
  armour::geometry::TriangleMesh cube = centredBox(1, 1, 1);
  armour::geometry::TriangleMesh slab = centredBox(3.6, 3.6, 0.4);
  std::vector<PosedMesh> bodies;
  /// In frame coordinates (s, t, n), placed in the world through `frame`; the frame's own
  /// rotation turns the stones with it.
  explicit Bed(const SlopeFrame& frame) {
    Eigen::Matrix3d axes;
    axes.col(0) = frame.upSlope;
    axes.col(1) = frame.trunk;
    axes.col(2) = frame.normal;
    const Quaterniond turn(axes);
    const double lift = std::sqrt(3.0) / 2.0; // centroid to the top vertex
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        bodies.push_back({&cube, 1.0, frame.toWorld(Vector3d(1.2 * i, 1.2 * j, 0.0)), turn * diamond()});
    // The slab rests 0.1 above the diamonds' tops over the middle 3 x 3 (s, t in [1.2, 3.6]).
    bodies.push_back({&slab, 1.0, frame.toWorld(Vector3d(2.4, 2.4, lift + 0.1 + 0.2)), turn});
  }
};

void expectMiddleCovered(const SurfaceStones& stones) {
  ASSERT_EQ(stones.exposed.size(), 26u);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const bool middle = i >= 1 && i <= 3 && j >= 1 && j <= 3;
      EXPECT_EQ(stones.exposed[static_cast<std::size_t>(5 * i + j)], !middle) << "diamond " << i << ", " << j;
    }
  EXPECT_TRUE(stones.exposed[25]) << "the slab is on top";
  EXPECT_EQ(stones.exposedCount, 17u);
}

} // namespace

TEST(UnderlayerSurface, ASlabCoversTheStonesUnderItAndTheMeanTopIsTheSurfaceStones) {
  const SlopeFrame frame = SlopeFrame::fromTanAlpha(0.0, Vector3d::Zero());
  const Bed bed(frame);
  const SurfaceStones stones = surfaceStones(bed.bodies, frame);
  expectMiddleCovered(stones);
  const double diamondTop = std::sqrt(3.0) / 2.0, slabTop = diamondTop + 0.1 + 0.4;
  for (std::size_t k = 0; k < 25; ++k) EXPECT_NEAR(stones.top[k], diamondTop, 1e-12);
  EXPECT_NEAR(stones.top[25], slabTop, 1e-12);
  const SlopeWindow all{-1.0, 6.0, -1.0, 6.0};
  EXPECT_NEAR(meanTopIn(stones, all), (16 * diamondTop + slabTop) / 17.0, 1e-12);
  EXPECT_NEAR(meanTopIn(stones, all, false), (25 * diamondTop + slabTop) / 26.0, 1e-12);
  // A window over the middle only: the slab alone (its centroid is there, the covered ones do not count).
  EXPECT_NEAR(meanTopIn(stones, SlopeWindow{1.0, 3.7, 1.0, 3.7}), slabTop, 1e-12);
  EXPECT_EQ(meanTopIn(stones, SlopeWindow{10.0, 11.0, 10.0, 11.0}), 0.0) << "no stone: the frame plane";
}

TEST(UnderlayerSurface, AHigherStoneBesideATopDoesNotCoverIt) {
  const SlopeFrame frame = SlopeFrame::fromTanAlpha(0.0, Vector3d::Zero());
  const auto cube = centredBox(1, 1, 1);
  // Cube 0's top point is its corner (-0.5, -0.5, 0.5) (the first highest vertex). Cube 1 stands
  // 0.05 beside that corner and 0.5 higher: its bounding circle holds the corner, so the ray is
  // cast, and misses. Cube 2 sits on cube 1 and covers it.
  const std::vector<PosedMesh> bodies{{&cube, 1.0, Vector3d(0, 0, 0), Quaterniond::Identity()},
                                      {&cube, 1.0, Vector3d(-1.05, -0.5, 0.5), Quaterniond::Identity()},
                                      {&cube, 1.0, Vector3d(-1.05, -0.5, 1.5), Quaterniond::Identity()}};
  const SurfaceStones stones = surfaceStones(bodies, frame);
  EXPECT_TRUE(stones.exposed[0]);
  EXPECT_FALSE(stones.exposed[1]) << "cube 2 sits on it";
  EXPECT_TRUE(stones.exposed[2]);
}

TEST(UnderlayerSurface, TheSameBedOnASlopeGivesTheSameStones) {
  const SlopeFrame frame = SlopeFrame::fromTanAlpha(0.75, Vector3d(2.0, 0.0, 3.0));
  const Bed bed(frame);
  const SurfaceStones stones = surfaceStones(bed.bodies, frame);
  expectMiddleCovered(stones);
  const double diamondTop = std::sqrt(3.0) / 2.0;
  for (std::size_t k = 0; k < 25; ++k) EXPECT_NEAR(stones.top[k], diamondTop, 1e-12);
}

TEST(UnderlayerSurface, AStoneWithoutAMeshOrScaleIsRefused) {
  const SlopeFrame frame = SlopeFrame::fromTanAlpha(0.0, Vector3d::Zero());
  const auto cube = centredBox(1, 1, 1);
  try {
    (void)surfaceStones({{&cube, 1.0, Vector3d::Zero(), Quaterniond::Identity()}, {nullptr}}, frame);
    FAIL() << "no error";
  } catch (const armour::core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("support body 1 has no mesh"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)surfaceStones({{&cube, 0.0, Vector3d::Zero(), Quaterniond::Identity()}}, frame),
               armour::core::InputError);
}
