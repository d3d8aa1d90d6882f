// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BodyContact.hpp
/// Normal contact between deformable bodies by Munjiza's distributed potential (seed 002
/// eq. 5-6; Munjiza 2004, "The Combined Finite-Discrete Element Method", ch. 2 and 5), on the
/// current element geometry (docs/theory.md section 19, "Contact between deformable bodies").
///
/// Friction between the parts is BodyFriction.hpp's, on the contactor side given by add().
///
/// The bodies are the disconnected parts of one mesh (e.g. a unit and its anvil merged into one
/// DeformableMesh): two nodes are in the same part when an element links them. Parts do not touch
/// themselves (no self-contact).
///
/// Every element t carries the potential phi_t(x) = 4 p min_i lambda_i(x), lambda_i the
/// barycentric coordinates of the tet: 0 on its faces, p at its centroid, linear on each of the
/// four sub-tets (face i with the centroid), p the penalty (unit: Pa). A 10-node element takes
/// part as its eight straight 4-node tets on corner and mid-edge nodes, as its surface takes part
/// as four flat triangles per face: the potential then moves with the same nodes that carry the
/// force. (With the potential of the corner tet and the force spread by the quadratic shape
/// functions, a test of two colliding bars gained 8 times its energy: the mid-edge nodes took
/// force without the potential depending on them.)
/// Munjiza's force between a contactor element c and a target element t is the integral over the
/// boundary of their overlap, f_c = integral of n_c (phi_c - phi_t) dGamma (eq. 6). Summed over the
/// elements of a body the faces shared by two of its elements cancel (opposite normals, same phi
/// of the other body), so only the body's outer surface remains: each surface triangle of part A
/// lying inside an element t of another part B takes the traction -phi_t n_A, and the same force,
/// reversed, goes to t's nodes at the same points, through t's linear shape functions (Munjiza's
/// distribution). The term with phi_c comes from the same loop with the parts' roles swapped.
/// Action equals reaction point by point, so the total force and moment of the contact are zero to
/// round-off. The contactor's share is the exact gradient of E = integral over (A in t) of phi_t dv
/// with respect to A's nodes; the target's share by shape functions is Munjiza's, not the exact
/// gradient with respect to t's nodes, so energy is conserved to the discretisation, not exactly
/// (test_deformable_body_contact measures it).
///
/// Each surface triangle is clipped in its own barycentric coordinates by the four half-planes of
/// each sub-tet (Sutherland-Hodgman; lambda is linear on the flat triangle) and the clipped polygon
/// integrated by a fan of triangles with Dunavant's 6-point rule (degree 4; the integrands
/// without damping are quadratic, so exact).
///
/// Damping: a contact pressure zeta Z w added where phi > 0, w the closing speed (v_A - v_B) . n_A
/// at the point, Z = rho c_d the material's impedance, zeta (unit: -) the given ratio; the pressure
/// is kept >= 0 (no adhesion).
///
/// Broad phase: each part's box bounds its target tets; the parts whose boxes meet are found by a
/// sweep along x, and a tet or triangle that meets none of its part's neighbours' boxes is
/// skipped (so 288 rocks apart cost their own checks, not 288 x 288). The remaining target tets (those with a node on the surface) are binned
/// by their bounding boxes on a uniform grid of cell = their largest box edge, as a sorted list of
/// (cell, element) pairs; each surface triangle takes the elements of the cells its box covers.
/// Threads: the triangles are shared among the threads (OpenMP), each pair's forces computed into
/// a record; the records are then added serially in a fixed order (triangle, then element index),
/// so the sums, and the bits, do not depend on the thread count.

#include "deformable/DeformableMesh.hpp"
#include "deformable/HalfSpaceContact.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace armour::deformable {

/// The contactor side of one evaluation, per node, for friction (BodyFriction.hpp): what a node
/// received as the corner of surface triangles lying inside other parts' elements.
struct ContactorLoads {
  std::vector<Vec3> force;          ///< the contactor forces on each node (unit: N); zero where none
  std::vector<std::int32_t> target; ///< the target tet (BodyContact::targetTet) of its largest share; -1 where none
  std::vector<double> share;        ///< that share's size (unit: N)
};

/// Totals of one contact evaluation.
struct BodyContactStats {
  std::size_t candidatePairs = 0; ///< (triangle, element) pairs from the broad phase
  std::size_t touchingPairs = 0;  ///< pairs with a non-zero force
  double normalForce = 0.0;       ///< sum of |force| over the contactor sides (unit: N), each pair counted once per side
};

class BodyContact {
public:
  /// @pre mesh valid (DeformableBody checked it); penalty > 0 (unit: Pa); dampingRatio >= 0;
  /// impedance = rho c_d (unit: Pa s/m).
  BodyContact(const DeformableMesh& mesh, const std::vector<SurfaceTriangle>& triangles, double penalty,
              double dampingRatio, double impedance);

  /// Add the contact forces (unit: N) at `positions`, `velocities` to `forces`; with `contactor`,
  /// also the contactor side per node (sized to the nodes and filled here).
  BodyContactStats add(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
                       std::vector<Vec3>& forces, ContactorLoads* contactor = nullptr) const;
  /// The target tets: straight 4-node tets on the surface of each part (positively oriented).
  [[nodiscard]] const std::array<std::int32_t, 4>& targetTet(std::size_t k) const { return tets_[k]; }
  [[nodiscard]] std::size_t targetTetCount() const { return tets_.size(); }

  [[nodiscard]] std::size_t partCount() const { return partCount_; }
  [[nodiscard]] const std::vector<std::int32_t>& nodeParts() const { return nodePart_; } ///< part of each node
  /// Largest potential gradient 4 p / H over the target tets (unit: Pa/m), H the smallest
  /// altitude of the tet in the reference mesh: the contact spring per area for the
  /// stable step (contactFrequency).
  [[nodiscard]] double gradientBound() const { return gradientBound_; }
  [[nodiscard]] double penalty() const { return penalty_; }

private:
  /// One (triangle, target element) pair's nodal forces: f_contactor = -contactorShare_k n on the
  /// triangle's corners, f_target = targetShare_b n on the element's.
  struct PairForce {
    std::size_t triangle = 0;
    std::size_t target = 0;
    Vec3 normal = Vec3::Zero();
    Eigen::Vector3d contactorShare = Eigen::Vector3d::Zero();
    Eigen::Vector4d targetShare = Eigen::Vector4d::Zero();
  };
  /// Add the records' forces in their order (serial: the same sums for any thread count), with
  /// the contactor side if asked, and count them.
  void applyPairs(const std::vector<PairForce>& all, std::vector<Vec3>& forces, ContactorLoads* contactor,
                  BodyContactStats& stats) const;
  /// The pair's forces into `out`; false when they are zero (not touching, or an inverted element).
  bool pairForce(std::size_t triangle, std::size_t target, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                 PairForce& out) const;

  using Tet4 = std::array<std::int32_t, 4>;
  std::vector<SurfaceTriangle> triangles_;
  std::vector<std::int32_t> trianglePart_;
  std::vector<std::int32_t> nodePart_;
  std::vector<Tet4> tets_;            ///< target tets (positively oriented): straight tets touching the surface
  std::vector<std::int32_t> tetPart_; ///< part of each target tet
  std::size_t partCount_ = 0;
  double penalty_ = 0.0;
  double dampingRatio_ = 0.0;
  double impedance_ = 0.0;
  double gradientBound_ = 0.0;
};

} // namespace armour::deformable
