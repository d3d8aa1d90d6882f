// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Error.hpp
/// Errors that reach the user. Every message names the source (file, key or variable), the bad
/// value, and how to fix it, e.g.
///   "unit.stl: 3 open edges, e.g. (12, 40): the mesh is not watertight; close the holes ...".

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace armour::core {

/// Bad user input: a file, a key, a command-line value. Always-on checks throw this.
class InputError : public std::runtime_error {
public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// Throw an InputError formatted with fmt. `where` names the file or key.
template <typename... Args>
[[noreturn]] void failInput(const std::string& where, fmt::format_string<Args...> format, Args&&... args) {
  throw InputError(where + ": " + fmt::format(format, std::forward<Args>(args)...));
}

/// Refuse a non-finite setting: "<key>: nan N: must be a finite number".
inline void requireFinite(double value, const std::string& key, const char* unit) {
  if (!(value - value == 0.0)) { // false for NaN and +-inf, without <cmath>
    failInput(key, "{} {}: must be a finite number", value, unit);
  }
}

} // namespace armour::core
