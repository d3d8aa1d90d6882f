// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/Exposure.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace armour::hydro {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Above this many rays the spacing is almost certainly in the wrong unit (unit: -).
constexpr std::size_t kMaxRays = 50'000'000;

using dynamics::MotionType;

} // namespace

// --- Exposure -----------------------------------------------------------------------------------

const MeshRayCaster& Exposure::caster(const simulation::World& world, simulation::ShapeId shape) {
  if (casters_.size() <= shape) {
    casters_.resize(shape + 1);
  }
  if (!casters_[shape]) {
    casters_[shape] = std::make_unique<MeshRayCaster>(world.shape(shape).mesh);
  }
  return *casters_[shape];
}

namespace {

using Ray = std::pair<std::int64_t, std::int64_t>; ///< grid point (i, j): (i + 1/2, j + 1/2) h in the slope plane

/// The rays: grid points of spacing h inside a loaded body's bounding circle (centre (cu, cv),
/// radius r in the slope plane; loaded: slot >= 0), sorted, each once. `largest` gets the largest
/// loaded radius. Refuses more than kMaxRays.
std::vector<Ray> exposureRays(const std::vector<std::int64_t>& slot, const std::vector<double>& cu,
                              const std::vector<double>& cv, const std::vector<double>& radius, double h,
                              const std::string& where, double& largest) {
  std::vector<Ray> rays;
  largest = 0.0;
  const auto count = static_cast<BodyId>(slot.size());
  for (BodyId b = 0; b < count; ++b) {
    if (slot[b] < 0) {
      continue;
    }
    const double r = radius[b];
    largest = std::max(largest, r);
    const auto i0 = static_cast<std::int64_t>(std::ceil((cu[b] - r) / h - 0.5));
    const auto i1 = static_cast<std::int64_t>(std::floor((cu[b] + r) / h - 0.5));
    const auto j0 = static_cast<std::int64_t>(std::ceil((cv[b] - r) / h - 0.5));
    const auto j1 = static_cast<std::int64_t>(std::floor((cv[b] + r) / h - 0.5));
    if (static_cast<double>(i1 - i0 + 1) * static_cast<double>(j1 - j0 + 1) + static_cast<double>(rays.size()) >
        static_cast<double>(kMaxRays)) {
      core::failInput(where, "ray spacing = {} m gives more than {} rays over units of radius {} m: is it in the "
                      "wrong unit? A quarter of the units' Dn is a good start", h, kMaxRays, r);
    }
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double du = (static_cast<double>(i) + 0.5) * h - cu[b];
      for (std::int64_t j = j0; j <= j1; ++j) {
        const double dv = (static_cast<double>(j) + 0.5) * h - cv[b];
        if (du * du + dv * dv <= r * r) {
          rays.emplace_back(i, j);
        }
      }
    }
  }
  std::sort(rays.begin(), rays.end());
  rays.erase(std::unique(rays.begin(), rays.end()), rays.end());
  return rays;
}

/// A bucket grid of the bodies' bounding circles over the rays' extent, cells about one loaded
/// body across; bodies enter their buckets in index order, so each bucket lists them sorted.
struct BlockerGrid {
  double uMin = 0.0, uMax = 0.0, vMin = 0.0, vMax = 0.0, cell = 0.0;
  std::int64_t nu = 0, nv = 0;
  std::vector<std::uint32_t> start; ///< bucket k's bodies: blockers[start[k] .. start[k + 1])
  std::vector<BodyId> blockers;
};

