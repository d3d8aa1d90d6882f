// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Interpenetration.hpp
/// Bodies that start inside each other: the common volume of every pair of bodies (and of a body
/// and the static planes and convex pieces) in a World's current state, and the refusal of a state
/// in which two bodies share more than a small fraction of the smaller one's volume.
///
/// Why a volume and not the contact's deepest point: the contact pushes a body out along the
/// gradient of the other's level set at its surface samples. Two bodies at the same pose, or one
/// turned about the other's centroid, have their samples deep inside each other, where the pushes
/// from opposite sides cancel (or the gradient vanishes): the guard rails, which watch the depth
/// of engaged samples, see nothing and the bodies stay inside each other for the whole run.
///
/// Estimate (docs/theory.md, "Interpenetration at the start"): each shape carries a lattice of
/// points at spacing h = Dn / pointsPerDn over its bounds, each with a smoothed inside fraction
/// w = clamp(1/2 - phi / h, 0, 1) (phi its own level set; w is the share of a slab of thickness h
/// about the point that lies inside, exact for a plane). A point of body A in body B adds a share
/// of h^3 to the common volume: min(w_A, w_B) where it lies deep in either; near both surfaces
/// max(0, w_A + w_B - 1) for opposite normals (two faces overlapping by delta give delta / h per
/// point of the slab, so the sum is area x delta whatever the lattice's offset, and exactly zero
/// for faces that only touch), min(w_A, w_B) for equal normals (the same pose), blended by the
/// normals' cosine between. Both directions (A's lattice in B, B's in A) are averaged. Only
/// lattice points in the overlap of the two world boxes are visited.
///
/// Containment: body A's centroid lies inside B (phi_B < 0) while it lies inside A's own solid
/// (units whose centroid falls in a hollow, between their legs, can interlock around a neighbour
/// and are not counted as contained).

#include "simulation/World.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace armour::simulation {

struct InterpenetrationSettings {
  /// Refuse a state in which two bodies share more than this fraction of the smaller one's volume,
  /// or a body shares more than it of its own volume with static geometry (unit: -). Settled packs
  /// share about 1e-4; the release of a 1 % face overlap under the default penalty modulus would
  /// throw a 5 m^3 unit by about its own size (docs/theory.md gives both figures).
  double maxOverlapFraction = 0.01;
  /// Lattice points per nominal diameter of each shape (unit: -). 12 gives ~1700 points for a unit
  /// with V = Dn^3.
  double pointsPerDn = 12.0;
};

/// The common volume of a body and another body or a static item.
struct BodyOverlap {
  BodyId a = 0;              ///< the first body
  std::int64_t b = -1;       ///< the other body, or -1 for static geometry
  std::string nameA;         ///< body names (static geometry: the item's name)
  std::string nameB;
  double volume = 0.0;       ///< estimated common volume (unit: m^3)
  double fraction = 0.0;     ///< volume / the smaller body's volume (static: / A's volume) (unit: -)
  bool contained = false;    ///< a centroid of one body lies inside the other (see the file comment)
  bool samePose = false;     ///< same shape, scale, position (1e-9 Dn) and orientation: a duplicate
};

/// What measureInterpenetration found.
struct InterpenetrationReport {
  std::vector<BodyOverlap> overlaps; ///< every pair with a positive common volume, largest fraction first
  std::size_t pairsTested = 0;       ///< pairs whose boxes overlap (bodies and static items)
  std::size_t pointsTested = 0;      ///< lattice points looked up in the other level set
  double seconds = 0.0;              ///< wall time of the measurement (unit: s)
};

/// Measure every body-body pair whose world boxes overlap, and every body against the given
/// planes (World keeps its own private) and the World's convex pieces. Read only.
InterpenetrationReport measureInterpenetration(const World& world, const std::vector<StaticPlane>& planes = {},
                                               const InterpenetrationSettings& settings = {});

/// The overlaps a run must refuse: containment, or a fraction above settings.maxOverlapFraction.
std::vector<BodyOverlap> refusedOverlaps(const InterpenetrationReport& report,
                                         const InterpenetrationSettings& settings = {});

/// Throw core::InputError naming `where` (the scene file), the worst refused pair (both names,
/// the common volume as a share of the smaller body), how many others there are, and the fix.
/// Does nothing when no pair is refused.
void refuseInterpenetration(const InterpenetrationReport& report, const std::string& where,
                            const InterpenetrationSettings& settings = {});

/// One line for `armour check` and the run log: pairs tested, the largest share, the cost.
std::string describeInterpenetration(const InterpenetrationReport& report);

} // namespace armour::simulation
