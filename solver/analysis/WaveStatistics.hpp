// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file WaveStatistics.hpp
/// Sea-state statistics of a surface elevation record eta(t) (the storm summary of `armour
/// report`): zero down-crossing analysis about the mean (Hs = H1/3, Hmax, Tm, the number of
/// waves) and the spectral Hm0 = 4 sqrt(m0) and peak period Tp of the periodogram (the record
/// resampled uniformly, zero-padded to a power of two; Eigen's FFT). docs/theory.md section 16.

#include <cstddef>
#include <limits>
#include <vector>

namespace armour::analysis {

struct WaveStatistics {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double hs = kNaN;      ///< H1/3 of the zero-down-crossing waves (unit: m)
  double hmax = kNaN;    ///< highest zero-down-crossing wave (unit: m)
  double hm0 = kNaN;     ///< 4 sqrt(m0) (unit: m)
  double tm = kNaN;      ///< mean zero-down-crossing period (unit: s)
  double tp = kNaN;      ///< peak period of the periodogram (unit: s)
  std::size_t waves = 0; ///< complete zero-down-crossing waves (unit: -)
};

/// Statistics of eta (m) at times t (s, increasing, possibly unevenly spaced); fewer than 4
/// samples give NaNs. Heights and periods are NaN when no complete wave is in the record.
WaveStatistics waveStatistics(const std::vector<double>& t, const std::vector<double>& eta);

} // namespace armour::analysis
