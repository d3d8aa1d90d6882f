// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/FdemMesh.hpp"

#include "core/Error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace armour::contact {

namespace {

constexpr std::uint32_t kLeafSize = 4; ///< elements per hierarchy leaf (unit: -)

} // namespace

double FdemElement::psi(const Vec3& x) const {
  double m = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    m = std::min(m, lambda(k, x));
  }
  return 4.0 * peak * m;
}

FdemMesh::FdemMesh(const geometry::TriangleMesh& surface, const FdemMeshSettings& settings, const std::string& source) {
  if (settings.elementsPerUnit < 24 || settings.elementsPerUnit > 2'000'000) {
    core::failInput(source, "contact.fdem.elements_per_unit = {}: use 24 to 2000000 tetrahedra per body (seed 002: "
                            "about 2500 per Core-Loc)",
                    settings.elementsPerUnit);
  }
  geometry::TetrahedralizeOptions options;
  options.targetTetCount = settings.elementsPerUnit;
  // Refine the surface to the lattice spacing: a coarse surface (a cube's 12 triangles) would
  // otherwise make long thin surface elements whose potential rises steeply only near the edges.
  options.keepSurface = false;
  options.source = source;
  build(geometry::tetrahedralize(surface, options), source);
}

FdemMesh::FdemMesh(const geometry::TetMesh& tets, const std::string& source) { build(tets, source); }

void FdemMesh::build(const geometry::TetMesh& tets, const std::string& source) {
  totalTets_ = tets.tets.size();
  volume_ = tets.totalVolume();
  vertices_ = tets.vertices;
  // Boundary faces: the faces used by exactly one tet. Face k of a tet is opposite its vertex k.
  std::map<std::array<std::int32_t, 3>, std::pair<int, std::pair<std::uint32_t, int>>> faceUse;
  for (std::uint32_t t = 0; t < tets.tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      std::array<std::int32_t, 3> key{};
      int n = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != k) key[n++] = tets.tets[t][j];
      }
      std::sort(key.begin(), key.end());
      auto& use = faceUse[key];
      use.first += 1;
      use.second = {t, k};
    }
  }
  std::vector<std::vector<int>> boundaryFaces(tets.tets.size());
  for (const auto& [key, use] : faceUse) {
    if (use.first == 1) boundaryFaces[use.second.first].push_back(use.second.second);
  }
  tets_ = tets.tets;
  if (std::none_of(boundaryFaces.begin(), boundaryFaces.end(), [](const auto& f) { return !f.empty(); })) {
    core::failInput(source, "the tetrahedral mesh has no boundary faces ({} tets): nothing can touch it", totalTets_);
  }

  elements_.clear();
  faces_.clear();
  std::vector<double> surfacePeaks;
  maxGradient_ = 0.0;
  for (std::uint32_t t = 0; t < tets.tets.size(); ++t) {
    const auto& tet = tets.tets[t];
    if (boundaryFaces[t].empty()) {
      // Out of reach: an element touching the surface only at a vertex or an edge has psi ~ 0
      // there, so within depth d of the surface it holds O(d^3) of energy against the face
      // elements' O(d^2): dropping it changes the force by a relative O(d / h).
      continue;
    }
    FdemElement e;
    e.nodes = tet;
    const Vec3& p0 = vertices_[tet[0]];
    geometry::Mat3 T;
    T.col(0) = vertices_[tet[1]] - p0;
    T.col(1) = vertices_[tet[2]] - p0;
    T.col(2) = vertices_[tet[3]] - p0;
    if (!(std::abs(T.determinant()) > 0.0)) {
      core::failInput(source, "tetrahedron {} is flat (zero volume): the contact mesh is degenerate", t);
    }
    const geometry::Mat3 inv = T.inverse();
    Vec3 sum = Vec3::Zero();
    double offsetSum = 0.0;
    for (int k = 1; k < 4; ++k) {
      e.lambdaGradient[k] = inv.row(k - 1).transpose();
      e.lambdaOffset[k] = -e.lambdaGradient[k].dot(p0);
      sum += e.lambdaGradient[k];
      offsetSum += e.lambdaOffset[k];
    }
    e.lambdaGradient[0] = -sum;
    e.lambdaOffset[0] = 1.0 - offsetSum;
    e.centroid = 0.25 * (p0 + vertices_[tet[1]] + vertices_[tet[2]] + vertices_[tet[3]]);
    for (int j = 0; j < 4; ++j) e.box.extend(vertices_[tet[j]]);
    // r_k = lambda_k(centroid) / |g_k| = 1 / (4 |g_k|): the centroid's distance to face k.
    std::array<double, 4> r{};
    for (int k = 0; k < 4; ++k) r[k] = 0.25 / e.lambdaGradient[k].norm();
    const auto& bf = boundaryFaces[t];
    double mean = 0.0;
    for (int k : bf) mean += r[k];
    e.peak = mean / static_cast<double>(bf.size());
    surfacePeaks.push_back(e.peak);
    for (int k = 0; k < 4; ++k) maxGradient_ = std::max(maxGradient_, e.peak / r[k]);
    e.firstFace = static_cast<std::uint32_t>(faces_.size());
    for (int k : bf) {
      FdemFace f;
      int n = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != k) f.corners[n++] = vertices_[tet[j]];
      }
      const Vec3 outward = -e.lambdaGradient[k].normalized();
      Vec3 c = (f.corners[1] - f.corners[0]).cross(f.corners[2] - f.corners[0]);
      if (c.dot(outward) < 0.0) {
        std::swap(f.corners[1], f.corners[2]);
        c = -c;
      }
      f.area = 0.5 * c.norm();
      f.normal = c.normalized();
      f.element = static_cast<std::uint32_t>(elements_.size());
      faces_.push_back(f);
    }
    e.faceCount = static_cast<std::uint32_t>(bf.size());
    elements_.push_back(e);
  }

  // The median, not the smallest: one sliver on the surface would set a reach far below that of
  // the elements that carry the contact.
  std::nth_element(surfacePeaks.begin(), surfacePeaks.begin() + surfacePeaks.size() / 2, surfacePeaks.end());
  reach_ = surfacePeaks[surfacePeaks.size() / 2];

  // Hierarchy: median split on the longest axis of the element centroids.
  order_.resize(elements_.size());
  std::vector<Vec3> centres(elements_.size());
  for (std::uint32_t i = 0; i < elements_.size(); ++i) {
    order_[i] = i;
    centres[i] = elements_[i].centroid;
  }
  nodes_.clear();
  nodes_.reserve(2 * elements_.size() / kLeafSize + 2);
  buildNode(0, static_cast<std::uint32_t>(elements_.size()), centres);
}

