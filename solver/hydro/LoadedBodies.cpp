// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/LoadedBodies.hpp"

#include "core/Error.hpp"

namespace armour::hydro {

bool nameTakesLoads(const std::string& name, const std::string& filter) {
  return filter == "all" || name.starts_with(filter);
}

std::vector<dynamics::BodyId> selectLoadedBodies(const simulation::World& world, const std::string& filter,
                                                 const std::string& key) {
  if (filter.empty()) {
    core::failInput(key, "empty: give \"all\" (every non-fixed body) or a body-name prefix such as \"unit_\"");
  }
  const auto& bodies = world.bodies();
  std::vector<dynamics::BodyId> loaded;
  for (dynamics::BodyId b = 0; b < bodies.size(); ++b) {
    if (bodies.motionType(b) != dynamics::MotionType::Static && nameTakesLoads(bodies.info(b).name, filter)) {
      loaded.push_back(b);
    }
  }
  if (loaded.empty()) {
    core::failInput(key, "\"{}\" selects no non-fixed body ({} bodies in the scene); fixed bodies never take wave "
                         "loads: give \"all\" or the prefix of the units' names",
                    filter, bodies.size());
  }
  return loaded;
}

} // namespace armour::hydro