BlockerGrid blockerGrid(const std::vector<Ray>& rays, double h, double largest, const std::vector<double>& cu,
                        const std::vector<double>& cv, const std::vector<double>& radius) {
  BlockerGrid g;
  const auto count = static_cast<BodyId>(cu.size());
  double uMin = kInfinity, uMax = -kInfinity, vMin = kInfinity, vMax = -kInfinity;
  for (const auto& [i, j] : rays) {
    uMin = std::min(uMin, (static_cast<double>(i) + 0.5) * h);
    uMax = std::max(uMax, (static_cast<double>(i) + 0.5) * h);
    vMin = std::min(vMin, (static_cast<double>(j) + 0.5) * h);
    vMax = std::max(vMax, (static_cast<double>(j) + 0.5) * h);
  }
  const double cell = std::max(2.0 * largest, h);
  const auto nu = static_cast<std::int64_t>(std::floor((uMax - uMin) / cell)) + 1;
  const auto nv = static_cast<std::int64_t>(std::floor((vMax - vMin) / cell)) + 1;
  auto cellRange = [&](double c, double r, double lo, std::int64_t cells) {
    const auto a = static_cast<std::int64_t>(std::floor((c - r - lo) / cell));
    const auto b = static_cast<std::int64_t>(std::floor((c + r - lo) / cell));
    return std::pair<std::int64_t, std::int64_t>(std::max<std::int64_t>(a, 0), std::min<std::int64_t>(b, cells - 1));
  };
  std::vector<std::uint32_t> start(static_cast<std::size_t>(nu * nv) + 1, 0);
  std::vector<BodyId> blockers;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t c = 1; c < start.size(); ++c) {
        start[c] += start[c - 1];
      }
      blockers.resize(start.back());
      fill.assign(start.begin(), start.end() - 1);
    }
    for (BodyId b = 0; b < count; ++b) {
      const double r = radius[b];
      if (cu[b] + r < uMin || cu[b] - r > uMax || cv[b] + r < vMin || cv[b] - r > vMax) {
        continue;
      }
      const auto [a0, a1] = cellRange(cu[b], r, uMin, nu);
      const auto [b0, b1] = cellRange(cv[b], r, vMin, nv);
      for (std::int64_t a = a0; a <= a1; ++a) {
        for (std::int64_t c = b0; c <= b1; ++c) {
          const auto bucket = static_cast<std::size_t>(a * nv + c);
          if (pass == 0) {
            ++start[bucket + 1];
          } else {
            blockers[fill[bucket]++] = b;
          }
        }
      }
    }
  }
  g.uMin = uMin;
  g.uMax = uMax;
  g.vMin = vMin;
  g.vMax = vMax;
  g.cell = cell;
  g.nu = nu;
  g.nv = nv;
  g.start = std::move(start);
  g.blockers = std::move(blockers);
  return g;
}

} // namespace

