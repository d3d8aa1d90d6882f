// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The pile case of bench_solver: N cubes, rocks or Core-Locs deposited (or dropped) into a walled
// box, settled, and timed over a window of steps.

#include "benchmarks/SolverBenchCase.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace armour::bench {

struct PileOptions {
  std::string shape = "cube";
  std::string placement = "deposit"; ///< "deposit" (a loose pile built in place) or "drop" (a grid released from above)
  int count = 100;
  std::vector<int> threads{1, 2};
  /// Measurement starts this long after release (s); < 0: 0.1 s for a deposit (every unit has
  /// taken up contact, the pile is compacting), the top layer's free fall + 0.3 s for a drop.
  double settle = -1.0;
  std::uint64_t steps = 500;   ///< measured steps per thread count
  int layers = 4;              ///< drop-grid layers: footprint side = ceil(sqrt(N / layers)) units
  double dn = 1.0;             ///< nominal diameter V^(1/3) (m)
  double gap = 0.05;           ///< clearance between bounding spheres at release / Dn (-)
  double friction = 0.6;       ///< (-)
  double restitution = 0.1;    ///< (-)
  bool sleep = true;
  int rockShapes = 20;
  int tries = 4;               ///< deposit: candidate poses per unit, the lowest kept (-)
  int moves = 20;              ///< deposit: failed downhill moves in a row that end a unit's slide (-)
  /// Deposit: gap left between units at release / Dn (-). Each layer falls through it before the
  /// next one loads it, so the pile takes up its weight in about layers x sqrt(2 gap / g).
  double clearance = 0.002;
  double trace = 0.0;          ///< print progress every this much simulated time while settling (s); 0: off
  std::uint64_t seed = 1;
};

/// Build, settle and measure one pile. Throws InvalidCase when no valid pile forms (units out of
/// the box, no contacts) and SimulationError when the solver stops.
CaseResult runPile(const PileOptions& o);

} // namespace armour::bench
