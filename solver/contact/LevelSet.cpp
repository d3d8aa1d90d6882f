// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/LevelSet.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"
#include "geometry/MassProperties.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace armour::contact {

namespace {

/// Deepest tree the fixed traversal stack can hold. A median split halves the triangle count per
/// level, so 2^64 triangles would be needed to reach it.
constexpr int kStackSize = 64;

/// Squared distance from x to the box [lo, hi] (0 inside).
double boxDistanceSquared(const Vec3& x, const Vec3& lo, const Vec3& hi) {
  const Vec3 below = (lo - x).cwiseMax(0.0);
  const Vec3 above = (x - hi).cwiseMax(0.0);
  return (below + above).squaredNorm();
}

/// Interior angle of a triangle at corner p between edges to q and r (radians). atan2 of the
/// cross and dot products stays accurate for angles near 0 and pi, where acos would not.
double cornerAngle(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 u = q - p;
  const Vec3 v = r - p;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

} // namespace

// ---------------------------------------------------------------------------------------------
// MeshDistance

MeshDistance::MeshDistance(const TriangleMesh& mesh) {
  const auto count = static_cast<std::int32_t>(mesh.triangleCount());
  if (count == 0) {
    return;
  }
  // Pseudo-normals (Baerentzen and Aanaes 2005): unit face normals; per undirected edge the sum of
  // its two face normals; per vertex the sum of face normals weighted by the face's angle there.
  std::vector<Vec3> faceNormal(mesh.triangleCount());
  std::vector<Vec3> vertexNormal(mesh.vertexCount(), Vec3::Zero());
  std::map<std::pair<std::int32_t, std::int32_t>, Vec3> edgeNormal;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto& f = mesh.triangles[t];
    const auto p = mesh.corners(t);
    faceNormal[t] = mesh.doubleAreaNormal(t).normalized();
    for (int k = 0; k < 3; ++k) {
      vertexNormal[f[k]] += cornerAngle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]) * faceNormal[t];
      const auto key = std::minmax(f[k], f[(k + 1) % 3]);
      // try_emplace with an explicit zero: Eigen vectors are not zeroed by default construction.
      edgeNormal.try_emplace({key.first, key.second}, Vec3::Zero()).first->second += faceNormal[t];
    }
  }

  geometry::TriangleTree tree = geometry::buildTriangleTree(mesh);
  nodes_ = std::move(tree.nodes);
  originalIndex_ = std::move(tree.order);

  // Store triangle data in tree order so a leaf reads contiguous memory.
  corners_.resize(mesh.triangleCount());
  faceNormals_.resize(mesh.triangleCount());
  edgeNormals_.resize(mesh.triangleCount());
  vertexNormals_.resize(mesh.triangleCount());
  for (std::size_t s = 0; s < mesh.triangleCount(); ++s) {
    const auto t = static_cast<std::size_t>(originalIndex_[s]);
    const auto& f = mesh.triangles[t];
    corners_[s] = mesh.corners(t);
    faceNormals_[s] = faceNormal[t];
    for (int k = 0; k < 3; ++k) {
      const auto key = std::minmax(f[k], f[(k + 1) % 3]);
      edgeNormals_[s][k] = edgeNormal.at({key.first, key.second});
      vertexNormals_[s][k] = vertexNormal[f[k]];
    }
  }
}

std::size_t MeshDistance::memoryBytes() const {
  return corners_.size() * sizeof(corners_[0]) + faceNormals_.size() * sizeof(Vec3) +
         edgeNormals_.size() * sizeof(edgeNormals_[0]) + vertexNormals_.size() * sizeof(vertexNormals_[0]) +
         originalIndex_.size() * sizeof(std::int32_t) + nodes_.size() * sizeof(Node);
}