std::vector<BodyExposure> Exposure::compute(const simulation::World& world, std::span<const BodyId> loaded,
                                            const ExposureQuery& query, const std::string& where) {
  stats_ = {};
  std::vector<BodyExposure> result(loaded.size());
  const double h = query.spacing;
  if (!std::isfinite(h) || !(h > 0.0)) {
    core::failInput(where, "ray spacing = {} m: must be a positive length (a quarter of the units' Dn is a good "
                    "start)", h);
  }
  if (!query.slopeNormal.allFinite() || query.slopeNormal.norm() < 1e-12) {
    core::failInput(where, "slope normal ({}, {}, {}) is not a finite non-zero vector", query.slopeNormal.x(),
                    query.slopeNormal.y(), query.slopeNormal.z());
  }
  // Slope-plane frame (u, v, n), right-handed: v along the trunk, u up the slope.
  const Vec3 n = query.slopeNormal.normalized();
  Vec3 v = Vec3::UnitY() - n.y() * n;
  if (v.norm() < 1e-6) {
    v = Vec3::UnitX() - n.x() * n;
  }
  v.normalize();
  const Vec3 u = v.cross(n);
  const Vec3 d = query.side == ExposureSide::FromSea ? Vec3(-n) : n;

  const auto& bodies = world.bodies();
  const auto count = static_cast<BodyId>(bodies.size());
  std::vector<std::int64_t> slot(count, -1);
  for (std::size_t k = 0; k < loaded.size(); ++k) {
    const BodyId b = loaded[k];
    if (b < count && bodies.motionType(b) != MotionType::Static && slot[b] < 0) {
      slot[b] = static_cast<std::int64_t>(k);
    }
  }

  // Every body's bounding circle in the slope plane (centre (cu, cv), radius r).
  std::vector<double> cu(count), cv(count), radius(count);
  for (BodyId b = 0; b < count; ++b) {
    cu[b] = bodies.position(b).dot(u);
    cv[b] = bodies.position(b).dot(v);
    radius[b] = world.shape(world.bodyShape(b)).radius * world.bodyScale(b);
  }

  double largest = 0.0;
  const std::vector<Ray> rays = exposureRays(slot, cu, cv, radius, h, where, largest);
  stats_.rays = rays.size();
  if (rays.empty()) {
    return result;
  }
  const BlockerGrid grid = blockerGrid(rays, h, largest, cu, cv, radius);
  const double uMin = grid.uMin, vMin = grid.vMin, cell = grid.cell;
  const std::int64_t nu = grid.nu, nv = grid.nv;
  const std::vector<std::uint32_t>& start = grid.start;
  const std::vector<BodyId>& blockers = grid.blockers;

  // Per-body ray transforms, and the shapes' trees built serially before the parallel loop.
  std::vector<Eigen::Matrix3d> toBody(count);
  std::vector<const MeshRayCaster*> casters(count, nullptr);
  for (const BodyId b : blockers) {
    if (casters[b] == nullptr) {
      casters[b] = &caster(world, world.bodyShape(b));
      toBody[b] = bodies.orientation(b).conjugate().toRotationMatrix();
    }
  }

  // Cast: each ray writes its own slot.
  const auto rayCount = static_cast<std::int64_t>(rays.size());
  std::vector<std::int64_t> winner(rays.size(), -1);
  std::vector<Vec3> point(rays.size(), Vec3::Zero());
  std::size_t candidates = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : candidates)
  for (std::int64_t r = 0; r < rayCount; ++r) {
    const double pu = (static_cast<double>(rays[static_cast<std::size_t>(r)].first) + 0.5) * h;
    const double pv = (static_cast<double>(rays[static_cast<std::size_t>(r)].second) + 0.5) * h;
    const Vec3 origin = pu * u + pv * v;
    const auto a = std::min<std::int64_t>(static_cast<std::int64_t>(std::floor((pu - uMin) / cell)), nu - 1);
    const auto c = std::min<std::int64_t>(static_cast<std::int64_t>(std::floor((pv - vMin) / cell)), nv - 1);
    const auto bucket = static_cast<std::size_t>(a * nv + c);
    double bestT = kInfinity;
    std::int64_t bestBody = -1;
    for (std::uint32_t e = start[bucket]; e < start[bucket + 1]; ++e) {
      const BodyId b = blockers[e];
      const double du = pu - cu[b];
      const double dv = pv - cv[b];
      if (du * du + dv * dv > radius[b] * radius[b]) {
        continue; // the line passes outside the bounding sphere
      }
      ++candidates;
      const double scale = world.bodyScale(b);
      const Vec3 localOrigin = toBody[b] * (origin - bodies.position(b)) / scale;
      const Vec3 localDirection = toBody[b] * d;
      const double t = scale * casters[b]->firstHit(localOrigin, localDirection);
      // Strict: of two bodies entered at the same distance the lower index (listed first) wins.
      if (t < bestT) {
        bestT = t;
        bestBody = b;
      }
    }
    if (bestBody >= 0) {
      winner[static_cast<std::size_t>(r)] = bestBody;
      point[static_cast<std::size_t>(r)] = origin + bestT * d;
    }
  }
  stats_.candidates = candidates;

  // Serial sums in ray order: the same for any thread count.
  for (std::size_t r = 0; r < rays.size(); ++r) {
    const std::int64_t b = winner[r];
    if (b < 0 || slot[static_cast<std::size_t>(b)] < 0) {
      continue;
    }
    BodyExposure& e = result[static_cast<std::size_t>(slot[static_cast<std::size_t>(b)])];
    ++e.hits;
    e.meanPoint += point[r];
    ++stats_.hits;
  }
  for (auto& e : result) {
    if (e.hits > 0) {
      e.meanPoint /= static_cast<double>(e.hits);
    }
  }
  return result;
}

} // namespace armour::hydro
