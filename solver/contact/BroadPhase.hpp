// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BroadPhase.hpp
/// Candidate body pairs from world-space bounding boxes: sweep and prune along x.
///
/// The boxes are kept sorted by their lower x bound between calls; bodies move little per step, so
/// insertion sort restores the order in near-linear time (temporal coherence, Baraff 1992). The
/// sweep then tests, for each box, only the boxes whose x interval starts before it ends, and
/// checks y and z. Pairs are returned sorted (i < j, lexicographic), so everything downstream is
/// independent of the sort history and of the thread count. A pair is reported only if at least
/// one of its bodies is active (dynamic and awake): static-static and sleeping-sleeping pairs cost
/// nothing.

#include "geometry/TriangleMesh.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace armour::contact {

using BodyPair = std::pair<std::uint32_t, std::uint32_t>; ///< body indices, first < second

class BroadPhase {
public:
  /// @param boxes world boxes, one per body (index = body index; an empty box never pairs)
  /// @param active nonzero for bodies that move this step
  /// @param pairs output, cleared first: overlapping pairs with at least one active body, sorted
  void findPairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active,
                 std::vector<BodyPair>& pairs);

private:
  std::vector<std::uint32_t> order_; ///< body indices sorted by box.min.x, kept between calls
};

/// Reference O(N^2) version, for tests.
std::vector<BodyPair> bruteForcePairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active);

} // namespace armour::contact
