// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BodyFriction.hpp
/// Coulomb friction between deformable bodies (issue 26; docs/theory.md section 19, "Friction
/// between deformable bodies"): the stick-slip law of HalfSpaceFriction.hpp, with the anchor a
/// material point of the other body.
///
/// A surface node a pressed into another part as a contactor (BodyContact: the corners of its
/// surface triangles inside that part's elements) carries the normal force N_a = |F_a|, F_a the
/// sum of its contactor forces, along n_a = F_a / N_a. Its anchor is the point where it stuck,
/// held as barycentric coordinates w in a target tet c of the other part (the tet of its largest
/// contactor share when it stuck), so that it moves and turns with that body: y = sum_i w_i x_ci.
/// The friction is a tangential spring to the anchor, f = -k_a (x_a - y)_t (t: the part normal to
/// n_a), capped at mu N_a; when the spring would pull harder, the node slips: f takes the cap, and
/// the anchor is set again in the tet the node now presses most, at y' = x_a + f / k_a (so that
/// the spring holds exactly the cap). The other body takes -f at the anchor, spread to c's nodes
/// by w (the coordinates may lie outside c when the node has stuck while the tet moved: the
/// affine map of c carries the point, and sum w_i = 1 keeps action equal to reaction). A node
/// that leaves contact forgets its anchor.
///
/// Both parts of a pair act as contactors in turn (BodyContact's two roles), each with its share
/// of the normal force, so the friction of the pair is mu times the sum of both shares.
/// Stability: k_a = kappa (4 p / H)_max A_a, inside the body contact frequency that bounds the step.

#include "deformable/BodyContact.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace armour::deformable {

/// The stick anchors of the body contact: one per node.
struct BodyFrictionAnchors {
  std::span<std::int32_t> tet;                 ///< target tet (BodyContact::targetTet) of the anchor; -1: none
  std::span<std::array<double, 4>> weights;    ///< the anchor's barycentric coordinates in that tet (unit: -)
};

/// Add the friction forces (unit: N) between the parts to `forces`, given the contactor side of
/// this evaluation (BodyContact::add), the positions, the Coulomb coefficient mu, the nodes'
/// tangential stiffnesses (unit: N/m), and update the anchors. Serial in node order (the sums do
/// not depend on threads). Returns the sum of the friction forces' magnitudes on the contactor
/// nodes (unit: N).
double addBodyFriction(const BodyContact& contact, const ContactorLoads& loads, const std::vector<Vec3>& positions,
                       double mu, const std::vector<double>& stiffness, BodyFrictionAnchors anchors,
                       std::vector<Vec3>& forces);

} // namespace armour::deformable