std::int32_t FdemMesh::buildNode(std::uint32_t first, std::uint32_t count, std::vector<Vec3>& centres) {
  const auto id = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  Box3 box, centreBox;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const FdemElement& e = elements_[order_[i]];
    box.extend(e.box.min);
    box.extend(e.box.max);
    centreBox.extend(e.centroid);
  }
  nodes_[id].box = box;
  if (count <= kLeafSize) {
    nodes_[id].first = first;
    nodes_[id].count = count;
    return id;
  }
  int axis = 0;
  centreBox.size().maxCoeff(&axis);
  const std::uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](std::uint32_t a, std::uint32_t b) { return centres[a][axis] < centres[b][axis]; });
  const std::int32_t left = buildNode(first, half, centres);
  const std::int32_t right = buildNode(first + half, count - half, centres);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

double FdemMesh::potential(const Vec3& x) const {
  // Walk the hierarchy; the elements do not overlap, so the first holding x is the one.
  std::vector<std::int32_t> stack{0};
  while (!stack.empty()) {
    const FdemBvhNode& n = nodes_[stack.back()];
    stack.pop_back();
    if ((x.array() < n.box.min.array()).any() || (x.array() > n.box.max.array()).any()) continue;
    if (n.left < 0) {
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
        const FdemElement& e = elements_[order_[i]];
        const double p = e.psi(x);
        if (p >= 0.0) return p;
      }
      continue;
    }
    stack.push_back(n.left);
    stack.push_back(n.right);
  }
  return 0.0;
}

} // namespace armour::contact
