// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file TestMeshes.hpp
/// Small closed meshes with known closed-form properties, for tests.

#include "geometry/TriangleMesh.hpp"

#include <Eigen/Geometry>

namespace armour::test {

using geometry::TriangleMesh;
using geometry::Vec3;

/// Box [0, a] x [0, b] x [0, c], outward, 12 triangles.
inline TriangleMesh makeBox(double a, double b, double c) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back((i & 1) ? a : 0.0, (i & 2) ? b : 0.0, (i & 4) ? c : 0.0);
  }
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

/// Tetrahedron with vertices p0..p3, outward whatever the order of p1..p3.
inline TriangleMesh makeTetrahedron(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  TriangleMesh m;
  m.vertices = {p0, p1, p2, p3};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  if ((p1 - p0).dot((p2 - p0).cross(p3 - p0)) < 0.0) {
    for (auto& f : m.triangles) {
      std::swap(f[1], f[2]);
    }
  }
  return m;
}

/// A fixed, non-trivial rotation (axis (1, 2, 3), 0.7 rad).
inline Eigen::Matrix3d someRotation() {
  return Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
}

} // namespace armour::test
