// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The armour-layer case of bench_solver: Core-Loc units on a static rock underlayer (seed 000's
// scene, simplified), timed over a window of simulated time and compared with Solidity_R.

#include "benchmarks/SolverBenchCase.hpp"

#include <cstdint>
#include <vector>

namespace armour::bench {

struct LayerOptions {
  int units = 242;
  int rocks = 3436;
  std::vector<int> threads{1, 2};
  double settle = 0.3;        ///< measurement starts this long after release (s)
  double seconds = 0.05;      ///< measured simulated time per thread count (s)
  double unitVolume = 5.0;    ///< m^3 (seed 000: 5 m^3 Core-Loc, Dn = 1.71 m)
  double rockVolume = 0.5;    ///< m^3 (underlayer W/10: Dn = 0.79 m)
  double width = 45.0;        ///< section width along the trunk (m), seed 000
  double slope = 4.0 / 3.0;   ///< cot(alpha): horizontal over vertical (-), seed 000 4H:3V
  double toe = 4.0;           ///< horizontal rock berm in front of the slope (m)
  double packing = 0.625;     ///< packing density N Dn^2 / A of the rows (-), seed 000 tight pack
  double friction = 0.6;
  double restitution = 0.1;
  bool sleep = false;         ///< a storm keeps every unit awake
  int rockShapes = 20;
  int tries = 8;              ///< orientations tried per unit, the lowest kept (-)
  int moves = 10;             ///< failed moves towards the slope in a row that end a unit's placement (-)
  double clearance = 0.002;   ///< gap left between units and rocks at release / Dn of the unit (-)
  double trace = 0.0;         ///< print progress every this much simulated time while settling (s); 0: off
  std::uint64_t seed = 1;
};

/// Build, settle and measure the armour layer. Throws InvalidCase when units leave the section,
/// go through the underlayer or do not touch, and SimulationError when the solver stops.
CaseResult runLayer(const LayerOptions& o);

} // namespace armour::bench
