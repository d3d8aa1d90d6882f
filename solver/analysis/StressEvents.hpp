// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StressEvents.hpp
/// What `armour stress` reports per unit from its stress time series (docs/theory.md section 19,
/// "Stress in a stormed pack"): the largest stresses with their times, and the events that caused
/// the peaks. An event is a record at which the body stress (sigma1 away from the contacts) is a
/// local maximum of the series, at least `eventFraction` of the unit's largest, with at most
/// `maxEvents` kept (the largest). Its kind, from the unit's own records in the `lookBack` before:
///  - "impact": the contact force rose more than `impactRise` times above its lowest in the
///    look-back (a blow: a neighbour struck the unit, or the unit struck something while moving);
///  - "rocking": an impact while the unit itself turned faster than `rockingSpin` in the
///    look-back but its centre travelled less than `rockingTravel` (it rocked in place on its
///    contacts and struck down, rather than fell or slid into the blow);
///  - "sustained": no such rise: the pack's weight and the wave's slow push.
/// Every threshold is ours (docs/theory.md says why).

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace armour::analysis {

/// One record of one unit.
struct StressSample {
  double time = 0.0;             ///< (unit: s)
  double sigma1 = 0.0;           ///< largest principal stress of any element (unit: Pa)
  double sigma1Away = 0.0;       ///< the same away from the contacts (unit: Pa)
  double differential = 0.0;     ///< largest sigma1 - sigma3 (unit: Pa)
  double contactForce = 0.0;     ///< sum of the contact point forces' magnitudes (unit: N)
  double speed = 0.0;            ///< of the centre of mass (unit: m/s)
  double angularSpeed = 0.0;     ///< (unit: rad/s)
  Eigen::Vector3d position = Eigen::Vector3d::Zero(); ///< of the centre of mass, world (unit: m)
  std::string dominant;          ///< the other body of the largest contact load ("static", "" if none)
  double dominantForce = 0.0;    ///< its magnitude (unit: N)
};

struct StressEventSettings {
  double eventFraction = 0.5;    ///< of the unit's largest body stress (unit: -)
  std::size_t maxEvents = 5;     ///< per unit (unit: -)
  double lookBack = 0.5;         ///< (unit: s)
  double impactRise = 2.0;       ///< contact force over its look-back minimum (unit: -)
  double rockingSpin = 0.05;     ///< (unit: rad/s)
  double rockingTravel = 0.1;    ///< (unit: m; `armour stress` gives 0.1 Dn)
};

struct StressEvent {
  std::size_t sample = 0;        ///< index in the series
  std::string kind;              ///< "impact", "rocking" or "sustained"
};

struct UnitStressSummary {
  std::size_t maxSigma1 = 0;     ///< sample of the largest sigma1 (any element)
  std::size_t maxAway = 0;       ///< sample of the largest body stress
  std::size_t maxDifferential = 0;
  std::vector<StressEvent> events; ///< by decreasing body stress
};

/// @pre samples is not empty and in time order.
[[nodiscard]] UnitStressSummary summarizeUnitStress(const std::vector<StressSample>& samples,
                                                    const StressEventSettings& settings = {});

/// The kind of the peak at sample i (see the file comment).
[[nodiscard]] std::string eventKind(const std::vector<StressSample>& samples, std::size_t i,
                                    const StressEventSettings& settings = {});

} // namespace armour::analysis
