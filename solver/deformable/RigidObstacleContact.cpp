// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/RigidObstacleContact.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>

namespace armour::deformable {

int obstacleSubdivisions(double edge, double cell) {
  int k = 1;
  while (k < 16 && cell > 0.0 && edge / k > cell) {
    k *= 2;
  }
  return k;
}

ObstacleLoad addObstacleContact(const std::vector<SurfaceTriangle>& triangles, const std::vector<Vec3>& positions,
                                const RigidObstacle& obstacle, double gradient, std::vector<Vec3>& forces,
                                bool withEnergy) {
  const bool analytic = obstacle.levelSet == nullptr && obstacle.distance;
  if (!analytic && (obstacle.levelSet == nullptr || obstacle.levelSet->empty())) {
    core::failInput("rigid obstacle", "has no level set; give the shape's level set (World::shape(id).levelSet)");
  }
  if (analytic && !(obstacle.resolution > 0.0)) {
    core::failInput("rigid obstacle", "an exact distance needs a positive sampling resolution (m), not {}",
                    obstacle.resolution);
  }
  const double s = obstacle.scale;
  const Eigen::Matrix3d toLocal = obstacle.orientation.conjugate().toRotationMatrix();
  const Eigen::Matrix3d toWorld = obstacle.orientation.toRotationMatrix();
  const auto localPhi = [&](const Vec3& local) {
    return analytic ? obstacle.distance(local) : obstacle.levelSet->value(local);
  };
  const auto phiAt = [&](const Vec3& x) { return s * localPhi(toLocal * (x - obstacle.position) / s); };
  // The outward normal in the shape's frame: the level set's, or central differences of the distance.
  const auto localNormal = [&](const Vec3& local) -> Vec3 {
    if (!analytic) return obstacle.levelSet->normal(local);
    const double h = 1e-6 * obstacle.resolution;
    Vec3 g;
    for (int k = 0; k < 3; ++k) {
      Vec3 e = Vec3::Zero();
      e[k] = h;
      g[k] = (obstacle.distance(local + e) - obstacle.distance(local - e)) / (2.0 * h);
    }
    return g.norm() > 0.0 ? Vec3(g.normalized()) : Vec3::Zero();
  };
  const double cell = analytic ? obstacle.resolution : obstacle.levelSet->cellSize();
  // How fast phi can change (unit: -): 1 for an exact distance, sqrt(3) for the trilinear level set
  // (its gradient's bound; 1 outside its grid).
  const double lipschitz = analytic ? 1.0 : std::sqrt(3.0);
  ObstacleLoad load;
  for (const auto& tri : triangles) {
    const Vec3& x0 = positions[tri[0]];
    const Vec3& x1 = positions[tri[1]];
    const Vec3& x2 = positions[tri[2]];
    const double edge = std::max({(x1 - x0).norm(), (x2 - x1).norm(), (x0 - x2).norm()});
    // Every point of a triangle lies within its longest edge of each corner, and phi changes by at
    // most `lipschitz` per metre: a triangle whose corners are all farther out than that cannot
    // reach inside.
    const double phi0 = phiAt(x0), phi1 = phiAt(x1), phi2 = phiAt(x2);
    if (std::min({phi0, phi1, phi2}) > lipschitz * edge) {
      continue;
    }
    const Vec3 areaVector = 0.5 * (x1 - x0).cross(x2 - x0); // n_body da
    const double area = areaVector.norm();
    if (!(area > 0.0)) {
      continue;
    }
    const Vec3 unit = areaVector / area;
    // Refine by halving toward k sub-triangles per edge, only where the depth can be positive: a
    // sub-triangle whose corners all lie farther out than lipschitz x its edge is skipped whole.
    const int k = obstacleSubdivisions(edge, s * cell);
    Eigen::Vector3d nd = Eigen::Vector3d::Zero();
    bool touched = false;
    const auto depthAt = [&](const Eigen::Vector3d& b) { return -phiAt(b[0] * x0 + b[1] * x1 + b[2] * x2); };
    const auto integrate = [&](const std::array<Eigen::Vector3d, 3>& b, const std::array<double, 3>& d, double subArea) {
      Eigen::Vector3d ndSub = Eigen::Vector3d::Zero();
      double dd = 0.0;
      integratePositiveDepth(d, subArea, ndSub, dd);
      nd += ndSub[0] * b[0] + ndSub[1] * b[1] + ndSub[2] * b[2];
      touched = true;
      if (!withEnergy) return;
      // E = -G/2 integral of d^2 (n . n_body), n the solid's outward normal (the half-space's
      // formula, exact where the surface is flat); n at the sub-triangle's centroid.
      const Eigen::Vector3d c = (b[0] + b[1] + b[2]) / 3.0;
      const Vec3 n = toWorld * localNormal(toLocal * (c[0] * x0 + c[1] * x1 + c[2] * x2 - obstacle.position) / s);
      load.energy -= 0.5 * gradient * dd * n.dot(unit);
    };
    const auto refine = [&](const auto& self, const std::array<Eigen::Vector3d, 3>& b, const std::array<double, 3>& d,
                            int perEdge) -> void {
      const double subEdge = edge / perEdge;
      if (std::max({d[0], d[1], d[2]}) < -lipschitz * subEdge) {
        return; // wholly outside
      }
      if (perEdge >= k) {
        if (d[0] > 0.0 || d[1] > 0.0 || d[2] > 0.0) integrate(b, d, area / (static_cast<double>(perEdge) * perEdge));
        return;
      }
      const std::array<Eigen::Vector3d, 3> m{0.5 * (b[0] + b[1]), 0.5 * (b[1] + b[2]), 0.5 * (b[2] + b[0])};
      const std::array<double, 3> dm{depthAt(m[0]), depthAt(m[1]), depthAt(m[2])};
      self(self, {b[0], m[0], m[2]}, {d[0], dm[0], dm[2]}, 2 * perEdge);
      self(self, {m[0], b[1], m[1]}, {dm[0], d[1], dm[1]}, 2 * perEdge);
      self(self, {m[2], m[1], b[2]}, {dm[2], dm[1], d[2]}, 2 * perEdge);
      self(self, {m[0], m[1], m[2]}, {dm[0], dm[1], dm[2]}, 2 * perEdge);
    };
    refine(refine, {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()},
           {-phi0, -phi1, -phi2}, 1);
    if (!touched) {
      continue;
    }
    ++load.triangles;
    for (int i = 0; i < 3; ++i) {
      const Vec3 f = -gradient * nd[i] * unit;
      forces[tri[i]] += f;
      load.force -= f;
      load.torque -= (positions[tri[i]] - obstacle.position).cross(f);
    }
  }
  return load;
}

} // namespace armour::deformable
