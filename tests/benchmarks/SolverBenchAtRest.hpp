// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// bench_solver at-rest: do small piles on a floor come to rest? N units of 1 m^3 dropped on a plane
// in random attitudes, in K scenes, with sleeping off; after the settle, the largest kinetic
// energy of any unit and its largest move over a window. A resting pile has round-off energy; a
// unit rocking in a limit cycle keeps tens of joules (issue 22; docs/benchmarks.md, "Kept points
// carry their samples' force").

#include <cstdint>
#include <string>

namespace armour::bench {

struct AtRestOptions {
  std::string shape = "dolos"; ///< any shape of the library (geometry::makeShape)
  int units = 3;               ///< per scene (unit: -)
  int scenes = 8;              ///< unit: -
  double settle = 30.0;        ///< simulated time before the window (unit: s)
  double window = 10.0;        ///< unit: s
  std::uint64_t seed = 100;    ///< scene k uses seed + k
  double friction = 0.75;      ///< unit: -
  double restitution = 0.3;    ///< unit: -
};

/// Run the scenes and print a markdown table; returns the number of scenes whose largest kinetic
/// energy in the window is above 1 mJ.
int runAtRest(const AtRestOptions& o);

} // namespace armour::bench