ClosestPoint MeshDistance::closest(const Vec3& x) const {
  ClosestPoint result;
  if (nodes_.empty()) {
    result.distance = result.signedDistance = std::numeric_limits<double>::infinity();
    return result;
  }
  double best = std::numeric_limits<double>::infinity(); // squared distance
  std::int32_t bestSlot = -1;
  std::array<std::int32_t, kStackSize> stack{};
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::int32_t self = stack[--top];
    const Node& node = nodes_[static_cast<std::size_t>(self)];
    if (boxDistanceSquared(x, node.lo, node.hi) >= best) {
      continue;
    }
    if (node.count > 0) {
      for (std::int32_t s = node.first; s < node.first + node.count; ++s) {
        const auto& p = corners_[static_cast<std::size_t>(s)];
        TriangleFeature feature{};
        const Vec3 c = geometry::closestPointOnTriangle(x, p[0], p[1], p[2], feature);
        const double d2 = (x - c).squaredNorm();
        if (d2 < best) {
          best = d2;
          bestSlot = s;
          result.point = c;
          result.feature = feature;
        }
      }
      continue;
    }
    // Inner node: its first child follows it, the second is at node.first. Push the farther
    // child first so the nearer one is searched first and tightens the bound sooner.
    const std::int32_t childA = self + 1;
    const std::int32_t childB = node.first;
    const Node& a = nodes_[static_cast<std::size_t>(childA)];
    const Node& b = nodes_[static_cast<std::size_t>(childB)];
    const double dA = boxDistanceSquared(x, a.lo, a.hi);
    const double dB = boxDistanceSquared(x, b.lo, b.hi);
    const bool aFirst = dA <= dB;
    const std::int32_t nearChild = aFirst ? childA : childB;
    const std::int32_t farChild = aFirst ? childB : childA;
    if ((aFirst ? dB : dA) < best) {
      stack[top++] = farChild;
    }
    if ((aFirst ? dA : dB) < best) {
      stack[top++] = nearChild;
    }
  }
  const auto s = static_cast<std::size_t>(bestSlot);
  result.triangle = originalIndex_[s];
  result.distance = std::sqrt(best);
  Vec3 pseudoNormal = Vec3::Zero();
  switch (result.feature) {
  case TriangleFeature::Face: pseudoNormal = faceNormals_[s]; break;
  case TriangleFeature::Edge01: pseudoNormal = edgeNormals_[s][0]; break;
  case TriangleFeature::Edge12: pseudoNormal = edgeNormals_[s][1]; break;
  case TriangleFeature::Edge20: pseudoNormal = edgeNormals_[s][2]; break;
  case TriangleFeature::Vertex0: pseudoNormal = vertexNormals_[s][0]; break;
  case TriangleFeature::Vertex1: pseudoNormal = vertexNormals_[s][1]; break;
  case TriangleFeature::Vertex2: pseudoNormal = vertexNormals_[s][2]; break;
  }
  result.signedDistance = (x - result.point).dot(pseudoNormal) < 0.0 ? -result.distance : result.distance;
  return result;
}

// ---------------------------------------------------------------------------------------------
// LevelSet

LevelSet::LevelSet(const TriangleMesh& mesh, const LevelSetSettings& settings, const std::string& source) {
  const auto start = std::chrono::steady_clock::now();
  const double volume = geometry::signedVolume(mesh);
  if (!(volume > 0.0) || !std::isfinite(volume)) {
    core::failInput(source, "enclosed volume = {} m^3: a level set needs a closed, outward mesh with positive "
                    "volume (validate the mesh first)", volume);
  }
  dn_ = std::cbrt(volume);
  if (settings.cellSize > 0.0) {
    h_ = settings.cellSize;
  } else {
    if (!(settings.cellsPerDn > 0.0) || !std::isfinite(settings.cellsPerDn)) {
      core::failInput(source, "cellsPerDn = {}: must be positive and finite (default 24 cells per Dn)",
                      settings.cellsPerDn);
    }
    h_ = dn_ / settings.cellsPerDn;
  }
  if (!std::isfinite(h_) || !(h_ > 0.0)) {
    core::failInput(source, "cellSize = {} m: must be positive and finite (or 0 to use cellsPerDn)", settings.cellSize);
  }
  if (settings.marginCells < 1) {
    core::failInput(source, "marginCells = {}: needs at least 1 cell of margin around the mesh (default 3)",
                    settings.marginCells);
  }
  invH_ = 1.0 / h_;
  meshBounds_ = mesh.bounds();
  const Vec3 size = meshBounds_.size();
  double nodes = 1.0;
  for (int k = 0; k < 3; ++k) {
    nodes *= std::ceil(size[k] / h_) + 1.0 + 2.0 * settings.marginCells;
  }
  if (nodes > static_cast<double>(settings.maxNodes)) {
    core::failInput(source, "cell size {:.4g} m gives {:.3g} grid nodes, more than maxNodes = {}: use a larger cell "
                    "size (Dn = {:.4g} m; is the mesh in metres?)", h_, nodes, settings.maxNodes, dn_);
  }
  for (int k = 0; k < 3; ++k) {
    n_[k] = static_cast<int>(std::ceil(size[k] / h_)) + 1 + 2 * settings.marginCells;
    // Centre the grid on the mesh box: the margin is the same on both sides, within half a cell.
    origin_[k] = meshBounds_.centre()[k] - 0.5 * (n_[k] - 1) * h_;
  }
  gridBounds_.min = origin_;
  gridBounds_.max = origin_ + h_ * Vec3(n_[0] - 1, n_[1] - 1, n_[2] - 1);

  const MeshDistance exact(mesh);
  const std::size_t nx = static_cast<std::size_t>(n_[0]);
  const std::size_t ny = static_cast<std::size_t>(n_[1]);
  values_.assign(nx * ny * static_cast<std::size_t>(n_[2]), 0.0F);
  // Every node is independent and written once, so the result does not depend on the number of
  // threads or the schedule.
  const int rows = n_[1] * n_[2];
#pragma omp parallel for schedule(dynamic, 4)
  for (int row = 0; row < rows; ++row) {
    const int j = row % n_[1];
    const int k = row / n_[1];
    const std::size_t base = nx * (static_cast<std::size_t>(j) + ny * static_cast<std::size_t>(k));
    for (int i = 0; i < n_[0]; ++i) {
      const Vec3 x = origin_ + h_ * Vec3(i, j, k);
      values_[base + static_cast<std::size_t>(i)] = static_cast<float>(exact.signedDistance(x));
    }
  }
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  core::logger("contact")->debug("{}: level set {} x {} x {} nodes, h = {:.4g} m (Dn / {:.3g}), {:.0f} kB, "
                                 "built in {:.3f} s",
                                 source, n_[0], n_[1], n_[2], h_, dn_ / h_, memoryBytes() / 1024.0, buildSeconds_);
}

