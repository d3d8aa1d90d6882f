// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file HalfSpaceContact.hpp
/// Frictionless potential contact of a deforming body with static half-spaces (a rigid anvil, a
/// floor): the first piece of seed 002's contact (eq. 5) on deforming elements, with distributed
/// nodal forces (docs/theory.md section 19, "Contact with a static half-space").
///
/// The static solid {x : (x - p) . n < 0} has the potential phi = G d, d = (p - x) . n its depth,
/// G the potential gradient (unit: Pa/m). The contact energy is E = integral over the body's part
/// inside the solid of phi dv, and its exact derivative with respect to the nodes of the body is a
/// traction over the body's boundary inside the solid:
///   f_a = - integral over (boundary of the body inside the solid) of N_a n_body G d da,
///   E   = - G/2 integral over the same of d^2 (n . n_body) da   (divergence theorem).
/// The boundary is the body's current surface made of flat triangles: each face of a 4-node tet,
/// and each 6-node face of a 10-node tet split into its four corner-and-mid-edge triangles, with
/// linear N on each. Each triangle is clipped by d = 0 and the quadratic integrands integrated
/// exactly (3-point edge-midpoint rule on the fan of the clipped polygon). No friction and no
/// damping yet (issue 26, later sessions).
///
/// Stiffness: a surface node with tributary area A_a (inside the solid) and mass m_a adds
/// omega_c^2 = G A_a / m_a to the element frequencies; `contactFrequency` bounds it for the stable step.

#include "deformable/DeformableMesh.hpp"
#include "deformable/SurfaceLoads.hpp"

#include <vector>

namespace armour::deformable {

struct HalfSpace {
  Vec3 point = Vec3::Zero();     ///< a point of the bounding plane (unit: m)
  Vec3 normal = Vec3::UnitZ();   ///< unit outward normal of the static solid, into free space (unit: -)
};

/// A flat surface triangle of the body, as node indices, counter-clockwise seen from outside.
using SurfaceTriangle = std::array<std::int32_t, 3>;

/// The body's surface as flat triangles (10-node faces split in four), deterministic order.
[[nodiscard]] std::vector<SurfaceTriangle> surfaceTriangles(const DeformableMesh& mesh,
                                                            const std::vector<BoundaryFace>& faces);

/// Add to nd the integrals of N_a d (unit: m^3) and to dd the integral of d^2 (unit: m^4) over the
/// part of a flat triangle of area `area` (unit: m^2) where the linear depth d, of corner values
/// `depth` (unit: m), is positive: exact (clipped at d = 0, edge-midpoint rule on the fan).
void integratePositiveDepth(const std::array<double, 3>& depth, double area, Eigen::Vector3d& nd, double& dd);

/// Add the contact forces (unit: N) of `halfSpace` with potential gradient G (unit: Pa/m) on the
/// body at `positions` to `forces`, triangle by triangle in order (deterministic), and return the
/// contact energy (unit: J).
double addHalfSpaceContact(const std::vector<SurfaceTriangle>& triangles, const std::vector<Vec3>& positions,
                           const HalfSpace& halfSpace, double gradient, std::vector<Vec3>& forces);

/// Tributary area of each node on the surface triangles (a third of each triangle around it) in the
/// reference configuration (unit: m^2); 0 for interior nodes.
[[nodiscard]] std::vector<double> tributaryAreas(const DeformableMesh& mesh, const std::vector<SurfaceTriangle>& triangles);

/// Largest contact frequency sqrt(G A_a / m_a) over the surface nodes (unit: rad/s), A_a the
/// node's tributary area (a third of each triangle around it, reference configuration): what
/// fully pressed contact adds to the element frequencies.
[[nodiscard]] double contactFrequency(const DeformableMesh& mesh, const std::vector<SurfaceTriangle>& triangles,
                                      const std::vector<double>& masses, double gradient);

} // namespace armour::deformable
