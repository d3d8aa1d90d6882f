// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file UnitLoads.hpp
/// The contact loads on chosen units during a rigid run, for `armour stress` (issue 26): the
/// scene's `output.unit_loads` names the units, and every `unit_loads_interval` one record per
/// unit goes to `<output>/unit_loads/` (io/UnitLoadsFile.hpp).
///
/// Peak hold: a record holds the step of the window (previous record, this one] at which the
/// unit's contact force (the sum of its point force magnitudes) was largest, so that an impact of
/// a few milliseconds is caught whatever the interval. The first record (t = 0) is the initial
/// state. The loads are the World's point forces on the unit (World::tracedContacts), merged per
/// other body into clusters no wider than `cluster` x the unit's Dn (each the sum of its points'
/// forces at their normal-force-weighted centre), in the unit's body frame. The final record of a
/// run holds the window it ended in; its window_end is that window's scheduled end.
///
/// Sleeping: the World does not examine pairs of which no body is awake, and their forces are
/// those of the step they fell asleep in. The recorder keeps each unit's loads of the last step,
/// and for a sleeping unit carries over those from static geometry and from sleeping bodies.
///
/// Restart: the interval and cluster width, the held peaks, the carried loads and the file rows go
/// into the checkpoint as text (state(); hexadecimal doubles, bit for bit), so that a restarted run
/// writes the same files; a restart with another interval or width is refused, naming the key.

#include "io/UnitLoadsFile.hpp"
#include "simulation/World.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace armour::simulation {

struct UnitLoadsSettings {
  std::vector<BodyId> bodies;       ///< World bodies traced (dynamic)
  std::vector<std::int32_t> sceneBodies; ///< their scene indices (for units.csv)
  std::vector<std::string> names;   ///< World body names, indexed by BodyId (other bodies named in loads.csv)
  double interval = 0.02;           ///< between records (unit: s of simulated time)
  double cluster = 0.1;             ///< largest cluster width (unit: the unit's Dn)
};

class UnitLoadsRecorder {
public:
  /// Start tracing `settings.bodies` in `world` and open the files in `folder`/unit_loads; with a
  /// non-empty `resumeState` (state() of a checkpoint), continue as the run stood then.
  /// Throws core::InputError if resumeState is not ours or lists other units.
  UnitLoadsRecorder(World& world, UnitLoadsSettings settings, const std::filesystem::path& folder,
                    const std::string& resumeState = {});

  /// After every step (and once before the first of a new run; a resumed run's recorder saw the
  /// checkpoint's step before it was taken): hold the peaks, write the records due.
  void update(const World& world);
  /// Write the held records of the window in progress (the end of a run; a restart drops them).
  void finish();
  /// The recorder's state as text for a checkpoint.
  [[nodiscard]] std::string state() const;

  [[nodiscard]] std::size_t records() const { return writer_->rows().records; }

private:
  struct Held;
  /// The unit's loads now: fresh ones, and for a sleeper those carried over (see the file comment).
  void mergeLoads(const World& world);
  [[nodiscard]] io::UnitLoadRecord recordOf(const World& world, std::size_t unit) const;
  /// Restore state() text; `where` names the checkpoint in messages.
  void parseState(const std::string& text, const std::string& where);

  UnitLoadsSettings settings_;
  std::vector<double> dn_;                    ///< per unit (unit: m)
  std::unique_ptr<io::UnitLoadsWriter> writer_;
  long nextRecord_ = 0;                       ///< index of the next record time (time = index x interval)
  io::UnitLoadsRows scheduledRows_;           ///< rows written by update() (finish()'s not included)
  std::vector<std::vector<TracedContact>> current_; ///< per unit: its contacts at the last step
  std::vector<io::UnitLoadRecord> held_;      ///< per unit: the peak of the window in progress
  std::vector<std::uint8_t> holding_;         ///< per unit: held_ is set
  std::vector<std::uint8_t> wasAwake_;        ///< per World body: awake at the last update
  std::vector<std::int32_t> unitOfBody_;      ///< per World body: its unit, -1 for none
};

} // namespace armour::simulation
