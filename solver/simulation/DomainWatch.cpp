// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/DomainWatch.hpp"

#include <fmt/format.h>

namespace armour::simulation {

DomainWatch::DomainWatch(const StaticDomain& domain, const World& world) : domain_(domain) {
  const std::size_t n = world.bodies().size();
  outside_.assign(n, 0);
  for (BodyId b = 0; b < n; ++b) {
    outside_[b] = domain_.beyondEdge(world.bodies().position(b)) ? 1 : 0;
    outsideCount_ += static_cast<std::size_t>(outside_[b]);
  }
}

std::vector<DomainExit> DomainWatch::update(const World& world) {
  std::vector<DomainExit> exits;
  // Only awake bodies move; a sleeping or fixed body keeps its flag.
  for (const BodyId b : world.bodies().awakeBodies()) {
    if (b >= outside_.size()) continue;
    const Vec3& x = world.bodies().position(b);
    const char out = domain_.beyondEdge(x) ? 1 : 0;
    if (out == outside_[b]) continue;
    outside_[b] = out;
    if (out != 0) {
      ++outsideCount_;
      exits.push_back({b, world.time(), x});
    } else {
      --outsideCount_;
    }
  }
  return exits;
}

std::string DomainWatch::describe(const World& world, const DomainExit& e) const {
  return fmt::format("t = {:.4g} s: body '{}' left the static domain at ({:.4g}, {:.4g}, {:.4g}) m (x in [{:.4g}, "
                     "{:.4g}] m, y in [{:.4g}, {:.4g}] m, fixed by the scene's positions): the scene's unbounded "
                     "items (a slope's crest, the plane around a height field) end there, so it falls off their "
                     "edge. A wall (static: type: wall) keeps bodies on the structure",
                     e.time, world.bodies().info(e.body).name, e.position.x(), e.position.y(), e.position.z(),
                     domain_.xMin, domain_.xMax, domain_.yMin, domain_.yMax);
}

} // namespace armour::simulation
