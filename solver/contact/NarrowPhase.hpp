// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file NarrowPhase.hpp
/// The narrow phase of the level-set contact model, on its own: for a candidate pair it lists the
/// contact points, each with a position, a normal, a depth, a tributary area and a stable sample
/// key. Both contact solvers consume it (the penalty law, contact/ContactLaw, turns each point into
/// a force; the constraint solver, contact/ContactSolver, reduces the points to a few per patch and
/// solves impulses on them), and so does placement (Deposit's touch test). docs/theory.md,
/// "Level sets and surface samples" and "The constraint solver".
///
/// Geometry:
///  - body against body: each body's surface samples in the other's level set (both directions,
///    so both bodies' edges and corners are seen), each direction's points weighted by the other
///    body's share of the sample density (w_A = Dn_B^2 / (Dn_A^2 + Dn_B^2));
///  - body against static geometry: the body's samples in a set of half-spaces n_k . x <= d_k (a
///    plane is one, a convex piece or a height-field cell several), at the depth of the nearest face.
///
/// Depth convention: depth > 0 is a penetration. With a speculative margin m > 0 the samples
/// outside within m are listed too, with depth in (-m, 0]: a constraint solver uses them to stop
/// an approach before it penetrates. With m = 0 (the penalty law) only samples inside are listed,
/// and the arithmetic is exactly that of the level-set model before this module existed.
///
/// Keys: the sample index, with kReverseSampleBit set for the second body's samples in a body pair.
/// A key stays the same while the same sample stays engaged: it carries friction history and warm
/// starts from step to step.
///
/// Thread safety: the functions only read the shapes; they may run concurrently over pairs.

#include "contact/LevelSet.hpp"
#include "contact/SampleBuckets.hpp"
#include "contact/SurfaceSamples.hpp"

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace armour::contact {

using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Key bit of a sample of the second body of a pair (in the first body's level set).
constexpr std::uint32_t kReverseSampleBit = 0x80000000u;

/// What the narrow phase needs of a shape; shared by every body of the shape (unscaled, body frame).
struct ContactShape {
  const LevelSet* levelSet = nullptr;
  const SurfaceSamples* samples = nullptr;
  const SampleBuckets* buckets = nullptr;
  double radius = 0.0; ///< largest vertex distance from the centroid (unit: m)
};

/// Where a body is: position of its centroid, orientation body -> world, uniform scale.
struct ContactPose {
  Vec3 position = Vec3::Zero();          ///< unit: m
  Quat orientation = Quat::Identity();   ///< unit: -
  Mat3 rotation = Mat3::Identity();      ///< orientation as a matrix (callers fill both)
  double scale = 1.0;                    ///< unit: -
  double dn = 1.0;                       ///< nominal diameter of the scaled body (unit: m)
};

/// A contact point of a pair (A, B): A is the body pushed along `normal`.
struct ContactPoint {
  std::uint32_t key = 0;       ///< sample index | kReverseSampleBit for B's samples
  Vec3 point = Vec3::Zero();   ///< the sample's world position (unit: m)
  Vec3 normal = Vec3::UnitZ(); ///< unit normal from B into A (unit: -)
  double depth = 0.0;          ///< penetration (> 0) or speculative gap (<= 0) (unit: m)
  double area = 0.0;           ///< tributary area facing the other body, weighted (unit: m^2)
};

/// A static solid as half-spaces n_k . x <= d_k (world): views, no copies.
struct HalfSpaces {
  std::span<const Vec3> normals;   ///< unit outward normals
  std::span<const double> offsets; ///< d_k (unit: m)
  Box3 region;                     ///< where a body's surface can be inside the solid (world)
};

/// The samples of `a` inside (or within `margin` of) the half-spaces, appended to `out` in a fixed
/// order. Returns the deepest penetration of any sample inside, facing or not (unit: m).
double samplesInHalfSpaces(const ContactShape& a, const ContactPose& pa, const HalfSpaces& solid, double margin,
                           std::vector<ContactPoint>& out);

/// What the last full search of one direction of a body pair (the probe's samples in the target's
/// level set) found within its reach: while the pair has not moved far enough since, the samples
/// outside this list cannot come within the margin, and only the list is tested. Exact: the points
/// found, their order and their arithmetic are those of a full search (docs/theory.md, "Near-sample
/// lists").
struct NearSampleList {
  const SurfaceSamples* probe = nullptr; ///< the shapes the list was made for
  const LevelSet* target = nullptr;
  Mat3 rotation = Mat3::Zero();          ///< probe frame -> target frame at the search (unscaled, with sp/st)
  Vec3 translation = Vec3::Zero();       ///< (target frame, unscaled: m / st)
  double reach = -1.0;                   ///< margin + slack of the search (target frame, unscaled); < 0: none
  std::vector<std::uint32_t> samples;    ///< in the order a full search visits them
  /// Each listed sample's level-set value at the search, rounded down (target frame, unscaled): a
  /// sample whose value then lay above the margin by more than the motion since can have moved,
  /// is skipped without a look-up (the same bound that lets the list serve the call).
  std::vector<float> values;
  /// Each listed sample's value at its last look-up and where it was then (target frame, unscaled):
  /// a sample that has not moved from there by (value - margin) / Lipschitz is skipped too.
  std::vector<double> lastValues;
  std::vector<Vec3> lastPoints;
  std::uint32_t searches = 0;            ///< full searches made (counters: reset by the caller)
  std::uint32_t reuses = 0;              ///< calls served from the list
  std::uint32_t listed = 0;              ///< listed samples in those calls
  std::uint32_t lookups = 0;             ///< of them, those looked up (the rest skipped)
};

/// A body pair's two near-sample lists: A's samples in B, B's samples in A.
struct PairSampleCache {
  std::array<NearSampleList, 2> directions;
};

/// The samples of each body inside (or within `margin` of) the other, appended to `out` (A's samples
/// first, then B's). Returns the deepest penetration of any sample inside, facing or not (unit: m).
/// With a cache, a full search lists the samples within margin + `slack` (m) and later calls test
/// only those while the pair's relative motion since stays within what the slack covers; the result
/// is the same as without the cache, bit for bit.
double samplesInLevelSets(const ContactShape& a, const ContactPose& pa, const ContactShape& b, const ContactPose& pb,
                          double margin, std::vector<ContactPoint>& out, PairSampleCache* cache = nullptr,
                          double slack = 0.0);

/// True when a sample of `probe` lies within `clearance` (m) of `target`'s surface or inside it
/// (the placement's touch test; one direction). Poses in any common frame.
bool anySampleWithin(const ContactShape& probe, const ContactPose& pp, const ContactShape& target,
                     const ContactPose& pt, double clearance);

} // namespace armour::contact
