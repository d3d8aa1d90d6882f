// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file TextFile.hpp
/// A whole text file read at once (scene files, placement files, docs), with the error every
/// reader gives when it cannot be opened.

#include <filesystem>
#include <string>

namespace armour::core {

/// The bytes of `path`. Throws InputError "PATH: cannot open WHAT (looked for ABSOLUTE PATH)"
/// when it cannot be opened; `what` names the file's role, e.g. "the scene file".
std::string readTextFile(const std::filesystem::path& path, const std::string& what);

} // namespace armour::core
