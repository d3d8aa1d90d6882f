// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ShallowWaveForce.hpp
/// The shallow-wave force of seed 003 (section 2.2, eq. 1-2) as a load stage. In this project's
/// axes (x onshore, z up; seed 003 has z onshore and y up), with s = x_c - toeX the horizontal
/// distance of a unit's centre of mass from the toe:
///
///   F(t, s) = F sin(w t + 2 w / (sqrt(g) tan th) (sqrt(d0 - s tan th) - sqrt(d0))),
///
/// the phase of a wave that left the toe at the shallow-water celerity c = sqrt(g d), d = d0 - s tan th
/// (the spatial term is -w times the travel time from the toe; it is zero at s = 0). Where
/// s tan th > d0 the unit is above the shore line, d < 0 has no celerity, and F = 0. The force acts
/// along e_x and only where it pushes an exposed surface: F(t, s) > 0 (onshore) only on units exposed
/// to rays cast from the sea side along -n, F(t, s) < 0 only on units exposed from behind (rays along
/// +n), n = (-sin th, 0, cos th) the slope normal (Exposure). On a unit it is
///
///   F(t, s) min(1, A / Dn^2) e_x   at the unit's mean hit point,   A = hits x spacing^2,
///
/// so a partly shadowed unit takes a share and the force carries a torque about the centre of mass.
/// docs/theory.md, "Analytic wave forces", has the derivation and the choices.
///
/// Exposure is recomputed every exposureInterval of simulated time (at once on the first call) and
/// held in between. The held mean hit point is kept in the body frame, so it moves with the unit
/// between updates instead of staying behind in the world.

#include "hydro/Exposure.hpp"
#include "hydro/HydroSettings.hpp"
#include "simulation/LoadStage.hpp"
#include "simulation/World.hpp"

#include <span>
#include <string>
#include <vector>

namespace armour::hydro {

class ShallowWaveForce final : public simulation::LoadStage {
public:
  /// g is |gravity| of the World. @param bodies "all" or a body-name prefix (HydroSettings::bodies).
  /// @throws core::InputError for invalid settings (naming the scene key, see validate()), a world
  /// without gravity, or a filter that selects no body.
  ShallowWaveForce(const simulation::World& world, const ShallowWaveForceSettings& settings,
                   const std::string& bodies = "all");

  /// Checks finite values, 0 < th < pi/2, d0 > 0, w > 0, spacing >= 0 and interval >= 0; errors
  /// name the scene keys hydro.shallow_wave.amplitude, .angular_frequency, .angle_deg, .toe_x,
  /// .depth_at_toe, .ray_spacing, .exposure_interval.
  static void validate(const ShallowWaveForceSettings& settings);

  [[nodiscard]] std::string name() const override { return "shallow_wave"; }
  void apply(const simulation::World& world, double time, std::span<dynamics::Vec3> force,
             std::span<dynamics::Vec3> torque) override;
  /// Held exposure and the time of the next update: 3 + 8 x (loaded bodies) numbers.
  [[nodiscard]] std::vector<double> saveState() const override;
  void restoreState(const std::vector<double>& state) override;

  /// Seed 003 eq. 2's phase at distance s from the toe and time t (unit: rad). @pre wet(s).
  [[nodiscard]] double phase(double s, double time) const;
  /// Water depth d0 - s tan th >= 0: below the shore line, where the phase is defined.
  [[nodiscard]] bool wet(double s) const;
  /// F(t, s): the signed onshore force before exposure scaling; 0 where !wet(s) (unit: N).
  [[nodiscard]] double forceMagnitude(double s, double time) const;
  /// (-sin th, 0, cos th): out of the slope, up and seaward (unit: -).
  [[nodiscard]] dynamics::Vec3 slopeNormal() const;
  /// The spacing in use: the setting, or Dn / 4 of the smallest loaded unit (unit: m).
  [[nodiscard]] double raySpacing() const { return spacing_; }
  [[nodiscard]] double gravity() const { return g_; }

  /// Exposure of one loaded body as last computed; points relative to the centre of mass, body frame.
  struct Held {
    std::int32_t seaHits = 0;               ///< rays from the sea side that hit it first (unit: -)
    dynamics::Vec3 seaPoint = dynamics::Vec3::Zero();  ///< their mean hit point (unit: m, body frame)
    std::int32_t backHits = 0;              ///< rays from behind (unit: -)
    dynamics::Vec3 backPoint = dynamics::Vec3::Zero(); ///< unit: m, body frame
  };
  [[nodiscard]] const std::vector<dynamics::BodyId>& loadedBodies() const { return loaded_; }
  /// held()[k] belongs to loadedBodies()[k]; empty before the first apply().
  [[nodiscard]] const std::vector<Held>& held() const { return held_; }
  /// Simulated time of the last exposure update (unit: s); negative before the first.
  [[nodiscard]] double lastExposureTime() const { return lastUpdate_; }
  /// Counters of the last update's two casts (sea side, behind).
  [[nodiscard]] const ExposureStatistics& seaStatistics() const { return seaStats_; }
  [[nodiscard]] const ExposureStatistics& backStatistics() const { return backStats_; }

private:
  void updateExposure(const simulation::World& world, double time);

  ShallowWaveForceSettings settings_;
  double g_ = 9.81;       ///< unit: m/s^2
  double tanTheta_ = 0.0; ///< unit: -
  double spacing_ = 0.0;  ///< unit: m
  std::vector<dynamics::BodyId> loaded_;
  std::vector<double> dn_; ///< nominal diameter of each loaded body (unit: m)
  Exposure exposure_;
  std::vector<Held> held_;
  bool haveExposure_ = false;
  double lastUpdate_ = -1.0;  ///< unit: s
  double nextUpdate_ = 0.0;   ///< unit: s
  ExposureStatistics seaStats_, backStats_;
};

} // namespace armour::hydro
