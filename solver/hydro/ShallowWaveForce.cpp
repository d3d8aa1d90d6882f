// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/ShallowWaveForce.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace armour::hydro {

void ShallowWaveForce::validate(const ShallowWaveForceSettings& s) {
  core::requireFinite(s.amplitude, "hydro.shallow_wave.amplitude", "N");
  core::requireFinite(s.angularFrequency, "hydro.shallow_wave.angular_frequency", "rad/s");
  core::requireFinite(s.slopeAngle, "hydro.shallow_wave.angle_deg", "rad");
  core::requireFinite(s.toeX, "hydro.shallow_wave.toe_x", "m");
  core::requireFinite(s.depthAtToe, "hydro.shallow_wave.depth_at_toe", "m");
  core::requireFinite(s.raySpacing, "hydro.shallow_wave.ray_spacing", "m");
  core::requireFinite(s.exposureInterval, "hydro.shallow_wave.exposure_interval", "s");
  if (!(s.angularFrequency > 0.0)) {
    core::failInput("hydro.shallow_wave.angular_frequency", "{} rad/s: must be positive (seed 003: pi)",
                    s.angularFrequency);
  }
  if (!(s.slopeAngle > 0.0 && s.slopeAngle < 0.5 * std::numbers::pi)) {
    // The scene gives the slope as angle_deg, tan or cot (SceneReader); name the key it reads.
    core::failInput("hydro.shallow_wave.angle_deg", "{} deg: the slope must lie between 0 and 90 deg (a slope rising "
                    "onshore; 1:2 is 26.57 deg, or give tan: 0.5 or cot: 2)", s.slopeAngle * 180.0 / std::numbers::pi);
  }
  if (!(s.depthAtToe > 0.0)) {
    core::failInput("hydro.shallow_wave.depth_at_toe", "{} m: the water depth at the toe must be positive",
                    s.depthAtToe);
  }
  if (s.raySpacing < 0.0) {
    core::failInput("hydro.shallow_wave.ray_spacing", "{} m: must be positive, or 0 for Dn / 4 of the smallest unit",
                    s.raySpacing);
  }
  if (s.exposureInterval < 0.0) {
    core::failInput("hydro.shallow_wave.exposure_interval", "{} s: must be >= 0 (0 = every force evaluation)",
                    s.exposureInterval);
  }
}

ShallowWaveForce::ShallowWaveForce(const simulation::World& world, const ShallowWaveForceSettings& settings,
                                   const std::string& bodies)
    : settings_(settings) {
  validate(settings_);
  g_ = world.settings().gravity.norm();
  if (!(g_ > 0.0) || !std::isfinite(g_)) {
    core::failInput("hydro.shallow_wave", "gravity is {} m/s^2: the shallow-wave celerity sqrt(g d) needs gravity",
                    g_);
  }
  tanTheta_ = std::tan(settings_.slopeAngle);
  loaded_ = selectLoadedBodies(world, bodies, "hydro.bodies");
  dn_.reserve(loaded_.size());
  double smallest = std::numeric_limits<double>::infinity();
  for (const dynamics::BodyId b : loaded_) {
    const double dn = std::cbrt(world.shape(world.bodyShape(b)).unitMass.volume) * world.bodyScale(b);
    dn_.push_back(dn);
    smallest = std::min(smallest, dn);
  }
  spacing_ = settings_.raySpacing > 0.0 ? settings_.raySpacing : 0.25 * smallest;
}

dynamics::Vec3 ShallowWaveForce::slopeNormal() const {
  return {-std::sin(settings_.slopeAngle), 0.0, std::cos(settings_.slopeAngle)};
}

bool ShallowWaveForce::wet(double s) const { return settings_.depthAtToe - s * tanTheta_ >= 0.0; }

double ShallowWaveForce::phase(double s, double time) const {
  const double w = settings_.angularFrequency;
  const double d0 = settings_.depthAtToe;
  return w * time + 2.0 * w / (std::sqrt(g_) * tanTheta_) * (std::sqrt(d0 - s * tanTheta_) - std::sqrt(d0));
}

double ShallowWaveForce::forceMagnitude(double s, double time) const {
  if (!wet(s)) {
    return 0.0;
  }
  return settings_.amplitude * std::sin(phase(s, time));
}

