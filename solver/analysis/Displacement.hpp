// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Displacement.hpp
/// Movement of the units between two states of a pack (e.g. before and after a storm): per-unit
/// displacement and rotation, and the pack measures of the seeds. docs/theory.md, "Pack measures".
///
///  - delta_rms, seed 001 eq. 3: delta_rms^2 = (1/N) sum |c_i' - c_i|^2 over all N units, c_i and
///    c_i' the initial and final centroids (unit: m; seed 001 Table 1 quotes metres). Seed 001
///    section 3.1 also uses it with the vertical component dropped (its y): deltaRmsHorizontal.
///    deltaRmsOverDn = sqrt((1/N) sum (|d_i| / Dn_i)^2) is the same in nominal diameters (ours).
///  - D, D_z, D'_z, seed 003 eqs. 3-5, over the units of the middle half of the structure along
///    the trunk ("excluding the outside quarter portions ... to eliminate boundary effects, as the
///    units on the side can easily fall off", seed 003 section 2.3), selected by their initial
///    centroid:  D = (1/N) sum |x_i' - x_i|,  D_z = (1/N) sum (x'_iz - x_iz),  D'_z = (1/N) sum
///    |x'_iz - x_iz|. Seed 003's z is horizontal, into the slope (its slope is y = z tan theta):
///    our x. Its eq. 4 prints (x_iz - x'_iz) but it expects D_z < 0 for units sliding down the
///    slope, i.e. final minus initial; that is what is computed. The same signed and absolute
///    means are given along y (seed 003's D'_x along the shore), z, the up-slope direction s and
///    the slope normal n ("Euclidean measures are also possible").
///  - counts of units with |d_i| > k Dn_i for thresholds k (default 0.2, 0.5, 1: seed 000 section
///    3.2 reports units moved above 0.2-0.4 Dn and maxima of 0.6-1.4 Dn), mean and maximum
///    |d_i| / Dn_i, and the total displacement sum |d_i| (seed 000 Figs. 9 and 12, "total
///    displacement of all units"), over all units.
///  - per unit, the rotation angle of q' q^-1 in [0, pi] and a rocking flag (rotation above a
///    threshold): a unit can rock in place without its centroid moving far.

#include "analysis/Orientation.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <numbers>
#include <vector>

namespace armour::analysis {

/// Parameters of the displacement measures.
struct DisplacementSettings {
  /// Thresholds for the counts of moved units (unit: Dn). Each must be finite and >= 0.
  std::vector<double> thresholdsDn = {0.2, 0.5, 1.0};
  /// A unit that turned by more than this is flagged as rocking (unit: rad; 5 degrees).
  double rockingAngle = 5.0 * std::numbers::pi / 180.0;
  /// Trunk (y) extent of the structure whose middle is kept for D, D_z, D'_z (unit: m). NaN for
  /// either: the extent of the units' initial centroids.
  double trunkMin = std::numeric_limits<double>::quiet_NaN();
  double trunkMax = std::numeric_limits<double>::quiet_NaN(); ///< (unit: m)
  /// Fraction of the trunk extent kept, centred (unit: -): 0.5 is seed 003's middle half.
  double middleFraction = 0.5;
};

/// Movement of one unit.
struct UnitDisplacement {
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero(); ///< final - initial centroid (unit: m)
  Eigen::Vector3d local = Eigen::Vector3d::Zero();        ///< displacement along (s, t, n) (unit: m)
  double distance = 0.0;                                  ///< |displacement| (unit: m)
  double distanceDn = 0.0;                                ///< |displacement| / Dn (unit: -)
  double rotation = 0.0;                                  ///< angle of q' q^-1, [0, pi] (unit: rad)
  bool rocking = false;                                   ///< rotation > rockingAngle
  bool middle = false; ///< initial centroid in the middle part of the trunk (seed 003)
};

/// Signed and absolute mean of one displacement component (unit: m).
struct ComponentMeans {
  double mean = 0.0;         ///< (1/N) sum d_i . e (unit: m)
  double meanAbsolute = 0.0; ///< (1/N) sum |d_i . e| (unit: m)
};

/// Pack measures between two states.
struct PackDisplacement {
  std::vector<UnitDisplacement> units;
  std::size_t count = 0; ///< units (unit: -)

  double deltaRms = 0.0;           ///< seed 001 eq. 3 over all units (unit: m)
  double deltaRmsHorizontal = 0.0; ///< eq. 3 with the z component dropped (seed 001 sec. 3.1) (unit: m)
  double deltaRmsOverDn = 0.0;     ///< sqrt(mean (|d_i|/Dn_i)^2) (unit: -)
  double meanDn = 0.0;             ///< mean |d_i| / Dn_i (unit: -)
  double maxDn = 0.0;              ///< max |d_i| / Dn_i (unit: -)
  std::size_t maxUnit = 0;         ///< the unit with maxDn (unit: -)
  double total = 0.0;              ///< sum |d_i| (seed 000 Figs. 9, 12) (unit: m)
  std::vector<double> thresholdsDn;       ///< as given (unit: Dn)
  std::vector<std::size_t> movedCounts;   ///< units with |d_i| > threshold x Dn_i, per threshold
  std::size_t rockingCount = 0;           ///< units flagged rocking (unit: -)
  double meanRotation = 0.0;              ///< (unit: rad)
  double maxRotation = 0.0;               ///< (unit: rad)

  /// Seed 003 eqs. 3-5 over the middle units; NaN when no unit is in the middle.
  double middleTrunkMin = 0.0; ///< lower trunk bound of the middle part (unit: m)
  double middleTrunkMax = 0.0; ///< upper trunk bound of the middle part (unit: m)
  std::size_t middleCount = 0; ///< units in the middle (unit: -)
  double D = 0.0;              ///< eq. 3 (unit: m)
  ComponentMeans x;            ///< eqs. 4-5 (seed 003's z: horizontal, onshore) (unit: m)
  ComponentMeans y;            ///< along the trunk (seed 003's x) (unit: m)
  ComponentMeans z;            ///< vertical (unit: m)
  ComponentMeans s;            ///< up-slope (unit: m)
  ComponentMeans n;            ///< slope normal, outward (unit: m)
};

/// Rotation angle of `after` relative to `before` (both body -> world): the angle of
/// after * before^-1, in [0, pi] (q and -q are the same rotation). Quaternions are normalised.
[[nodiscard]] double rotationAngle(const Eigen::Quaterniond& before, const Eigen::Quaterniond& after);

/// All the measures. `dn` holds each unit's nominal diameter (m), or a single value for all.
/// The frame gives the s and n components. Throws core::InputError for mismatched sizes, an empty
/// pack, a non-finite position or quaternion or a non-positive Dn (naming the unit index), bad
/// thresholds, middleFraction outside (0, 1], or trunkMin >= trunkMax.
[[nodiscard]] PackDisplacement measureDisplacement(const std::vector<Eigen::Vector3d>& positionsBefore,
                                                   const std::vector<Eigen::Vector3d>& positionsAfter,
                                                   const std::vector<Eigen::Quaterniond>& orientationsBefore,
                                                   const std::vector<Eigen::Quaterniond>& orientationsAfter,
                                                   const std::vector<double>& dn, const SlopeFrame& frame,
                                                   const DisplacementSettings& settings = {});

} // namespace armour::analysis
