// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file LoadedBodies.hpp
/// Which bodies take wave loads (HydroSettings::bodies): "all" non-fixed bodies, or those whose
/// name starts with a prefix such as "unit_". Fixed bodies (the rock underlayer) never do. One
/// rule for every load stage.

#include "simulation/World.hpp"

#include <string>
#include <vector>

namespace armour::hydro {

/// Does a (non-fixed) body called `name` take loads under `filter` ("all" or a name prefix)?
[[nodiscard]] bool nameTakesLoads(const std::string& name, const std::string& filter);

/// The non-fixed bodies of `world` that take loads. `key` names the setting in errors.
/// @throws core::InputError if `filter` is empty or selects no non-fixed body.
[[nodiscard]] std::vector<dynamics::BodyId> selectLoadedBodies(const simulation::World& world,
                                                               const std::string& filter, const std::string& key);

} // namespace armour::hydro
