// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StableStep.hpp
/// The largest stable step of explicit central differences on a mesh (docs/theory.md,
/// "Deformable units (seed 002)"):
///   dt = safety * (l_min / c_d) * (sqrt(1 + xi^2) - xi),   xi = 2 eta / (rho c_d l_min),
/// c_d = sqrt((lambda + 2 mu) / rho) the dilatational wave speed, l_min the smallest element
/// length, xi the damping ratio that the viscosity eta gives the highest mode (omega = 2 c_d / l).
/// Element length: the smallest altitude of the (corner) tet, 3 V / (largest face area), divided by
/// 2 for 4-node and by 4 for 10-node tets. The divisors were measured: with them l / c_d is at or
/// below 2 / omega_max of the element itself (lumped masses, linearised at rest) for regular,
/// cube-split, corner, flat, needle and sliver tets, nu from 0 to 0.49, with and without F-bar
/// (the ratio 2 / (omega_max l / c_d) lies in 1.00-1.86; test_deformable_element checks it).
/// The element bound is above the mesh's own limit (Irons' theorem), so safety 1 is stable.
/// The lengths are those of the reference mesh: a strongly compressed element is stiffer, which
/// the safety factor must cover.

#include "deformable/DeformableMesh.hpp"
#include "deformable/NeoHookean.hpp"
#include "deformable/TetElement.hpp"

#include <Eigen/Sparse>

#include <cstddef>
#include <vector>

namespace armour::deformable {

/// Element length = smallest altitude of the corner tet over this (unit: -).
inline constexpr double kLinearLengthDivisor = 2.0;
inline constexpr double kQuadraticLengthDivisor = 4.0;

struct StableStepEstimate {
  double dt = 0.0;            ///< largest allowed step (unit: s), the safety factor included
  double lengthMin = 0.0;     ///< l_min (unit: m)
  std::size_t element = 0;    ///< the element with l_min
  double waveSpeed = 0.0;     ///< c_d (unit: m/s)
  double dampingRatio = 0.0;  ///< xi of the highest mode (unit: -)
  double safety = 0.0;        ///< the safety factor used (unit: -)
  double contactFrequency = 0.0; ///< omega_c of fully pressed half-space contact (unit: rad/s); 0 = none
  /// The mesh's own bound (meshFrequencyBound) was lower than the element bound and set the step:
  /// lengthMin is then the effective length 2 c_d / omega_mesh.
  bool meshBound = false;
  double meshFrequency = 0.0; ///< Gershgorin's bound on the mesh's omega_max (unit: rad/s); 0 = not computed
};

/// Element length l_e (unit: m) of element e.
[[nodiscard]] double elementLength(const DeformableMesh& mesh, std::size_t e);

/// The mesh's tangent stiffness at rest (unit: N/m), 3 n x 3 n with dof 3 a + i for node a, axis i:
/// the element tangents (elementTangentAtRest) assembled.
[[nodiscard]] Eigen::SparseMatrix<double> tangentAtRest(const DeformableMesh& mesh,
                                                        const std::vector<ElementGeometry>& geometry,
                                                        const ElementModel& model);

/// Gershgorin's bound on the highest frequency of the assembled mesh (unit: rad/s): omega_max^2 <=
/// max over rows i of sum_j |K_ij| / m_i, with K the tangent at rest (elementTangentAtRest) and m
/// the lumped masses (M^-1 K has the eigenvalues omega^2 and Gershgorin's circles hold them). A
/// rigorous bound like the element one, and much closer on gmsh's meshes: their near-flat surface
/// elements share nodes with large ones, whose mass the element bound does not see (a 5 m^3
/// Core-Loc of 2 311 tets: element bound 6.6 times the power-iteration omega_max for tet4, 2.7
/// for tet10; Gershgorin 1.5 and 1.9; docs/benchmarks.md).
[[nodiscard]] double meshFrequencyBound(const DeformableMesh& mesh, const std::vector<ElementGeometry>& geometry,
                                        const ElementModel& model, const std::vector<double>& masses);

/// Selective mass scaling (ours; the usual remedy of explicit codes for a few small elements,
/// docs/theory.md "Mass scaling"): element e's density is multiplied by s_e >= 1, which lengthens
/// its own limit by sqrt(s_e) (c_d falls as 1 / sqrt(s_e)). Every element shorter than a target
/// length L gets s_e = (L / l_e)^2, so none is shorter than L in effect, and L is the largest for
/// which the mass added to each body (each disconnected part of the mesh) is at most
/// `maxAddedFraction` of that body's mass (exact: the sum is a piecewise quadratic in L over the
/// sorted lengths).
struct MassScaling {
  std::vector<double> factor;   ///< s_e per element (unit: -); 1 where unscaled
  double length = 0.0;          ///< the target length L, the effective l_min (unit: m)
  std::size_t scaled = 0;       ///< elements with s_e > 1
  double addedMass = 0.0;       ///< sum (s_e - 1) rho V_e (unit: kg)
  double mass = 0.0;            ///< the unscaled mass rho sum V_e (unit: kg)
  double largestPartFraction = 0.0; ///< the largest added mass of a body over its own mass (unit: -)
  std::size_t element = 0;      ///< the unscaled shortest element
  double lengthMin = 0.0;       ///< its length, l_min without scaling (unit: m)
};

/// @pre volumes[e] > 0 is element e's volume; maxAddedFraction >= 0 (0: factors all 1, L = l_min).
[[nodiscard]] MassScaling massScaling(const DeformableMesh& mesh, const std::vector<double>& volumes, double density,
                                      double maxAddedFraction);

/// @pre the mesh has elements; material validated; 0 < safety <= 1; contactFrequency >= 0.
/// With contact, the element bound 2 c_d / l_min and omega_c combine as
/// omega = sqrt((2 c_d / l_min)^2 + omega_c^2) (a surface node's frequency with its contact spring
/// is at most that), and dt = safety (2 / omega) (sqrt(1 + xi^2) - xi).
[[nodiscard]] StableStepEstimate stableStep(const DeformableMesh& mesh, const MaterialSettings& material,
                                            double safety, double contactFrequency = 0.0);
/// The same from a given l_min (e.g. MassScaling::length) and the element that has it.
[[nodiscard]] StableStepEstimate stableStepForLength(double lengthMin, std::size_t element,
                                                     const MaterialSettings& material, double safety,
                                                     double contactFrequency = 0.0);

} // namespace armour::deformable
