// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SceneSchema.hpp
/// The scene file's key tables, generated from the schema the reader reads with (io/SceneTables):
/// `armour schema` prints them, and docs/scene-file.md holds them between markers
///
///     <!-- schema: contact.constraint (generated: armour schema --update-doc docs/scene-file.md) -->
///     | key | type | unit | default | meaning |
///     ...
///     <!-- end schema -->
///
/// so that a CI test (`scene_file_tables`) fails when the docs and the code drift apart.

#include <string>
#include <vector>

namespace armour::io {

/// Paths of the blocks whose tables are generated, in the docs' order ("contact", "sleep", ...).
std::vector<std::string> schemaBlocks();

/// The markdown key table of one block (header, rule and a row per key, each line ending in '\n').
/// Throws core::InputError naming the valid paths for an unknown one.
std::string schemaTable(const std::string& path);

/// A document with its generated tables made current.
struct SchemaDocUpdate {
  std::string text;                 ///< the document with every marked table regenerated
  std::vector<std::string> changed; ///< blocks whose table differed from the generated one
  std::vector<std::string> missing; ///< blocks with no marked table in the document
};

/// Regenerate the tables between the markers of `document` (its text; `name` for messages).
/// Throws core::InputError for a marker naming an unknown block or without its end marker.
SchemaDocUpdate updateSchemaTables(const std::string& document, const std::string& name);

} // namespace armour::io
