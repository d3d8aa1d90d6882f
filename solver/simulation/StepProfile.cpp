// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/StepProfile.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace armour::simulation {

const char* stageName(Stage s) {
  switch (s) {
  case Stage::Integrate: return "integrate";
  case Stage::Boxes: return "boxes";
  case Stage::BroadPhase: return "broad phase";
  case Stage::NarrowPhase: return "narrow phase";
  case Stage::Accumulate: return "accumulate";
  case Stage::Prepare: return "prepare";
  case Stage::Solve: return "solve";
  case Stage::Loads: return "loads";
  case Stage::Sleep: return "sleep";
  case Stage::Guards: return "guards";
  case Stage::Count: break;
  }
  return "?";
}

double StepProfile::total() const {
  double t = 0.0;
  for (double s : seconds_) t += s;
  return t;
}

std::string StepProfile::table(std::uint64_t steps) const {
  const double all = std::max(total(), 1e-300);
  const double perStep = steps > 0 ? 1e3 / static_cast<double>(steps) : 0.0;
  std::string out = fmt::format("{:<14} {:>10} {:>7} {:>12}\n", "stage", "wall (s)", "share", "ms per step");
  for (std::size_t k = 0; k < seconds_.size(); ++k) {
    if (seconds_[k] == 0.0) continue;
    out += fmt::format("{:<14} {:>10.3f} {:>6.1f}% {:>12.4f}\n", stageName(static_cast<Stage>(k)), seconds_[k],
                       100.0 * seconds_[k] / all, seconds_[k] * perStep);
  }
  out += fmt::format("{:<14} {:>10.3f} {:>6.1f}% {:>12.4f}\n", "total", total(), 100.0, total() * perStep);
  const double n = steps > 0 ? static_cast<double>(steps) : 1.0;
  out += fmt::format("per step: {:.0f} awake bodies, {:.0f} candidate pairs, {:.0f} contact points, {:.0f} full "
                     "sample searches, {:.0f} listed samples of which {:.0f} looked up\n",
                     counts_.awake / n, counts_.pairs / n, counts_.points / n, counts_.searches / n,
                     counts_.listed / n, counts_.lookups / n);
  return out;
}

} // namespace armour::simulation
