// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SceneTables.hpp
/// The scene schema as data (internal to io): one schema::Table per block, read by SceneReader.cpp
/// and printed by io/SceneSchema.hpp into docs/scene-file.md. The blocks not listed here are
/// still declared in the reader by their key lists alone (issue 27 converts them block by block).

#include "io/Scene.hpp" // Vec3 and the settings structs, which YamlSchema.hpp reads into
#include "io/YamlSchema.hpp"

#include <vector>

namespace armour::io::tables {

/// The top level of the file (its path in messages is empty; "top" names its docs table).
const schema::Table& top();
const schema::Table& materials();
const schema::Table& contact();
const schema::Table& contactFdem();
const schema::Table& contactConstraint();
const schema::Table& output();
const schema::Table& sleep();
const schema::Table& bodyDamping();

/// Every table, in the order of docs/scene-file.md.
const std::vector<const schema::Table*>& all();

} // namespace armour::io::tables
