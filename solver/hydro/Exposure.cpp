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
constexpr int kLeafTriangles = 4;
/// Barycentric slack of the triangle test: a line within 1e-10 of a triangle's size outside it
/// still hits, so a line through a shared edge cannot fall between the two triangles by round-off.
constexpr double kBarycentricSlack = 1e-10;
/// Above this many rays the spacing is almost certainly in the wrong unit (unit: -).
constexpr std::size_t kMaxRays = 50'000'000;

using dynamics::MotionType;

} // namespace

// --- MeshRayCaster ------------------------------------------------------------------------------

MeshRayCaster::MeshRayCaster(const geometry::TriangleMesh& mesh) {
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
                                  const std::vector<Vec3>& centroids, const geometry::TriangleMesh& mesh) {
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

  // Rays: grid points inside a loaded body's circle; the same point from two bodies is one ray.
  std::vector<std::pair<std::int64_t, std::int64_t>> rays;
  double largest = 0.0;
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
  stats_.rays = rays.size();
  if (rays.empty()) {
    return result;
  }

  // Bucket grid of bounding circles over the rays' extent, cells about one loaded body across;
  // bodies enter their buckets in index order, so each bucket lists them sorted.
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
