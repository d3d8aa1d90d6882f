// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file OrderParameters.hpp
/// Orientational order of a pack: the P2 order parameter of seed 001 (eq. 4, after
/// Vieillard-Baron 1972) in its two forms, for the unit axes u_i (e.g. a dolos's axis normal to
/// the shank, a Core-Loc's nose axis). docs/theory.md, "Order parameters".
///
///  - Seed 001's form: the director is the mean direction of the axes, d = sum u_i / |sum u_i|,
///    and P2 = (1/N) sum (3 cos^2 w_i - 1)/2 with cos w_i = u_i . d. (The seed prints the sum
///    without 1/N; its stated values, 1 for aligned axes, -1/2 for axes normal to the director and
///    1/4 for random ones, are those of the mean.) It depends on the sign of each axis: it suits
///    axes with a head and a tail that the construction keeps consistent (units lowered in one
///    orientation); for axes of random sign the mean direction is noise.
///  - The Q-tensor form (de Gennes): Q = (1/N) sum (3 u_i u_i^T - I)/2; P2 is its largest
///    eigenvalue and the director its eigenvector. Head-tail symmetric (u and -u count the same);
///    1 for aligned axes, about 0 for isotropic 3D axes (a positive bias of order 1/sqrt(N)),
///    1/4 for axes isotropic in a plane.

#include <Eigen/Core>

#include <vector>

namespace armour::analysis {

struct OrderParameter {
  double p2 = 0.0;                               ///< unit: -
  Eigen::Vector3d director = Eigen::Vector3d::UnitZ(); ///< unit vector (unit: -)
  std::size_t count = 0;                         ///< axes used (unit: -)
};

/// Seed 001 eq. 4 with the mean-direction director. Axes need not be unit (they are normalised);
/// throws core::InputError for no axes, a zero or non-finite axis, or axes whose sum vanishes
/// (no mean direction: use the Q-tensor form).
[[nodiscard]] OrderParameter p2MeanDirector(const std::vector<Eigen::Vector3d>& axes);

/// The Q-tensor form: largest eigenvalue of Q and its eigenvector. Throws core::InputError for no
/// axes or a zero or non-finite axis.
[[nodiscard]] OrderParameter p2QTensor(const std::vector<Eigen::Vector3d>& axes);

} // namespace armour::analysis
