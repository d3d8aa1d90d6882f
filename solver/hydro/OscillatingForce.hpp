// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file OscillatingForce.hpp
/// The oscillating disturbance of seed 001 (eq. 1-2) as a load stage: a force of tunable strength
/// that rotates in the x-z plane and is strongest at the still-water line,
///
///   F = F0 [e_x cos(w t - k x) + e_z sin(w t - k x)] phi(z),   0 <= t <= n T,   F = 0 otherwise,
///
/// w = 2 pi / T, phi rising linearly from 0 at zMin to 1 at zSwl and falling back to 0 at zMax.
/// Seed 001 has y up and z inland: its (z, y) are our (x, z) (docs/theory.md, "Analytic wave
/// forces").
///
/// Where it acts: on each loaded body's centre of mass, (x, z) of the centre of mass in the
/// formula, so it carries no torque. Seed 001 applies it at points of the units' upper and lower
/// surfaces found by ray casting normal to the slope; the settings of this model have no slope
/// (OscillatingForceSettings), and the model's purpose is a disturbance whose strength one
/// parameter sets (seed 001 itself calls better wave models easy to formulate), for which the
/// resultant matters and the point of application does not. ShallowWaveForce is the model with
/// exposure and torque.

#include "hydro/HydroSettings.hpp"
#include "simulation/LoadStage.hpp"
#include "simulation/World.hpp"

#include <span>
#include <string>
#include <vector>

namespace armour::hydro {

class OscillatingForce final : public simulation::LoadStage {
public:
  /// @param bodies "all" (every non-fixed body) or a body-name prefix (HydroSettings::bodies).
  /// @throws core::InputError for invalid settings (naming the scene key, see validate()) or a
  /// filter that selects no body.
  OscillatingForce(const simulation::World& world, const OscillatingForceSettings& settings,
                   const std::string& bodies = "all");

  /// Checks finite values, T > 0, n >= 0 and zMin < zSwl < zMax; errors name the scene keys
  /// hydro.oscillating.amplitude, .period, .wave_number, .z_min, .z_swl, .z_max, .waves.
  static void validate(const OscillatingForceSettings& settings);

  [[nodiscard]] std::string name() const override { return "oscillating"; }
  void apply(const simulation::World& world, double time, std::span<dynamics::Vec3> force,
             std::span<dynamics::Vec3> torque) override;

  /// Seed 001 eq. 2: 0 below zMin and above zMax, 1 at zSwl, linear in between (unit: -).
  [[nodiscard]] double phi(double z) const;
  /// Seed 001 eq. 1 at a centre of mass (x, z) and time t (unit: N, world).
  [[nodiscard]] dynamics::Vec3 force(double x, double z, double time) const;
  /// True while the force acts: 0 <= t <= n T, or t >= 0 when n = 0.
  [[nodiscard]] bool active(double time) const;

  [[nodiscard]] const std::vector<dynamics::BodyId>& loadedBodies() const { return loaded_; }
  [[nodiscard]] const OscillatingForceSettings& settings() const { return settings_; }

private:
  OscillatingForceSettings settings_;
  double omega_ = 0.0; ///< 2 pi / T (unit: rad/s)
  std::vector<dynamics::BodyId> loaded_;
};

} // namespace armour::hydro
