// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The pile case of bench_solver: N cubes, rocks or Core-Locs deposited (or dropped) into a walled
// box, settled, and timed over a window of steps.

#include "benchmarks/SolverBenchCase.hpp"
#include "benchmarks/SolverBenchDeposit.hpp"

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

/// A pile scene as built, before any step: what bench_solver's pile case and bench_peers share.
struct PileScene {
  std::string name;          ///< e.g. "cube 256"
  MaterialId concrete = 0;
  ShapeSet shapes;
  double radius = 0.0;       ///< bounding radius of the largest instance (unit: m)
  double cell = 0.0;         ///< drop-grid pitch: 2 (radius + gap) (unit: m)
  int side = 0;              ///< units per row of the drop grid (-)
  double halfWidth = 0.0;    ///< walls at x, y = +-halfWidth (unit: m)
  std::vector<Deposit::Plane> box; ///< floor at z = 0, then the walls x0, x1, y0, y1
  double top = 0.0;          ///< highest centroid at release (unit: m)
  double meanZ = 0.0;        ///< mean centroid height at release (unit: m)
  double buildShapes = 0.0;  ///< wall time of the shapes (s)
  double placement = 0.0;    ///< wall time placing the units (s)
  double buildBodies = 0.0;  ///< wall time of the units and the walls, placement included (s)
  MemoryMark memShapes;      ///< after the shapes
};

/// Add the pile of `o` to an empty world: the concrete, the shapes, the units (dropped from the
/// grid or deposited, random orientations from o.seed) and the five walls, in that order. The
/// same options give the same scene for either contact solver.
PileScene buildPile(World& world, const PileOptions& o);

/// Build, settle and measure one pile. Throws InvalidCase when no valid pile forms (units out of
/// the box, no contacts) and SimulationError when the solver stops.
CaseResult runPile(const PileOptions& o);

} // namespace armour::bench
