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
  void reset() { seconds_.fill(0.0); }
  /// A table, one stage per line: seconds, share of the total, milliseconds per step.
  [[nodiscard]] std::string table(std::uint64_t steps) const;

private:
  std::array<double, static_cast<std::size_t>(Stage::Count)> seconds_{};
};

} // namespace armour::simulation
