// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RigidObstacleContact.hpp
/// Potential contact of a deforming body with rigid bodies of any shape (issue 26: "deformable,
/// rigid and static bodies in one scene"; docs/theory.md section 19, "Contact with rigid bodies").
///
/// A rigid body is given by its level set (contact/LevelSet.hpp, phi < 0 inside, in the body's own
/// frame, shared by every body of the shape) and its pose. As for a half-space
/// (HalfSpaceContact.hpp) the body inside the rigid solid stores E = integral of G d dv with
/// d = -phi the depth, and the exact derivative with respect to the deforming body's nodes is the
/// traction f_a = - integral over (its boundary inside the solid) of N_a n_body G d da: Reynolds'
/// transport theorem holds for any fixed field d. Here d is not linear over a surface triangle, so
/// each triangle is halved recursively toward k^2 equal sub-triangles (k a power of two so that a
/// sub-triangle's edge is at most the level set's cell), skipping the parts that lie wholly
/// outside; d is sampled at their corners and taken linear on each, and the half-space
/// integration (integratePositiveDepth) is done exactly on that interpolant, then distributed to
/// the triangle's nodes by their shape functions.
///
/// The rigid body takes minus the sum of the nodal forces, and minus their moment about its
/// centre: action equals reaction exactly, whatever the quadrature.

#include "contact/LevelSet.hpp"
#include "deformable/HalfSpaceContact.hpp"

#include <Eigen/Geometry>

#include <functional>
#include <vector>

namespace armour::deformable {

/// One rigid body as the deforming body sees it, at one instant.
struct RigidObstacle {
  const contact::LevelSet* levelSet = nullptr; ///< the shape's level set, its own frame (not owned)
  /// Instead of a level set: an exact signed distance in the shape's own frame (negative inside,
  /// unscaled), e.g. a sphere's |x| - R for a Hertz test, sampled with cells of `resolution`.
  std::function<double(const Vec3&)> distance;
  double resolution = 0.0;                     ///< with `distance`: the sampling length (unit: m)
  double scale = 1.0;                          ///< uniform scale of the shape (unit: -)
  Vec3 position = Vec3::Zero();                ///< origin of the shape's frame, world (unit: m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< shape frame -> world
  /// The pose is state that the caller moves (a body of a rigid solver, which keeps it in its own
  /// checkpoint), not setup: a deformable checkpoint then leaves it out of its setup text.
  bool moving = false;
};

/// What the contact does to the rigid body, at the last evaluation.
struct ObstacleLoad {
  Vec3 force = Vec3::Zero();  ///< on the rigid body (unit: N)
  Vec3 torque = Vec3::Zero(); ///< on the rigid body, about its position (unit: N m)
  double energy = 0.0;        ///< contact energy, from the level set's normal at each sub-triangle, if asked (unit: J)
  int triangles = 0;          ///< surface triangles of the deforming body that touch it
};

/// Sub-triangles per edge of a surface triangle whose longest edge is `edge` (unit: m) against a
/// level set of cell `cell` (unit: m): the least power of two with edge / k <= cell, at most 16.
[[nodiscard]] int obstacleSubdivisions(double edge, double cell);

/// Add the contact forces (unit: N) of `obstacle` with potential gradient G (unit: Pa/m) on the
/// body at `positions` to `forces`, triangle by triangle in order (deterministic), and return the
/// rigid body's load (its energy only `withEnergy`: it costs a normal per sub-triangle, which the
/// step does not need). Throws core::InputError when the obstacle has neither a level set nor a
/// distance with a positive resolution.
ObstacleLoad addObstacleContact(const std::vector<SurfaceTriangle>& triangles, const std::vector<Vec3>& positions,
                                const RigidObstacle& obstacle, double gradient, std::vector<Vec3>& forces,
                                bool withEnergy = false);

} // namespace armour::deformable
