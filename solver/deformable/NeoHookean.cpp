// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/NeoHookean.hpp"

#include "core/Error.hpp"

#include <Eigen/LU>

#include <cmath>

namespace armour::deformable {

void validateMaterial(const MaterialSettings& m, const std::string& where) {
  core::requireFinite(m.density, where + ".density", "kg/m^3");
  core::requireFinite(m.youngModulus, where + ".young_modulus", "Pa");
  core::requireFinite(m.poissonRatio, where + ".poisson_ratio", "(-)");
  core::requireFinite(m.viscosity, where + ".viscosity", "Pa s");
  if (!(m.density > 0.0)) {
    core::failInput(where + ".density", "{} kg/m^3: the density must be positive (concrete: about 2300-2400)",
                    m.density);
  }
  if (!(m.youngModulus > 0.0)) {
    core::failInput(where + ".young_modulus", "{} Pa: Young's modulus must be positive (concrete: about 3e10 Pa)",
                    m.youngModulus);
  }
  if (!(m.poissonRatio < 0.5)) {
    core::failInput(where + ".poisson_ratio",
                    "{}: Poisson's ratio must be below 0.5, the incompressible limit where lambda = nu E / ((1 + nu) "
                    "(1 - 2 nu)) is infinite (concrete: about 0.2; nearly incompressible: 0.49)",
                    m.poissonRatio);
  }
  if (!(m.poissonRatio > -1.0)) {
    core::failInput(where + ".poisson_ratio",
                    "{}: Poisson's ratio must be above -1, the limit where mu = E / (2 (1 + nu)) is infinite "
                    "(concrete: about 0.2)",
                    m.poissonRatio);
  }
  if (m.viscosity < 0.0) {
    core::failInput(where + ".viscosity", "{} Pa s: the viscosity must be 0 or positive; a negative one adds energy",
                    m.viscosity);
  }
}

LameConstants lameConstants(const MaterialSettings& m) {
  const double E = m.youngModulus;
  const double nu = m.poissonRatio;
  return {E / (2.0 * (1.0 + nu)), nu * E / ((1.0 + nu) * (1.0 - 2.0 * nu))};
}

double dilatationalWaveSpeed(const MaterialSettings& m) {
  const auto lame = lameConstants(m);
  return std::sqrt((lame.lambda + 2.0 * lame.mu) / m.density);
}

double criticalViscosity(const MaterialSettings& m, double elementSize) {
  return 2.0 * elementSize * std::sqrt(m.youngModulus * m.density);
}

namespace {

/// ln J from H = F - I without cancellation: J - 1 = I1 + I2 + I3 (the invariants of H), then
/// log1p. At rest and under rigid translation J - 1 is then 0 to round-off of H, not of 1.
double logJacobian(const Mat3& H) {
  const double i1 = H.trace();
  const double i2 = 0.5 * (i1 * i1 - (H * H).trace());
  return std::log1p(i1 + i2 + H.determinant());
}

} // namespace

Mat3 kirchhoffStress(const Mat3& F, const LameConstants& lame) {
  // B - I = H + H^T + H H^T with H = F - I: small strains keep their digits (F F^T - I would lose
  // them to the 1 on the diagonal).
  const Mat3 H = F - Mat3::Identity();
  Mat3 tau = lame.mu * (H + H.transpose() + H * H.transpose());
  tau.diagonal().array() += lame.lambda * logJacobian(H);
  return tau;
}

Mat3 cauchyStress(const Mat3& F, const Mat3& Fdot, const LameConstants& lame, double viscosity) {
  const double J = F.determinant();
  Mat3 T = kirchhoffStress(F, lame) / J;
  if (viscosity != 0.0) {
    const Mat3 L = Fdot * F.inverse();
    T += viscosity * (L + L.transpose());
  }
  return T;
}

double strainEnergyDensity(const Mat3& F, const LameConstants& lame) {
  // psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2 with tr C - 3 = 2 tr H + |H|^2, so that
  // the first-order terms mu (tr H - ln J) cancel in exact arithmetic, not after rounding 3.
  const Mat3 H = F - Mat3::Identity();
  const double lnJ = logJacobian(H);
  return lame.mu * ((H.trace() - lnJ) + 0.5 * H.squaredNorm()) + 0.5 * lame.lambda * lnJ * lnJ;
}

} // namespace armour::deformable
