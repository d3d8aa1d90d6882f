// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/BodyContact.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <omp.h>

namespace armour::deformable {
namespace {

/// A point of a surface triangle in its barycentric coordinates.
using Bary = Eigen::Vector3d;

/// Dunavant's 6-point rule on a triangle, degree 4 (Dunavant 1985): barycentric points, weights
/// summing to 1.
struct QuadraturePoint {
  Bary point;
  double weight;
};
const std::array<QuadraturePoint, 6>& dunavant4() {
  static const std::array<QuadraturePoint, 6> rule = [] {
    const double a = 0.445948490915965;
    const double b = 0.091576213509771;
    const double wa = 0.223381589678011;
    const double wb = 0.109951743655322;
    return std::array<QuadraturePoint, 6>{{{Bary(1 - 2 * a, a, a), wa},
                                           {Bary(a, 1 - 2 * a, a), wa},
                                           {Bary(a, a, 1 - 2 * a), wa},
                                           {Bary(1 - 2 * b, b, b), wb},
                                           {Bary(b, 1 - 2 * b, b), wb},
                                           {Bary(b, b, 1 - 2 * b), wb}}};
  }();
  return rule;
}

/// Keep the part of a convex polygon (barycentric vertices) where the linear function with
/// values g at the triangle's corners is >= 0 (Sutherland-Hodgman, one plane).
int clip(const std::array<Bary, 10>& in, int count, const Eigen::Vector3d& g, std::array<Bary, 10>& out) {
  int n = 0;
  for (int k = 0; k < count; ++k) {
    const Bary& a = in[k];
    const Bary& b = in[(k + 1) % count];
    const double ga = g.dot(a);
    const double gb = g.dot(b);
    if (ga >= 0.0) {
      out[n++] = a;
    }
    if ((ga >= 0.0) != (gb >= 0.0)) {
      out[n++] = a + (ga / (ga - gb)) * (b - a);
    }
  }
  return n;
}

/// The 10-node tet as eight straight 4-node tets on its corner and mid-edge nodes (local, VTK
/// order): the four corner tets and the inner octahedron cut along its diagonal 4-9 (mid-edges of
/// (0,1) and (2,3)). Orientation is fixed per element from the reference volume.
constexpr std::array<std::array<int, 4>, 8> kTet10SubTets{{{0, 4, 6, 7}, {4, 1, 5, 8}, {6, 5, 2, 9}, {7, 8, 9, 3},
                                                            {4, 9, 5, 6}, {4, 9, 6, 7}, {4, 9, 7, 8}, {4, 9, 8, 5}}};

double signedVolume(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  return (p1 - p0).cross(p2 - p0).dot(p3 - p0) / 6.0;
}


/// For each part, the parts whose boxes meet its box: a sweep along x over the boxes (empty boxes
/// have no neighbours).
std::vector<std::vector<std::int32_t>> neighbourParts(const std::vector<Eigen::AlignedBox3d>& partBoxes) {
  std::vector<std::vector<std::int32_t>> neighbours(partBoxes.size());
  std::vector<std::int32_t> order;
  for (std::size_t p = 0; p < partBoxes.size(); ++p) {
    if (!partBoxes[p].isEmpty()) order.push_back(static_cast<std::int32_t>(p));
  }
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return partBoxes[a].min().x() < partBoxes[b].min().x() || (partBoxes[a].min().x() == partBoxes[b].min().x() && a < b);
  });
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (std::size_t j = i + 1; j < order.size() && partBoxes[order[j]].min().x() <= partBoxes[order[i]].max().x(); ++j) {
      if (partBoxes[order[i]].intersects(partBoxes[order[j]])) {
        neighbours[order[i]].push_back(order[j]);
        neighbours[order[j]].push_back(order[i]);
      }
    }
  }
  return neighbours;
}

} // namespace