std::size_t LevelSet::locate(const Vec3& x, double f[3]) const {
  int cell[3];
  for (int k = 0; k < 3; ++k) {
    // Clamp to the last cell so a point on the upper box face uses the cell below it (f = 1).
    // Written so that a NaN coordinate lands in cell 0 with f = NaN: the result is NaN, never
    // an out-of-range read.
    const double u = (x[k] - origin_[k]) * invH_;
    const double top = n_[k] - 2;
    const double clamped = u > 0.0 ? std::min(std::floor(u), top) : 0.0;
    cell[k] = static_cast<int>(clamped);
    f[k] = u - clamped;
  }
  const auto sy = static_cast<std::size_t>(n_[0]);
  const std::size_t sz = sy * static_cast<std::size_t>(n_[1]);
  return static_cast<std::size_t>(cell[0]) + sy * static_cast<std::size_t>(cell[1]) + sz * static_cast<std::size_t>(cell[2]);
}

double LevelSet::interpolateValue(const Vec3& x) const {
  double f[3];
  return interpolateAt(locate(x, f), f);
}

double LevelSet::interpolateAt(std::size_t base, const double f[3]) const {
  const std::size_t sy = static_cast<std::size_t>(n_[0]);
  const std::size_t sz = sy * static_cast<std::size_t>(n_[1]);
  const float* v = values_.data() + base;
  // The same arithmetic as gradientAt's differences: phi agrees bit for bit whichever call made it.
  const double v000 = v[0], v100 = v[1], v010 = v[sy], v110 = v[1 + sy];
  const double v001 = v[sz], v101 = v[1 + sz], v011 = v[sy + sz], v111 = v[1 + sy + sz];
  const double fx = f[0], fy = f[1], fz = f[2];
  const double gy = 1.0 - fy, gz = 1.0 - fz;
  const double c00 = v000 + fx * (v100 - v000);
  const double c10 = v010 + fx * (v110 - v010);
  const double c01 = v001 + fx * (v101 - v001);
  const double c11 = v011 + fx * (v111 - v011);
  return gz * (gy * c00 + fy * c10) + fz * (gy * c01 + fy * c11);
}

double LevelSet::value(const Vec3& local) const {
  const Vec3 c = local.cwiseMax(gridBounds_.min).cwiseMin(gridBounds_.max);
  const double phi = interpolateValue(c);
  const double d2 = (local - c).squaredNorm();
  return d2 > 0.0 ? phi + std::sqrt(d2) : phi;
}

double LevelSet::value(const Vec3& local, Lookup& at) const {
  const Vec3 c = local.cwiseMax(gridBounds_.min).cwiseMin(gridBounds_.max);
  at.base = locate(c, at.f);
  at.away = local - c;
  const double phi = interpolateAt(at.base, at.f);
  const double d2 = at.away.squaredNorm();
  at.phi = d2 > 0.0 ? phi + std::sqrt(d2) : phi;
  return at.phi;
}

double LevelSet::distanceLowerBound(const Vec3& local) const {
  const bool inGrid = (local.array() >= gridBounds_.min.array()).all() && (local.array() <= gridBounds_.max.array()).all();
  if (inGrid) {
    // phi is a convex combination of exact node distances within sqrt(3) h: phi <= d + sqrt(3) h.
    return interpolateValue(local) - std::sqrt(3.0) * h_ - 1e-6 * h_;
  }
  // Outside the grid value() follows a path through the grid box, which can be longer than the
  // shortest one: only the distance to the mesh's bounding box is a safe bound there.
  return std::sqrt(boxDistanceSquared(local, meshBounds_.min, meshBounds_.max));
}

