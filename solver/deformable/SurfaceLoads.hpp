// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SurfaceLoads.hpp
/// Boundary faces of a deformable mesh and the consistent nodal forces of a uniform traction on
/// some of them (seed 002 eq. 3, second term, f_a = integral of N_a t over the face). On a
/// straight 3-node face each corner takes A/3; on a straight 6-node face the corners take 0 and
/// each mid-edge node A/3 (the integral of L_i (2 L_i - 1) over a triangle is 0, of 4 L_i L_j A/3).

#include "deformable/DeformableMesh.hpp"

#include <functional>
#include <vector>

namespace armour::deformable {

struct BoundaryFace {
  std::size_t element = 0;
  std::array<std::int32_t, 3> corners{};  ///< counter-clockwise seen from outside
  std::array<std::int32_t, 3> midEdges{}; ///< 10-node meshes: nodes on edges (c0,c1), (c1,c2), (c2,c0); else -1
  Vec3 normal = Vec3::Zero();             ///< outward unit normal (reference configuration)
  double area = 0.0;                      ///< (unit: m^2)
  Vec3 centroid = Vec3::Zero();           ///< (unit: m)
};

/// Faces used by one element only, in a deterministic order (by element, then local face).
[[nodiscard]] std::vector<BoundaryFace> boundaryFaces(const DeformableMesh& mesh);

/// Nodal forces (unit: N, one per node) of a uniform traction (unit: Pa) on the boundary faces
/// for which select(face) is true, in the reference configuration (small deformation).
[[nodiscard]] std::vector<Vec3> tractionLoads(const DeformableMesh& mesh, const std::vector<BoundaryFace>& faces,
                                              const std::function<bool(const BoundaryFace&)>& select,
                                              const Vec3& traction);

/// Nodal forces (unit: N) of a pressure p (unit: Pa, positive pushes into the body: t = -p n) on
/// the selected boundary faces, with each face's own reference normal.
[[nodiscard]] std::vector<Vec3> pressureLoads(const DeformableMesh& mesh, const std::vector<BoundaryFace>& faces,
                                              const std::function<bool(const BoundaryFace&)>& select, double pressure);

} // namespace armour::deformable
