// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/Displacement.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>

namespace armour::analysis {

namespace {

constexpr const char* kWhere = "displacement";

void requireUnitQuaternion(const Eigen::Quaterniond& q, std::size_t unit, const char* which) {
  const double n = q.norm();
  if (!std::isfinite(n) || n == 0.0) {
    core::failInput(kWhere, "unit {}: {} orientation (w {}, x {}, y {}, z {}) is zero or not finite", unit, which,
                    q.w(), q.x(), q.y(), q.z());
  }
}

/// Accumulates the signed and absolute means of one component.
struct ComponentSum {
  double sum = 0.0;
  double sumAbs = 0.0;
  void add(double v) {
    sum += v;
    sumAbs += std::abs(v);
  }
  [[nodiscard]] ComponentMeans mean(std::size_t count) const {
    const double c = static_cast<double>(count);
    return {sum / c, sumAbs / c};
  }
};

} // namespace

double rotationAngle(const Eigen::Quaterniond& before, const Eigen::Quaterniond& after) {
  const Eigen::Quaterniond rel = after.normalized() * before.normalized().conjugate();
  // 2 atan2(|v|, |w|) is accurate at every angle (acos(w) loses half the digits near 0), and |w|
  // picks the shorter of q and -q, so the angle is in [0, pi].
  return 2.0 * std::atan2(rel.vec().norm(), std::abs(rel.w()));
}

PackDisplacement measureDisplacement(const std::vector<Eigen::Vector3d>& positionsBefore,
                                     const std::vector<Eigen::Vector3d>& positionsAfter,
                                     const std::vector<Eigen::Quaterniond>& orientationsBefore,
                                     const std::vector<Eigen::Quaterniond>& orientationsAfter,
                                     const std::vector<double>& dn, const SlopeFrame& frame,
                                     const DisplacementSettings& settings) {
  const std::size_t count = positionsBefore.size();
  if (count == 0) {
    core::failInput(kWhere, "no units given: the displacement of an empty pack is undefined");
  }
  if (positionsAfter.size() != count || orientationsBefore.size() != count || orientationsAfter.size() != count ||
      (dn.size() != count && dn.size() != 1)) {
    core::failInput(kWhere, "sizes differ: {} initial positions, {} final positions, {} initial orientations, {} "
                            "final orientations, {} Dn values (give one Dn for all units or one per unit); the two "
                            "states must list the same units in the same order",
                    count, positionsAfter.size(), orientationsBefore.size(), orientationsAfter.size(), dn.size());
  }
  for (const double k : settings.thresholdsDn) {
    if (!std::isfinite(k) || k < 0.0) {
      core::failInput(kWhere, "threshold {} Dn: thresholds must be finite and non-negative", k);
    }
  }
  if (!std::isfinite(settings.rockingAngle) || settings.rockingAngle < 0.0) {
    core::failInput(kWhere, "rocking angle {} rad: must be finite and non-negative", settings.rockingAngle);
  }
  if (!(settings.middleFraction > 0.0 && settings.middleFraction <= 1.0)) {
    core::failInput(kWhere, "middle fraction {}: must be in (0, 1] (0.5 keeps the middle half, seed 003)",
                    settings.middleFraction);
  }

  PackDisplacement r;
  r.count = count;
  r.units.resize(count);
  r.thresholdsDn = settings.thresholdsDn;
  r.movedCounts.assign(settings.thresholdsDn.size(), 0);

  double yMin = std::numeric_limits<double>::infinity();
  double yMax = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < count; ++i) {
    if (!positionsBefore[i].allFinite() || !positionsAfter[i].allFinite()) {
      const auto& p = positionsBefore[i].allFinite() ? positionsAfter[i] : positionsBefore[i];
      core::failInput(kWhere, "unit {}: {} position ({}, {}, {}) is not finite", i,
                      positionsBefore[i].allFinite() ? "final" : "initial", p.x(), p.y(), p.z());
    }
    requireUnitQuaternion(orientationsBefore[i], i, "initial");
    requireUnitQuaternion(orientationsAfter[i], i, "final");
    const double d = dn.size() == 1 ? dn.front() : dn[i];
    if (!std::isfinite(d) || d <= 0.0) {
      core::failInput(kWhere, "unit {}: Dn = {} m: the nominal diameter must be positive and finite", i, d);
    }
    yMin = std::min(yMin, positionsBefore[i].y());
    yMax = std::max(yMax, positionsBefore[i].y());
  }

