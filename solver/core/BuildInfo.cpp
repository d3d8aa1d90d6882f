// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/BuildInfo.hpp"

#include "GitHash.hpp" // generated at build time: ARMOUR_GIT_HASH

#include <fmt/format.h>
#include <omp.h>

namespace armour::core {
namespace {

std::string compiler() {
#if defined(__clang__)
  return fmt::format("Clang {}.{}.{}", __clang_major__, __clang_minor__, __clang_patchlevel__);
#elif defined(__GNUC__)
  return fmt::format("GCC {}.{}.{}", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__);
#else
  return "unknown compiler";
#endif
}

} // namespace

std::string version() { return ARMOUR_VERSION; }

std::string buildInfo() {
  return fmt::format("armour {} (git {}, {}, {}, OpenMP {}, {} threads)", ARMOUR_VERSION, ARMOUR_GIT_HASH,
                     ARMOUR_BUILD_TYPE, compiler(), _OPENMP, omp_get_max_threads());
}

} // namespace armour::core
