// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file AtomicFile.hpp
/// Outputs are written atomically: to a temporary file in the same folder, then renamed over the
/// destination, so a reader (or a crash) never sees a half-written file.

#include <filesystem>
#include <functional>
#include <ostream>

namespace armour::core {

/// Call `write` with a stream to a temporary sibling of `path`, then rename it to `path`.
/// Throws InputError naming the path when the folder is not writable or the write fails.
void writeFileAtomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write,
                         bool binary = false);

/// Temporary sibling path used for atomic writes by libraries that write files themselves
/// (VTK, netCDF): write there, then call commitAtomicFile.
std::filesystem::path temporarySibling(const std::filesystem::path& path);
/// Rename `temporary` over `path` (same folder, so the rename is atomic on POSIX).
void commitAtomicFile(const std::filesystem::path& temporary, const std::filesystem::path& path);

} // namespace armour::core