  // The middle part of the trunk, from the structure's extent or the units'.
  const double lo = std::isnan(settings.trunkMin) ? yMin : settings.trunkMin;
  const double hi = std::isnan(settings.trunkMax) ? yMax : settings.trunkMax;
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) {
    core::failInput(kWhere, "trunk extent [{}, {}] m: give trunkMin <= trunkMax (finite), or NaN for the extent "
                            "of the units",
                    lo, hi);
  }
  const double margin = 0.5 * (1.0 - settings.middleFraction) * (hi - lo);
  r.middleTrunkMin = lo + margin;
  r.middleTrunkMax = hi - margin;

  double sumSq = 0.0;
  double sumSqHorizontal = 0.0;
  double sumSqDn = 0.0;
  double sumDn = 0.0;
  double sumRotation = 0.0;
  double sumMiddle = 0.0;
  ComponentSum cx;
  ComponentSum cy;
  ComponentSum cz;
  ComponentSum cs;
  ComponentSum cn;
  for (std::size_t i = 0; i < count; ++i) {
    UnitDisplacement& u = r.units[i];
    const double d = dn.size() == 1 ? dn.front() : dn[i];
    u.displacement = positionsAfter[i] - positionsBefore[i];
    u.local = {u.displacement.dot(frame.upSlope), u.displacement.dot(frame.trunk), u.displacement.dot(frame.normal)};
    u.distance = u.displacement.norm();
    u.distanceDn = u.distance / d;
    u.rotation = rotationAngle(orientationsBefore[i], orientationsAfter[i]);
    u.rocking = u.rotation > settings.rockingAngle;
    const double y = positionsBefore[i].y();
    u.middle = y >= r.middleTrunkMin && y <= r.middleTrunkMax;

    sumSq += u.distance * u.distance;
    sumSqHorizontal += u.displacement.head<2>().squaredNorm();
    sumSqDn += u.distanceDn * u.distanceDn;
    sumDn += u.distanceDn;
    if (u.distanceDn > r.maxDn || i == 0) {
      r.maxDn = u.distanceDn;
      r.maxUnit = i;
    }
    r.total += u.distance;
    for (std::size_t k = 0; k < settings.thresholdsDn.size(); ++k) {
      if (u.distanceDn > settings.thresholdsDn[k]) {
        ++r.movedCounts[k];
      }
    }
    r.rockingCount += u.rocking ? 1 : 0;
    sumRotation += u.rotation;
    r.maxRotation = std::max(r.maxRotation, u.rotation);

    if (u.middle) {
      ++r.middleCount;
      sumMiddle += u.distance;
      cx.add(u.displacement.x());
      cy.add(u.displacement.y());
      cz.add(u.displacement.z());
      cs.add(u.local.x());
      cn.add(u.local.z());
    }
  }
  const double c = static_cast<double>(count);
  r.deltaRms = std::sqrt(sumSq / c);
  r.deltaRmsHorizontal = std::sqrt(sumSqHorizontal / c);
  r.deltaRmsOverDn = std::sqrt(sumSqDn / c);
  r.meanDn = sumDn / c;
  r.meanRotation = sumRotation / c;
  if (r.middleCount > 0) {
    r.D = sumMiddle / static_cast<double>(r.middleCount);
    r.x = cx.mean(r.middleCount);
    r.y = cy.mean(r.middleCount);
    r.z = cz.mean(r.middleCount);
    r.s = cs.mean(r.middleCount);
    r.n = cn.mean(r.middleCount);
  } else {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.D = nan;
    r.x = r.y = r.z = r.s = r.n = ComponentMeans{nan, nan};
  }
  return r;
}

} // namespace armour::analysis
