// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StressHistory.hpp
/// Time series of a deformable unit's extreme stresses (issue 26 outputs): at each sample the
/// largest principal tension sigma_1 (tension positive, seed 002), the largest differential
/// stress sigma_1 - sigma_3 and the largest von Mises stress over the elements, each with the
/// element and its current centroid; and the extremes over the whole record with their times.
/// Written as CSV (atomically) for plots and for comparing with a tensile strength.

#include "deformable/DeformableBody.hpp"

#include <filesystem>
#include <vector>

namespace armour::deformable {

/// One extreme value and where it occurs.
struct StressPeak {
  double value = 0.0;            ///< (unit: Pa)
  std::size_t element = 0;       ///< element index
  Vec3 location = Vec3::Zero();  ///< current centroid of the element (unit: m)
  double time = 0.0;             ///< (unit: s)
};

struct StressSample {
  StressPeak tension;      ///< largest sigma_1
  StressPeak differential; ///< largest sigma_1 - sigma_3
  StressPeak vonMises;     ///< largest von Mises stress
};

/// The extremes of `body`'s element stresses now. The first element wins a tie.
[[nodiscard]] StressSample sampleStressPeaks(const DeformableBody& body);

class StressHistory {
public:
  /// Record the body's extremes at its current time.
  void record(const DeformableBody& body);
  /// Add a sample (its times in the peaks); the extremes follow.
  void add(const StressSample& sample);
  /// Drop the samples after `time` (unit: s), the extremes with them: a restart continues from its
  /// checkpoint's time, and samples written after it are recorded again.
  void keepUpTo(double time);
  [[nodiscard]] const std::vector<StressSample>& samples() const { return samples_; }
  /// The extremes over every recorded sample (the earliest sample wins a tie); all zero if empty.
  [[nodiscard]] const StressSample& extremes() const { return extremes_; }
  /// CSV: time_s, then for tension, differential and von_mises: value_Pa, element, x_m, y_m, z_m.
  /// Throws core::InputError naming the path if it cannot be written.
  void writeCsv(const std::filesystem::path& path) const;
  /// Read a history writeCsv wrote (a restart continues it): the same samples to the last bit
  /// (the numbers are written in their shortest exact form). Throws core::InputError naming the
  /// file and line of a damaged row.
  [[nodiscard]] static StressHistory readCsv(const std::filesystem::path& path);

private:
  std::vector<StressSample> samples_;
  StressSample extremes_;
};

} // namespace armour::deformable
