// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file QuasiStatic.hpp
/// The stress in a free unit under point loads, by linear statics with inertia relief (docs/theory.md
/// section 19, "Quasi-static stress with inertia relief"): the first stage of `armour stress`
/// (issue 26), which reads the contact forces a rigid storm replay recorded on a unit and asks what
/// stress they set up in it.
///
/// A unit in a pack is free: the loads on it (contacts, gravity, water) need not balance, and
/// what they leave over accelerates it as a rigid body. Inertia relief applies that acceleration
/// as a body force, -m_n (a + alpha x r_n + omega x (omega x r_n)) on each node of lumped mass m_n
/// at r_n from the mass centre, with a and alpha solved from the loads on the discrete masses so
/// that the loaded body is in exact equilibrium; then K u = f is solved with the six rigid modes
/// held by soft springs that carry no force (the load is balanced). Gravity and a load that acts
/// on every node in proportion to its mass (the water's force, as recorded) set up no stress this
/// way (they are balanced by their own share of the inertia), so only the contact forces are given.
///
/// K is the tangent of the body's own elements at rest (DeformableBody's element kernels, F-bar
/// included), assembled by central differences of the internal forces and factored once
/// (Eigen's sparse LDL^T): each load case is then one back substitution. Linear: for the small
/// strains of concrete (below 1e-3) the stress is the Neo-Hookean body's to O(strain).
///
/// A point force is spread over the surface nodes within `radius` of its point, in proportion
/// to their tributary areas times (1 - d / radius); where fewer than `minNodes` (3) surface nodes
/// lie within, the radius grows to 1.5 times the distance of the minNodes-th nearest (a coarse mesh). A rigid
/// model resolves a contact's force, not its pressure, so the stress within about `radius` of a
/// contact depends on that choice (ours; docs/theory.md).

#include "deformable/DeformableBody.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <memory>
#include <vector>

namespace armour::deformable {

struct PointLoad {
  Vec3 point = Vec3::Zero(); ///< where it acts, in the mesh's frame (unit: m); on or near the surface
  Vec3 force = Vec3::Zero(); ///< (unit: N), in the mesh's frame
};

struct QuasiStaticResult {
  std::vector<Mat3> stress;              ///< mean Cauchy stress per element (unit: Pa), tension positive
  std::vector<Vec3> displacement;        ///< per node (unit: m), up to a rigid motion
  Vec3 acceleration = Vec3::Zero();      ///< rigid acceleration of the mass centre the loads cause (unit: m/s^2)
  Vec3 angularAcceleration = Vec3::Zero(); ///< (unit: rad/s^2)
  /// |sum of the relieved nodal loads| + |their moment| / (radius of gyration), over the largest
  /// relieved nodal load (unit: -): 0 up to round-off.
  double imbalance = 0.0;
};

class QuasiStaticUnit {
public:
  /// Assemble and factor the stiffness of `body`'s mesh at rest. `body` must outlive this object.
  /// Throws core::InputError naming the body when the stiffness cannot be factored (a mesh that is
  /// not one connected body, or with inverted elements).
  explicit QuasiStaticUnit(const DeformableBody& body);

  /// The stress under `loads`, with the unit spinning at `angularVelocity` (unit: rad/s, mesh
  /// frame; its centrifugal load is relieved too). @pre radius > 0 (unit: m); minNodes >= 1.
  [[nodiscard]] QuasiStaticResult solve(const std::vector<PointLoad>& loads, const Vec3& angularVelocity,
                                        double radius, std::size_t minNodes = 3) const;

  /// The nodal forces that `loads` spread into (unit: N), before inertia relief: over the surface
  /// nodes within `radius`, or over at least `minNodes` of them (the radius grown) on a coarse mesh.
  [[nodiscard]] std::vector<Vec3> spread(const std::vector<PointLoad>& loads, double radius,
                                         std::size_t minNodes = 3) const;

  [[nodiscard]] const Vec3& massCentre() const { return centre_; }
  [[nodiscard]] double mass() const { return mass_; }

private:
  const DeformableBody& body_;
  Eigen::SparseMatrix<double> stiffness_;
  std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> factor_;
  std::vector<std::size_t> surfaceNodes_;
  std::vector<double> surfaceArea_; ///< tributary area of each surface node (unit: m^2)
  Vec3 centre_ = Vec3::Zero();
  double mass_ = 0.0;
  Mat3 inertia_ = Mat3::Zero(); ///< of the lumped masses about the centre (unit: kg m^2)
};

} // namespace armour::deformable
