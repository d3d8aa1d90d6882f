// SPDX-License-Identifier: GPL-3.0-or-later
#include "bridge/DeviationHistogram.hpp"

#include "bridge/VoxelGrid.hpp"
#include "bridge/WeibullMle.hpp"

#include <cmath>
#include <sstream>

namespace armour {
namespace bridge {

DeviationHistogram::DeviationHistogram() : data_(size(), 0.0) {}

void DeviationHistogram::add(bool crest, double deviation, double weight) {
  const double magnitude = std::fabs(deviation);
  if (!(magnitude >= minimum())) { // also NaN: the caller only passes finite values
    data_[static_cast<std::size_t>(kZeros + (crest ? 0 : 1))] += weight;
    return;
  }
  const bool above = deviation > 0.0;
  const int c = crest ? (above ? 0 : 1) : (above ? 2 : 3); // VariabilityClass order
  int b = static_cast<int>(std::floor((std::log10(magnitude) - std::log10(minimum())) * kBinsPerDecade));
  if (b >= kBins) {
    b = kBins - 1;
    data_[static_cast<std::size_t>(kOverflow)] += weight;
  }
  if (b < 0) b = 0;
  data_[static_cast<std::size_t>(c * kBins + b)] += weight;
}

void DeviationHistogram::merge(const DeviationHistogram& other) {
  for (std::size_t i = 0; i < data_.size(); ++i) data_[i] += other.data_[i];
}

double DeviationHistogram::classCount(int c) const {
  double n = 0.0;
  for (int b = 0; b < kBins; ++b) n += binCount(c, b);
  return n;
}

double DeviationHistogram::binCentre(int b) {
  return minimum() * std::pow(10.0, (b + 0.5) / kBinsPerDecade);
}

storm::Variability DeviationHistogram::fit(double normalisationPressure, double normalisationElevation,
                                           const std::string& source) const {
  if (!(normalisationPressure > 0.0) || !std::isfinite(normalisationPressure)) {
    std::ostringstream m;
    m << "= " << normalisationPressure << " Pa: must be positive (rho g a_n)";
    failSetting("normalisationPressure", m.str());
  }
  if (!(normalisationElevation > 0.0) || !std::isfinite(normalisationElevation)) {
    std::ostringstream m;
    m << "= " << normalisationElevation << " m: must be positive (the wave amplitude a_n)";
    failSetting("normalisationElevation", m.str());
  }
  storm::Variability v;
  v.present = true;
  v.normalisationPressure = normalisationPressure;
  v.normalisationElevation = normalisationElevation;
  v.source = source;
  for (int c = 0; c < storm::kVariabilityClasses; ++c) {
    std::vector<double> values, weights;
    for (int b = 0; b < kBins; ++b) {
      const double n = binCount(c, b);
      if (n <= 0.0) continue;
      values.push_back(binCentre(b) / normalisationPressure);
      weights.push_back(n);
    }
    v.classes[static_cast<std::size_t>(c)] = fitWeibull(values, weights);
  }
  for (int phase = 0; phase < 2; ++phase) {
    const double above = classCount(2 * phase);
    const double below = classCount(2 * phase + 1);
    v.probabilityAbove[static_cast<std::size_t>(phase)] = above + below > 0.0 ? above / (above + below) : 0.5;
  }
  return v;
}

} // namespace bridge
} // namespace armour
