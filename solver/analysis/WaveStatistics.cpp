// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/WaveStatistics.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>

namespace armour::analysis {

WaveStatistics waveStatistics(const std::vector<double>& t, const std::vector<double>& eta) {
  WaveStatistics s;
  const std::size_t n = t.size();
  if (n < 4) return s;
  double mean = 0.0;
  for (double e : eta) mean += e / static_cast<double>(n);
  double var = 0.0;
  for (double e : eta) var += (e - mean) * (e - mean) / static_cast<double>(n);
  s.hm0 = 4.0 * std::sqrt(var);
  // Zero down-crossings (about the mean), at the interpolated crossing times.
  std::vector<double> crossings;
  std::vector<std::size_t> crossingIndex;
  for (std::size_t k = 1; k < n; ++k) {
    const double a = eta[k - 1] - mean, b = eta[k] - mean;
    if (a > 0.0 && b <= 0.0) {
      crossings.push_back(t[k - 1] + (t[k] - t[k - 1]) * a / (a - b));
      crossingIndex.push_back(k);
    }
  }
  std::vector<double> heights;
  for (std::size_t w = 1; w < crossings.size(); ++w) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t k = crossingIndex[w - 1]; k < crossingIndex[w]; ++k) {
      lo = std::min(lo, eta[k]);
      hi = std::max(hi, eta[k]);
    }
    heights.push_back(hi - lo);
  }
  s.waves = heights.size();
  if (!heights.empty()) {
    s.tm = (crossings.back() - crossings.front()) / static_cast<double>(heights.size());
    std::sort(heights.begin(), heights.end(), std::greater<>());
    const std::size_t third = std::max<std::size_t>(1, heights.size() / 3);
    double sum = 0.0;
    for (std::size_t i = 0; i < third; ++i) sum += heights[i];
    s.hs = sum / static_cast<double>(third);
    s.hmax = heights.front();
  }
  // Periodogram on a uniform resampling (records may be unevenly spaced), zero-padded to 2^m.
  const double duration = t.back() - t.front();
  const double dt = duration / static_cast<double>(n - 1);
  std::size_t m = 1;
  while (m < n) m <<= 1;
  std::vector<double> a(m, 0.0);
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ti = t.front() + dt * static_cast<double>(i);
    while (j + 2 < n && t[j + 1] < ti) ++j;
    const double r = std::clamp((ti - t[j]) / (t[j + 1] - t[j]), 0.0, 1.0);
    a[i] = (1.0 - r) * eta[j] + r * eta[j + 1] - mean;
  }
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, a);
  double best = 0.0;
  std::size_t peak = 0;
  for (std::size_t f = 1; f < m / 2; ++f)
    if (std::norm(spectrum[f]) > best) {
      best = std::norm(spectrum[f]);
      peak = f;
    }
  if (peak > 0) s.tp = static_cast<double>(m) * dt / static_cast<double>(peak);
  return s;
}

} // namespace armour::analysis