BodyContact::BodyContact(const DeformableMesh& mesh, const std::vector<SurfaceTriangle>& triangles, double penalty,
                         double dampingRatio, double impedance)
    : triangles_(triangles), penalty_(penalty),
      dampingRatio_(dampingRatio), impedance_(impedance) {
  const std::size_t nodes = mesh.nodeCount();
  nodePart_ = deformable::nodeParts(mesh, partCount_);
  trianglePart_.resize(triangles_.size());
  std::vector<char> onSurface(nodes, 0);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    trianglePart_[t] = nodePart_[triangles_[t][0]];
    for (const auto n : triangles_[t]) {
      onSurface[n] = 1;
    }
  }
  // Target tets: the straight 4-node tets that touch the surface (a 10-node element as its eight
  // sub-tets, so that potential, distribution and the contactor's flat sub-triangles all use the
  // same nodes: the forces are then the potential's gradient up to O(depth / H)).
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    const auto* c = mesh.element(e);
    const int subTets = mesh.order == ElementOrder::Linear ? 1 : 8;
    for (int s = 0; s < subTets; ++s) {
      Tet4 tet{};
      for (int a = 0; a < 4; ++a) {
        tet[a] = mesh.order == ElementOrder::Linear ? c[a] : c[kTet10SubTets[s][a]];
      }
      const Vec3& p0 = mesh.nodes[tet[0]];
      const Vec3& p1 = mesh.nodes[tet[1]];
      const Vec3& p2 = mesh.nodes[tet[2]];
      const Vec3& p3 = mesh.nodes[tet[3]];
      const double volume = signedVolume(p0, p1, p2, p3);
      if (volume < 0.0) {
        std::swap(tet[2], tet[3]);
      }
      bool surface = false;
      for (const auto n : tet) {
        surface = surface || onSurface[n] != 0;
      }
      if (!surface) {
        continue;
      }
      tets_.push_back(tet);
      tetPart_.push_back(nodePart_[tet[0]]);
      // Smallest altitude 3 V / (largest face area): the steepest potential.
      double face = 0.0;
      for (const auto& f : {std::array<Vec3, 3>{p0, p1, p2}, std::array<Vec3, 3>{p0, p1, p3},
                            std::array<Vec3, 3>{p0, p2, p3}, std::array<Vec3, 3>{p1, p2, p3}}) {
        face = std::max(face, 0.5 * (f[1] - f[0]).cross(f[2] - f[0]).norm());
      }
      gradientBound_ = std::max(gradientBound_, 4.0 * penalty_ / (3.0 * std::abs(volume) / face));
    }
  }
}

BodyContactStats BodyContact::add(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                  std::vector<Vec3>& forces, ContactorLoads* contactor) const {
  BodyContactStats stats;
  if (contactor != nullptr) {
    contactor->force.assign(x.size(), Vec3::Zero());
    contactor->target.assign(x.size(), -1);
    contactor->share.assign(x.size(), 0.0);
  }
  if (partCount_ < 2 || tets_.empty()) {
    return stats;
  }
  // Boxes of the target elements (corners: straight edges) and the grid cell.
  std::vector<Eigen::AlignedBox3d> boxes(tets_.size());
  double cell = 0.0;
  for (std::size_t k = 0; k < tets_.size(); ++k) {
    for (const auto n : tets_[k]) {
      boxes[k].extend(x[n]);
    }
    cell = std::max(cell, boxes[k].sizes().maxCoeff());
  }
  // Each part's box: a tet or triangle that meets no other part's box cannot touch (most of an
  // anvil's surface is far from the unit); skipping them changes no sum, only the work.
  std::vector<Eigen::AlignedBox3d> partBoxes(partCount_);
  for (std::size_t k = 0; k < tets_.size(); ++k) {
    partBoxes[tetPart_[k]].extend(boxes[k]);
  }
  // The parts whose boxes meet each part's box (sweep along x): a tet or triangle of part q lies
  // in q's box, so only those parts' boxes can meet it. Many parts (a rock dump) then cost their
  // neighbours, not every part; the skipped set is the same as testing every part.
  const std::vector<std::vector<std::int32_t>> neighbours = neighbourParts(partBoxes);
  const auto nearOtherPart = [&partBoxes, &neighbours](const Eigen::AlignedBox3d& box, std::int32_t part) {
    for (const std::int32_t p : neighbours[static_cast<std::size_t>(part)]) {
      if (partBoxes[p].intersects(box)) {
        return true;
      }
    }
    return false;
  };
  const auto cellOf = [cell](const Vec3& p) {
    return Eigen::Array3i((p / cell).array().floor().cast<int>());
  };
  const auto key = [](int i, int j, int k) {
    return (static_cast<std::int64_t>(i) + (1 << 20)) | ((static_cast<std::int64_t>(j) + (1 << 20)) << 21) |
           ((static_cast<std::int64_t>(k) + (1 << 20)) << 42);
  };
  std::vector<std::pair<std::int64_t, std::int32_t>> bins;
  bins.reserve(tets_.size() * 8);
  for (std::size_t k = 0; k < tets_.size(); ++k) {
    if (!nearOtherPart(boxes[k], tetPart_[k])) {
      continue;
    }
    const auto lo = cellOf(boxes[k].min());
    const auto hi = cellOf(boxes[k].max());
    for (int i = lo[0]; i <= hi[0]; ++i) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int l = lo[2]; l <= hi[2]; ++l) {
          bins.emplace_back(key(i, j, l), static_cast<std::int32_t>(k));
        }
      }
    }
  }
  std::sort(bins.begin(), bins.end());
  // Triangles in parallel, each pair's force computed into a record; then the records applied in
  // the serial order (triangle, then target element): the same sums as one thread, so 1 and N
  // threads give the same bits.
  const auto triangleCount = static_cast<std::int64_t>(triangles_.size());
  std::vector<std::vector<PairForce>> found;
  std::vector<std::size_t> candidatePairs;
