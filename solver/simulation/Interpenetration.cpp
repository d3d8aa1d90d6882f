// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/Interpenetration.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

namespace armour::simulation {
namespace {

constexpr double kFar = std::numeric_limits<double>::infinity();

/// A shape's lattice (body frame, unscaled): points origin + h (i, j, k) and their smoothed inside
/// fractions w = clamp(1/2 - phi / h, 0, 1); 0 for points at least h/2 outside.
struct ShapeLattice {
  Vec3 origin = Vec3::Zero();
  double h = 1.0;
  std::array<int, 3> n{0, 0, 0};
  std::vector<float> weight;
  std::vector<Eigen::Vector3f> normal; ///< outward unit normal where 0 < w < 1, else zero
  bool centroidInside = false; ///< the shape's own centroid lies in its solid
};

double smoothedInside(double phi, double h) { return std::clamp(0.5 - phi / h, 0.0, 1.0); }

ShapeLattice makeLattice(const ShapeModel& shape, double pointsPerDn) {
  const contact::LevelSet& ls = *shape.levelSet;
  ShapeLattice l;
  l.h = std::cbrt(shape.unitMass.volume) / pointsPerDn;
  // Half a spacing beyond the bounds on each side: the last points there have w = 0 or nearly.
  l.origin = shape.bounds.min - Vec3::Constant(0.5 * l.h);
  for (int a = 0; a < 3; ++a) l.n[a] = static_cast<int>(std::ceil(shape.bounds.size()[a] / l.h)) + 2;
  l.weight.resize(static_cast<std::size_t>(l.n[0]) * l.n[1] * l.n[2]);
  l.normal.assign(l.weight.size(), Eigen::Vector3f::Zero());
  std::size_t idx = 0;
  for (int k = 0; k < l.n[2]; ++k)
    for (int j = 0; j < l.n[1]; ++j)
      for (int i = 0; i < l.n[0]; ++i, ++idx) {
        const contact::LevelSetQuery q = ls.query(l.origin + l.h * Vec3(i, j, k));
        const double w = smoothedInside(q.phi, l.h);
        l.weight[idx] = static_cast<float>(w);
        if (w > 0.0 && w < 1.0) l.normal[idx] = q.normal.cast<float>();
      }
  l.centroidInside = ls.value(Vec3::Zero()) < 0.0;
  return l;
}

/// A body as the measurement sees it.
struct Placed {
  BodyId id = 0;
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  double s = 1.0;
  ShapeId shapeId = 0;
  const ShapeModel* shape = nullptr;
  const ShapeLattice* lattice = nullptr;
  geometry::Box3 box;     ///< world box of the mesh (unit: m)
  double volume = 0.0;    ///< unit: m^3
  bool movable = true;    ///< not Static

