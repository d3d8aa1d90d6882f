// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/UnderlayerSurface.hpp"

#include "core/Error.hpp"
#include "geometry/MeshRayCaster.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <unordered_map>

namespace armour::analysis {

namespace {

/// A stone covers another's top only if it reaches above it by more than this (unit: m): stones
/// that merely touch at the top point leave it exposed.
constexpr double kCoverTolerance = 1e-9;

/// A square bin of the slope plane holding the bodies whose projected bounding circles overlap it.
struct PlaneBins {
  double cell = 1.0;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> bins;

  static std::int64_t key(std::int64_t i, std::int64_t j) { return (i << 32) ^ (j & 0xffffffff); }
  [[nodiscard]] std::int64_t index(double x) const { return static_cast<std::int64_t>(std::floor(x / cell)); }

  void insert(std::size_t body, double s, double t, double radius) {
    for (std::int64_t i = index(s - radius); i <= index(s + radius); ++i)
      for (std::int64_t j = index(t - radius); j <= index(t + radius); ++j) bins[key(i, j)].push_back(body);
  }
  [[nodiscard]] const std::vector<std::size_t>* at(double s, double t) const {
    const auto it = bins.find(key(index(s), index(t)));
    return it == bins.end() ? nullptr : &it->second;
  }
};

} // namespace

SurfaceStones surfaceStones(const std::vector<PosedMesh>& bodies, const SlopeFrame& frame) {
  const std::size_t n = bodies.size();
  SurfaceStones out;
  out.local.resize(n);
  out.top.resize(n);
  out.exposed.assign(n, true);
  std::vector<Eigen::Vector3d> topPoint(n);
  std::vector<double> radius(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const PosedMesh& b = bodies[i];
    if (b.mesh == nullptr || b.mesh->vertices.empty())
      core::failInput("underlayer survey", "support body {} has no mesh; the survey needs every support's surface", i);
    if (!(b.scale > 0.0) || !std::isfinite(b.scale))
      core::failInput("underlayer survey", "support body {} has scale {}; scales must be positive", i, b.scale);
    out.local[i] = frame.toLocal(b.position);
    double top = -std::numeric_limits<double>::infinity();
    for (const auto& v : b.mesh->vertices) {
      const Eigen::Vector3d w = b.position + b.orientation * (b.scale * v);
      const Eigen::Vector3d l = frame.toLocal(w);
      radius[i] = std::max(radius[i], std::hypot(l.x() - out.local[i].x(), l.y() - out.local[i].y()));
      if (l.z() > top) {
        top = l.z();
        topPoint[i] = w;
      }
    }
    out.top[i] = top;
  }
  if (n == 0) return out;

  // Bins about twice the median stone radius: each top point meets a handful of candidates.
  std::vector<double> sorted = radius;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.end());
  PlaneBins bins;
  bins.cell = std::max(2.0 * sorted[n / 2], 1e-6);
  for (std::size_t i = 0; i < n; ++i) bins.insert(i, out.local[i].x(), out.local[i].y(), radius[i]);

  std::map<const geometry::TriangleMesh*, std::unique_ptr<geometry::MeshRayCaster>> casters;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d li = frame.toLocal(topPoint[i]);
    const auto* candidates = bins.at(li.x(), li.y());
    if (candidates == nullptr) continue;
    for (std::size_t j : *candidates) {
      if (j == i || out.top[j] <= out.top[i] + kCoverTolerance) continue;
      if (std::hypot(li.x() - out.local[j].x(), li.y() - out.local[j].y()) > radius[j]) continue;
      auto& caster = casters[bodies[j].mesh];
      if (!caster) caster = std::make_unique<geometry::MeshRayCaster>(*bodies[j].mesh);
      // In body j's frame (scale 1): the line through the top point along the normal. Cast
      // against -normal, the first hit along -n is where the line leaves body j along +n, so j
      // covers the top when that exit lies above it.
      const Eigen::Quaterniond toBody = bodies[j].orientation.conjugate();
      const Eigen::Vector3d origin = toBody * (topPoint[i] - bodies[j].position) / bodies[j].scale;
      const Eigen::Vector3d down = toBody * (-frame.normal);
      const double t = caster->firstHit(origin, down);
      if (std::isfinite(t) && -t * bodies[j].scale > kCoverTolerance) {
        out.exposed[i] = false;
        break;
      }
    }
  }
  for (bool e : out.exposed) out.exposedCount += e ? 1 : 0;
  return out;
}

double meanTopIn(const SurfaceStones& stones, const SlopeWindow& window, bool surfaceOnly) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t j = 0; j < stones.top.size(); ++j) {
    if (surfaceOnly && !stones.exposed[j]) continue;
    if (window.containsLocal(stones.local[j])) {
      sum += stones.top[j];
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

} // namespace armour::analysis
