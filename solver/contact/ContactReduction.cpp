// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/ContactReduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace armour::contact {

namespace {

/// Index (into `members`) of the best point by `score`, ties to the lower key; -1 if no score > floor.
/// `bonus` turns a raw score of a point kept in the previous step into its preferred score.
template <typename Score, typename Bonus>
int best(const std::vector<ContactPoint>& points, const std::vector<int>& members, double floor, Score&& score,
         const std::vector<std::uint32_t>& kept, Bonus&& bonus) {
  int chosen = -1;
  double top = floor;
  for (int m : members) {
    double s = score(points[m]);
    if (s > floor && std::binary_search(kept.begin(), kept.end(), points[m].key)) s = bonus(s);
    if (s > top || (s == top && chosen >= 0 && points[m].key < points[chosen].key)) {
      top = s;
      chosen = m;
    }
  }
  return chosen;
}

/// Up to four points spanning one patch.
ContactPatchPoints reducePatch(const std::vector<ContactPoint>& points, const std::vector<int>& members,
                               const ReductionSettings& settings, const std::vector<std::uint32_t>& kept) {
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
  for (int m : members) {
    if (points[m].depth > 0.0) patch.area += points[m].area;
  }
  patch.count = count;
  for (int k = 0; k < count; ++k) {
    const ContactPoint& p = points[chosen[k]];
    patch.keys[k] = p.key;
    patch.points[k] = p.point;
    patch.depths[k] = depth(p);
  }
  return patch;
}

} // namespace

void reduceContacts(const std::vector<ContactPoint>& points, const ReductionSettings& settings,
                    const std::vector<std::uint32_t>& kept, std::vector<ContactPatchPoints>& out) {
  if (points.empty()) {
    return;
  }
  // Deepest first (ties: lower key), each unassigned point seeding a patch.
  std::vector<int> order(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    return points[x].depth != points[y].depth ? points[x].depth > points[y].depth : points[x].key < points[y].key;
  });
  const double cosAngle = std::cos(settings.patchAngle);
  std::vector<Vec3> seeds;
  std::vector<std::vector<int>> members;
  for (int i : order) {
    const Vec3& n = points[i].normal;
    int joined = -1;
    double closest = -2.0;
    int nearest = -1;
    for (std::size_t s = 0; s < seeds.size(); ++s) {
      const double c = seeds[s].dot(n);
      if (c >= cosAngle) {
        joined = static_cast<int>(s);
        break;
      }
      if (c > closest) {
        closest = c;
        nearest = static_cast<int>(s);
      }
    }
    if (joined < 0 && static_cast<int>(seeds.size()) < settings.maxPatches) {
      seeds.push_back(n);
      members.emplace_back();
      joined = static_cast<int>(seeds.size()) - 1;
    }
    if (joined < 0) {
      joined = nearest;
    }
    members[joined].push_back(i);
  }
  for (const auto& m : members) {
    out.push_back(reducePatch(points, m, settings, kept));
  }
}

} // namespace armour::contact
