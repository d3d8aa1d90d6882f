// SPDX-License-Identifier: GPL-3.0-or-later
// The broad phase (sweep and prune over moving boxes, a grid over resting ones) finds exactly the
// overlapping pairs the O(N^2) reference finds, step after step while boxes move, fall asleep and
// wake, and skips pairs with no active body.

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
  // A few resting boxes much larger than the rest (a slope's toe): the large-box list.
  for (std::size_t i = 0; i < 12; i += 3) {
    boxes[i].max.x() += 15.0;
  }
  BroadPhase broad;
  std::vector<BodyPair> pairs;
  std::size_t total = 0;
  for (int step = 0; step < 30; ++step) {
    broad.findPairs(boxes, active, pairs);
    EXPECT_EQ(pairs, bruteForcePairs(boxes, active)) << "step " << step;
    total += pairs.size();
    for (std::size_t i = 0; i < boxes.size(); ++i) { // active boxes drift by up to a box size
      if (active[i]) {
        const Vec3 d(0.8 * ((rng() >> 11) * 0x1.0p-53 - 0.5), 0.3 * ((rng() >> 11) * 0x1.0p-53 - 0.5), 0.0);
        boxes[i].min += d;
        boxes[i].max += d;
      }
    }
    if (step % 7 == 3) { // some bodies fall asleep, others wake
      for (int k = 0; k < 20; ++k) {
        const std::size_t i = rng() % active.size();
        active[i] = active[i] != 0 ? 0 : 1;
      }
    }
    if (step % 10 == 5) { // resting boxes moved by hand: the caller says so
      for (std::size_t i = 0; i < boxes.size(); ++i) {
        if (!active[i]) {
          boxes[i].min.y() += 0.4;
          boxes[i].max.y() += 0.4;
        }
      }
      broad.invalidate();
    }
  }
  EXPECT_GT(total, 1000u) << "the scene must actually have overlaps to test anything";
  EXPECT_GE(broad.restingBuilds(), 6u) << "the resting grid is rebuilt when the resting set changes";
  EXPECT_LE(broad.restingBuilds(), 10u) << "and only then";
}

TEST(BroadPhase, KeptNeighbourListsFindThePairsOfCreepingBoxes) {
  // Units rocking in place on a bed of rocks: each moving box keeps the resting boxes near it and
  // searches the grid again only when it leaves its grown box (5 % of its size). Over 300 steps of
  // drift of up to 1 % of a box size per step, in one direction for some boxes (they leave their
  // grown boxes every few steps) and back and forth for others, the pairs are the brute force's at
  // every step, and most steps use the kept lists.
  std::mt19937_64 rng(11);
  auto boxes = randomBoxes(rng, 600, 30.0, 1.0);
  std::vector<std::uint8_t> active(boxes.size(), 0);
  for (std::size_t i = 0; i < active.size(); i += 4) {
    active[i] = 1; // a quarter moving, the rest resting (rocks)
  }
  std::vector<Vec3> drift(boxes.size(), Vec3::Zero());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    drift[i] = Vec3((rng() >> 11) * 0x1.0p-53 - 0.5, (rng() >> 11) * 0x1.0p-53 - 0.5, 0.0) * 0.02;
  }
  BroadPhase broad;
  std::vector<BodyPair> pairs;
  std::size_t total = 0, activeQueries = 0;
  const std::size_t steps = 300;
  for (std::size_t step = 0; step < steps; ++step) {
    broad.findPairs(boxes, active, pairs);
    ASSERT_EQ(pairs, bruteForcePairs(boxes, active)) << "step " << step;
    total += pairs.size();
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      if (!active[i]) continue;
      ++activeQueries;
      // Odd boxes walk on; even ones rock back and forth with a period of 20 steps.
      const Vec3 d = (i % 8 == 4) ? drift[i] : Vec3(drift[i] * ((step / 10) % 2 == 0 ? 1.0 : -1.0));
      boxes[i].min += d;
      boxes[i].max += d;
    }
  }
  EXPECT_GT(total, 2000u) << "the scene must actually have overlaps to test anything";
  RecordProperty("neighbour_searches", std::to_string(broad.neighbourSearches()));
  RecordProperty("active_queries", std::to_string(activeQueries));
  EXPECT_EQ(broad.restingBuilds(), 1u);
  EXPECT_LT(broad.neighbourSearches(), activeQueries / 3) << "the kept lists serve most queries";
  EXPECT_GT(broad.neighbourSearches(), 150u + activeQueries / steps) << "the walking boxes search again";
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
