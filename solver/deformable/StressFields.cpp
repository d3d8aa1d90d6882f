// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/StressFields.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace armour::deformable {

StressSummary summarizeStress(const Mat3& cauchy) {
  // The iterative solver (not computeDirect): its eigenvalues are accurate to round-off of the
  // largest stress also when two principal stresses are close.
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(0.5 * (cauchy + cauchy.transpose()), Eigen::EigenvaluesOnly);
  const Vec3 ascending = solver.eigenvalues();
  StressSummary out;
  out.principal = Vec3(ascending[2], ascending[1], ascending[0]);
  out.differential = out.principal[0] - out.principal[2];
  const Vec3& s = out.principal;
  out.vonMises = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                  (s[2] - s[0]) * (s[2] - s[0])));
  return out;
}

std::vector<Mat3> nodalStresses(const DeformableMesh& mesh, const std::vector<Mat3>& elementStress,
                                const std::vector<double>& weights) {
  std::vector<Mat3> sum(mesh.nodeCount(), Mat3::Zero());
  std::vector<double> weight(mesh.nodeCount(), 0.0);
  const int nen = mesh.nodesPerElement();
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    for (int a = 0; a < nen; ++a) {
      const auto n = static_cast<std::size_t>(mesh.element(e)[a]);
      sum[n] += weights[e] * elementStress[e];
      weight[n] += weights[e];
    }
  }
  for (std::size_t n = 0; n < sum.size(); ++n) {
    if (weight[n] > 0.0) {
      sum[n] /= weight[n];
    }
  }
  return sum;
}

} // namespace armour::deformable
