// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ShapeCache.hpp
/// Library shapes at V = 1 m^3 (Dn = 1 m), built once per test program: the OpenCASCADE units
/// take about 0.1 s each to build.

#include "geometry/ShapeLibrary.hpp"

#include <map>
#include <string>

namespace armour::test {

inline const geometry::TriangleMesh& unitShape(const std::string& name) {
  static std::map<std::string, geometry::TriangleMesh> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    geometry::ShapeRequest request;
    request.volume = 1.0;
    it = cache.emplace(name, geometry::makeShape(name, request)).first;
  }
  return it->second;
}

/// Something built from a unit shape (a level set, surface samples) with its default settings,
/// once per shape name and test program.
template <typename T>
const T& perUnitShape(const std::string& name) {
  static std::map<std::string, T> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    it = cache.emplace(name, T(unitShape(name))).first;
  }
  return it->second;
}

} // namespace armour::test
