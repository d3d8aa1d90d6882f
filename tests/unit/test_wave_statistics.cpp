// SPDX-License-Identifier: GPL-3.0-or-later
// Sea-state statistics of `armour report` (analysis/WaveStatistics): a regular wave of height H
// and period T sampled for 40 periods has Hs = Hmax = H (every wave alike, to the sampling of its
// crest and trough), Tm = T (interpolated zero crossings), Hm0 = 4 sqrt(H^2 / 8) = sqrt(2) H (the
// variance of a sine), and Tp = T within the periodogram's frequency resolution; uneven sampling
// gives the same; too short a record gives NaN, not a number.

#include "analysis/WaveStatistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

using armour::analysis::waveStatistics;

namespace {

void sine(double h, double period, double dt, bool jitter, std::vector<double>& t, std::vector<double>& eta) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  t.clear();
  eta.clear();
  for (double time = 0.0; time < 40.0 * period; time += dt * (1.0 + (jitter ? u(rng) : 0.0))) {
    t.push_back(time);
    eta.push_back(0.5 * h * std::sin(2.0 * std::numbers::pi * time / period + 0.3));
  }
}

} // namespace

TEST(WaveStatistics, RegularWaveHasItsHeightAndPeriod) {
  for (const bool jitter : {false, true}) {
    std::vector<double> t, eta;
    const double h = 1.5, period = 6.0, dt = 0.05;
    sine(h, period, dt, jitter, t, eta);
    const auto s = waveStatistics(t, eta);
    // Crest and trough fall between samples: the sampled height is short by at most
    // H (1 - cos(pi dt / T)) = 1e-3 H.
    EXPECT_NEAR(s.hs, h, 2e-3 * h) << "jitter " << jitter;
    EXPECT_NEAR(s.hmax, h, 2e-3 * h);
    EXPECT_NEAR(s.tm, period, 1e-3 * period);
    // 40 waves: the mean of a sine over a whole number of periods is 0, so Hm0 = sqrt(2) H to the
    // end effects of the record (1 %).
    EXPECT_NEAR(s.hm0, std::sqrt(2.0) * h, 0.01 * h);
    // Zero-padded to 2^m points: the peak bin is within one bin of 1 / T.
    const double df = 1.0 / (t.back() - t.front()) / 2.0;
    EXPECT_NEAR(1.0 / s.tp, 1.0 / period, df);
    EXPECT_GE(s.waves, 38u);
  }
}

TEST(WaveStatistics, ShortOrFlatRecordsGiveNoNumbers) {
  const auto tooShort = waveStatistics({0.0, 0.1, 0.2}, {0.0, 1.0, 0.0});
  EXPECT_TRUE(std::isnan(tooShort.hs));
  EXPECT_TRUE(std::isnan(tooShort.tp));
  const auto flat = waveStatistics({0.0, 1.0, 2.0, 3.0, 4.0}, {2.0, 2.0, 2.0, 2.0, 2.0});
  EXPECT_EQ(flat.waves, 0u);
  EXPECT_TRUE(std::isnan(flat.hs));
  EXPECT_EQ(flat.hm0, 0.0);
}
