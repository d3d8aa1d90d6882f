// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/Interlock.hpp"

#include "contact/SurfaceSamples.hpp"
#include "geometry/ConvexHull.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace armour::placement {

LayerContact layerContact(const Deposit& deposit, const Placed& u, std::size_t firstUnitBody, double clearance,
                          const Vec3& normal, double baseOffset) {
  LayerContact out;
  double top = -std::numeric_limits<double>::infinity();
  for (const Vec3& v : u.shape->mesh.vertices) top = std::max(top, (u.x + u.R * (u.scale * v)).dot(normal));
  out.top = top - baseOffset;
  const double reach = 2.0 * clearance;
  out.onSupport = deposit.touchesStatics(u, reach);
  for (std::size_t k : deposit.touching(u, reach)) {
    if (k < firstUnitBody) out.onSupport = true;
    else ++out.unitsTouched;
  }
  return out;
}

InterlockJudge::InterlockJudge(const Deposit& deposit, const simulation::ShapeModel& unit, std::size_t firstUnitBody,
                               double clearance, double dn, const OrientationSettings& settings, const Vec3& normal,
                               double baseOffset)
    : deposit_(deposit), unit_(unit), firstUnitBody_(firstUnitBody), clearance_(clearance), dn_(dn), s_(settings),
      normal_(normal), baseOffset_(baseOffset) {
  const geometry::ConvexPolyhedron hull = geometry::convexHullPolyhedron(unit.mesh.vertices, "the unit's envelope");
  hullNormals_ = hull.normals;
  hullOffsets_ = hull.offsets;
}

double InterlockJudge::envelopeShare(const Placed& u) const {
  std::vector<const Placed*> units;
  for (std::size_t k : deposit_.near(u, clearance_)) {
    if (k < firstUnitBody_ || deposit_.body(k).shape != &unit_) continue;
    units.push_back(&deposit_.body(k));
  }
  const auto& samples = u.shape->samples->positions();
  if (units.empty() || samples.empty()) return 0.0;
  std::size_t inside = 0;
  for (const Vec3& q : samples) {
    const Vec3 p = u.x + u.R * (u.scale * q);
    for (const Placed* o : units) {
      // In o's body frame, unscaled: inside every face plane of its hull (within a hair).
      const Vec3 local = o->R.transpose() * (p - o->x) / o->scale;
      bool in = true;
      for (std::size_t f = 0; f < hullNormals_.size() && in; ++f) in = hullNormals_[f].dot(local) <= hullOffsets_[f];
      if (in) {
        ++inside;
        break;
      }
    }
  }
  return static_cast<double>(inside) / static_cast<double>(samples.size());
}

InterlockScore InterlockJudge::score(const Placed& u, const Vec3& gridPoint) const {
  InterlockScore out;
  const LayerContact contact = layerContact(deposit_, u, firstUnitBody_, clearance_, normal_, baseOffset_);
  out.top = contact.top / dn_;
  out.centroid = (u.x.dot(normal_) - baseOffset_) / dn_;
  out.onSupport = contact.onSupport;
  out.unitsTouched = contact.unitsTouched;
  out.stacked = !out.onSupport && out.centroid > 1.0;
  out.envelopeShare = s_.envelopeReward > 0.0 ? envelopeShare(u) : 0.0;
  const double shift = (u.x - gridPoint).head<2>().norm() / dn_;
  const double height = s_.layerThickness > 0.0 ? std::abs(out.top - s_.layerThickness) : out.top;
  out.cost = height + s_.centroidWeight * out.centroid - s_.keyReward * std::min(out.unitsTouched, 2) -
             s_.envelopeReward * out.envelopeShare + (out.onSupport ? 0.0 : s_.offUnderlayerCost) +
             (out.stacked ? s_.stackedCost : 0.0) + s_.driftCost * shift;
  return out;
}

} // namespace armour::placement
