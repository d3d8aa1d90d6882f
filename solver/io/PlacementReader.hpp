// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacementReader.hpp
/// The `placement:` block of a scene (docs/placement.md), read into Scene::placement by the scene
/// reader: grid, orientations, crane, settle, nest, lowering and rock underlayer, each value
/// checked with the file, key and fix (YamlSchema).

#include "io/Scene.hpp"
#include "io/YamlSchema.hpp"

namespace armour::io::detail {

/// Read `top`'s placement block, if any, into scene.placement (resolves the unit shape against
/// the scene's shapes or the generators, and the material names).
void readPlacement(const schema::Block& top, Scene& scene);

} // namespace armour::io::detail
