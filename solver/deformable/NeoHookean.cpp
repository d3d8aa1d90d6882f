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

Mat3 kirchhoffStress(const Mat3& F, const LameConstants& lame) {
  const double J = F.determinant();
  Mat3 tau = lame.mu * (F * F.transpose() - Mat3::Identity());
  tau.diagonal().array() += lame.lambda * std::log(J);
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
  const double lnJ = std::log(F.determinant());
  return 0.5 * lame.mu * (F.squaredNorm() - 3.0) - lame.mu * lnJ + 0.5 * lame.lambda * lnJ * lnJ;
}

} // namespace armour::deformable
