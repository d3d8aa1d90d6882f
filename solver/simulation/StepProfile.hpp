// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StepProfile.hpp
/// Wall time spent in each named stage of the time step (docs/architecture.md, "The time step"),
/// summed over a run: the run log ends with the table, and `armour run --profile` prints it. The
/// clock is read twice per stage per step (tens of nanoseconds), far below any stage's own cost.

#include <array>
#include <chrono>
#include <cstdint>
#include <string>

namespace armour::simulation {

/// The named stages of both solvers' steps. A stage a solver does not have stays at zero.
enum class Stage : std::uint8_t {
  Integrate,    ///< penalty: the two half kicks and the drift; constraint: velocities and positions per substep
  Boxes,        ///< world boxes of the awake bodies
  BroadPhase,   ///< candidate pairs
  NarrowPhase,  ///< contact points of every pair (penalty: with the contact law, fused)
  Accumulate,   ///< penalty: forces into bodies in pair order, guard rails, friction history
  Prepare,      ///< constraint: contact reduction, warm-start matching, effective masses
  Solve,        ///< constraint: warm start, solve and relax over the substeps, restitution
  Loads,        ///< external-load stages (storm replay: hydrodynamics)
  Sleep,        ///< rest timers, islands, waking
  Guards,       ///< non-finite state and energy guard rails
  Count
};

/// Name of a stage for tables and logs.
const char* stageName(Stage s);

class StepProfile {
public:
  using Clock = std::chrono::steady_clock;

  /// Add the time since `since` to stage s and return now (to chain stages).
  Clock::time_point add(Stage s, Clock::time_point since) {
    const Clock::time_point now = Clock::now();
    seconds_[static_cast<std::size_t>(s)] += std::chrono::duration<double>(now - since).count();
    return now;
  }
  [[nodiscard]] double seconds(Stage s) const { return seconds_[static_cast<std::size_t>(s)]; }
  [[nodiscard]] double total() const;
  /// What the narrow phase did in one step, summed over the run for the table's last line.
  struct Counts {
    double awake = 0.0;          ///< bodies integrated
    double pairs = 0.0;          ///< candidate pairs
    double points = 0.0;         ///< engaged sample points
    double searches = 0.0;       ///< body-pair directions searched in full
    double listed = 0.0;         ///< listed samples in the others (near-sample lists)
    double lookups = 0.0;        ///< of them, those looked up
  };
  void count(const Counts& step) {
    counts_.awake += step.awake;
    counts_.pairs += step.pairs;
    counts_.points += step.points;
    counts_.searches += step.searches;
    counts_.listed += step.listed;
    counts_.lookups += step.lookups;
  }
  void reset() {
    seconds_.fill(0.0);
    counts_ = {};
  }
  /// A table, one stage per line: seconds, share of the total, milliseconds per step; then the
  /// counts per step.
  [[nodiscard]] std::string table(std::uint64_t steps) const;

private:
  std::array<double, static_cast<std::size_t>(Stage::Count)> seconds_{};
  Counts counts_;
};

} // namespace armour::simulation
