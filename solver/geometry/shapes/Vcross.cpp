// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Vcross.cpp
/// The Vcross: the hypothetical cruciform test unit of the deformable FEMDEM drop tests (seed paper
/// 002, Figs. 2-3): seven cubes of side a, a central one and one on each of its faces, so three
/// square arms a x a cross at the centre and the unit fills a 3a x 3a x 3a box.
///
/// Built exactly as a polyhedron: the union is the set of occupied cells of a 3 x 3 x 3 voxel grid,
/// its surface the cell faces between an occupied and an empty cell, two triangles each. Every
/// vertex is a node of the 4 x 4 x 4 lattice and every face a whole cell face, so no vertex lies
/// inside another face's edge (no T-junctions) and the mesh is watertight by construction.

#include "geometry/shapes/Generators.hpp"

#include <array>
#include <map>

namespace armour::geometry::shapes {
namespace {

/// Arm section side of the published unit (m): seed 002, Fig. 2, "1.26 m x 1.26 m".
constexpr double kArmSide = 1.26;

/// True for the seven occupied cells of the 3 x 3 x 3 grid: the centre and its six face neighbours,
/// i.e. the cells with at most one index different from 1.
bool occupied(int i, int j, int k) {
  if (i < 0 || j < 0 || k < 0 || i > 2 || j > 2 || k > 2) {
    return false;
  }
  return (i != 1) + (j != 1) + (k != 1) <= 1;
}

TriangleMesh buildVcross(double a) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::int32_t> nodeIndex; // lattice node -> vertex, so faces share vertices
  auto node = [&](std::array<int, 3> n) {
    auto [it, inserted] = nodeIndex.try_emplace(n, static_cast<std::int32_t>(mesh.vertices.size()));
    if (inserted) {
      // Centred on the central cube: lattice nodes 0..3 map to -1.5a .. 1.5a.
      mesh.vertices.emplace_back((n[0] - 1.5) * a, (n[1] - 1.5) * a, (n[2] - 1.5) * a);
    }
    return it->second;
  };
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        if (!occupied(i, j, k)) {
          continue;
        }
        const std::array<int, 3> cell{i, j, k};
        for (int axis = 0; axis < 3; ++axis) {
          for (int side : {0, 1}) {
            std::array<int, 3> neighbour = cell;
            neighbour[axis] += side == 1 ? 1 : -1;
            if (occupied(neighbour[0], neighbour[1], neighbour[2])) {
              continue; // interior face
            }
            // Tangent axes u, v with e_u x e_v = e_axis; the corners 0, u, u+v, v run counter-clockwise
            // seen from +axis, so they are kept for the + face and reversed for the - face.
            const int u = (axis + 1) % 3;
            const int v = (axis + 2) % 3;
            std::array<int, 3> c0 = cell;
            c0[axis] += side;
            std::array<int, 3> c1 = c0;
            c1[u] += 1;
            std::array<int, 3> c2 = c1;
            c2[v] += 1;
            std::array<int, 3> c3 = c0;
            c3[v] += 1;
            const std::int32_t q[4] = {node(c0), node(c1), node(c2), node(c3)};
            if (side == 1) {
              mesh.triangles.push_back({q[0], q[1], q[2]});
              mesh.triangles.push_back({q[0], q[2], q[3]});
            } else {
              mesh.triangles.push_back({q[0], q[2], q[1]});
              mesh.triangles.push_back({q[0], q[3], q[2]});
            }
          }
        }
      }
    }
  }
  return mesh;
}

} // namespace

ShapeGenerator vcrossGenerator() {
  ShapeGenerator g;
  g.name = "vcross";
  g.summary = "Vcross: three square arms crossing at the centre, seven cubes (FEMDEM test unit, seed 002)";
  g.proportions = "seven cubes of side a (a central cube and one on each of its faces); bounding box 3a x 3a x 3a; "
                  "V = 7 a^3; built at a = 1.26 m (V = 14.0 m^3, height 3.78 m); 60 triangles, faces exactly "
                  "planar";
  g.source = "seed paper 002 (deformable FEMDEM, Vcross drop test): square arm section 1.26 m x 1.26 m, volume "
             "14 m^3, height 3.78 m; a hypothetical, non-commercial unit, so the geometry is exact";
  g.parameters = {};
  g.build = [](const ShapeParameterValues&) { return buildVcross(kArmSide); };
  return g;
}

} // namespace armour::geometry::shapes
