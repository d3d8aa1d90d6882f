// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SceneReader.hpp
/// Read a scene file (YAML, docs/scene-file.md) into a fully resolved io::Scene.
///
/// The schema lives in SceneReader.cpp as one small table of keys per mapping, each with its
/// type, unit, range and default. Every user error throws core::InputError naming the file, the
/// line, the key path with list indices, the bad value and the fix, e.g.
///   "pile.yaml:14: bodies[3].orientaton: unknown key (did you mean 'orientation'?); valid keys
///    are: name, shape, volume, dn, ..."
///   "pile.yaml:7: materials.concrete.density = -2400: must be > 0 (unit: kg/m^3), e.g. 2400".
/// Reading does not build meshes: it checks that generator names, parameters and mesh files
/// exist, so `armour check` is fast; `armour run` builds the shapes afterwards.

#include "io/Scene.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace armour::io {

/// Read and resolve a scene file; relative paths in it are relative to its folder. `overrides`
/// are --set KEY=VALUE changes applied before the file is checked (io/SceneOverrides.hpp).
/// @throws core::InputError for an unreadable file or any schema violation.
Scene readScene(const std::filesystem::path& path, const std::vector<std::string>& overrides = {});

/// Parse scene text. `baseDir` resolves relative paths; `sourceName` names the text in messages
/// and its stem names the scene (default output folder "<stem>-out").
/// @throws core::InputError as readScene.
Scene parseScene(const std::string& yaml, const std::filesystem::path& baseDir, const std::string& sourceName,
                 const std::vector<std::string>& overrides = {});

} // namespace armour::io
