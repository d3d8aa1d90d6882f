// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/HalfSpaceFriction.hpp"

#include <cmath>

namespace armour::deformable {

namespace {

/// One node's stick-slip spring against a surface of unit normal n pressing it with `normal` > 0:
/// the friction force; the anchor (world) follows the node when the spring would exceed mu N.
Vec3 nodeFriction(const Vec3& position, const Vec3& n, double normal, double mu, double stiffness, Vec3& anchor) {
  const Vec3 offset = position - anchor;
  Vec3 tangential = offset - offset.dot(n) * n;
  const double stretch = tangential.norm();
  const double cap = mu * normal / stiffness; // the longest stretch friction can hold (unit: m)
  if (stretch > cap) {
    tangential *= cap / stretch; // slip: the anchor follows the node, cap behind it
    anchor = position - tangential;
  }
  return -stiffness * tangential;
}

} // namespace

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
    const Vec3 f = nodeFriction(positions[a], n, normal, mu, stiffness[a], anchors.anchor[a]);
    forces[a] += f;
    total += f;
  }
  return total;
}

Vec3 addObstacleFriction(const std::vector<Vec3>& pressure, const std::vector<Vec3>& positions,
                         const Eigen::Quaterniond& orientation, const Vec3& origin, double mu,
                         const std::vector<double>& stiffness, FrictionAnchors anchors, std::vector<Vec3>& forces) {
  Vec3 total = Vec3::Zero();
  for (std::size_t a = 0; a < positions.size(); ++a) {
    const double normal = pressure[a].norm();
    if (!(normal > 0.0) || !(stiffness[a] > 0.0)) {
      anchors.active[a] = 0;
      continue;
    }
    if (anchors.active[a] == 0) {
      anchors.anchor[a] = orientation.conjugate() * (positions[a] - origin);
      anchors.active[a] = 1;
    }
    // The anchor lives in the rigid body's frame: it moves with the body.
    Vec3 anchor = origin + orientation * anchors.anchor[a];
    const Vec3 f = nodeFriction(positions[a], pressure[a] / normal, normal, mu, stiffness[a], anchor);
    anchors.anchor[a] = orientation.conjugate() * (anchor - origin);
    forces[a] += f;
    total += f;
  }
  return total;
}

} // namespace armour::deformable
