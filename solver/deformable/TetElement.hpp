// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file TetElement.hpp
/// Element kernels of the 4- and 10-node tetrahedra: shape functions, quadrature, the reference
/// gradients of an element, and its internal nodal forces (seed 002 eq. 2), stored energy and
/// mean Cauchy stress, with or without F-bar (seed 002 eq. 10).
///
/// Shape functions in barycentric coordinates L1 = 1 - xi - eta - zeta, L2 = xi, L3 = eta,
/// L4 = zeta: 4-node N_i = L_i; 10-node N_i = L_i (2 L_i - 1) at corners and N = 4 L_a L_b at the
/// mid-edge node of edge (a, b) (VTK order, DeformableMesh.hpp). Quadrature: 1 point (centroid)
/// for 4 nodes, the 4-point Gauss rule (exact to degree 2) for 10 nodes.
///
/// Internal forces are integrated over the reference volume: f_a = sum_q W_q tau_q g_qa, with
/// W_q = w_q det(dX/dxi), g_qa = F_q^-T dN_a/dX the spatial gradient and tau = J T the Kirchhoff
/// stress: the same as eq. 2's integral over the current volume, since dv = J dV.
///
/// F-bar (de Souza Neto et al. 1996): at each point F_bar = (J_0 / J)^(1/3) F, with J_0 = det F at
/// the centroid, so the volume change is one value per element. The forces are the exact
/// derivative of the stored energy sum_q W_q psi(F_bar_q):
///   f_a = sum_q W_q [ tau_bar g_qa + tr(tau_bar) / 3 (g_0a - g_qa) ],
/// g_0a = F_0^-T dN_a/dX at the centroid, tau_bar = kirchhoffStress(F_bar). The second term is what
/// makes the element conserve energy in explicit dynamics; it vanishes under uniform deformation,
/// so patch tests and stresses are those of de Souza Neto's form. For the 4-node tet F is constant
/// and F-bar changes nothing.
///
/// The viscous part of eq. 7, 2 eta D, uses the point's own F and dF/dt (no F-bar): it only damps.

#include "deformable/DeformableMesh.hpp"
#include "deformable/NeoHookean.hpp"

#include <Eigen/Core>

#include <array>

namespace armour::deformable {

/// Up to 10 rows (nodes) of 3 columns: node positions, velocities, forces or shape gradients.
using NodeMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor, 10, 3>;
using NodeVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 10, 1>;

/// Quadrature on the reference tet {xi, eta, zeta >= 0, xi + eta + zeta <= 1}; weights sum to 1/6.
struct QuadratureRule {
  int points = 0;
  std::array<Vec3, 4> xi{};
  std::array<double, 4> weight{};
};
[[nodiscard]] QuadratureRule quadratureRule(ElementOrder order);

[[nodiscard]] NodeVector shapeValues(ElementOrder order, const Vec3& xi);
/// dN_a/dxi_j: row a, column j.
[[nodiscard]] NodeMatrix shapeDerivatives(ElementOrder order, const Vec3& xi);

/// What an element keeps from its reference configuration.
struct ElementGeometry {
  int points = 0;
  std::array<double, 4> weight{};     ///< W_q = w_q det(dX/dxi) (unit: m^3); they sum to the volume
  std::array<NodeMatrix, 4> gradient; ///< dN_a/dX at each point (unit: 1/m)
  NodeMatrix centroidGradient;        ///< dN_a/dX at the centroid (unit: 1/m), for F-bar
  double volume = 0.0;                ///< reference volume (unit: m^3)
};

/// @pre X holds the element's reference node positions (rows), positively oriented.
/// Returns false (and leaves `out` unusable) if the Jacobian is not positive at a point.
bool elementGeometry(ElementOrder order, const NodeMatrix& X, ElementGeometry& out);

/// Material and formulation switches shared by every element of a body.
struct ElementModel {
  LameConstants lame;
  double viscosity = 0.0; ///< eta (unit: Pa s)
  bool fBar = true;       ///< use F-bar (only changes 10-node elements)
};

/// Internal nodal forces (unit: N) of an element at positions x and velocities v (rows per node).
/// Returns false if J <= 0 at a point or at the centroid (an inverted element); `force` is then
/// not meaningful.
bool internalForces(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& x, const NodeMatrix& v,
                    NodeMatrix& force);
/// The same on raw row-major arrays of `nodes` (4 or 10) x 3 values: the form the body's step
/// uses, writing straight into its per-element force array.
bool internalForces(const ElementGeometry& g, const ElementModel& model, const double* x, const double* v, int nodes,
                    double* force);

/// The element's tangent stiffness at its reference positions X (rows), d f_int / d x (unit: N/m),
/// 3 nen x 3 nen with dof 3 a + i for node a, axis i: central differences of internalForces (F-bar
/// included; step 1e-6 V^(1/3)), symmetrised (the exact tangent is symmetric; the differences
/// leave O(h^2) asymmetry). At rest the Neo-Hookean tangent is linear elasticity's.
[[nodiscard]] Eigen::MatrixXd elementTangentAtRest(const ElementGeometry& g, const ElementModel& model,
                                                   const NodeMatrix& X);

/// Stored energy sum_q W_q psi(F_bar_q) (unit: J); NaN for an inverted element.
[[nodiscard]] double elementStrainEnergy(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& x);

/// Mean Cauchy stress over the element's current volume (unit: Pa), with F-bar as in the forces.
[[nodiscard]] Mat3 elementCauchyStress(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& x,
                                       const NodeMatrix& v);

} // namespace armour::deformable
