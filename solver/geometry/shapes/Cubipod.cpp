// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Cubipod.cpp
/// The Cubipod (Gomez-Martin and Medina, Universitat Politecnica de Valencia, 2006-2014): a cube
/// with a protrusion on the middle of each face, so that units cannot lie face to face and the
/// layer does not self-arrange into a block-work (the "heterogeneous packing" of cube layers).
///
/// Construction: a cube of side L with, centred on each face, a square frustum (truncated pyramid)
/// whose base square lies on the face and whose top square is parallel to it. Built directly as an
/// exact polyhedron: per face, the ring between the cube face and the frustum base (8 triangles),
/// the frustum's four sloping sides (8) and its top (2): 108 triangles, no T-junctions (the rings
/// of neighbouring faces share only the cube's corners and edges).
///
/// Natural frame: cube side L = 1 m, centred at the origin, standing on the top square of the
/// lower protrusion.

#include "core/Error.hpp"
#include "geometry/shapes/Generators.hpp"

#include <array>

namespace armour::geometry::shapes {
namespace {

/// Cube side of the natural-scale unit (m); makeShape rescales to the requested volume.
constexpr double kSide = 1.0;

struct CubipodSize {
  double side = kSide;    ///< cube side L (m)
  double bossBase = 0.0;  ///< side of the protrusion's base square (m)
  double bossTop = 0.0;   ///< side of the protrusion's top square (m)
  double bossHeight = 0.0; ///< protrusion height above the face (m)
};

TriangleMesh buildCubipod(const CubipodSize& s) {
  TriangleMesh mesh;
  auto add = [&](const Vec3& p) {
    mesh.vertices.push_back(p);
    return static_cast<std::int32_t>(mesh.vertices.size() - 1);
  };
  // Square corners counter-clockwise in the face frame (u, v), seen from outside (+n).
  const double corner[4][2] = {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}};
  const double half = 0.5 * s.side;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      // Right-handed face frame: u x v = n.
      const Vec3 n = sign * Vec3::Unit(axis);
      const Vec3 u = Vec3::Unit((axis + 1) % 3);
      const Vec3 v = sign * Vec3::Unit((axis + 2) % 3);
      std::array<std::int32_t, 4> outer{}, base{}, top{};
      for (int i = 0; i < 4; ++i) {
        // Cube corners: every coordinate is exactly +-L/2, so the welding below merges the copies
        // that neighbouring faces create.
        outer[i] = add(half * n + half * corner[i][0] * u + half * corner[i][1] * v);
        base[i] = add(half * n + 0.5 * s.bossBase * (corner[i][0] * u + corner[i][1] * v));
        top[i] = add((half + s.bossHeight) * n + 0.5 * s.bossTop * (corner[i][0] * u + corner[i][1] * v));
      }
      for (int i = 0; i < 4; ++i) {
        const int j = (i + 1) % 4;
        mesh.triangles.push_back({outer[i], outer[j], base[j]}); // ring, in the cube face
        mesh.triangles.push_back({outer[i], base[j], base[i]});
        mesh.triangles.push_back({base[i], base[j], top[j]}); // sloping side of the frustum
        mesh.triangles.push_back({base[i], top[j], top[i]});
      }
      mesh.triangles.push_back({top[0], top[1], top[2]});
      mesh.triangles.push_back({top[0], top[2], top[3]});
    }
  }
  weldVertices(mesh, 0.0);
  return mesh;
}

} // namespace

ShapeGenerator cubipodGenerator() {
  ShapeGenerator g;
  g.name = "cubipod";
  g.summary = "Cubipod: cube with a truncated-pyramid protrusion on each face (Gomez-Martin and Medina)";
  g.proportions =
      "cube of side L with, centred on each of its six faces, a square frustum: base 0.5 L, top 0.3 L, "
      "height 0.1 L (45-degree sides); overall extent 1.2 L across opposite protrusions; V = 1.098 L^3 "
      "(Dn = 1.032 L); built at L = 1 m, standing on a protrusion; 108 triangles, faces exactly planar";
  g.source = "Gomez-Martin and Medina (2014), 'Heterogeneous packing and hydraulic stability of cube and Cubipod "
             "armor units', J. Waterway, Port, Coastal, Ocean Eng. 140(1), and the Cubipod Manual (Medina and "
             "Gomez-Martin, 2016): cube with six truncated-pyramid protrusions. The protrusion dimensions here are "
             "an approximation of published photos and drawings, not the patented dimensions";
  g.parameters = {
      {"boss_base", 0.5, 0.1, 0.95, "-", "side of a protrusion's base square / cube side L"},
      {"boss_top", 0.3, 0.05, 0.95, "-", "side of a protrusion's top square / cube side L (at most boss_base)"},
      {"boss_height", 0.1, 0.01, 0.5, "-", "height of a protrusion above its face / cube side L"},
  };
  g.build = [](const ShapeParameterValues& p) {
    CubipodSize s;
    s.bossBase = p.get("boss_base") * s.side;
    s.bossTop = p.get("boss_top") * s.side;
    s.bossHeight = p.get("boss_height") * s.side;
    if (!(s.bossTop <= s.bossBase)) {
      core::failInput("shape cubipod", "boss_top = {} is larger than boss_base = {}: the protrusion would overhang "
                      "its base; use boss_top <= boss_base", p.get("boss_top"), p.get("boss_base"));
    }
    return buildCubipod(s);
  };
  return g;
}

} // namespace armour::geometry::shapes
