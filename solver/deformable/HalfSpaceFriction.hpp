// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file HalfSpaceFriction.hpp
/// Coulomb friction of a deforming body's surface nodes on a static half-space (issue 26: the
/// tangential part of the contact, which seed 002 leaves out: "The model does not capture the
/// friction between units"). docs/theory.md section 19, "Friction on a static half-space".
///
/// Each surface node a pressed by the half-space's potential (HalfSpaceContact.hpp) carries a
/// normal force N_a = f_a . n > 0 and a stick anchor: the point where it stuck. Its friction force
/// is a tangential spring to the anchor, f_t = -k_a (x_a - anchor)_t with k_a = kappa G A_a (A_a
/// its tributary area, G the potential gradient, kappa the tangential stiffness ratio), capped at
/// mu N_a: when the spring would pull harder, the anchor moves to the cap (slip). A sticking node
/// is held by an elastic force, so a body below the friction angle does not creep; a sliding one
/// is resisted by exactly mu N_a. A node that leaves contact (N_a = 0) forgets its anchor.
///
/// Stability: k_a <= G A_a for kappa <= 1, inside the contact frequency sqrt(G A_a / m_a) that
/// already bounds the step (StableStep.hpp).

#include "deformable/DeformableMesh.hpp"
#include "deformable/HalfSpaceContact.hpp"

#include <Eigen/Geometry>

#include <cstdint>
#include <span>
#include <vector>

namespace armour::deformable {

/// The stick anchors of one half-space: one per node.
struct FrictionAnchors {
  std::span<Vec3> anchor;          ///< where the node stuck (unit: m)
  std::span<std::uint8_t> active;  ///< 1 while the node is in contact and has an anchor
};

/// Add the friction forces (unit: N) of `halfSpace` on the nodes to `forces`, given this
/// half-space's normal nodal forces `pressure` (addHalfSpaceContact on a zeroed vector), the
/// Coulomb coefficient mu, the nodes' tangential stiffnesses `stiffness` (unit: N/m; 0 for nodes
/// that cannot touch), and update the anchors. Returns the sum of the friction forces (unit: N).
Vec3 addHalfSpaceFriction(const std::vector<Vec3>& pressure, const std::vector<Vec3>& positions,
                          const HalfSpace& halfSpace, double mu, const std::vector<double>& stiffness,
                          FrictionAnchors anchors, std::vector<Vec3>& forces);

/// The same against a rigid body (RigidObstacleContact.hpp) at pose (orientation, origin): the
/// normal of node a is the direction of its nodal force from that body, `pressure[a]`
/// (addObstacleContact on a zeroed vector), and the anchors are kept in the rigid body's frame,
/// so that a node sticks to a moving body. Returns the sum of the friction forces on the nodes (N).
Vec3 addObstacleFriction(const std::vector<Vec3>& pressure, const std::vector<Vec3>& positions,
                         const Eigen::Quaterniond& orientation, const Vec3& origin, double mu,
                         const std::vector<double>& stiffness, FrictionAnchors anchors, std::vector<Vec3>& forces);

} // namespace armour::deformable
