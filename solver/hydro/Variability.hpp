// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Variability.hpp
/// The 3D pressure variability of seed 000 (section 2.2) added back to the y-averaged storm
/// pressure: "distributed with random sampling to populate unique p-t histories", "determined
/// uniquely for each different unit" and drawn from the Weibull fit of the class (crest/trough,
/// above/below the mean) the wave is in.
///
/// On each patch k of unit b, in the half wave h at the unit's centroid x_c, every wet element
/// gets the pressure deviation
///
///   dp = s d P_n |eta(x_c, t)| / a_n,
///
/// where (s, d) is drawn once per (seed, b, k, h): crest = eta > 0 in half wave h; s = +1 with
/// probability probabilityAbove[crest ? 0 : 1], else -1; d = lambda (-ln(1 - U))^(1/k_w) with the
/// Weibull (k_w, lambda) of the class (crest|trough, above|below) so chosen (inverse transform
/// sampling); P_n and a_n are the file's normalisation pressure and elevation.
///
/// The uniform variates U come from a counter-based generator: splitmix64 (Steele, Lea and Flood
/// 2014) chained over the key (seed, body, patch, half wave, stream). No generator state is kept,
/// so a draw depends only on its key: the same for any thread count, update order or restart.
/// Scaling by the local |eta| keeps the deviation continuous at the zero crossings, where the class
/// and the draw change.

#include "hydro/HydroSettings.hpp"
#include "storm/StormFile.hpp"
#include "storm/StormSampler.hpp"

#include <cstdint>

namespace armour::hydro {

/// splitmix64 finaliser: a bijective 64-bit mix (Steele, Lea and Flood 2014).
[[nodiscard]] std::uint64_t splitmix64(std::uint64_t x);

/// A uniform variate in [0, 1) from the key (53 random bits) (unit: -).
[[nodiscard]] double uniformDraw(std::uint64_t seed, std::uint64_t body, std::uint64_t patch, std::int64_t halfWave,
                                 std::uint64_t stream);

class VariabilityModel {
public:
  VariabilityModel() = default;
  /// Active when settings.enabled and model.present with a positive normalisation elevation.
  VariabilityModel(const storm::Variability& model, const VariabilitySettings& settings);

  [[nodiscard]] bool active() const { return active_; }
  /// The draw s d for (body, patch) in half wave `halfWave` of class crest / trough (unit: -).
  [[nodiscard]] double normalisedDeviation(std::uint64_t body, int patch, std::int64_t halfWave, bool crest) const;
  /// The pressure deviation s d P_n |eta| / a_n of (body, patch) at the wave phase `phase` of the
  /// unit's centroid (unit: Pa); 0 when inactive.
  [[nodiscard]] double pressureDeviation(std::uint64_t body, int patch, const storm::WavePhase& phase) const;

private:
  storm::Variability model_;
  std::uint64_t seed_ = 1;
  bool active_ = false;
};

} // namespace armour::hydro
