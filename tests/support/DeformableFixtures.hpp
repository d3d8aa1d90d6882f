// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableFixtures.hpp
/// Small scenes for the deformable-body tests: bars and boxes of 4- or 10-node tets, the nodes on
/// a plane, and the element's own highest frequency for stable-step checks.

#include "deformable/DeformableBody.hpp"
#include "deformable/StructuredBox.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <functional>
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
  const int nen = static_cast<int>(X.rows());
  const int n = 3 * nen;
  Eigen::MatrixXd K(n, n);
  const NodeMatrix v = NodeMatrix::Zero(nen, 3);
  const double h = 1e-7 * std::cbrt(g.volume);
  for (int j = 0; j < n; ++j) {
    NodeMatrix xp = X;
    NodeMatrix xm = X;
    xp(j / 3, j % 3) += h;
    xm(j / 3, j % 3) -= h;
    NodeMatrix fp;
    NodeMatrix fm;
    internalForces(g, model, xp, v, fp);
    internalForces(g, model, xm, v, fm);
    for (int i = 0; i < n; ++i) {
      K(i, j) = (fp(i / 3, i % 3) - fm(i / 3, i % 3)) / (2.0 * h);
    }
  }
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

} // namespace armour::deformable::test
