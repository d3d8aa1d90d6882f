// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/HydroStages.hpp"

#include "core/Error.hpp"
#include "hydro/LoadedBodies.hpp"
#include "hydro/OscillatingForce.hpp"
#include "hydro/ShallowWaveForce.hpp"
#include "hydro/StormLoads.hpp"
#include "storm/StormFile.hpp"

#include <fmt/format.h>

#include <memory>

namespace armour::hydro {

namespace {

/// The storm file must hold every storm time the run asks for: [offset, offset + duration].
void checkStormCovers(const storm::StormReader& reader, const StormLoadSettings& s, double duration) {
  const std::vector<double>& t = reader.times();
  const double first = s.timeOffset;
  const double last = s.timeOffset + duration;
  // Half a microsecond of slack: times written as float sums of 0.05 s are not exact.
  constexpr double kSlack = 5e-7;
  if (first < t.front() - kSlack || last > t.back() + kSlack) {
    core::failInput(reader.path(), "holds storm times {} .. {} s, but the run needs {} .. {} s (hydro.storm.time_offset "
                                   "= {} s plus the duration {} s); shorten the duration to at most {} s, change the "
                                   "offset, or use a longer storm file",
                    t.front(), t.back(), first, last, s.timeOffset, duration, t.back() - s.timeOffset);
  }
}

} // namespace

std::string attachLoadStages(simulation::World& world, const HydroSettings& settings, double duration) {
  if (!settings.enabled) {
    return {};
  }
  switch (settings.model) {
  case HydroModel::Storm: {
    auto reader = std::make_shared<const storm::StormReader>(settings.storm.file);
    checkStormCovers(*reader, settings.storm, duration);
    const std::size_t loaded = selectLoadedBodies(world, settings.bodies, "hydro.bodies").size();
    auto stage = std::make_shared<StormLoads>(world, settings.storm, settings.bodies, reader);
    const storm::StormHeader& h = reader->header();
    world.addLoadStage(stage);
    return fmt::format("hydro: storm {} ({} records, t = {} .. {} s, {} x {} voxels of {} x {} m, variability {}), "
                       "{} loaded bodies, update every {} s",
                       settings.storm.file, reader->times().size(), reader->times().front(), reader->times().back(),
                       h.nx(), h.nz(), h.dx(), h.dz(),
                       h.variability.present ? (settings.storm.variability.enabled ? "on" : "off (scene)")
                                             : "none in the file",
                       loaded, settings.storm.updateInterval);
  }
  case HydroModel::Oscillating:
    world.addLoadStage(std::make_shared<OscillatingForce>(world, settings.oscillating, settings.bodies));
    return fmt::format("hydro: oscillating force (seed 001), F0 = {} N, T = {} s, bodies '{}'",
                       settings.oscillating.amplitude, settings.oscillating.period, settings.bodies);
  case HydroModel::ShallowWave:
    world.addLoadStage(std::make_shared<ShallowWaveForce>(world, settings.shallowWave, settings.bodies));
    return fmt::format("hydro: shallow-wave force (seed 003), F = {} N, omega = {} rad/s, bodies '{}'",
                       settings.shallowWave.amplitude, settings.shallowWave.angularFrequency, settings.bodies);
  }
  return {};
}

} // namespace armour::hydro
