// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file WorldInternal.hpp
/// Shared by the World's source files (World.cpp and the World*.cpp of its stages) and nothing
/// else: not installed, not included by any public header. It holds the flag bits that tell the
/// kinds of contact pair and of sample key apart, the look-up of a point's contact history, and
/// the view of static geometry as half-spaces that both solvers' narrow phases test against. The
/// flag bits are also the contact_second and contact_key values of a checkpoint (CheckpointFile.cpp
/// documents them in the file), so changing them breaks existing checkpoints.

#include "simulation/World.hpp"

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace armour::simulation::detail {

constexpr std::uint32_t kPlaneBit = 0x80000000u;  ///< second pair index of a body-plane pair
constexpr std::uint32_t kConvexBit = 0x40000000u; ///< second pair index of a body-convex pair
constexpr std::uint32_t kStaticBits = kPlaneBit | kConvexBit;
constexpr std::uint32_t kReverseBit = contact::kReverseSampleBit; ///< sample key: B's samples in A (NarrowPhase.hpp)

/// The friction history of sample `key` in a pair's history (sorted by key), or null.
inline const contact::PointHistory* findHistory(
    const std::vector<std::pair<std::uint32_t, contact::PointHistory>>* h, std::uint32_t key) {
  if (h == nullptr) {
    return nullptr;
  }
  auto it = std::lower_bound(h->begin(), h->end(), key, [](const auto& e, std::uint32_t k) { return e.first < k; });
  return it != h->end() && it->first == key ? &it->second : nullptr;
}

/// A static solid as the half-spaces n_k . x <= d_k both contact models test against: a plane
/// is one, a convex piece several. Views, no copies (every body-static pair, every step); the
/// plane's offset is held here, so use offsets() while the target is alive.
struct StaticTarget {
  std::span<const Vec3> normals;
  std::span<const double> pieceOffsets;
  double planeOffset = 0.0;
  bool plane = false;
  MaterialId material = 0;
  geometry::Box3 region; ///< where a body's surface can be inside it (world)
  [[nodiscard]] std::span<const double> offsets() const {
    return plane ? std::span<const double>(&planeOffset, 1) : pieceOffsets;
  }
};

inline StaticTarget staticTarget(const std::vector<StaticPlane>& planes, const std::vector<StaticConvex>& convex,
                                 bool isPlane, std::uint32_t index, const geometry::Box3& bodyBox) {
  StaticTarget t;
  t.plane = isPlane;
  if (isPlane) {
    const StaticPlane& pl = planes[index];
    t.planeOffset = pl.normal.dot(pl.point);
    t.normals = std::span<const Vec3>(&pl.normal, 1);
    t.material = pl.material;
    t.region = bodyBox; // a plane reaches everywhere: the body's box bounds the search
  } else {
    const StaticConvex& piece = convex[index];
    t.normals = piece.normals;
    t.pieceOffsets = piece.offsets;
    t.material = piece.material;
    t.region = piece.box;
  }
  return t;
}

} // namespace armour::simulation::detail

namespace armour::simulation {

/// One candidate pair's reduced contact patches (constraint solver): written by one thread, read
/// serially.
struct World::PairManifold {
  contact::BodyPair key;
  std::vector<contact::ContactPatchPoints> patches;
  double maxOverlap = 0.0; ///< deepest sample inside, for the guard rails (unit: m)
  /// The speculative margin of its full narrow phase: every sample within it of the other body was
  /// found (unit: m).
  double margin = 0.0;
};

} // namespace armour::simulation
