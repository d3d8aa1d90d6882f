// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/ContactReduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace armour::contact {

namespace {

/// Patches per pair this reduction can make (ReductionSettings::maxPatches is clamped to it).
constexpr int kMaxPatches = 8;

/// Index (into `members`) of the best point by `score`, ties to the lower key; -1 if no score > floor.
/// `bonus` turns a raw score of a point kept in the previous step into its preferred score.
template <typename Score, typename Bonus>
int best(const std::vector<ContactPoint>& points, std::span<const int> members, double floor, Score&& score,
         const std::vector<char>& kept, Bonus&& bonus) {
  int chosen = -1;
  double top = floor;
  for (int m : members) {
    double s = score(points[m]);
    if (s > floor && kept[static_cast<std::size_t>(m)] != 0) s = bonus(s);
    if (s > top || (s == top && chosen >= 0 && points[m].key < points[chosen].key)) {
      top = s;
      chosen = m;
    }
  }
  return chosen;
}

/// Up to four points spanning one patch.
ContactPatchPoints reducePatch(const std::vector<ContactPoint>& points, std::span<const int> members,
                               const ReductionSettings& settings, const std::vector<char>& kept) {
  ContactPatchPoints patch;
  Vec3 normal = Vec3::Zero();
  for (int m : members) {
    normal += std::max(points[m].area, 1e-300) * points[m].normal;
  }
  patch.normal = normal.norm() > 0.0 ? Vec3(normal.normalized()) : points[members.front()].normal;
  const Vec3 n = patch.normal;
  const auto depth = [&](const ContactPoint& p) { return p.depth * p.normal.dot(n); };
  const auto flat = [&](const Vec3& d) { return Vec3(d - d.dot(n) * n); }; // tangent-plane part
  const auto deeper = [&](double s) { return s + settings.keepDepth; };
  const double f = settings.keepFactor;
  const auto farther = [&](double s) { return s * f; };
  const auto fartherSquared = [&](double s) { return s * f * f; };
  const int p1 = best(points, members, -std::numeric_limits<double>::infinity(), depth, kept, deeper);
  const Vec3 a = points[p1].point;
  const int p2 = best(
      points, members, 0.0, [&](const ContactPoint& p) { return flat(p.point - a).squaredNorm(); }, kept,
      fartherSquared);
  int chosen[4] = {p1, -1, -1, -1};
  int count = 1;
  if (p2 >= 0) {
    chosen[count++] = p2;
    const Vec3 edge = points[p2].point - a;
    // Signed doubled area of the triangle (1, 2, p) about the normal.
    const auto area = [&](const ContactPoint& p) { return n.dot(edge.cross(p.point - a)); };
    const int p3 = best(points, members, 0.0, [&](const ContactPoint& p) { return std::abs(area(p)); }, kept, farther);
    if (p3 >= 0) {
      chosen[count++] = p3;
      const double side = area(points[p3]) > 0.0 ? 1.0 : -1.0;
      const int p4 = best(points, members, 0.0, [&](const ContactPoint& p) { return -side * area(p); }, kept, farther);
      if (p4 >= 0) {
        chosen[count++] = p4;
      }
    }
  }
  patch.count = count;
  double force[4] = {0, 0, 0, 0}; // sum of area x overlap each kept point stands for (unit: m^3)
  for (int k = 0; k < count; ++k) {
    const ContactPoint& p = points[chosen[k]];
    patch.keys[k] = p.key;
    patch.points[k] = p.point;
    patch.depths[k] = p.depth;
    patch.normals[k] = p.normal;
    patch.areas[k] = p.area;
    force[k] = p.area * std::max(p.depth, 0.0);
  }
  // Every other sample lends its area to the nearest kept point, in full inside the other body,
  // fading to nothing at the gap rampDepth outside.
  for (int m : members) {
    if (m == chosen[0] || m == chosen[1] || m == chosen[2] || m == chosen[3]) continue;
    const double weight = settings.rampDepth > 0.0 ? std::clamp(1.0 + points[m].depth / settings.rampDepth, 0.0, 1.0)
                                                   : (points[m].depth > 0.0 ? 1.0 : 0.0);
    if (weight == 0.0) continue;
    int nearest = 0;
    double closest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < count; ++k) {
      const double d = flat(points[m].point - patch.points[k]).squaredNorm();
      if (d < closest) {
        closest = d;
        nearest = k;
      }
    }
    patch.areas[nearest] += weight * points[m].area;
    force[nearest] += points[m].area * std::max(points[m].depth, 0.0);
  }
  // Each kept point carries the penalty force of the samples it stands for: its depth becomes their
  // mean overlap over its area, so that its spring k_k d_k = (E_p / L) sum a_i max(d_i, 0). A point
  // none of whose samples is inside keeps its own (negative) gap: speculative. (Moving the point to
  // the samples' force centroid as well rested small piles of Accropodes and cubes better but let a
  // block creep down an incline, 0.23 mm in 60 s: docs/benchmarks.md.)
  for (int k = 0; k < count; ++k) {
    if (force[k] > 0.0 && patch.areas[k] > 0.0) patch.depths[k] = force[k] / patch.areas[k];
  }
  return patch;
}

} // namespace

