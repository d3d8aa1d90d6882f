// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file NeoHookean.hpp
/// Compressible Neo-Hookean material with viscous damping (seed 002, eq. 7-9):
///   T = mu / J (B - I) + lambda / J ln(J) I + 2 eta D,
///   mu = E / (2 (1 + nu)),  lambda = nu E / ((1 + nu) (1 - 2 nu)),
/// with B = F F^T, J = det F and D = sym(dF/dt F^-1). The elastic part derives from the stored
/// energy per reference volume psi = mu/2 (tr B - 3) - mu ln J + lambda/2 (ln J)^2; its Kirchhoff
/// stress is tau = J T_elastic = mu (B - I) + lambda ln(J) I. Small strains recover Hooke's law
/// with E and nu. docs/theory.md, "Deformable units (seed 002)".

#include <Eigen/Core>

#include <string>

namespace armour::deformable {

using Mat3 = Eigen::Matrix3d;

struct MaterialSettings {
  double density = 2340.0;      ///< reference density rho_0 (unit: kg/m^3); seed 002 Table 2 concrete
  double youngModulus = 26.6e9; ///< E (unit: Pa); seed 002 Table 2
  double poissonRatio = 0.205;  ///< nu (unit: -); seed 002 Table 2; -1 < nu < 0.5
  /// eta of eq. 7 (unit: Pa s). Default 0: elastic, as the verification tests need. For impacts,
  /// criticalViscosity(material, h) damps the mesh's highest mode critically (Munjiza 2004's
  /// choice, 2 h sqrt(E rho)); a few per cent of it removes the ringing of the smallest elements
  /// while leaving the unit's own modes (wavelengths >> h) almost undamped.
  double viscosity = 0.0;
};

/// Lame constants (seed 002 eq. 8-9).
struct LameConstants {
  double mu = 0.0;     ///< shear modulus (unit: Pa)
  double lambda = 0.0; ///< first Lame constant (unit: Pa)
};

/// Refuse E <= 0, nu <= -1 or nu >= 0.5, rho <= 0, eta < 0 or a non-finite value, naming `where`
/// (e.g. "scene.yaml: deformable.material"), the key, the value and the limit.
void validateMaterial(const MaterialSettings& material, const std::string& where);

[[nodiscard]] LameConstants lameConstants(const MaterialSettings& material);

/// Dilatational (P-wave) speed sqrt((lambda + 2 mu) / rho) (unit: m/s): the fastest signal, which
/// sets the stable step.
[[nodiscard]] double dilatationalWaveSpeed(const MaterialSettings& material);

/// Viscosity that damps a mode of wavelength about 2 h critically (unit: Pa s): 2 h sqrt(E rho).
[[nodiscard]] double criticalViscosity(const MaterialSettings& material, double elementSize);

/// Kirchhoff stress tau = mu (B - I) + lambda ln(J) I (unit: Pa). @pre det F > 0.
[[nodiscard]] Mat3 kirchhoffStress(const Mat3& F, const LameConstants& lame);

/// Cauchy stress of eq. 7 (unit: Pa), for deformation gradient F and its rate Fdot (unit: 1/s).
/// @pre det F > 0.
[[nodiscard]] Mat3 cauchyStress(const Mat3& F, const Mat3& Fdot, const LameConstants& lame, double viscosity);

/// Stored energy per reference volume psi (unit: J/m^3). @pre det F > 0.
[[nodiscard]] double strainEnergyDensity(const Mat3& F, const LameConstants& lame);

} // namespace armour::deformable
