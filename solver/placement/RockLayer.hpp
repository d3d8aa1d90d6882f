// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RockLayer.hpp
/// The rock passes of a placement (`placement.rocks`, the underlayer, and `placement.toe_berm`, the
/// berm on it in front of the first row): rocks of the rock shapes dropped on a jittered grid of
/// points up the face, each lowered along the face normal in the best of a few orientations, slid
/// and tilted into the holes and frozen (docs/placement.md, "Rocks"; docs/theory.md section 15).

#include "io/Scene.hpp"
#include "placement/PlacementProgress.hpp"
#include "placement/PlacementSettings.hpp"
#include "simulation/SceneBuilder.hpp"

#include <spdlog/logger.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace armour::placement {

/// What a rock pass needs of the placement in progress.
struct RockSite {
  const io::StaticSlope* slope = nullptr; ///< the face the rocks lie on
  double y0 = 0.0, y1 = 0.0;              ///< along the trunk: between its walls, or the grid's width (unit: m)
  double unitDn = 0.0;                    ///< the units' nominal diameter; the deposit's cells are at least half (unit: m)
  std::uint64_t seed = 0;                 ///< the placement seed (each pass salts it)
  std::string unitMaterial;               ///< the units' material, the rocks' when the pass names none
  bool resuming = false;                  ///< a restart lays none: the checkpoint's rocks come back with its state
};

/// One pass: `settings.count` rocks from s0 to s1 up the face, measured from the slope foot
/// (negative: offshore of the foot, on the toe). `key` names the pass's block (rocks or toe_berm)
/// in messages; `salt` keeps each pass's random streams apart.
struct RockPass {
  const RockSettings* settings = nullptr;
  double s0 = 0.0, s1 = 0.0; ///< unit: m
  std::string key;
  std::uint64_t salt = 0;
};

/// Lay one pass into `built`'s World and into `scene` (fixed bodies named rock_NNNN, numbered on
/// from `rockBodies`), appending each to `rockBodies` and its record to `added`.
void depositRocks(simulation::BuiltScene& built, io::Scene& scene, const RockSite& site, const RockPass& pass,
                  const std::vector<std::pair<std::size_t, simulation::ShapeId>>& rockShapes,
                  std::vector<simulation::BodyId>& rockBodies, std::vector<AddedBody>& added, spdlog::logger& log);

} // namespace armour::placement
