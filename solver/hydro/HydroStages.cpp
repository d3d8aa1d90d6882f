// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/HydroStages.hpp"

#include "core/Error.hpp"
#include "hydro/LoadedBodies.hpp"
#include "hydro/OscillatingForce.hpp"
#include "hydro/ShallowWaveForce.hpp"
#include "hydro/StormLoads.hpp"
#include "simulation/RunOutputs.hpp"
#include "storm/StormFile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <memory>

namespace armour::hydro {

namespace {

/// The storm file must hold every storm time the run asks for: [offset, offset + duration]. The
/// refusal gives the fix that fits the case: an offset before the first record, a duration longer
/// than the file, or a window that runs past the last record.
void checkStormCovers(const storm::StormReader& reader, const StormLoadSettings& s, double duration) {
  const std::vector<double>& t = reader.times();
  const double first = s.timeOffset;
  const double last = s.timeOffset + duration;
  // Half a microsecond of slack: times written as float sums of 0.05 s are not exact.
  constexpr double kSlack = 5e-7;
  if (first >= t.front() - kSlack && last <= t.back() + kSlack) return;
  const double span = t.back() - t.front();
  std::string fix;
  if (duration > span + kSlack) {
    fix = fmt::format("the file spans {:.6g} s, less than the duration: shorten the duration to at most {:.6g} s "
                      "(with the offset at the first record, {:.6g} s), or use a longer storm file",
                      span, span, t.front());
  } else if (first < t.front() - kSlack) {
    fix = fmt::format("the offset lies before the file's first record: set the offset to at least {:.6g} s (at most "
                      "{:.6g} s for this duration), or use a storm file that starts earlier",
                      t.front(), t.back() - duration);
  } else {
    fix = fmt::format("shorten the duration to at most {:.6g} s, set the offset to at most {:.6g} s, or use a longer "
                      "storm file",
                      t.back() - first, t.back() - duration);
  }
  core::failInput(reader.path(), "holds storm times {} .. {} s, but the run needs {} .. {} s (hydro.storm.time_offset, "
                                 "or --time-offset of armour storm, = {} s plus the duration {} s): {}",
                  t.front(), t.back(), first, last, s.timeOffset, duration, fix);
}

} // namespace

std::string validateStormRecords(const HydroSettings& settings, double duration) {
  if (!settings.enabled || settings.model != HydroModel::Storm) return {};
  const auto start = std::chrono::steady_clock::now();
  const storm::StormReader reader(settings.storm.file);
  const double from = settings.storm.timeOffset;
  // The loads of each update interval are computed at its start with a look-ahead to its end
  // (StormLoads::update), up to the last record.
  const double to = std::min(from + duration + settings.storm.updateInterval, reader.times().back());
  const std::size_t records = reader.validateRecords(from, to);
  return fmt::format("storm records: the {} records the run reads (storm times {} .. {} s) hold finite values "
                     "({:.2f} s to read)",
                     records, from, to,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

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
    // The step need not divide the record or the update interval: loads are evaluated at the
    // exact update times k x update_interval (interpolated between records), at the step that
    // first reaches each one, and blended (or held) between updates.
    const double dt = world.timeStep();
    const double recordInterval = (reader->times().back() - reader->times().front()) /
                                  static_cast<double>(reader->times().size() - 1);
    return fmt::format("hydro: storm {} ({} records, t = {} .. {} s, {} x {} voxels of {} x {} m, variability {}), "
                       "{} loaded bodies, update every {} s ({}; records every {:.6g} s on average, {}): loads are "
                       "evaluated at the exact update times, interpolated between records, so the step need not "
                       "divide either interval",
                       settings.storm.file, reader->times().size(), reader->times().front(), reader->times().back(),
                       h.nx(), h.nz(), h.dx(), h.dz(),
                       h.variability.present ? (settings.storm.variability.enabled ? "on" : "off (scene)")
                                             : "none in the file",
                       loaded, settings.storm.updateInterval,
                       simulation::stepsPerInterval(settings.storm.updateInterval, dt), recordInterval,
                       simulation::stepsPerInterval(recordInterval, dt));
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
