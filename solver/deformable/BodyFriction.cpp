// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/BodyFriction.hpp"

#include <Eigen/LU>

namespace armour::deformable {
namespace {

/// Barycentric coordinates of p in the tet of corners x[c]; false when the tet is flat or inverted.
bool barycentric(const std::array<std::int32_t, 4>& c, const std::vector<Vec3>& x, const Vec3& p,
                 std::array<double, 4>& w) {
  Eigen::Matrix3d edges;
  edges << x[c[1]] - x[c[0]], x[c[2]] - x[c[0]], x[c[3]] - x[c[0]];
  if (!(edges.determinant() > 0.0)) {
    return false;
  }
  const Vec3 l = edges.inverse() * (p - x[c[0]]);
  w = {1.0 - l.sum(), l.x(), l.y(), l.z()};
  return true;
}

Vec3 pointOf(const std::array<std::int32_t, 4>& c, const std::vector<Vec3>& x, const std::array<double, 4>& w) {
  return w[0] * x[c[0]] + w[1] * x[c[1]] + w[2] * x[c[2]] + w[3] * x[c[3]];
}

} // namespace

double addBodyFriction(const BodyContact& contact, const ContactorLoads& loads, const std::vector<Vec3>& x, double mu,
                       const std::vector<double>& stiffness, BodyFrictionAnchors anchors, std::vector<Vec3>& forces) {
  double total = 0.0;
  for (std::size_t a = 0; a < x.size(); ++a) {
    const double normalForce = loads.force[a].norm();
    if (!(normalForce > 0.0) || loads.target[a] < 0 || !(stiffness[a] > 0.0)) {
      anchors.tet[a] = -1; // out of contact: the anchor is forgotten
      continue;
    }
    const Vec3 n = loads.force[a] / normalForce;
    if (anchors.tet[a] < 0) { // sticks where it touched
      if (!barycentric(contact.targetTet(static_cast<std::size_t>(loads.target[a])), x, x[a], anchors.weights[a])) {
        continue;
      }
      anchors.tet[a] = loads.target[a];
    }
    const auto* c = &contact.targetTet(static_cast<std::size_t>(anchors.tet[a]));
    const Vec3 u = x[a] - pointOf(*c, x, anchors.weights[a]);
    Vec3 f = -stiffness[a] * (u - u.dot(n) * n);
    const double cap = mu * normalForce;
    if (f.norm() > cap) { // slips: the cap, and a new anchor where the spring holds it
      f *= cap / f.norm();
      const auto& now = contact.targetTet(static_cast<std::size_t>(loads.target[a]));
      std::array<double, 4> w{};
      if (barycentric(now, x, x[a] + f / stiffness[a], w)) {
        anchors.tet[a] = loads.target[a];
        anchors.weights[a] = w;
        c = &now;
      } else if (!barycentric(*c, x, x[a] + f / stiffness[a], anchors.weights[a])) {
        anchors.tet[a] = -1;
        continue;
      }
    }
    forces[a] += f;
    for (int i = 0; i < 4; ++i) {
      forces[static_cast<std::size_t>((*c)[i])] -= anchors.weights[a][i] * f;
    }
    total += f.norm();
  }
  return total;
}

} // namespace armour::deformable
