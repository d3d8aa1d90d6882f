// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ContactReduction.hpp
/// Contact reduction for the constraint solver: the narrow phase lists every engaged surface
/// sample of a pair (hundreds on a face-to-face contact); an impulse solver needs a few points per
/// contact patch, placed to span the patch so that it can hold a moment (docs/theory.md, "The
/// constraint solver").
///
/// Patches: the points, deepest first, seed patches in turn; a point joins the first patch whose
/// seed normal is within `patchAngle` of its own. A concave unit touching another at two legs
/// gets two patches with their own normals; a flat face one.
/// Per patch, up to 4 points (after the manifold reduction of Bullet and Box2D; our version):
///  1. the deepest point;
///  2. the point farthest from it in the patch's tangent plane;
///  3. the point that makes the largest triangle with 1 and 2;
///  4. the point on the other side of the line 1-2 that makes the largest triangle with 1 and 2.
/// The patch normal is the area-weighted mean normal of its points (for the tangent plane). Each
/// kept point keeps its key, position and normal, and stands for the samples nearest to it in the
/// tangent plane: their tributary area (its own as the least) and, if any of them is inside, their
/// penalty force, as its depth: their mean overlap over that area. A kept point none of whose
/// samples is inside keeps its own gap (speculative). Ties go to the lower key, so the reduction
/// depends only on the points and the previous step's keys, never on the thread count. Points kept
/// in the previous step are preferred within a tolerance (ReductionSettings::keepDepth, keepFactor),
/// so that the warm start finds them again.

#include "contact/NarrowPhase.hpp"

#include <cstdint>
#include <vector>

namespace armour::contact {

struct ReductionSettings {
  double patchAngle = 0.5;     ///< largest angle between a point's normal and its patch seed's (unit: rad)
  int maxPatches = 4;          ///< patches per pair (1 to 8); points of further patches join the nearest normal (unit: -)
  /// Hysteresis: a point kept in the previous step wins against a deeper one unless that one is
  /// deeper by more than this (unit: m), and against a farther one unless that one is farther by
  /// more than `keepFactor` - 1 (relative). On a flat face every sample is about as deep, and
  /// without it the choice flips with every micro-rotation and the warm start is lost.
  double keepDepth = 0.0;
  double keepFactor = 1.1;     ///< unit: -
  /// A sample's area enters its kept point's spring with the weight clamp(1 + depth / rampDepth,
  /// 0, 1): all of it inside, none beyond this gap (unit: m); 0: inside only (a step).
  double rampDepth = 0.0;
};

/// A reduced contact patch: one normal, up to four points.
struct ContactPatchPoints {
  Vec3 normal = Vec3::UnitZ();       ///< unit, pushes body A (unit: -)
  int count = 0;                     ///< points used (unit: -)
  std::uint32_t keys[4] = {0, 0, 0, 0};
  Vec3 points[4];                    ///< world (unit: m)
  Vec3 normals[4];                   ///< each kept sample's own normal (unit: -)
  /// > 0 penetrating (unit: m): the mean overlap of the samples the point stands for, weighted by
  /// their areas (sum a_i max(d_i, 0) / areas[k]), or the point's own (negative) gap if none of
  /// them is inside.
  double depths[4] = {0, 0, 0, 0};
  /// Tributary area each kept point stands for (unit: m^2): its own, plus that of every
  /// sample of the patch nearer to it than to the other kept points, weighted from 1 inside the
  /// other body to 0 at the gap rampDepth (ReductionSettings), so that the points' springs
  /// E_p a_k / L add up to the penalty law's over the patch and change smoothly with the depths.
  double areas[4] = {0, 0, 0, 0};
};

/// Reduce a pair's points (NarrowPhase output) to patches, appended to `out`. `kept`: the keys the
/// pair's patches held in the previous step, sorted (hysteresis; may be empty).
void reduceContacts(const std::vector<ContactPoint>& points, const ReductionSettings& settings,
                    const std::vector<std::uint32_t>& kept, std::vector<ContactPatchPoints>& out);

} // namespace armour::contact
