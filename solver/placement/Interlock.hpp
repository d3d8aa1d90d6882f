// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Interlock.hpp
/// The cost of a lowered candidate under `orientation: {select: interlocked}` (issue 24, session
/// 28; docs/theory.md section 15, "Interlocked"; docs/placement.md, "Session 28"). A Core-Loc
/// layer is thinner than its unit is tall (k_t = 1.52 Dn against the unit's height C = 1.657 Dn)
/// only because its units' members enter the openings of the units below and the underlayer's
/// voids; the judge rewards that (samples of the candidate inside the convex hulls of the units
/// near it) besides a low top and centroid and contacts with the units below, and penalises a
/// candidate off the underlayer, stacked on another unit, or shifted far from its grid point.

#include "placement/Deposit.hpp"
#include "placement/PlacementSettings.hpp"

#include <cstddef>
#include <vector>

namespace armour::placement {

/// Where a lowered candidate stands against the layer, for `select: keyed` and `interlocked`.
struct LayerContact {
  double top = 0.0;       ///< highest point above the underlayer's top, along the slope normal (unit: m)
  bool onSupport = false; ///< touches a support (a body added before the units, or a static)
  int unitsTouched = 0;   ///< units placed before that it touches (unit: -)
};

/// The candidate's LayerContact: contacts within twice the clearance (m); deposit indices below
/// firstUnitBody are supports. `normal` and `baseOffset` as for InterlockJudge.
LayerContact layerContact(const Deposit& deposit, const Placed& u, std::size_t firstUnitBody, double clearance,
                          const Vec3& normal, double baseOffset);

/// What the judge measured of one candidate (lengths in Dn).
struct InterlockScore {
  double cost = 0.0;          ///< the total (unit: Dn)
  double top = 0.0;           ///< highest point above the underlayer's top, along the slope normal (unit: Dn)
  double centroid = 0.0;      ///< centroid above the underlayer's top (unit: Dn)
  int unitsTouched = 0;       ///< units placed before within twice the clearance (unit: -)
  bool onSupport = false;     ///< touches a support (a rock, the slope, the toe)
  bool stacked = false;       ///< no support touched and the centroid more than 1 Dn above the underlayer
  double envelopeShare = 0.0; ///< share of its surface samples inside the convex hull of a unit near it (unit: -)
};

/// Judges candidates of one unit shape against a deposit. Deposit indices below firstUnitBody are
/// supports (the bodies added before the units: rocks), the rest units placed before.
class InterlockJudge {
public:
  /// `normal` is the slope's outward normal in the deposit frame and `baseOffset` normal . x of
  /// the underlayer's top (the mean top of its surface stones); `clearance` and `dn` in m.
  InterlockJudge(const Deposit& deposit, const simulation::ShapeModel& unit, std::size_t firstUnitBody,
                 double clearance, double dn, const OrientationSettings& settings, const Vec3& normal,
                 double baseOffset);

  /// The score of u where it lies; `gridPoint` is its grid point in the deposit frame (the shift
  /// is measured in the plane normal to the lowering direction, z).
  [[nodiscard]] InterlockScore score(const Placed& u, const Vec3& gridPoint) const;

private:
  /// Share of u's surface samples inside the convex hull of a unit of the judged shape near it.
  [[nodiscard]] double envelopeShare(const Placed& u) const;

  const Deposit& deposit_;
  const simulation::ShapeModel& unit_;
  std::size_t firstUnitBody_;
  double clearance_, dn_;
  const OrientationSettings& s_;
  Vec3 normal_;
  double baseOffset_;
  std::vector<Vec3> hullNormals_; ///< the unit's convex hull in its body frame, unscaled
  std::vector<double> hullOffsets_;
};

} // namespace armour::placement
