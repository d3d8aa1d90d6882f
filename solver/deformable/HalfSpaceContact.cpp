// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/HalfSpaceContact.hpp"

#include <algorithm>
#include <cmath>

namespace armour::deformable {
namespace {

/// A vertex of the clipped polygon: barycentric coordinates in the triangle.
using Bary = Eigen::Vector3d;

/// The part of the triangle where the linear depth is positive, as a polygon of up to 4 vertices.
int clipToPositiveDepth(const std::array<double, 3>& depth, std::array<Bary, 4>& polygon) {
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    Bary corner = Bary::Zero();
    corner[i] = 1.0;
    if (depth[i] > 0.0) {
      polygon[count++] = corner;
    }
    if ((depth[i] > 0.0) != (depth[j] > 0.0)) {
      const double t = depth[i] / (depth[i] - depth[j]);
      Bary cut = Bary::Zero();
      cut[i] = 1.0 - t;
      cut[j] = t;
      polygon[count++] = cut;
    }
  }
  return count;
}

} // namespace

std::vector<SurfaceTriangle> surfaceTriangles(const DeformableMesh& mesh, const std::vector<BoundaryFace>& faces) {
  std::vector<SurfaceTriangle> out;
  out.reserve(faces.size() * (mesh.order == ElementOrder::Quadratic ? 4 : 1));
  for (const auto& f : faces) {
    if (mesh.order == ElementOrder::Linear) {
      out.push_back(f.corners);
      continue;
    }
    // Corners c0, c1, c2 and mid-edge nodes m0 (c0-c1), m1 (c1-c2), m2 (c2-c0): four triangles,
    // all counter-clockwise as the face.
    const auto& c = f.corners;
    const auto& m = f.midEdges;
    out.push_back({c[0], m[0], m[2]});
    out.push_back({m[0], c[1], m[1]});
    out.push_back({m[2], m[1], c[2]});
    out.push_back({m[0], m[1], m[2]});
  }
  return out;
}

void integratePositiveDepth(const std::array<double, 3>& depth, double area, Eigen::Vector3d& nd, double& dd) {
  std::array<Bary, 4> polygon;
  const int count = clipToPositiveDepth(depth, polygon);
  // integral of N_a d over the clipped part, and of d^2, by fan triangles and the edge-midpoint
  // rule (exact for quadratics); sub-triangle areas from barycentric determinants.
  const Eigen::Vector3d d(depth[0], depth[1], depth[2]);
  for (int k = 1; k + 1 < count; ++k) {
    const Bary& a = polygon[0];
    const Bary& b = polygon[k];
    const Bary& c = polygon[k + 1];
    // Area fraction of the sub-triangle in the parent: |det| of two barycentric edges (2D).
    const double fraction = std::abs((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]));
    for (const Bary& mid : {Bary(0.5 * (a + b)), Bary(0.5 * (b + c)), Bary(0.5 * (c + a))}) {
      const double depthHere = mid.dot(d);
      nd += (fraction * area / 3.0) * depthHere * mid;
      dd += (fraction * area / 3.0) * depthHere * depthHere;
    }
  }
}

double addHalfSpaceContact(const std::vector<SurfaceTriangle>& triangles, const std::vector<Vec3>& positions,
                           const HalfSpace& halfSpace, double gradient, std::vector<Vec3>& forces) {
  double energy = 0.0;
  for (const auto& tri : triangles) {
    std::array<double, 3> depth{};
    bool any = false;
    for (int i = 0; i < 3; ++i) {
      depth[i] = (halfSpace.point - positions[tri[i]]).dot(halfSpace.normal);
      any = any || depth[i] > 0.0;
    }
    if (!any) {
      continue;
    }
    const Vec3& x0 = positions[tri[0]];
    const Vec3 areaVector = 0.5 * (positions[tri[1]] - x0).cross(positions[tri[2]] - x0); // n_body da
    const double area = areaVector.norm();
    if (!(area > 0.0)) {
      continue;
    }
    Eigen::Vector3d nd = Eigen::Vector3d::Zero();
    double dd = 0.0;
    integratePositiveDepth(depth, area, nd, dd);
    const Vec3 unit = areaVector / area;
    for (int i = 0; i < 3; ++i) {
      forces[tri[i]] -= gradient * nd[i] * unit;
    }
    energy -= 0.5 * gradient * dd * halfSpace.normal.dot(unit);
  }
  return energy;
}

std::vector<double> tributaryAreas(const DeformableMesh& mesh, const std::vector<SurfaceTriangle>& triangles) {
  std::vector<double> area(mesh.nodeCount(), 0.0);
  for (const auto& tri : triangles) {
    const double a = 0.5 * (mesh.nodes[tri[1]] - mesh.nodes[tri[0]]).cross(mesh.nodes[tri[2]] - mesh.nodes[tri[0]]).norm();
    for (const auto n : tri) {
      area[n] += a / 3.0;
    }
  }
  return area;
}

double contactFrequency(const DeformableMesh& mesh, const std::vector<SurfaceTriangle>& triangles,
                        const std::vector<double>& masses, double gradient) {
  const std::vector<double> area = tributaryAreas(mesh, triangles);
  double omega2 = 0.0;
  for (std::size_t n = 0; n < area.size(); ++n) {
    omega2 = std::max(omega2, gradient * area[n] / masses[n]);
  }
  return std::sqrt(omega2);
}

} // namespace armour::deformable
