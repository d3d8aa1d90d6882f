// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file TriangleMesh.hpp
/// An indexed triangle mesh: the surface of one armour unit, rock or fixed body.
///
/// Convention: a closed mesh describes a solid; its triangles are ordered counter-clockwise seen
/// from outside, so that the right-hand normal (b - a) x (c - a) points out of the solid and the
/// signed volume is positive. Units: metres.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

namespace armour::geometry {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Triangle = std::array<std::int32_t, 3>; ///< vertex indices, counter-clockwise from outside

/// Axis-aligned box.
struct Box3 {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  [[nodiscard]] Vec3 size() const { return max - min; }
  [[nodiscard]] Vec3 centre() const { return 0.5 * (min + max); }
  [[nodiscard]] bool empty() const { return !(min.array() <= max.array()).all(); }
};

struct TriangleMesh {
  std::vector<Vec3> vertices;      ///< positions (unit: m)
  std::vector<Triangle> triangles; ///< counter-clockwise seen from outside

  [[nodiscard]] std::size_t vertexCount() const { return vertices.size(); }
  [[nodiscard]] std::size_t triangleCount() const { return triangles.size(); }

  /// Corner positions of triangle t.
  [[nodiscard]] std::array<Vec3, 3> corners(std::size_t t) const {
    const auto& f = triangles[t];
    return {vertices[f[0]], vertices[f[1]], vertices[f[2]]};
  }
  /// Area-weighted normal of triangle t: (b - a) x (c - a), length = 2 x area.
  [[nodiscard]] Vec3 doubleAreaNormal(std::size_t t) const {
    const auto c = corners(t);
    return (c[1] - c[0]).cross(c[2] - c[0]);
  }
  [[nodiscard]] double area(std::size_t t) const { return 0.5 * doubleAreaNormal(t).norm(); }
  [[nodiscard]] double surfaceArea() const;
  [[nodiscard]] Box3 bounds() const;

  /// Append another mesh (as a separate component).
  void append(const TriangleMesh& other);
};

/// In-place rigid transform p -> R p + t (R must be a rotation).
void transform(TriangleMesh& mesh, const Mat3& rotation, const Vec3& translation);
/// In-place translation.
void translate(TriangleMesh& mesh, const Vec3& offset);
/// In-place uniform scaling about the origin (factor > 0).
void scale(TriangleMesh& mesh, double factor);
/// Reverse the orientation of every triangle.
void flipOrientation(TriangleMesh& mesh);

/// Merge vertices closer than `tolerance` (m; 0 merges exactly equal positions only), drop
/// triangles that collapse, and renumber. Returns the number of vertices removed.
std::size_t weldVertices(TriangleMesh& mesh, double tolerance = 0.0);

/// Drop vertices that no triangle uses, renumbering the triangles.
void removeUnusedVertices(TriangleMesh& mesh);

} // namespace armour::geometry
