// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BroadPhase.hpp
/// Candidate body pairs from world-space bounding boxes.
///
/// Two structures, because a scene is mostly at rest (static rocks, height-field cells, sleeping
/// units) while a few bodies move:
/// - moving (active) boxes: sweep and prune along x. They are kept sorted by their lower x bound
///   between calls; bodies move little per step, so insertion sort restores the order in
///   near-linear time (temporal coherence, Baraff 1992);
/// - resting (inactive) boxes: a uniform grid over x and y, built when the set of resting boxes
///   changes (a body falls asleep or wakes, or invalidate() is called) and queried by each active
///   box for the cells it covers. Boxes much larger than a cell (a slope's toe, a long wall piece)
///   are kept in a short list that every active box tests.
/// So a step costs in proportion to the active boxes and their neighbours, not to the whole scene:
/// 3000 static rocks under 200 moving units cost the same as the rocks the units touch. An active
/// box keeps the resting boxes near it (those overlapping its box grown by kGrowth of its size)
/// and queries the grid again only when it leaves that grown box: a unit rocking in its place
/// tests a short list, not the grid's cells, and finds the same pairs.
/// Pairs are returned sorted (i < j, lexicographic), so everything downstream is independent of
/// the sort history and of the thread count. A pair is reported only if at least one of its
/// bodies is active: static-static and sleeping-sleeping pairs cost nothing.

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
  /// Inactive boxes are assumed not to have moved since the last call unless their active flag
  /// changed or invalidate() was called.
  void findPairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active,
                 std::vector<BodyPair>& pairs);
  /// The inactive boxes moved (a restart, a body placed by hand): rebuild the grid on the next call.
  void invalidate() { restingValid_ = false; }
  /// Number of grid rebuilds so far (for tests and statistics).
  [[nodiscard]] std::size_t restingBuilds() const { return restingBuilds_; }
  /// Number of times an active box's resting neighbours were searched for in the grid so far
  /// (for tests and statistics; the other queries used the kept lists).
  [[nodiscard]] std::size_t neighbourSearches() const { return neighbourSearches_; }

private:
  void buildResting(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active);

  std::vector<std::uint32_t> order_;        ///< active indices sorted by box.min.x, kept between calls
  std::vector<std::uint8_t> activeCopy_;    ///< flags of the last call
  bool restingValid_ = false;
  std::size_t restingBuilds_ = 0;
  std::size_t neighbourSearches_ = 0;
  // Resting grid over x, y (CSR: items of cell c are cellItems_[cellStart_[c] .. cellStart_[c+1])).
  double gridX0_ = 0.0, gridY0_ = 0.0, cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cellStart_;
  std::vector<std::uint32_t> cellItems_;
  std::vector<std::uint32_t> large_;        ///< resting boxes spanning many cells
  std::vector<std::uint32_t> stamp_;        ///< per box: last query that saw it (dedupe across cells)
  std::uint32_t query_ = 0;
  /// An active box's resting neighbours: every resting box overlapping `grown`, which holds the
  /// active box as it was then, grown by kGrowth of its largest side on every side.
  struct Neighbours {
    geometry::Box3 grown;
    std::vector<std::uint32_t> resting;
    bool valid = false;
  };
  std::vector<Neighbours> neighbours_;      ///< per body index (used for active ones)
  /// Fraction of an active box's largest side it may move before its neighbours are found again
  /// (ours): larger keeps lists longer and makes them longer.
  static constexpr double kGrowth = 0.05;
  /// Fill n.resting with the resting boxes overlapping n.grown (the grid's cells and the large boxes).
  void findNeighbours(const std::vector<geometry::Box3>& boxes, Neighbours& n);
};

/// Reference O(N^2) version, for tests.
std::vector<BodyPair> bruteForcePairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active);

} // namespace armour::contact
