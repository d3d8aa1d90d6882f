// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeviationHistogram.hpp
/// The deviation statistics behind the four Weibull fits of seed 000 (section 2.2), accumulated
/// without per-face time series: for each class (crest/trough x above/below the voxel mean) the
/// number of face deviations |p_face - p_voxel_mean| in logarithmic bins of 200 per decade from
/// 1e-6 Pa to 1e7 Pa, plus the number of zero deviations per phase (no sign, no logarithm).
///
/// Why a histogram: a 65 s regular-wave run of seed 000 has ~1e9 face deviations; the bins keep
/// 10 400 numbers, add across MPI ranks and runs by plain summation, and do not depend on the
/// normalisation P_n, which is only known at the end (bins are logarithmic, so dividing by P_n
/// shifts them). The bin width is 1.16 % (10^(1/200)); the fit treats the counts of a bin as
/// samples at its geometric centre, which changes ln d by at most 0.58 %: its effect on the fitted
/// shape and scale is far below the 3 % asked of the fit (test_weibull_mle checks it).
///
/// Plain C++11 (shared with the OpenFOAM function object).

#include "storm/StormFile.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace armour {
namespace bridge {

class DeviationHistogram {
public:
  static const int kBinsPerDecade = 200;
  static const int kDecades = 13;
  static const int kBins = kBinsPerDecade * kDecades;
  /// Lower edge of the first bin (unit: Pa); smaller deviations count as zero (float round-off of
  /// pressures of 1e5 Pa is ~1e-2 Pa, so 1e-6 Pa is no deviation at all).
  static double minimum() { return 1e-6; }
  /// Upper edge of the last bin (unit: Pa); larger deviations go to the last bin.
  static double maximum() { return 1e7; }

  DeviationHistogram();

  /// Add a deviation (unit: Pa, the signed p_face - p_mean) of a face in a crest (eta > 0) or trough.
  void add(bool crest, double deviation, double weight = 1.0);
  /// Add another histogram (MPI reduction, several runs).
  void merge(const DeviationHistogram& other);

  /// Count in class c (VariabilityClass order), excluding zero deviations.
  double classCount(int c) const;
  /// Zero deviations in crests (true) or troughs (false).
  double zeroCount(bool crest) const { return data_[static_cast<std::size_t>(kZeros + (crest ? 0 : 1))]; }
  /// Deviations beyond maximum() (counted in the last bin).
  double overflowCount() const { return data_[static_cast<std::size_t>(kOverflow)]; }
  /// Geometric centre of bin b (unit: Pa).
  static double binCentre(int b);
  double binCount(int c, int b) const { return data_[static_cast<std::size_t>(c * kBins + b)]; }

  /// The four fits of d = deviation / normalisationPressure, probabilityAbove per phase
  /// (0.5 where a phase has no nonzero deviation) and the normalisation (both > 0).
  storm::Variability fit(double normalisationPressure, double normalisationElevation, const std::string& source) const;

  /// Flat storage for reductions: 4 x kBins class counts, 2 zero counts, 1 overflow count.
  std::vector<double>& data() { return data_; }
  const std::vector<double>& data() const { return data_; }
  static std::size_t size() { return static_cast<std::size_t>(4 * kBins + 3); }

private:
  static const int kZeros = 4 * kBins;
  static const int kOverflow = 4 * kBins + 2;
  std::vector<double> data_;
};

} // namespace bridge
} // namespace armour
