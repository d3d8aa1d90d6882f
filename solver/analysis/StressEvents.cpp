// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/StressEvents.hpp"

#include <algorithm>
#include <stdexcept>

namespace armour::analysis {

std::string eventKind(const std::vector<StressSample>& samples, std::size_t i, const StressEventSettings& settings) {
  double lowest = samples[i].contactForce;
  double spin = samples[i].angularSpeed;
  double travel = 0.0;
  for (std::size_t k = i; k-- > 0 && samples[k].time >= samples[i].time - settings.lookBack;) {
    lowest = std::min(lowest, samples[k].contactForce);
    spin = std::max(spin, samples[k].angularSpeed);
    travel = std::max(travel, (samples[i].position - samples[k].position).norm());
  }
  if (!(samples[i].contactForce > settings.impactRise * lowest)) return "sustained";
  return spin > settings.rockingSpin && travel < settings.rockingTravel ? "rocking" : "impact";
}

UnitStressSummary summarizeUnitStress(const std::vector<StressSample>& samples, const StressEventSettings& settings) {
  if (samples.empty()) throw std::invalid_argument("summarizeUnitStress: no samples");
  UnitStressSummary out;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    if (samples[i].sigma1 > samples[out.maxSigma1].sigma1) out.maxSigma1 = i;
    if (samples[i].sigma1Away > samples[out.maxAway].sigma1Away) out.maxAway = i;
    if (samples[i].differential > samples[out.maxDifferential].differential) out.maxDifferential = i;
  }
  const double largest = samples[out.maxAway].sigma1Away;
  if (!(largest > 0.0)) return out;
  std::vector<std::size_t> peaks;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double s = samples[i].sigma1Away;
    // A local maximum; on a plateau (a unit at rest) its first sample.
    const bool left = i == 0 || s > samples[i - 1].sigma1Away;
    const bool right = i + 1 == samples.size() || s >= samples[i + 1].sigma1Away;
    if (left && right && s >= settings.eventFraction * largest) peaks.push_back(i);
  }
  std::stable_sort(peaks.begin(), peaks.end(),
                   [&](std::size_t a, std::size_t b) { return samples[a].sigma1Away > samples[b].sigma1Away; });
  if (peaks.size() > settings.maxEvents) peaks.resize(settings.maxEvents);
  for (std::size_t i : peaks) out.events.push_back({i, eventKind(samples, i, settings)});
  return out;
}

} // namespace armour::analysis
