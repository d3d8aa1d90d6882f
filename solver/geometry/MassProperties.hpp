// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file MassProperties.hpp
/// Exact volume, centroid and inertia of a closed, outward-oriented triangle mesh.
///
/// Method (docs/theory.md, "Mass properties"): the solid is the signed sum of the tetrahedra
/// (o, a, b, c) spanned by a reference point o and each triangle; for each tetrahedron the volume
/// and the second moment  int x x^T dV = V/20 (sum_i v_i v_i^T + s s^T),  s = sum_i v_i  are exact
/// polynomial integrals (divergence theorem; Tonon 2004, Eberly 2002). Accumulation is done relative
/// to o = the box centre to keep round-off independent of where the body sits in the world.

#include "geometry/TriangleMesh.hpp"

namespace armour::geometry {

struct MassProperties {
  double volume = 0.0;                      ///< m^3 (signed: negative if the mesh is inward)
  Vec3 centroid = Vec3::Zero();             ///< m
  Mat3 inertia = Mat3::Zero();              ///< per unit density, about the centroid, world axes (m^5)
  Vec3 principalMoments = Vec3::Zero();     ///< ascending eigenvalues of `inertia` (m^5)
  Mat3 principalAxes = Mat3::Identity();    ///< columns are the principal axes; right-handed
  /// Volume-equivalent cube side Dn = V^(1/3) (m).
  [[nodiscard]] double nominalDiameter() const;
  /// Inertia for density rho (kg/m^3): rho x inertia (kg m^2).
  [[nodiscard]] Mat3 inertiaForDensity(double rho) const { return rho * inertia; }
};

/// Mass properties per unit density. The mesh should be closed and outward (validate first);
/// an open mesh gives a result that depends on the reference point.
MassProperties computeMassProperties(const TriangleMesh& mesh);

/// Signed volume only (m^3).
double signedVolume(const TriangleMesh& mesh);

/// Scale the mesh about its centroid so that its volume equals `targetVolume` (m^3) to round-off.
/// @pre the mesh is closed with positive volume.
void scaleToVolume(TriangleMesh& mesh, double targetVolume);

/// Translate the mesh so its centroid is at the origin.
void centreOnCentroid(TriangleMesh& mesh);

} // namespace armour::geometry