void reduceContacts(const std::vector<ContactPoint>& points, const ReductionSettings& settings,
                    const std::vector<std::uint32_t>& kept, std::vector<ContactPatchPoints>& out) {
  if (points.empty()) {
    return;
  }
  const std::size_t n = points.size();
  // Scratch of this thread, reused from pair to pair (the narrow phase calls this for every pair).
  thread_local std::vector<char> wasKept;
  thread_local std::vector<int> patchOf, members;
  wasKept.assign(n, 0);
  if (!kept.empty()) {
    for (std::size_t i = 0; i < n; ++i) wasKept[i] = std::binary_search(kept.begin(), kept.end(), points[i].key) ? 1 : 0;
  }
  // Seeds: the deepest unassigned point (ties: lower key); it takes every unassigned point within
  // the patch angle of its normal. Then the next seed, up to maxPatches; points left over join the
  // patch of the nearest seed normal. (The same patches as visiting the points deepest first, each
  // joining the first seed within the angle, without sorting them.)
  const double cosAngle = std::cos(settings.patchAngle);
  patchOf.assign(n, -1);
  Vec3 seeds[kMaxPatches];
  int patches = 0;
  const int maxPatches = std::clamp(settings.maxPatches, 1, kMaxPatches);
  std::size_t assigned = 0;
  while (assigned < n && patches < maxPatches) {
    int seed = -1;
    for (std::size_t i = 0; i < n; ++i) {
      if (patchOf[i] >= 0) continue;
      if (seed < 0 || points[i].depth > points[seed].depth ||
          (points[i].depth == points[seed].depth && points[i].key < points[seed].key)) {
        seed = static_cast<int>(i);
      }
    }
    const Vec3 normal = points[seed].normal;
    const int patch = patches++;
    seeds[patch] = normal;
    for (std::size_t i = 0; i < n; ++i) {
      if (patchOf[i] < 0 && normal.dot(points[i].normal) >= cosAngle) {
        patchOf[i] = patch;
        ++assigned;
      }
    }
  }
  // Members of each patch in point order, one array (a counting sort by patch).
  int start[kMaxPatches + 1] = {};
  for (std::size_t i = 0; i < n; ++i) {
    if (patchOf[i] < 0) {
      double closest = -2.0;
      for (int s = 0; s < patches; ++s) {
        if (const double c = seeds[s].dot(points[i].normal); c > closest) {
          closest = c;
          patchOf[i] = s;
        }
      }
    }
    ++start[patchOf[i] + 1];
  }
  for (int s = 0; s < patches; ++s) start[s + 1] += start[s];
  members.resize(n);
  int fill[kMaxPatches];
  std::copy(start, start + patches, fill);
  for (std::size_t i = 0; i < n; ++i) members[static_cast<std::size_t>(fill[patchOf[i]]++)] = static_cast<int>(i);
  for (int s = 0; s < patches; ++s) {
    const std::span<const int> m(members.data() + start[s], static_cast<std::size_t>(start[s + 1] - start[s]));
    out.push_back(reducePatch(points, m, settings, wasKept));
  }
}

} // namespace armour::contact