#pragma omp parallel
  {
#pragma omp single
    {
      found.resize(static_cast<std::size_t>(omp_get_num_threads()));
      candidatePairs.assign(found.size(), 0);
    }
    auto& mine = found[static_cast<std::size_t>(omp_get_thread_num())];
    std::size_t& myCandidates = candidatePairs[static_cast<std::size_t>(omp_get_thread_num())];
    std::vector<std::int32_t> candidates;
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t ti = 0; ti < triangleCount; ++ti) {
      const auto t = static_cast<std::size_t>(ti);
      Eigen::AlignedBox3d box;
      for (const auto n : triangles_[t]) {
        box.extend(x[n]);
      }
      if (!nearOtherPart(box, trianglePart_[t])) {
        continue;
      }
      const auto lo = cellOf(box.min());
      const auto hi = cellOf(box.max());
      candidates.clear();
      for (int i = lo[0]; i <= hi[0]; ++i) {
        for (int j = lo[1]; j <= hi[1]; ++j) {
          for (int l = lo[2]; l <= hi[2]; ++l) {
            const auto k = key(i, j, l);
            auto it = std::lower_bound(bins.begin(), bins.end(), std::make_pair(k, std::int32_t{-1}));
            for (; it != bins.end() && it->first == k; ++it) {
              if (tetPart_[it->second] != trianglePart_[t] && boxes[it->second].intersects(box)) {
                candidates.push_back(it->second);
              }
            }
          }
        }
      }
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      myCandidates += candidates.size();
      for (const auto k : candidates) {
        PairForce f;
        if (pairForce(t, static_cast<std::size_t>(k), x, v, f)) {
          mine.push_back(f);
        }
      }
    }
  }
  // Each thread's records are in triangle order (a triangle is one thread's); merged by triangle,
  // a triangle's records keep their target order.
  std::vector<PairForce> all;
  for (auto& f : found) {
    all.insert(all.end(), f.begin(), f.end());
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const PairForce& a, const PairForce& b) { return a.triangle < b.triangle; });
  for (const std::size_t c : candidatePairs) {
    stats.candidatePairs += c;
  }
  applyPairs(all, forces, contactor, stats);
  return stats;
}

