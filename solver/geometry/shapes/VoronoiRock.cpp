// SPDX-License-Identifier: GPL-3.0-or-later
// PLACEHOLDER: replaced by the generator's real implementation.
#include "geometry/shapes/Generators.hpp"
#include <stdexcept>
namespace armour::geometry::shapes {
ShapeGenerator voronoiRockGenerator() {
  ShapeGenerator g;
  g.name = "voronoirock";
  g.summary = "placeholder";
  g.build = [](const ShapeParameterValues&) -> TriangleMesh { throw std::logic_error("placeholder"); };
  return g;
}
} // namespace armour::geometry::shapes
