// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/StructuredBox.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <utility>

namespace armour::deformable {

geometry::TetMesh structuredBox(const geometry::Vec3& size, int nx, int ny, int nz) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!(size[axis] > 0.0)) {
      core::failInput("structuredBox", "size[{}] = {} m: box sides must be positive", axis, size[axis]);
    }
  }
  for (const int n : {nx, ny, nz}) {
    if (n < 1 || n > 1000) {
      core::failInput("structuredBox", "{} cells along an axis: give 1 to 1000", n);
    }
  }
  geometry::TetMesh mesh;
  const auto index = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        mesh.vertices.emplace_back(size.x() * i / nx, size.y() * j / ny, size.z() * k / nz);
      }
    }
  }
  // Kuhn's six tets of the unit cell: walk from corner (0,0,0) to (1,1,1) one axis at a time, in
  // each of the six axis orders.
  constexpr std::array<std::array<int, 3>, 6> kOrders{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        for (const auto& axes : kOrders) {
          std::array<int, 3> c{i, j, k};
          geometry::Tet tet{};
          tet[0] = index(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[axes[s]];
            tet[s + 1] = index(c[0], c[1], c[2]);
          }
          mesh.tets.push_back(tet);
          if (mesh.volume(mesh.tets.size() - 1) < 0.0) {
            std::swap(mesh.tets.back()[1], mesh.tets.back()[2]);
          }
        }
      }
    }
  }
  return mesh;
}

} // namespace armour::deformable
