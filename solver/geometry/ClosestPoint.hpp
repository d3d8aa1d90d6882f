// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ClosestPoint.hpp
/// Closest point on a triangle, with the Voronoi region (vertex, edge or face) that holds it.
/// Used by the exact signed distance of the contact stage and by the tetrahedraliser.

#include "geometry/TriangleMesh.hpp"

#include <cstdint>

namespace armour::geometry {

/// The part of a triangle its closest point lies on (Voronoi region of the triangle).
enum class TriangleFeature : std::uint8_t { Vertex0, Vertex1, Vertex2, Edge01, Edge12, Edge20, Face };

/// Closest point on triangle (a, b, c) to x; `feature` tells which region holds it.
Vec3 closestPointOnTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, TriangleFeature& feature);

/// Squared distance from x to triangle (a, b, c) (unit: m^2).
inline double squaredDistanceToTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleFeature feature;
  return (closestPointOnTriangle(x, a, b, c, feature) - x).squaredNorm();
}

} // namespace armour::geometry