  [[nodiscard]] Vec3 toWorld(const Vec3& local) const { return x + q * (s * local); }
  /// Signed distance of a world point, positive far outside (cheap: outside the mesh box grown by
  /// `band`, the value is only known to exceed `band`).
  [[nodiscard]] double phi(const Vec3& world, double band) const {
    const Vec3 local = q.conjugate() * (world - x) / s;
    const geometry::Box3& b = shape->bounds;
    const double g = band / s;
    if ((local.array() < b.min.array() - g).any() || (local.array() > b.max.array() + g).any()) return kFar;
    return s * shape->levelSet->value(local);
  }
  /// Outward unit normal at a world point near the surface (zero on the medial axis).
  [[nodiscard]] Vec3 normal(const Vec3& world) const {
    return q * shape->levelSet->query(q.conjugate() * (world - x) / s).normal;
  }
};

/// The share of a cell about a point that lies in both solids, from their smoothed inside
/// fractions and outward normals: opposite normals (two faces pressed into each other) overlap by
/// max(0, wa + wb - 1), zero for faces that only touch; parallel normals (one face inside the
/// other's slab, as at the same pose) by min(wa, wb); between, a blend by the normals' cosine.
double cellShare(double wa, double wb, const Vec3& na, const Vec3& nb) {
  const double opposite = std::max(0.0, wa + wb - 1.0);
  if (wa >= 1.0 || wb >= 1.0 || wb <= 0.0) return opposite; // deep in one: both forms agree
  const double c = std::clamp(na.dot(nb), -1.0, 1.0);
  return 0.5 * (1.0 - c) * opposite + 0.5 * (1.0 + c) * std::min(wa, wb);
}

geometry::Box3 worldBox(const Placed& p) {
  geometry::Box3 box;
  const geometry::Box3& b = p.shape->bounds;
  for (int c = 0; c < 8; ++c)
    box.extend(p.toWorld(Vec3(c & 1 ? b.max.x() : b.min.x(), c & 2 ? b.max.y() : b.min.y(), c & 4 ? b.max.z() : b.min.z())));
  return box;
}

bool boxesOverlap(const geometry::Box3& a, const geometry::Box3& b) {
  return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
}

geometry::Box3 grown(const geometry::Box3& b, double by) {
  return {b.min - Vec3::Constant(by), b.max + Vec3::Constant(by)};
}

/// Common volume of A and a solid given by its signed distance `phiB` (world point, band -> m),
/// from A's lattice points in the world box `region` (unit: m^3).
template <class Phi, class Normal>
double commonVolume(const Placed& a, const geometry::Box3& region, const Phi& phiB, const Normal& normalB,
                    std::size_t& points) {
  const ShapeLattice& l = *a.lattice;
  const double hs = a.s * l.h; // the lattice spacing at the body's size (m)
  geometry::Box3 local;        // the region in A's unscaled body frame
  for (int c = 0; c < 8; ++c) {
    const Vec3 w(c & 1 ? region.max.x() : region.min.x(), c & 2 ? region.max.y() : region.min.y(),
                 c & 4 ? region.max.z() : region.min.z());
    local.extend(a.q.conjugate() * (w - a.x) / a.s);
  }
  std::array<int, 3> lo{}, hi{};
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::max(0, static_cast<int>(std::floor((local.min[d] - l.origin[d]) / l.h)));
    hi[d] = std::min(l.n[d] - 1, static_cast<int>(std::ceil((local.max[d] - l.origin[d]) / l.h)));
  }
  double sum = 0.0;
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        const std::size_t idx = static_cast<std::size_t>(i) + static_cast<std::size_t>(l.n[0]) *
                                    (static_cast<std::size_t>(j) + static_cast<std::size_t>(l.n[1]) * k);
        const double wa = l.weight[idx];
        if (wa <= 0.0) continue;
        ++points;
        const Vec3 w = a.toWorld(l.origin + l.h * Vec3(i, j, k));
        const double wb = smoothedInside(phiB(w, 0.5 * hs), hs);
        if (wb <= 0.0) continue;
        const bool band = wa < 1.0 && wb < 1.0; // near both surfaces: the normals decide
        sum += band ? cellShare(wa, wb, a.q * l.normal[idx].cast<double>(), normalB(w)) : std::min(wa, wb);
      }
  return sum * hs * hs * hs;
}

std::vector<Placed> placeBodies(const World& world, const InterpenetrationSettings& settings,
                                std::map<ShapeId, ShapeLattice>& lattices) {
  const dynamics::RigidBodies& bodies = world.bodies();
  std::vector<Placed> placed(bodies.size());
  for (BodyId b = 0; b < bodies.size(); ++b) {
    Placed& p = placed[b];
    p.id = b;
    p.x = bodies.position(b);
    p.q = bodies.orientation(b);
    p.s = world.bodyScale(b);
    p.shapeId = world.bodyShape(b);
    p.shape = &world.shape(p.shapeId);
    auto it = lattices.find(p.shapeId);
    if (it == lattices.end()) it = lattices.emplace(p.shapeId, makeLattice(*p.shape, settings.pointsPerDn)).first;
    p.lattice = &it->second;
    p.box = worldBox(p);
    p.volume = p.shape->unitMass.volume * p.s * p.s * p.s;
    p.movable = bodies.motionType(b) != dynamics::MotionType::Static;
  }
  return placed;
}

