// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SceneOverrides.hpp
/// `--set KEY=VALUE` on the command line: change one setting of a scene file for one run without
/// editing the file (a fidelity ladder, an ensemble member's seed, a sensitivity study).
///
/// KEY is the dotted path of a setting as the scene file nests it, with list items by index:
///   --set hydro.storm.update_interval=0.5   --set contact.model=fdem   --set static[0].friction=0.7
/// VALUE is YAML: a number, a word, or a flow list or block ([1, 2, 3], {enabled: false}).
/// Missing blocks on the path are created (hydro.storm.variability.seed=3 works on a scene whose
/// storm block has no variability block); the scene reader then checks the result as it checks the
/// file, so a misspelt key gets the same "unknown key (did you mean ...)" error.

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace armour::io {

/// Apply each "KEY=VALUE" of `sets`, in order, to the loaded scene `root`.
/// @throws core::InputError naming the --set option, the bad part and the fix: no '=', an empty
///   key or value, an index on something that is not a list or out of its range, a key below a
///   setting that is a single value.
void applyOverrides(YAML::Node& root, const std::vector<std::string>& sets);

/// The scene text with `sets` applied, re-emitted (comments are lost); `yaml` itself when there
/// are none. For commands that copy the scene text into their outputs (the placed scene).
/// @throws core::InputError as applyOverrides, or for a YAML syntax error naming `sourceName`.
std::string applyOverridesToText(const std::string& yaml, const std::vector<std::string>& sets,
                                 const std::string& sourceName);

} // namespace armour::io