void BodyContact::applyPairs(const std::vector<PairForce>& all, std::vector<Vec3>& forces, ContactorLoads* contactor,
                             BodyContactStats& stats) const {
  for (const PairForce& f : all) {
    ++stats.touchingPairs;
    stats.normalForce += f.contactorShare.sum();
    const auto& tri = triangles_[f.triangle];
    const auto& c = tets_[f.target];
    for (int k = 0; k < 3; ++k) {
      forces[tri[k]] -= f.contactorShare[k] * f.normal;
      if (contactor != nullptr) {
        const auto a = static_cast<std::size_t>(tri[k]);
        contactor->force[a] -= f.contactorShare[k] * f.normal;
        if (f.contactorShare[k] > contactor->share[a]) { // the first of equal shares: serial order
          contactor->share[a] = f.contactorShare[k];
          contactor->target[a] = static_cast<std::int32_t>(f.target);
        }
      }
    }
    for (int n = 0; n < 4; ++n) {
      forces[c[n]] += f.targetShare[n] * f.normal;
    }
  }
}

bool BodyContact::pairForce(std::size_t triangle, std::size_t target, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, PairForce& out) const {
  const auto& c = tets_[target];
  const auto& tri = triangles_[triangle];
  // Barycentric coordinates of the element at the triangle's corners: L(i, corner).
  Eigen::Matrix3d edges;
  edges << x[c[1]] - x[c[0]], x[c[2]] - x[c[0]], x[c[3]] - x[c[0]];
  const double det = edges.determinant();
  if (!(det > 0.0)) {
    return false; // an inverted element: DeformableBody stops on it
  }
  const Eigen::Matrix3d inverse = edges.inverse();
  Eigen::Matrix<double, 4, 3> L;
  for (int k = 0; k < 3; ++k) {
    const Vec3 l = inverse * (x[tri[k]] - x[c[0]]);
    L(0, k) = 1.0 - l.sum();
    L.block<3, 1>(1, k) = l;
  }
  for (int i = 0; i < 4; ++i) {
    if (L.row(i).maxCoeff() <= 0.0) {
      return false; // the triangle is outside face i's plane
    }
  }
  const Vec3 areaVector = 0.5 * (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
  const double area = areaVector.norm();
  if (!(area > 0.0)) {
    return false;
  }
  const Vec3 normal = areaVector / area;
  Eigen::Vector3d contactorShare = Eigen::Vector3d::Zero(); // integral of P N_a da
  Eigen::Vector4d targetShare = Eigen::Vector4d::Zero();    // integral of P lambda_b da
  for (int i = 0; i < 4; ++i) {
    // Sub-tet i: lambda_i >= 0 and lambda_j - lambda_i >= 0; there phi = 4 p lambda_i.
    std::array<Bary, 10> a{Bary(1, 0, 0), Bary(0, 1, 0), Bary(0, 0, 1)};
    std::array<Bary, 10> b;
    int count = clip(a, 3, L.row(i).transpose(), b);
    for (int j = 0; j < 4 && count >= 3; ++j) {
      if (j != i) {
        count = clip(b, count, (L.row(j) - L.row(i)).transpose(), a);
        std::swap(a, b);
      }
    }
    for (int k = 1; k + 1 < count; ++k) {
      const Bary& p0 = b[0];
      const Bary& p1 = b[k];
      const Bary& p2 = b[k + 1];
      const double fraction = std::abs((p1[1] - p0[1]) * (p2[2] - p0[2]) - (p1[2] - p0[2]) * (p2[1] - p0[1]));
      for (const auto& q : dunavant4()) {
        const Bary mu = q.point[0] * p0 + q.point[1] * p1 + q.point[2] * p2;
        const Eigen::Vector4d lambda = L * mu;
        double P = 4.0 * penalty_ * lambda[i];
        if (dampingRatio_ > 0.0) {
          Vec3 vA = mu[0] * v[tri[0]] + mu[1] * v[tri[1]] + mu[2] * v[tri[2]];
          const Vec3 vB = lambda[0] * v[c[0]] + lambda[1] * v[c[1]] + lambda[2] * v[c[2]] + lambda[3] * v[c[3]];
          P = std::max(0.0, P + dampingRatio_ * impedance_ * (vA - vB).dot(normal));
        }
        const double w = q.weight * fraction * area * P;
        contactorShare += w * mu;
        targetShare += w * lambda;
      }
    }
  }
  if (contactorShare.sum() == 0.0) {
    return false;
  }
  out.triangle = triangle;
  out.target = target;
  out.normal = normal;
  out.contactorShare = contactorShare;
  out.targetShare = targetShare;
  return true;
}

} // namespace armour::deformable