/// Body pairs whose boxes overlap (sweep along x), at least one of them movable: two fixed bodies
/// are never examined by the contact stage, so their overlap changes nothing in a run.
std::vector<std::pair<BodyId, BodyId>> candidatePairs(const std::vector<Placed>& placed) {
  std::vector<BodyId> order(placed.size());
  for (BodyId b = 0; b < order.size(); ++b) order[b] = b;
  std::sort(order.begin(), order.end(), [&](BodyId a, BodyId b) { return placed[a].box.min.x() < placed[b].box.min.x(); });
  std::vector<std::pair<BodyId, BodyId>> pairs;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Placed& a = placed[order[i]];
    for (std::size_t j = i + 1; j < order.size() && placed[order[j]].box.min.x() <= a.box.max.x(); ++j) {
      const Placed& b = placed[order[j]];
      if ((a.movable || b.movable) && boxesOverlap(a.box, b.box))
        pairs.emplace_back(std::min(a.id, b.id), std::max(a.id, b.id));
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

bool samePose(const Placed& a, const Placed& b) {
  const double tol = 1e-9 * std::cbrt(std::min(a.volume, b.volume));
  return a.shapeId == b.shapeId && std::abs(a.s - b.s) <= 1e-9 * a.s && (a.x - b.x).norm() <= tol &&
         a.q.angularDistance(b.q) <= 1e-9;
}

BodyOverlap bodyPair(const World& world, const Placed& a, const Placed& b, std::size_t& points) {
  BodyOverlap o;
  o.a = a.id;
  o.b = b.id;
  o.nameA = world.bodies().info(a.id).name;
  o.nameB = world.bodies().info(b.id).name;
  const double margin = std::max(a.s * a.lattice->h, b.s * b.lattice->h);
  geometry::Box3 region{a.box.min.cwiseMax(b.box.min), a.box.max.cwiseMin(b.box.max)};
  region = grown(region, margin);
  const double inB = commonVolume(a, region, [&](const Vec3& w, double band) { return b.phi(w, band); },
                                  [&](const Vec3& w) { return b.normal(w); }, points);
  const double inA = commonVolume(b, region, [&](const Vec3& w, double band) { return a.phi(w, band); },
                                  [&](const Vec3& w) { return a.normal(w); }, points);
  o.volume = 0.5 * (inA + inB);
  o.fraction = o.volume / std::min(a.volume, b.volume);
  o.contained = (a.lattice->centroidInside && b.phi(a.x, 0.0) < 0.0) || (b.lattice->centroidInside && a.phi(b.x, 0.0) < 0.0);
  o.samePose = samePose(a, b);
  return o;
}

/// A body against the static planes and convex pieces (A's lattice only).
void staticOverlaps(const World& world, const Placed& a, const std::vector<StaticPlane>& planes,
                    std::vector<BodyOverlap>& out, std::size_t& pairs, std::size_t& points) {
  const double hs = a.s * a.lattice->h;
  const auto add = [&](const std::string& name, double volume, bool centreInside) {
    if (!(volume > 0.0) && !centreInside) return;
    BodyOverlap o;
    o.a = a.id;
    o.nameA = world.bodies().info(a.id).name;
    o.nameB = name;
    o.volume = volume;
    o.fraction = volume / a.volume;
    o.contained = centreInside && a.lattice->centroidInside;
    out.push_back(o);
  };
  for (const StaticPlane& plane : planes) {
    const auto phi = [&](const Vec3& w, double) { return (w - plane.point).dot(plane.normal); };
    double lowest = kFar;
    for (int c = 0; c < 8; ++c)
      lowest = std::min(lowest, phi(Vec3(c & 1 ? a.box.max.x() : a.box.min.x(), c & 2 ? a.box.max.y() : a.box.min.y(),
                                         c & 4 ? a.box.max.z() : a.box.min.z()), 0.0));
    if (lowest > hs) continue;
    ++pairs;
    const auto normal = [&](const Vec3&) { return plane.normal; };
    add(plane.name, commonVolume(a, grown(a.box, hs), phi, normal, points), phi(a.x, 0.0) < 0.0);
  }
  for (std::size_t k = 0; k < world.staticConvexCount(); ++k) {
    const StaticConvex& piece = world.staticConvex(k);
    if (!boxesOverlap(grown(a.box, hs), piece.box)) continue;
    ++pairs;
    // max_k (n_k . x - d_k): the distance inside, a lower bound of it outside (w errs high there).
    const auto face = [&](const Vec3& w) { // the face of the largest n_k . x - d_k
      std::size_t best = 0;
      for (std::size_t f = 1; f < piece.normals.size(); ++f)
        if (piece.normals[f].dot(w) - piece.offsets[f] > piece.normals[best].dot(w) - piece.offsets[best]) best = f;
      return best;
    };
    const auto phi = [&](const Vec3& w, double) {
      const std::size_t f = face(w);
      return piece.normals[f].dot(w) - piece.offsets[f];
    };
    const auto normal = [&](const Vec3& w) { return piece.normals[face(w)]; };
    geometry::Box3 region{a.box.min.cwiseMax(piece.box.min), a.box.max.cwiseMin(piece.box.max)};
    add(piece.name, commonVolume(a, grown(region, hs), phi, normal, points), phi(a.x, 0.0) < 0.0);
  }
}

std::string percent(double fraction) {
  return fraction >= 0.1 ? fmt::format("{:.0f} %", 100.0 * fraction) : fmt::format("{:.2g} %", 100.0 * fraction);
}

} // namespace

InterpenetrationReport measureInterpenetration(const World& world, const std::vector<StaticPlane>& planes,
                                               const InterpenetrationSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  InterpenetrationReport r;
  std::map<ShapeId, ShapeLattice> lattices;
  const std::vector<Placed> placed = placeBodies(world, settings, lattices);
  const std::vector<std::pair<BodyId, BodyId>> pairs = candidatePairs(placed);
  std::vector<BodyOverlap> found(pairs.size());
  std::size_t points = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : points)
  for (std::size_t k = 0; k < pairs.size(); ++k)
    found[k] = bodyPair(world, placed[pairs[k].first], placed[pairs[k].second], points);
  r.pairsTested = pairs.size();
  for (BodyOverlap& o : found)
    if (o.volume > 0.0 || o.contained) r.overlaps.push_back(std::move(o));
  for (const Placed& p : placed)
    if (p.movable) staticOverlaps(world, p, planes, r.overlaps, r.pairsTested, points);
  r.pointsTested = points;
  std::stable_sort(r.overlaps.begin(), r.overlaps.end(),
                   [](const BodyOverlap& x, const BodyOverlap& y) { return x.fraction > y.fraction; });
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::vector<BodyOverlap> refusedOverlaps(const InterpenetrationReport& report, const InterpenetrationSettings& settings) {
  std::vector<BodyOverlap> refused;
  for (const BodyOverlap& o : report.overlaps)
    if (o.contained || o.fraction > settings.maxOverlapFraction) refused.push_back(o);
  return refused;
}

void refuseInterpenetration(const InterpenetrationReport& report, const std::string& where,
                            const InterpenetrationSettings& settings) {
  const std::vector<BodyOverlap> refused = refusedOverlaps(report, settings);
  if (refused.empty()) return;
  const BodyOverlap& o = refused.front();
  const bool isStatic = o.b < 0;
  std::string what = isStatic ? fmt::format("body '{}' lies inside the static item '{}': they share {} of the body's "
                                            "volume ({:.3g} m^3)",
                                            o.nameA, o.nameB, percent(o.fraction), o.volume)
                              : fmt::format("bodies '{}' and '{}' lie inside each other: they share {} of the smaller "
                                            "one's volume ({:.3g} m^3)",
                                            o.nameA, o.nameB, percent(o.fraction), o.volume);
  if (o.samePose) what += ", at the same position and orientation (a duplicated body)";
  else if (o.contained) what += isStatic ? ", its centroid inside" : ", a centroid of one inside the other";
  std::string others;
  for (std::size_t k = 1; k < std::min<std::size_t>(refused.size(), 4); ++k)
    others += fmt::format("{}'{}' and '{}' {}", k == 1 ? "; also " : ", ", refused[k].nameA, refused[k].nameB,
                          percent(refused[k].fraction));
  if (refused.size() > 4) others += fmt::format(" and {} more pairs", refused.size() - 4);
  core::failInput(where,
                  "{}{}; more than {} cannot be run (the contact finds no direction to push bodies apart from deep "
                  "inside each other): move them apart, remove the duplicate, or check the placement file that "
                  "gave these positions",
                  what, others, percent(settings.maxOverlapFraction));
}

std::string describeInterpenetration(const InterpenetrationReport& report) {
  const double largest = report.overlaps.empty() ? 0.0 : report.overlaps.front().fraction;
  std::string worst;
  if (!report.overlaps.empty())
    worst = fmt::format(" ('{}' and '{}')", report.overlaps.front().nameA, report.overlaps.front().nameB);
  return fmt::format("interpenetration: {} pairs with overlapping boxes, {} sharing volume, largest share {}{} of the "
                     "smaller body; {} lattice points in {:.3f} s",
                     report.pairsTested, report.overlaps.size(), percent(largest), worst, report.pointsTested,
                     report.seconds);
}

} // namespace armour::simulation
