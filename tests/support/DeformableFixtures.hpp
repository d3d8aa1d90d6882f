// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableFixtures.hpp
/// Small scenes for the deformable-body tests: bars and boxes of 4- or 10-node tets, the nodes on
/// a plane, and the element's own highest frequency for stable-step checks.

#include "deformable/DeformableBody.hpp"
#include "deformable/StructuredBox.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>

#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace armour::deformable::test {

/// A box [0, size] of nx x ny x nz Kuhn cells, as a mesh of the given order.
inline DeformableMesh boxMesh(const Vec3& size, int nx, int ny, int nz, ElementOrder order) {
  return makeDeformableMesh(structuredBox(size, nx, ny, nz), order, "test box");
}

/// Nodes whose reference position satisfies `select`.
inline std::vector<std::size_t> nodesWhere(const DeformableMesh& mesh, const std::function<bool(const Vec3&)>& select) {
  std::vector<std::size_t> out;
  for (std::size_t n = 0; n < mesh.nodeCount(); ++n) {
    if (select(mesh.nodes[n])) {
      out.push_back(n);
    }
  }
  return out;
}

/// Concrete-like material of the seed (E = 26.6 GPa, rho = 2340 kg/m^3) with the given nu.
inline MaterialSettings concrete(double poissonRatio = 0.205, double viscosity = 0.0) {
  MaterialSettings m;
  m.poissonRatio = poissonRatio;
  m.viscosity = viscosity;
  return m;
}

/// Highest angular frequency (unit: rad/s) of one free element with the body's lumped masses,
/// linearised at the reference state: the element eigenvalue bound (Irons) on the mesh's.
inline double elementMaxFrequency(ElementOrder order, const NodeMatrix& X, const ElementModel& model, double density) {
  ElementGeometry g;
  elementGeometry(order, X, g);
  const int n = 3 * static_cast<int>(X.rows());
  const Eigen::MatrixXd K = elementTangentAtRest(g, model, X);
  Eigen::VectorXd invSqrtMass(n);
  for (int i = 0; i < n; ++i) {
    const int a = i / 3;
    const double share = order == ElementOrder::Linear ? 0.25 : (a < 4 ? 1.0 / 36.0 : 4.0 / 27.0);
    invSqrtMass[i] = 1.0 / std::sqrt(share * density * g.volume);
  }
  Eigen::MatrixXd A = invSqrtMass.asDiagonal() * K * invSqrtMass.asDiagonal();
  A = 0.5 * (A + A.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(A, Eigen::EigenvaluesOnly);
  return std::sqrt(solver.eigenvalues().maxCoeff());
}

/// A lower estimate of the mesh's highest frequency (unit: rad/s): power iteration on
/// M^-1/2 K M^-1/2 (its eigenvalues are omega^2), from a start that is no rigid mode.
inline double highestFrequencyByPowerIteration(const Eigen::SparseMatrix<double>& K, const std::vector<double>& masses,
                                               int iterations) {
  const Eigen::Index n = K.rows();
  Eigen::VectorXd s(n), x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    s[i] = 1.0 / std::sqrt(masses[static_cast<std::size_t>(i / 3)]);
    x[i] = std::sin(1.0 + 7.0 * static_cast<double>(i));
  }
  double lambda = 0.0;
  for (int it = 0; it < iterations; ++it) {
    x.normalize();
    const Eigen::VectorXd y = s.cwiseProduct(K * s.cwiseProduct(x));
    lambda = x.dot(y);
    x = y;
  }
  return std::sqrt(lambda);
}

/// The mass-weighted mean position and velocity of a body's nodes: its centroid's motion.
inline std::pair<Vec3, Vec3> centroidMotion(const DeformableBody& body) {
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
  double m = 0.0;
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    x += body.masses()[n] * body.positions()[n];
    v += body.masses()[n] * body.velocities()[n];
    m += body.masses()[n];
  }
  return {x / m, v / m};
}

} // namespace armour::deformable::test
