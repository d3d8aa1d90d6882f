// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/TriangleTree.hpp"

#include <algorithm>

namespace armour::geometry {

namespace {

struct TreeBuilder {
  const TriangleMesh& mesh;
  const std::vector<Vec3>& centroids;
  double relativePad = 0.0;
  TriangleTree& tree;

  std::int32_t build(std::int32_t begin, std::int32_t end) {
    const auto index = static_cast<std::int32_t>(tree.nodes.size());
    tree.nodes.emplace_back();
    Box3 box, centres;
    for (std::int32_t k = begin; k < end; ++k) {
      const auto t = static_cast<std::size_t>(tree.order[static_cast<std::size_t>(k)]);
      for (const Vec3& p : mesh.corners(t)) box.extend(p);
      centres.extend(centroids[t]);
    }
    const double pad = relativePad > 0.0 ? relativePad * std::max(box.size().maxCoeff(), 1e-300) : 0.0;
    TriangleTree::Node& node = tree.nodes[static_cast<std::size_t>(index)];
    node.lo = pad > 0.0 ? Vec3((box.min.array() - pad).matrix()) : box.min;
    node.hi = pad > 0.0 ? Vec3((box.max.array() + pad).matrix()) : box.max;
    if (end - begin <= TriangleTree::kLeafSize) {
      node.first = begin;
      node.count = end - begin;
      return index;
    }
    int axis = 0;
    centres.size().maxCoeff(&axis);
    const std::int32_t middle = begin + (end - begin) / 2;
    std::nth_element(tree.order.begin() + begin, tree.order.begin() + middle, tree.order.begin() + end,
                     [&](std::int32_t a, std::int32_t b) {
                       const double ca = centroids[static_cast<std::size_t>(a)][axis];
                       const double cb = centroids[static_cast<std::size_t>(b)][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    build(begin, middle);
    const std::int32_t second = build(middle, end);
    // `node` may have moved as the children were added: index again.
    tree.nodes[static_cast<std::size_t>(index)].first = second;
    tree.nodes[static_cast<std::size_t>(index)].count = 0;
    return index;
  }
};

} // namespace

TriangleTree buildTriangleTree(const TriangleMesh& mesh, double relativePad) {
  TriangleTree tree;
  const auto n = static_cast<std::int32_t>(mesh.triangleCount());
  if (n == 0) return tree;
  std::vector<Vec3> centroids(static_cast<std::size_t>(n));
  tree.order.resize(static_cast<std::size_t>(n));
  for (std::int32_t t = 0; t < n; ++t) {
    const auto c = mesh.corners(static_cast<std::size_t>(t));
    centroids[static_cast<std::size_t>(t)] = (c[0] + c[1] + c[2]) / 3.0;
    tree.order[static_cast<std::size_t>(t)] = t;
  }
  tree.nodes.reserve(2 * static_cast<std::size_t>(n) / TriangleTree::kLeafSize + 2);
  TreeBuilder{mesh, centroids, relativePad, tree}.build(0, n);
  return tree;
}

} // namespace armour::geometry
