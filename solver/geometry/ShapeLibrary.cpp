// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/ShapeLibrary.hpp"

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/shapes/Generators.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <stdexcept>

namespace armour::geometry {

double ShapeParameterValues::get(const std::string& name) const {
  if (auto it = values_.find(name); it != values_.end()) {
    return it->second;
  }
  if (schema_ != nullptr) {
    for (const auto& p : *schema_) {
      if (p.name == name) {
        return p.defaultValue;
      }
    }
  }
  throw std::logic_error("shape parameter '" + name + "' is not declared by its generator");
}

const std::vector<ShapeGenerator>& shapeGenerators() {
  // The registry: one entry per file under shapes/.
  static const std::vector<ShapeGenerator> generators = [] {
    std::vector<ShapeGenerator> g;
    for (auto make : {shapes::cubeGenerator, shapes::antiferGenerator, shapes::dolosGenerator,
                      shapes::coreLocGenerator, shapes::accropodeGenerator, shapes::xblocGenerator,
                      shapes::tetrapodGenerator, shapes::cubipodGenerator, shapes::vcrossGenerator,
                      shapes::vrcrossGenerator, shapes::rockGenerator, shapes::voronoiRockGenerator}) {
      g.push_back(make());
    }
    return g;
  }();
  return generators;
}

const ShapeGenerator& findShapeGenerator(const std::string& name) {
  std::vector<std::string> names;
  for (const auto& g : shapeGenerators()) {
    if (g.name == name) {
      return g;
    }
    names.push_back(g.name);
  }
  core::failInput("shape", "unknown shape '{}'; valid shapes are: {}", name, fmt::join(names, ", "));
}

TriangleMesh makeShape(const std::string& name, const ShapeRequest& request) {
  const ShapeGenerator& generator = findShapeGenerator(name);
  if (!(request.volume > 0.0) || !std::isfinite(request.volume)) {
    core::failInput("shape " + name, "volume = {} m^3: the volume must be positive and finite (give --volume or --dn)",
                    request.volume);
  }
  for (const auto& [key, value] : request.params) {
    const ShapeParameter* found = nullptr;
    for (const auto& p : generator.parameters) {
      if (p.name == key) {
        found = &p;
      }
    }
    if (found == nullptr) {
      std::vector<std::string> valid;
      for (const auto& p : generator.parameters) {
        valid.push_back(p.name);
      }
      core::failInput("shape " + name, "unknown parameter '{}'; valid parameters are: {}", key,
                      valid.empty() ? std::string("(none)") : fmt::format("{}", fmt::join(valid, ", ")));
    }
    if (!(value >= found->min && value <= found->max)) {
      core::failInput("shape " + name, "{} = {} is outside its range [{}, {}] ({}); {}", key, value, found->min,
                      found->max, found->unit, found->description);
    }
  }
  const ShapeParameterValues values(&generator.parameters, request.params, request.seed);
  TriangleMesh mesh = generator.build(values);
  validateMesh(mesh, "generated shape '" + name + "'");
  centreOnCentroid(mesh);
  scaleToVolume(mesh, request.volume);
  return mesh;
}

} // namespace armour::geometry
