// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/RigidObstacleContact.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>

namespace armour::deformable {

int obstacleSubdivisions(double edge, double cell) {
  if (!(cell > 0.0) || !(edge > 0.0)) {
    return 1;
  }
  return std::clamp(static_cast<int>(std::ceil(edge / cell)), 1, 16);
}

ObstacleLoad addObstacleContact(const std::vector<SurfaceTriangle>& triangles, const std::vector<Vec3>& positions,
                                const RigidObstacle& obstacle, double gradient, std::vector<Vec3>& forces) {
  if (obstacle.levelSet == nullptr || obstacle.levelSet->empty()) {
    core::failInput("rigid obstacle", "has no level set; give the shape's level set (World::shape(id).levelSet)");
  }
  const contact::LevelSet& ls = *obstacle.levelSet;
  const double s = obstacle.scale;
  const Eigen::Matrix3d toLocal = obstacle.orientation.conjugate().toRotationMatrix();
  const Eigen::Matrix3d toWorld = obstacle.orientation.toRotationMatrix();
  const auto phiAt = [&](const Vec3& x) { return s * ls.value(toLocal * (x - obstacle.position) / s); };
  ObstacleLoad load;
  std::vector<Eigen::Vector3d> bary;
  std::vector<double> depth;
  for (const auto& tri : triangles) {
    const Vec3& x0 = positions[tri[0]];
    const Vec3& x1 = positions[tri[1]];
    const Vec3& x2 = positions[tri[2]];
    const double edge = std::max({(x1 - x0).norm(), (x2 - x1).norm(), (x0 - x2).norm()});
    // The interpolant's gradient is at most sqrt(3) (and 1 outside the grid): a triangle whose
    // corners are all farther than sqrt(3) x its longest edge cannot reach inside.
    if (std::min({phiAt(x0), phiAt(x1), phiAt(x2)}) > std::sqrt(3.0) * edge) {
      continue;
    }
    const Vec3 areaVector = 0.5 * (x1 - x0).cross(x2 - x0); // n_body da
    const double area = areaVector.norm();
    if (!(area > 0.0)) {
      continue;
    }
    const int k = obstacleSubdivisions(edge, s * ls.cellSize());
    // The sub-triangles' corners, (i, j) at barycentric ((k - i - j) / k, i / k, j / k).
    const auto at = [k](int i, int j) { return static_cast<std::size_t>(j * (k + 1) - j * (j - 1) / 2 + i); };
    bary.clear();
    depth.clear();
    bool any = false;
    for (int j = 0; j <= k; ++j) {
      for (int i = 0; i + j <= k; ++i) {
        const Eigen::Vector3d b(static_cast<double>(k - i - j) / k, static_cast<double>(i) / k,
                                static_cast<double>(j) / k);
        bary.push_back(b);
        depth.push_back(-phiAt(b[0] * x0 + b[1] * x1 + b[2] * x2));
        any = any || depth.back() > 0.0;
      }
    }
    if (!any) {
      continue;
    }
    const Vec3 unit = areaVector / area;
    const double subArea = area / (k * k);
    Eigen::Vector3d nd = Eigen::Vector3d::Zero();
    const auto addSub = [&](std::size_t a, std::size_t b, std::size_t c) {
      const std::array<double, 3> d{depth[a], depth[b], depth[c]};
      if (!(d[0] > 0.0 || d[1] > 0.0 || d[2] > 0.0)) {
        return;
      }
      Eigen::Vector3d ndSub = Eigen::Vector3d::Zero();
      double dd = 0.0;
      integratePositiveDepth(d, subArea, ndSub, dd);
      nd += ndSub[0] * bary[a] + ndSub[1] * bary[b] + ndSub[2] * bary[c];
      // E = -G/2 integral of d^2 (n . n_body), n the solid's outward normal (the half-space's
      // formula, exact where the surface is flat); n at the sub-triangle's centroid.
      const Eigen::Vector3d centre = (bary[a] + bary[b] + bary[c]) / 3.0;
      const Vec3 n = toWorld * ls.normal(toLocal * (centre[0] * x0 + centre[1] * x1 + centre[2] * x2 - obstacle.position) / s);
      load.energy -= 0.5 * gradient * dd * n.dot(unit);
    };
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i + j < k; ++i) {
        addSub(at(i, j), at(i + 1, j), at(i, j + 1));
        if (i + j + 1 < k) {
          addSub(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
      }
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
