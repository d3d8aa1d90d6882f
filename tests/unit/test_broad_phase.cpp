// SPDX-License-Identifier: GPL-3.0-or-later
// Sweep and prune finds exactly the overlapping pairs the O(N^2) reference finds, step after step
// while boxes move (insertion-sort path), and skips pairs with no active body.

#include "contact/BroadPhase.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace armour::contact;
using armour::geometry::Box3;
using armour::geometry::Vec3;

namespace {

std::vector<Box3> randomBoxes(std::mt19937_64& rng, std::size_t n, double extent, double size) {
  std::vector<Box3> boxes(n);
  for (auto& b : boxes) {
    const Vec3 c(extent * (rng() >> 11) * 0x1.0p-53, extent * (rng() >> 11) * 0x1.0p-53,
                 0.2 * extent * (rng() >> 11) * 0x1.0p-53);
    const Vec3 h = Vec3::Constant(size * (0.5 + (rng() >> 11) * 0x1.0p-53));
    b.min = c - h;
    b.max = c + h;
  }
  return boxes;
}

} // namespace

TEST(BroadPhase, MatchesBruteForceWhileBoxesMove) {
  std::mt19937_64 rng(3);
  auto boxes = randomBoxes(rng, 800, 40.0, 1.0);
  std::vector<std::uint8_t> active(boxes.size(), 1);
  for (std::size_t i = 0; i < active.size(); i += 3) {
    active[i] = 0; // every third body static or asleep
  }
  BroadPhase broad;
  std::vector<BodyPair> pairs;
  std::size_t total = 0;
  for (int step = 0; step < 20; ++step) {
    broad.findPairs(boxes, active, pairs);
    EXPECT_EQ(pairs, bruteForcePairs(boxes, active)) << "step " << step;
    total += pairs.size();
    for (auto& b : boxes) { // drift by up to a box size so the x order really changes
      const Vec3 d(0.8 * ((rng() >> 11) * 0x1.0p-53 - 0.5), 0.3 * ((rng() >> 11) * 0x1.0p-53 - 0.5), 0.0);
      b.min += d;
      b.max += d;
    }
  }
  EXPECT_GT(total, 1000u) << "the scene must actually have overlaps to test anything";
}

TEST(BroadPhase, InactivePairsAndEmptyBoxesAreSkipped) {
  std::vector<Box3> boxes(3);
  for (auto& b : boxes) {
    b.min = Vec3::Zero();
    b.max = Vec3::Ones();
  }
  boxes[2] = Box3{}; // empty: never pairs
  BroadPhase broad;
  std::vector<BodyPair> pairs;
  broad.findPairs(boxes, {0, 0, 1}, pairs);
  EXPECT_TRUE(pairs.empty());
  broad.findPairs(boxes, {1, 0, 1}, pairs);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0], BodyPair(0, 1));
}
