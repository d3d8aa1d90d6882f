// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StressFields.hpp
/// Stress outputs of a deformable unit: the Cauchy stress tensor, its principal stresses with
/// tension positive (seed 002's convention: sigma_1 the largest tension), the differential stress
/// sigma_1 - sigma_3 and the von Mises stress sqrt(1/2 ((s1-s2)^2 + (s2-s3)^2 + (s3-s1)^2)),
/// per element and averaged to nodes.

#include "deformable/DeformableMesh.hpp"
#include "deformable/NeoHookean.hpp"

#include <vector>

namespace armour::deformable {

struct StressSummary {
  Vec3 principal = Vec3::Zero(); ///< sigma_1 >= sigma_2 >= sigma_3 (unit: Pa), tension positive
  double differential = 0.0;     ///< sigma_1 - sigma_3 (unit: Pa)
  double vonMises = 0.0;         ///< (unit: Pa)
};

[[nodiscard]] StressSummary summarizeStress(const Mat3& cauchy);

/// Volume-weighted mean of the stresses of the elements around each node (unit: Pa).
/// `weights` are one per element, e.g. the reference volumes.
[[nodiscard]] std::vector<Mat3> nodalStresses(const DeformableMesh& mesh, const std::vector<Mat3>& elementStress,
                                              const std::vector<double>& weights);

} // namespace armour::deformable
