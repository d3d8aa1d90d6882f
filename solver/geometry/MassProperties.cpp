// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/MassProperties.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace armour::geometry {

double MassProperties::nominalDiameter() const { return std::cbrt(volume); }

namespace {

Vec3 referencePoint(const TriangleMesh& mesh) {
  return mesh.vertices.empty() ? Vec3::Zero() : mesh.bounds().centre();
}

} // namespace

double signedVolume(const TriangleMesh& mesh) {
  const Vec3 o = referencePoint(mesh);
  double sixV = 0.0;
  for (const auto& f : mesh.triangles) {
    const Vec3 a = mesh.vertices[f[0]] - o;
    const Vec3 b = mesh.vertices[f[1]] - o;
    const Vec3 c = mesh.vertices[f[2]] - o;
    sixV += a.dot(b.cross(c));
  }
  return sixV / 6.0;
}

MassProperties computeMassProperties(const TriangleMesh& mesh) {
  MassProperties mp;
  const Vec3 o = referencePoint(mesh);
  double sixV = 0.0;
  Vec3 firstMoment = Vec3::Zero();       // 24 x int x dV (relative to o)
  Mat3 secondMoment = Mat3::Zero();      // 120 x int x x^T dV (relative to o)
  for (const auto& f : mesh.triangles) {
    const Vec3 a = mesh.vertices[f[0]] - o;
    const Vec3 b = mesh.vertices[f[1]] - o;
    const Vec3 c = mesh.vertices[f[2]] - o;
    const double det = a.dot(b.cross(c)); // 6 x signed volume of tetrahedron (o, a, b, c)
    const Vec3 s = a + b + c;             // the fourth vertex o is the origin of the local frame
    sixV += det;
    firstMoment += det * s;               // int x dV = V (a + b + c) / 4 = det s / 24
    secondMoment += det * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  mp.volume = sixV / 6.0;
  if (mp.volume == 0.0) {
    return mp;
  }
  const Vec3 centroidLocal = firstMoment / (24.0 * mp.volume);
  // int x x^T dV about o is secondMoment / 120; shift to the centroid (parallel-axis theorem).
  const Mat3 covariance = secondMoment / 120.0 - mp.volume * centroidLocal * centroidLocal.transpose();
  mp.centroid = o + centroidLocal;
  mp.inertia = covariance.trace() * Mat3::Identity() - covariance;
  mp.inertia = 0.5 * (mp.inertia + mp.inertia.transpose());

  Eigen::SelfAdjointEigenSolver<Mat3> eig(mp.inertia);
  mp.principalMoments = eig.eigenvalues();
  mp.principalAxes = eig.eigenvectors();
  if (mp.principalAxes.determinant() < 0.0) {
    mp.principalAxes.col(2) *= -1.0; // right-handed frame
  }
  return mp;
}

void scaleToVolume(TriangleMesh& mesh, double targetVolume) {
  const MassProperties mp = computeMassProperties(mesh);
  const Vec3 c = mp.centroid;
  const double factor = std::cbrt(targetVolume / mp.volume);
  for (auto& v : mesh.vertices) {
    v = c + factor * (v - c);
  }
}

void centreOnCentroid(TriangleMesh& mesh) { translate(mesh, -computeMassProperties(mesh).centroid); }

} // namespace armour::geometry
