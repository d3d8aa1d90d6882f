// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Measuring one bench_solver case: windows of steps timed from one captured state on each thread
// count, the bit-for-bit comparison of their end states, the contact census and motion at the
// measurement point, and the result a case hands to the tables (SolverBenchReport).

#include "benchmarks/BenchClock.hpp"
#include "benchmarks/SolverBenchReport.hpp"
#include "benchmarks/SolverBenchScene.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace armour::bench {

/// The case cannot be timed: its result is wrong.
class InvalidCase : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Counters of a run of steps.
struct Window {
  int threads = 0;
  std::uint64_t steps = 0;
  double wall = 0.0;       ///< s
  double cpu = 0.0;        ///< process CPU time, all threads (s)
  double simulated = 0.0;  ///< s
  double awakeSum = 0.0;   ///< sum over steps of awake dynamic bodies
  double pairSum = 0.0;    ///< sum over steps of candidate pairs (bodies, planes)
  double pointSum = 0.0;   ///< sum over steps of engaged contact points
  double listReuseSum = 0.0;  ///< sum over steps of body-pair directions served by near-sample lists
  double listSearchSum = 0.0; ///< sum over steps of body-pair directions searched in full for a list
  double listLookupSum = 0.0; ///< sum over steps of listed samples looked up (the rest skipped by value)
  double maxOverlap = 0.0; ///< m
  WorldState end;

  [[nodiscard]] double perStep(double sum) const { return steps > 0 ? sum / static_cast<double>(steps) : 0.0; }
  [[nodiscard]] double stepsPerSecond() const { return static_cast<double>(steps) / wall; }
  [[nodiscard]] double bodyStepsPerCoreSecond() const { return awakeSum / (wall * threads); }
  /// Core time (wall x threads) per engaged contact point per step (unit: s): flat across pile
  /// sizes if the cost is linear in the contacts, and across thread counts if it scales.
  [[nodiscard]] double corePerPoint() const { return pointSum > 0.0 ? wall * threads / pointSum : 0.0; }
  /// Core time per candidate pair per step (unit: s).
  [[nodiscard]] double corePerPair() const { return pairSum > 0.0 ? wall * threads / pairSum : 0.0; }
};

/// Run `steps` steps (or until `untilTime` when steps == 0) on `threads` threads. The World
/// throws SimulationError on a non-finite state or an overlap past the guard rail.
Window runWindow(World& world, int threads, std::uint64_t steps, double untilTime, bool capture);

/// First body whose state differs bit for bit, or -1.
long firstDifference(const WorldState& a, const WorldState& b);

/// Contacts in the current state: distinct touching pairs by kind, and per dynamic body.
struct ContactCensus {
  std::size_t unitUnit = 0;   ///< pairs of dynamic bodies
  std::size_t unitFixed = 0;  ///< dynamic body with a fixed body (rock underlayer)
  std::size_t unitStatic = 0; ///< dynamic body with a plane or static piece
  double pointsPerUnit = 0.0; ///< engaged points per dynamic body
  double pairsPerUnit = 0.0;  ///< touching pairs per dynamic body (each pair counts for both)
  double touchingFraction = 0.0; ///< dynamic bodies with at least one engaged point
};

/// The census of `state`, captured from `world`.
ContactCensus census(const World& world, const WorldState& state);

/// Speeds of the dynamic bodies (unit: m/s).
struct Motion {
  double mean = 0.0;
  double max = 0.0;
  double meanZ = 0.0; ///< mean centroid height (m)
  std::size_t awake = 0;
  std::size_t dynamic = 0;
};

Motion motion(const World& world);

/// Run to `until` on `threads` threads; with traceEvery > 0, print the progress on stderr every
/// traceEvery simulated seconds (how the contacts build up while the pile forms).
Window settleWorld(World& world, int threads, double until, double traceEvery);

struct CaseResult {
  std::string name;      ///< e.g. "cube 1000", "armour layer"
  std::size_t dynamic = 0;
  std::size_t fixed = 0;
  double dt = 0.0;
  double sampleListSlack = 0.0; ///< WorldSettings::sampleListSlackPerDn of the run
  double buildShapes = 0.0, buildBodies = 0.0; ///< wall (s), bodies including their placement
  double placement = 0.0; ///< wall spent placing the units (s)
  Window settle;
  double landing = 0.0; ///< estimated time the last unit reaches the pile (s)
  Motion atStart;
  ContactCensus contacts;
  std::vector<Window> windows;
  MemoryMark memBase, memShapes, memBodies, memRunning; ///< before shapes, after shapes, after bodies, after the settle
  bool deterministic = true;
  double load = 0.0;    ///< one-minute load average when the windows started
  std::string invalid;  ///< why the case could not be timed (empty: valid)
  std::string notes;
};

/// Run the measured window (`steps` steps, or `seconds` of simulated time when steps == 0) once per
/// thread count, each from the state the world is in now; a difference between the end states
/// marks the case not deterministic.
void measureWindows(World& world, CaseResult& r, std::uint64_t steps, double seconds, const std::vector<int>& threads);

} // namespace armour::bench
