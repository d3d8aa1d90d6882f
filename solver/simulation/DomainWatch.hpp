// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DomainWatch.hpp
/// Bodies that leave the static domain. The scene's unbounded items (a slope's level crest
/// onshore, the plane around a height field, a slope along y) are cut to the StaticDomain
/// (SceneBuilder.hpp): a body whose centroid passes its x or y bounds has fallen off their edge,
/// onto the half-spaces that remain (a slope's seabed) or into nothing (StaticDomain::edge: the
/// sides where that happens; a slope's offshore side is not one). That is a model's edge,
/// not the structure's behaviour, so a run says so, once per body, with the time and the bounds.
/// A wall (scene `static: type: wall`) keeps bodies in; the domain is fixed by the scene's own
/// positions when the World is built, so a restart and `armour analyse` see the same one.

#include "simulation/SceneBuilder.hpp"
#include "simulation/World.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace armour::simulation {

/// A body that left the domain, and where and when.
struct DomainExit {
  BodyId body = 0;
  double time = 0.0;            ///< first step after which its centroid was outside (unit: s)
  Vec3 position = Vec3::Zero(); ///< its centroid then (unit: m)
};

class DomainWatch {
public:
  /// Bodies already outside the domain in `world` (a restart after they left) are counted as
  /// having left before, without a new exit.
  DomainWatch(const StaticDomain& domain, const World& world);

  /// The movable bodies that are outside the domain now and were inside at the last call.
  std::vector<DomainExit> update(const World& world);

  /// Bodies past an edge of the domain at the last call (unit: -).
  [[nodiscard]] std::size_t outsideCount() const { return outsideCount_; }

  /// One log line for an exit: the body, the time, the position, the bounds and the fix.
  [[nodiscard]] std::string describe(const World& world, const DomainExit& exit) const;

private:
  StaticDomain domain_;
  std::vector<char> outside_;
  std::size_t outsideCount_ = 0;
};

} // namespace armour::simulation
