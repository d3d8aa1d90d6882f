// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file MeshRayCaster.hpp
/// Where a straight line first meets a closed triangle mesh. Used by the ray-cast exposure of the
/// analytic wave forces (hydro/Exposure, seed 003) and by the survey of an underlayer's surface
/// stones (analysis/UnderlayerSurface).

#include "geometry/TriangleMesh.hpp"
#include "geometry/TriangleTree.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace armour::geometry {

/// First intersection of a straight line with a closed triangle mesh, through an axis-aligned
/// bounding-box tree over the triangles (median split on the longest axis of the triangle
/// centroids, up to 4 triangles per leaf), searched nearest box first and pruned by the best hit.
///
/// Exact on the mesh (the exposed area of a unit is a property of its surface, not of the
/// level-set approximation the contact uses), and its cost does not depend on how closely a ray
/// grazes the surface; docs/theory.md says why this was preferred over sphere tracing.
/// Thread-safe: const member functions only read.
class MeshRayCaster {
public:
  /// @pre the mesh is closed (validated by the World when the shape was added).
  explicit MeshRayCaster(const TriangleMesh& mesh);

  /// Smallest t such that origin + t direction lies on the surface, over the whole line (t may be
  /// negative), or +infinity if the line misses the mesh. For a closed mesh that is where the line
  /// enters the solid, seen along `direction`. `direction` need not be unit; t is in its units.
  /// Triangles are tested with a small tolerance on the barycentric coordinates, so a line through
  /// a shared edge or vertex cannot slip between two triangles.
  [[nodiscard]] double firstHit(const Vec3& origin, const Vec3& direction) const;

  [[nodiscard]] std::size_t triangleCount() const { return v0_.size(); }

private:
  using Node = TriangleTree::Node;

  std::vector<Vec3> v0_, e1_, e2_; // triangle corner 0 and edges 0->1, 0->2, in tree order
  std::vector<Node> nodes_;
};

} // namespace armour::geometry
