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
/// Barycentric slack of the triangle test: a line within 1e-10 of a triangle's size outside it
/// still hits, so a line through a shared edge cannot fall between the two triangles by round-off.
constexpr double kBarycentricSlack = 1e-10;

} // namespace

MeshRayCaster::MeshRayCaster(const TriangleMesh& mesh) {
  // A face lying in a coordinate plane gives a flat box; the pad keeps the slab test of a line
  // hitting it exactly from failing by round-off.
  TriangleTree tree = buildTriangleTree(mesh, 1e-9);
  nodes_ = std::move(tree.nodes);
  v0_.reserve(tree.order.size());
  e1_.reserve(tree.order.size());
  e2_.reserve(tree.order.size());
  for (const std::int32_t t : tree.order) {
    const auto c = mesh.corners(static_cast<std::size_t>(t));
    v0_.push_back(c[0]);
    e1_.push_back(c[1] - c[0]);
    e2_.push_back(c[2] - c[0]);
  }
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
