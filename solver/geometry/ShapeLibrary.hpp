// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ShapeLibrary.hpp
/// The library of parametric armour-unit and rock shapes.
///
/// Each generator builds a closed mesh at its natural scale; makeShape() then validates it, puts
/// its centroid at the origin and scales it uniformly to the requested volume, so every shape
/// meets its volume to round-off (far inside the 0.1 % the library promises). Orientation: the
/// generator's documented "up" is +z (the unit as it stands on a horizontal floor, or its main
/// axis along z where it has no natural base). New shapes plug in through the registry table in
/// ShapeLibrary.cpp, one file per shape under shapes/.

#include "geometry/TriangleMesh.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace armour::geometry {

/// A named, bounded, dimensionless or dimensioned knob of a generator.
struct ShapeParameter {
  std::string name;
  double defaultValue = 0.0;
  double min = 0.0;
  double max = 0.0;
  std::string unit;        ///< "-" for ratios
  std::string description;
};

/// Values for a generator's parameters; unset names take their defaults.
class ShapeParameterValues {
public:
  ShapeParameterValues() = default;
  ShapeParameterValues(const std::vector<ShapeParameter>* schema, std::map<std::string, double> values,
                       std::uint64_t seed)
      : schema_(schema), values_(std::move(values)), seed_(seed) {}
  /// Value of parameter `name` (the user's or the default). Throws std::logic_error for a name
  /// the generator did not declare (a programming error).
  [[nodiscard]] double get(const std::string& name) const;
  /// Seed for random shapes (rocks); deterministic across platforms.
  [[nodiscard]] std::uint64_t seed() const { return seed_; }

private:
  const std::vector<ShapeParameter>* schema_ = nullptr;
  std::map<std::string, double> values_;
  std::uint64_t seed_ = 1;
};

struct ShapeGenerator {
  std::string name;        ///< command-line name, e.g. "antifer"
  std::string summary;     ///< one line for `armour shape list`
  std::string proportions; ///< the proportions used, in words
  std::string source;      ///< where the proportions come from
  std::vector<ShapeParameter> parameters;
  bool random = false;     ///< depends on the seed
  /// Build the closed surface at any scale (makeShape scales it to the requested volume).
  std::function<TriangleMesh(const ShapeParameterValues&)> build;
};

/// How large, and which variant.
struct ShapeRequest {
  double volume = 1.0;                  ///< m^3 (Dn = volume^(1/3))
  std::map<std::string, double> params; ///< generator parameters by name
  std::uint64_t seed = 1;               ///< random shapes only
};

/// All generators, in the order `armour shape list` shows them.
const std::vector<ShapeGenerator>& shapeGenerators();

/// The generator called `name`; throws core::InputError listing the valid names.
const ShapeGenerator& findShapeGenerator(const std::string& name);

/// Build, validate, centre on the centroid and scale to request.volume.
/// Throws core::InputError for an unknown parameter or a value outside its range.
TriangleMesh makeShape(const std::string& name, const ShapeRequest& request);

} // namespace armour::geometry
