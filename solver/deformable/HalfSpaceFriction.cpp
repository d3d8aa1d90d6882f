// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/HalfSpaceFriction.hpp"

#include <cmath>

namespace armour::deformable {

Vec3 addHalfSpaceFriction(const std::vector<Vec3>& pressure, const std::vector<Vec3>& positions,
                          const HalfSpace& halfSpace, double mu, const std::vector<double>& stiffness,
                          FrictionAnchors anchors, std::vector<Vec3>& forces) {
  const Vec3& n = halfSpace.normal;
  Vec3 total = Vec3::Zero();
  for (std::size_t a = 0; a < positions.size(); ++a) {
    const double normal = pressure[a].dot(n);
    if (!(normal > 0.0) || !(stiffness[a] > 0.0)) {
      anchors.active[a] = 0;
      continue;
    }
    if (anchors.active[a] == 0) {
      anchors.anchor[a] = positions[a];
      anchors.active[a] = 1;
    }
    const Vec3 offset = positions[a] - anchors.anchor[a];
    Vec3 tangential = offset - offset.dot(n) * n;
    const double stretch = tangential.norm();
    const double cap = mu * normal / stiffness[a]; // the longest stretch friction can hold (unit: m)
    if (stretch > cap) {
      tangential *= cap / stretch; // slip: the anchor follows the node, cap behind it
      anchors.anchor[a] = positions[a] - tangential;
    }
    const Vec3 f = -stiffness[a] * tangential;
    forces[a] += f;
    total += f;
  }
  return total;
}

} // namespace armour::deformable