void ShallowWaveForce::updateExposure(const simulation::World& world, double time) {
  ExposureQuery query;
  query.slopeNormal = slopeNormal();
  query.spacing = spacing_;
  query.side = ExposureSide::FromSea;
  const auto sea = exposure_.compute(world, loaded_, query, "hydro.shallow_wave.ray_spacing");
  seaStats_ = exposure_.lastStatistics();
  query.side = ExposureSide::FromBehind;
  const auto back = exposure_.compute(world, loaded_, query, "hydro.shallow_wave.ray_spacing");
  backStats_ = exposure_.lastStatistics();

  const auto& bodies = world.bodies();
  held_.assign(loaded_.size(), Held{});
  for (std::size_t k = 0; k < loaded_.size(); ++k) {
    const dynamics::BodyId b = loaded_[k];
    const dynamics::Quat toBody = bodies.orientation(b).conjugate();
    Held& h = held_[k];
    h.seaHits = sea[k].hits;
    h.backHits = back[k].hits;
    if (h.seaHits > 0) {
      h.seaPoint = toBody * (sea[k].meanPoint - bodies.position(b));
    }
    if (h.backHits > 0) {
      h.backPoint = toBody * (back[k].meanPoint - bodies.position(b));
    }
  }
  haveExposure_ = true;
  lastUpdate_ = time;
  nextUpdate_ = time + settings_.exposureInterval;
}

void ShallowWaveForce::apply(const simulation::World& world, double time, std::span<dynamics::Vec3> force,
                             std::span<dynamics::Vec3> torque) {
  if (!haveExposure_ || time >= nextUpdate_) {
    updateExposure(world, time);
  }
  const auto& bodies = world.bodies();
  const double cellArea = spacing_ * spacing_;
  for (std::size_t k = 0; k < loaded_.size(); ++k) {
    const dynamics::BodyId b = loaded_[k];
    if (bodies.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    const dynamics::Vec3& x = bodies.position(b);
    const double f = forceMagnitude(x.x() - settings_.toeX, time);
    // Only pushes: onshore on surfaces the sea side sees, seaward on surfaces seen from behind.
    const Held& h = held_[k];
    const std::int32_t hits = f > 0.0 ? h.seaHits : h.backHits;
    if (f == 0.0 || hits == 0) {
      continue;
    }
    const double share = std::min(1.0, hits * cellArea / (dn_[k] * dn_[k]));
    const dynamics::Vec3 load(f * share, 0.0, 0.0);
    const dynamics::Vec3 arm = bodies.orientation(b) * (f > 0.0 ? h.seaPoint : h.backPoint);
    force[b] += load;
    torque[b] += arm.cross(load);
  }
}

std::vector<double> ShallowWaveForce::saveState() const {
  std::vector<double> state;
  state.reserve(3 + 8 * held_.size());
  state.push_back(haveExposure_ ? 1.0 : 0.0);
  state.push_back(lastUpdate_);
  state.push_back(nextUpdate_);
  if (!haveExposure_) {
    return state;
  }
  for (const Held& h : held_) {
    state.push_back(h.seaHits);
    state.insert(state.end(), h.seaPoint.data(), h.seaPoint.data() + 3);
    state.push_back(h.backHits);
    state.insert(state.end(), h.backPoint.data(), h.backPoint.data() + 3);
  }
  return state;
}

void ShallowWaveForce::restoreState(const std::vector<double>& state) {
  const std::size_t expected = 3 + 8 * loaded_.size();
  const bool have = !state.empty() && state[0] != 0.0;
  if (state.size() < 3 || (have && state.size() != expected) || (!have && state.size() != 3)) {
    core::failInput("checkpoint, stage 'shallow_wave'", "{} numbers where this scene ({} loaded bodies) needs {}: "
                    "the checkpoint belongs to another scene; restart from the scene's own checkpoint",
                    state.size(), loaded_.size(), have ? expected : std::size_t{3});
  }
  haveExposure_ = have;
  lastUpdate_ = state[1];
  nextUpdate_ = state[2];
  held_.clear();
  if (!have) {
    return;
  }
  held_.resize(loaded_.size());
  for (std::size_t k = 0; k < loaded_.size(); ++k) {
    const double* p = state.data() + 3 + 8 * k;
    held_[k].seaHits = static_cast<std::int32_t>(p[0]);
    held_[k].seaPoint = dynamics::Vec3(p[1], p[2], p[3]);
    held_[k].backHits = static_cast<std::int32_t>(p[4]);
    held_[k].backPoint = dynamics::Vec3(p[5], p[6], p[7]);
  }
}

} // namespace armour::hydro
