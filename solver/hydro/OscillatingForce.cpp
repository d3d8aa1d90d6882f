// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/OscillatingForce.hpp"

#include "core/Error.hpp"
#include "hydro/Exposure.hpp"

#include <cmath>
#include <numbers>

namespace armour::hydro {

void OscillatingForce::validate(const OscillatingForceSettings& s) {
  core::requireFinite(s.amplitude, "hydro.oscillating.amplitude", "N");
  core::requireFinite(s.period, "hydro.oscillating.period", "s");
  core::requireFinite(s.waveNumber, "hydro.oscillating.wave_number", "1/m");
  core::requireFinite(s.zMin, "hydro.oscillating.z_min", "m");
  core::requireFinite(s.zSwl, "hydro.oscillating.z_swl", "m");
  core::requireFinite(s.zMax, "hydro.oscillating.z_max", "m");
  core::requireFinite(s.waves, "hydro.oscillating.waves", "");
  if (!(s.period > 0.0)) {
    core::failInput("hydro.oscillating.period", "{} s: the wave period must be positive", s.period);
  }
  if (s.waves < 0.0) {
    core::failInput("hydro.oscillating.waves", "{}: the number of waves must be >= 0 (0 = for the whole run)",
                    s.waves);
  }
  if (!(s.zMin < s.zSwl)) {
    core::failInput("hydro.oscillating.z_min", "{} m is not below z_swl = {} m: phi rises from z_min to the still "
                    "water line, so z_min < z_swl < z_max is needed", s.zMin, s.zSwl);
  }
  if (!(s.zSwl < s.zMax)) {
    core::failInput("hydro.oscillating.z_max", "{} m is not above z_swl = {} m: phi falls from the still water line "
                    "to z_max, so z_min < z_swl < z_max is needed", s.zMax, s.zSwl);
  }
}

OscillatingForce::OscillatingForce(const simulation::World& world, const OscillatingForceSettings& settings,
                                   const std::string& bodies)
    : settings_(settings) {
  validate(settings_);
  omega_ = 2.0 * std::numbers::pi / settings_.period;
  loaded_ = selectLoadedBodies(world, bodies, "hydro.bodies");
}

double OscillatingForce::phi(double z) const {
  const auto& s = settings_;
  // Seed 001 eq. 2 with H(0) = 1/2 is continuous, so the closed intervals below give the same values.
  if (z <= s.zMin || z >= s.zMax) {
    return 0.0;
  }
  if (z <= s.zSwl) {
    return (z - s.zMin) / (s.zSwl - s.zMin);
  }
  return (s.zMax - z) / (s.zMax - s.zSwl);
}

bool OscillatingForce::active(double time) const {
  return time >= 0.0 && (settings_.waves == 0.0 || time <= settings_.waves * settings_.period);
}

dynamics::Vec3 OscillatingForce::force(double x, double z, double time) const {
  if (!active(time)) {
    return dynamics::Vec3::Zero();
  }
  const double p = phi(z);
  if (p == 0.0) {
    return dynamics::Vec3::Zero();
  }
  const double phase = omega_ * time - settings_.waveNumber * x;
  return settings_.amplitude * p * dynamics::Vec3(std::cos(phase), 0.0, std::sin(phase));
}

void OscillatingForce::apply(const simulation::World& world, double time, std::span<dynamics::Vec3> force,
                             std::span<dynamics::Vec3> /*torque*/) {
  if (!active(time)) {
    return;
  }
  const auto& bodies = world.bodies();
  for (const dynamics::BodyId b : loaded_) {
    if (bodies.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    const dynamics::Vec3& x = bodies.position(b);
    force[b] += this->force(x.x(), x.z(), time);
  }
}

} // namespace armour::hydro
