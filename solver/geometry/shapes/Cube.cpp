// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/shapes/Generators.hpp"

namespace armour::geometry::shapes {

ShapeGenerator cubeGenerator() {
  ShapeGenerator g;
  g.name = "cube";
  g.summary = "cube or rectangular block (armour cube, test block)";
  g.proportions = "sides 1 : aspect_y : aspect_z; 12 triangles, faces exactly planar";
  g.source = "plain geometry; the parallelepiped armour cube of EurOtop (2018) when aspect = 1";
  g.parameters = {
      {"aspect_y", 1.0, 0.05, 20.0, "-", "side along y relative to the side along x"},
      {"aspect_z", 1.0, 0.05, 20.0, "-", "side along z relative to the side along x"},
  };
  g.build = [](const ShapeParameterValues& p) {
    const double hx = 0.5;
    const double hy = 0.5 * p.get("aspect_y");
    const double hz = 0.5 * p.get("aspect_z");
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) {
      m.vertices.emplace_back((i & 1) ? hx : -hx, (i & 2) ? hy : -hy, (i & 4) ? hz : -hz);
    }
    // Two triangles per face, counter-clockwise seen from outside.
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
  };
  return g;
}

} // namespace armour::geometry::shapes
