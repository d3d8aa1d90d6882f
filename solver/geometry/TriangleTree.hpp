// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file TriangleTree.hpp
/// A bounding-volume hierarchy over a mesh's triangles: nodes in depth-first order, each with the
/// box of its triangles, split at the median centroid along the longest axis of the centroids'
/// box (balanced: depth log2(triangles / 4)), ties broken by triangle index so the tree is the
/// same on every platform. Built once; its users walk it their own way (contact::MeshDistance for
/// the closest point, MeshRayCaster for the first hit along a line).

#include "geometry/TriangleMesh.hpp"

#include <cstdint>
#include <vector>

namespace armour::geometry {

struct TriangleTree {
  /// Triangles per leaf at most: a leaf test stays cheap and the tree shallow (the usual
  /// compromise for closest-point and ray queries).
  static constexpr std::int32_t kLeafSize = 4;
  struct Node {
    Vec3 lo;                  ///< box of the node's triangles (unit: m)
    Vec3 hi;
    std::int32_t first = 0;   ///< leaf: first triangle in `order`; inner: index of the second child
    std::int32_t count = 0;   ///< leaf: number of triangles; inner: 0 (the first child follows the node)
  };
  std::vector<Node> nodes;          ///< root at 0; empty for a mesh without triangles
  std::vector<std::int32_t> order;  ///< tree order -> mesh triangle index
};

/// The tree of `mesh`'s triangles. `relativePad` grows each node's box by that fraction of its
/// largest extent on every side (a ray caster's slab test then cannot miss a flat box by
/// round-off); 0 keeps the exact boxes.
TriangleTree buildTriangleTree(const TriangleMesh& mesh, double relativePad = 0.0);

} // namespace armour::geometry
