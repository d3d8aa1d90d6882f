// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/Variability.hpp"

#include <cmath>

namespace armour::hydro {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double uniformDraw(std::uint64_t seed, std::uint64_t body, std::uint64_t patch, std::int64_t halfWave,
                   std::uint64_t stream) {
  // Chaining the mix over the fields (rather than adding them) keeps keys that differ in one field
  // by the same amount as another differs apart: (b + 1, k) and (b, k + 1) give unrelated draws.
  std::uint64_t h = splitmix64(seed);
  h = splitmix64(h ^ body);
  h = splitmix64(h ^ patch);
  h = splitmix64(h ^ static_cast<std::uint64_t>(halfWave));
  h = splitmix64(h ^ stream);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

VariabilityModel::VariabilityModel(const storm::Variability& model, const VariabilitySettings& settings)
    : model_(model), seed_(settings.seed),
      active_(settings.enabled && model.present && model.normalisationElevation > 0.0 &&
              model.normalisationPressure > 0.0) {}

double VariabilityModel::normalisedDeviation(std::uint64_t body, int patch, std::int64_t halfWave, bool crest) const {
  const auto k = static_cast<std::uint64_t>(patch);
  const bool above = uniformDraw(seed_, body, k, halfWave, 0) < model_.probabilityAbove[crest ? 0 : 1];
  using storm::VariabilityClass;
  const VariabilityClass c = crest ? (above ? VariabilityClass::CrestAbove : VariabilityClass::CrestBelow)
                                   : (above ? VariabilityClass::TroughAbove : VariabilityClass::TroughBelow);
  const storm::WeibullFit& fit = model_.classes[static_cast<int>(c)];
  if (!(fit.scale > 0.0) || !(fit.shape > 0.0)) {
    return 0.0;
  }
  // Inverse transform of F(d) = 1 - exp(-(d / lambda)^k): d = lambda (-ln(1 - U))^(1/k), U in [0, 1).
  const double u = uniformDraw(seed_, body, k, halfWave, 1);
  const double d = fit.scale * std::pow(-std::log1p(-u), 1.0 / fit.shape);
  return above ? d : -d;
}

double VariabilityModel::pressureDeviation(std::uint64_t body, int patch, const storm::WavePhase& phase) const {
  if (!active_) {
    return 0.0;
  }
  return normalisedDeviation(body, patch, phase.halfWave, phase.crest) * model_.normalisationPressure *
         std::abs(phase.elevation) / model_.normalisationElevation;
}

} // namespace armour::hydro
