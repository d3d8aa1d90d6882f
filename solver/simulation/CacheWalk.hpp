// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CacheWalk.hpp
/// A walk along the entries a per-pair cache handed out at the last step (the constraint solver's
/// manifolds, the narrow phase's near-sample lists). The candidate pairs of a step come in one
/// order (the broad phase's, sorted, then the plane pairs, sorted) and are mostly those of the
/// step before, so a cursor moving along the last step's keys finds most entries without hashing;
/// a key it does not find (a new pair, or one out of that order) is for the cache's hash map. The
/// entries are elements of an std::unordered_map: their addresses survive its rehashing and the
/// erasing of other entries, not the erasing of their own (the caches erase only entries their
/// step did not use).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace armour::simulation {

template <class Entry>
struct CacheWalk {
  std::vector<std::uint64_t> keys; ///< the last step's pair keys, in its order
  std::vector<Entry*> entries;     ///< their entries (null: none)
  std::uint64_t late = 0;          ///< keys with any of these bits come after all others (plane pairs)
  std::size_t cursor = 0;

  void clear() {
    keys.clear();
    entries.clear();
    cursor = 0;
  }
  /// The last step's entry of `key`, or null. Keys must be asked in the candidate pairs' order;
  /// start each step with cursor = 0.
  Entry* find(std::uint64_t key) {
    while (cursor < keys.size() && before(keys[cursor], key)) ++cursor;
    return cursor < keys.size() && keys[cursor] == key ? entries[cursor++] : nullptr;
  }

private:
  [[nodiscard]] bool before(std::uint64_t a, std::uint64_t b) const {
    const bool lateA = (a & late) != 0, lateB = (b & late) != 0;
    return lateA != lateB ? lateB : a < b;
  }
};

} // namespace armour::simulation
