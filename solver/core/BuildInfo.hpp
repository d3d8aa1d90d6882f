// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BuildInfo.hpp
/// The version/build line printed at the top of every run log: version, git hash, build type,
/// compiler and the number of OpenMP threads the run will use.

#include <string>

namespace armour::core {

/// e.g. "armour 0.1.0 (git 1a2b3c4d5e6f, Release, GCC 12.2.0, OpenMP 4.5, 2 threads)".
std::string buildInfo();

/// Version string "0.1.0".
std::string version();

} // namespace armour::core
