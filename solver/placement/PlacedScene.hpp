// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacedScene.hpp
/// What `armour place` writes (docs/placement.md, "Outputs"):
///  - the placed scene: the input file with its `placement:` block removed and the placed rocks,
///    their shapes and the units added (positions and unit quaternions to 17 significant digits,
///    so `armour run` starts from the pack as it lay), beside the input file so relative paths
///    still hold; its run output goes to "<placed stem>-out";
///  - the placed state "<placed stem>-state.nc" beside it (a checkpoint file of the World at the
///    end, at time 0: positions, velocities, sleep, the contacts and their friction springs),
///    which the placed scene names as its `initial_state:` so that a run starts from the pack as
///    the placement left it, not from its positions alone (without the springs, units held by
///    friction on a face steeper than the friction angle slip until the springs are rebuilt);
///  - units.csv: one row per unit (grid point, final pose, release and rest times);
///  - placement.json and the same summary as text.
/// Every file is written atomically (a partial file is never left under the final name).

#include "placement/Placer.hpp"

#include <filesystem>
#include <string>

namespace armour::placement {

/// The placed scene as YAML text, made from the input file's text; with `initialState` (a file
/// name beside the scene) its `initial_state:` key.
std::string placedSceneYaml(const std::string& inputYaml, const PlacementResult& result,
                            const std::string& initialState = {});

/// The summary as lines of text (for the log and summary.txt).
std::string summaryText(const PlacementResult& result);

/// The summary as JSON.
std::string summaryJson(const PlacementResult& result);

/// The per-unit table as CSV.
std::string unitsCsv(const PlacementResult& result);

/// Write the placed scene to `scenePath`, its state beside it, and units.csv, placement.json and
/// placement.txt into `folder` (created). Throws core::InputError naming the file it could not write.
void writePlacementOutputs(const std::string& inputYaml, const PlacementResult& result,
                           const std::filesystem::path& scenePath, const std::filesystem::path& folder);

} // namespace armour::placement
