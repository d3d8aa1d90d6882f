// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/MeshRayCaster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace armour::geometry {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int kLeafTriangles = 4;
/// Barycentric slack of the triangle test: a line within 1e-10 of a triangle's size outside it
/// still hits, so a line through a shared edge cannot fall between the two triangles by round-off.
constexpr double kBarycentricSlack = 1e-10;

} // namespace

MeshRayCaster::MeshRayCaster(const TriangleMesh& mesh) {
  const auto n = static_cast<std::int32_t>(mesh.triangleCount());
  std::vector<Vec3> centroids(static_cast<std::size_t>(n));
  std::vector<std::int32_t> order(static_cast<std::size_t>(n));
  for (std::int32_t t = 0; t < n; ++t) {
    const auto c = mesh.corners(static_cast<std::size_t>(t));
    centroids[static_cast<std::size_t>(t)] = (c[0] + c[1] + c[2]) / 3.0;
    order[static_cast<std::size_t>(t)] = t;
  }
  if (n == 0) {
    return;
  }
  nodes_.reserve(2 * static_cast<std::size_t>(n) / kLeafTriangles + 2);
  build(0, n, order, centroids, mesh);
  v0_.reserve(order.size());
  e1_.reserve(order.size());
  e2_.reserve(order.size());
  for (const std::int32_t t : order) {
    const auto c = mesh.corners(static_cast<std::size_t>(t));
    v0_.push_back(c[0]);
    e1_.push_back(c[1] - c[0]);
    e2_.push_back(c[2] - c[0]);
  }
}

std::int32_t MeshRayCaster::build(std::int32_t begin, std::int32_t end, std::vector<std::int32_t>& order,
                                  const std::vector<Vec3>& centroids, const TriangleMesh& mesh) {
  const auto index = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  geometry::Box3 box, centres;
  for (std::int32_t k = begin; k < end; ++k) {
    const auto t = static_cast<std::size_t>(order[static_cast<std::size_t>(k)]);
    for (const Vec3& p : mesh.corners(t)) {
      box.extend(p);
    }
    centres.extend(centroids[t]);
  }
  // A face lying in a coordinate plane gives a flat box; the pad keeps the slab test of a line
  // hitting it exactly from failing by round-off.
  const double pad = 1e-9 * std::max(box.size().maxCoeff(), 1e-300);
  nodes_[static_cast<std::size_t>(index)].lo = (box.min.array() - pad).matrix();
  nodes_[static_cast<std::size_t>(index)].hi = (box.max.array() + pad).matrix();
  if (end - begin <= kLeafTriangles) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return index;
  }
  int axis = 0;
  centres.size().maxCoeff(&axis);
  const std::int32_t mid = begin + (end - begin) / 2;
  // Ties broken by triangle index: the tree (and so the order hits are found in) is the same on
  // every platform.
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](std::int32_t a, std::int32_t b) {
                     const double ca = centroids[static_cast<std::size_t>(a)][axis];
                     const double cb = centroids[static_cast<std::size_t>(b)][axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  build(begin, mid, order, centroids, mesh);
  const std::int32_t second = build(mid, end, order, centroids, mesh);
  nodes_[static_cast<std::size_t>(index)].first = second;
  nodes_[static_cast<std::size_t>(index)].count = 0;
  return index;
}

double MeshRayCaster::firstHit(const Vec3& origin, const Vec3& direction) const {
  double best = kInfinity;
  if (nodes_.empty()) {
    return best;
  }
  // Slab test of the whole line against a box: the parameter where the line enters it, or false
  // when it misses it or enters beyond the best hit so far.
  std::array<double, 3> inverse{};
  std::array<bool, 3> parallel{};
  for (int k = 0; k < 3; ++k) {
    parallel[k] = direction[k] == 0.0;
    inverse[k] = parallel[k] ? 0.0 : 1.0 / direction[k];
  }
  auto enters = [&](const Node& node, double& tEnter) {
    double t0 = -kInfinity, t1 = best;
    for (int k = 0; k < 3; ++k) {
      if (parallel[k]) {
        if (origin[k] < node.lo[k] || origin[k] > node.hi[k]) {
          return false;
        }
        continue;
      }
      double a = (node.lo[k] - origin[k]) * inverse[k];
      double b = (node.hi[k] - origin[k]) * inverse[k];
      if (a > b) {
        std::swap(a, b);
      }
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) {
        return false;
      }
    }
    tEnter = t0;
    return true;
  };

  std::array<std::pair<std::int32_t, double>, 64> stack{};
  int top = 0;
  double tRoot = 0.0;
  if (!enters(nodes_[0], tRoot)) {
    return best;
  }
  stack[top++] = {0, tRoot};
  while (top > 0) {
    const auto [index, tEnter] = stack[--top];
    if (tEnter > best) {
      continue;
    }
    const Node& node = nodes_[static_cast<std::size_t>(index)];
    if (node.count > 0) {
      for (std::int32_t k = node.first; k < node.first + node.count; ++k) {
        // Moller-Trumbore (1997) on the whole line: no t >= 0 condition.
        const auto i = static_cast<std::size_t>(k);
        const Vec3 p = direction.cross(e2_[i]);
        const double det = e1_[i].dot(p);
        // A line parallel to the face (det ~ 0) enters through a neighbouring face instead.
        if (std::abs(det) <= 1e-12 * e1_[i].cross(e2_[i]).norm() * direction.norm()) {
          continue;
        }
        const double invDet = 1.0 / det;
        const Vec3 s = origin - v0_[i];
        const double u = s.dot(p) * invDet;
        if (u < -kBarycentricSlack || u > 1.0 + kBarycentricSlack) {
          continue;
        }
        const Vec3 q = s.cross(e1_[i]);
        const double v = direction.dot(q) * invDet;
        if (v < -kBarycentricSlack || u + v > 1.0 + kBarycentricSlack) {
          continue;
        }
        best = std::min(best, e2_[i].dot(q) * invDet);
      }
      continue;
    }
    const std::int32_t a = index + 1;
    const std::int32_t b = node.first;
    double ta = 0.0, tb = 0.0;
    const bool hitA = enters(nodes_[static_cast<std::size_t>(a)], ta);
    const bool hitB = enters(nodes_[static_cast<std::size_t>(b)], tb);
    // Nearer child on top of the stack: it is searched first and its hit prunes the other.
    if (hitA && hitB) {
      if (ta <= tb) {
        stack[top++] = {b, tb};
        stack[top++] = {a, ta};
      } else {
        stack[top++] = {a, ta};
        stack[top++] = {b, tb};
      }
    } else if (hitA) {
      stack[top++] = {a, ta};
    } else if (hitB) {
      stack[top++] = {b, tb};
    }
  }
  return best;
}

} // namespace armour::geometry