Vec3 LevelSet::gradientAt(std::size_t base, const double f[3]) const {
  const std::size_t sx = 1;
  const std::size_t sy = static_cast<std::size_t>(n_[0]);
  const std::size_t sz = sy * static_cast<std::size_t>(n_[1]);
  const double v000 = values_[base];
  const double v100 = values_[base + sx];
  const double v010 = values_[base + sy];
  const double v110 = values_[base + sx + sy];
  const double v001 = values_[base + sz];
  const double v101 = values_[base + sx + sz];
  const double v011 = values_[base + sy + sz];
  const double v111 = values_[base + sx + sy + sz];
  const double fx = f[0];
  const double fy = f[1];
  const double fz = f[2];
  const double gx = 1.0 - fx;
  const double gy = 1.0 - fy;
  const double gz = 1.0 - fz;
  // Differences along x on the four x-edges of the cell, then the same for y and z.
  const double dx00 = v100 - v000;
  const double dx10 = v110 - v010;
  const double dx01 = v101 - v001;
  const double dx11 = v111 - v011;
  const double dy00 = v010 - v000;
  const double dy10 = v110 - v100;
  const double dy01 = v011 - v001;
  const double dy11 = v111 - v101;
  const double dz00 = v001 - v000;
  const double dz10 = v101 - v100;
  const double dz01 = v011 - v010;
  const double dz11 = v111 - v110;
  return {(gz * (gy * dx00 + fy * dx10) + fz * (gy * dx01 + fy * dx11)) * invH_,
          (gz * (gx * dy00 + fx * dy10) + fz * (gx * dy01 + fx * dy11)) * invH_,
          (gy * (gx * dz00 + fx * dz10) + fy * (gx * dz01 + fx * dz11)) * invH_};
}

LevelSetQuery LevelSet::query(const Lookup& at) const {
  LevelSetQuery q;
  q.phi = at.phi;
  q.gradient = gradientAt(at.base, at.f);
  const double d2 = at.away.squaredNorm();
  if (d2 > 0.0) {
    // Outside the box: phi = |x - c| + phi(c). Along a clamped axis c does not move with x, so
    // the gradient there is that of |x - c|; along a free axis |x - c| does not change.
    const double d = std::sqrt(d2);
    for (int k = 0; k < 3; ++k) {
      if (at.away[k] != 0.0) {
        q.gradient[k] = at.away[k] / d;
      }
    }
  }
  const double g = q.gradient.norm();
  q.normal = g >= LevelSetQuery::kMinGradient ? Vec3(q.gradient / g) : Vec3::Zero();
  return q;
}

LevelSetQuery LevelSet::query(const Vec3& local) const {
  Lookup at;
  static_cast<void>(value(local, at));
  return query(at);
}

double LevelSet::distance(const Vec3& local) const { return value(local); }

Vec3 LevelSet::gradient(const Vec3& local) const { return query(local).gradient; }

LevelSetQuery LevelSet::query(const Vec3& local, double scale) const {
  LevelSetQuery q = query(local / scale);
  q.phi *= scale;
  return q;
}

bool LevelSet::mayPenetrate(const Box3& localBox, double scale) const {
  if (empty() || localBox.empty()) {
    return false;
  }
  const Box3 box{localBox.min / scale, localBox.max / scale};
  // Every interpolated value is a convex combination of nodes within sqrt(3) h of the point,
  // and the nodes hold exact distances, so phi < 0 needs a true distance below sqrt(3) h: outside
  // the mesh box grown by that much, phi is positive.
  const Vec3 grow = Vec3::Constant(std::sqrt(3.0) * h_);
  const Vec3 lo = meshBounds_.min - grow;
  const Vec3 hi = meshBounds_.max + grow;
  if ((box.max.array() < lo.array()).any() || (box.min.array() > hi.array()).any()) {
    return false;
  }
  // phi is 1-Lipschitz in the 1-norm (each partial derivative of the interpolant is a weighted
  // mean of node differences over one cell edge, at most h apart in value): the minimum over the
  // box is at least phi(centre) minus the sum of the half-extents. The small allowance covers the
  // float rounding of the node values.
  // The true distance d is 1-Lipschitz and phi < 0 needs d < sqrt(3) h (above): no point of the
  // box can have phi < 0 when the lower bound of d at the centre exceeds the half-diagonal plus that.
  const Vec3 half = 0.5 * box.size();
  return distanceLowerBound(box.centre()) <= half.norm() + std::sqrt(3.0) * h_;
}

} // namespace armour::contact
