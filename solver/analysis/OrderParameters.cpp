// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/OrderParameters.hpp"

#include "core/Error.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace armour::analysis {

namespace {

/// The axes as unit vectors; refuses what has no direction.
std::vector<Eigen::Vector3d> unitAxes(const std::vector<Eigen::Vector3d>& axes, const char* what) {
  if (axes.empty()) {
    core::failInput(what, "no unit axes given: the order parameter of an empty pack is undefined");
  }
  std::vector<Eigen::Vector3d> units;
  units.reserve(axes.size());
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const double n = axes[i].norm();
    if (!std::isfinite(n) || n == 0.0) {
      core::failInput(what, "axis {} = ({}, {}, {}) has no direction (zero or not finite)", i, axes[i].x(), axes[i].y(),
                      axes[i].z());
    }
    units.push_back(axes[i] / n);
  }
  return units;
}

} // namespace

OrderParameter p2MeanDirector(const std::vector<Eigen::Vector3d>& axes) {
  const auto units = unitAxes(axes, "P2 (mean director)");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& u : units) {
    sum += u;
  }
  // A resultant shorter than 1e-9 of the count is round-off of cancelling axes: no mean direction.
  if (sum.norm() <= 1e-9 * static_cast<double>(units.size())) {
    core::failInput("P2 (mean director)", "the {} axes cancel out (|sum| = {:.3g}): there is no mean direction; use "
                                          "the Q-tensor form, which does not need one",
                    units.size(), sum.norm());
  }
  OrderParameter r;
  r.director = sum.normalized();
  r.count = units.size();
  double total = 0.0;
  for (const auto& u : units) {
    const double c = u.dot(r.director);
    total += 0.5 * (3.0 * c * c - 1.0);
  }
  r.p2 = total / static_cast<double>(units.size());
  return r;
}

OrderParameter p2QTensor(const std::vector<Eigen::Vector3d>& axes) {
  const auto units = unitAxes(axes, "P2 (Q tensor)");
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
  for (const auto& u : units) {
    q += 1.5 * u * u.transpose();
  }
  q /= static_cast<double>(units.size());
  q -= 0.5 * Eigen::Matrix3d::Identity();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(q);
  OrderParameter r;
  r.p2 = eigen.eigenvalues()(2); // ascending: the largest is last
  r.director = eigen.eigenvectors().col(2).normalized();
  r.count = units.size();
  return r;
}

} // namespace armour::analysis
