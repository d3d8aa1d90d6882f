// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PackGeometry.hpp
/// Geometry of a placed pack: packing density, layer thickness and coefficient, porosity per
/// slope-parallel slab, and contact (coordination) numbers. docs/theory.md, "Pack measures".
///
///  - Packing density (seed 000 section 3: "packing density 0.603 / 0.625", the CHL/CLI measure):
///    phi = N Dn^2 / A, A the area of the slope face covered, measured in the slope plane; with
///    mixed sizes sum Dn_i^2 / A. Two ways to get A and N: a rectangular window of the slope plane
///    (s0 <= s < s1, t0 <= t < t1; N counts the units whose centroid projects into it), or the
///    convex hull of the projected centroids (N all units). The hull joins the outer units' centres,
///    so it misses about half a unit spacing all round: it overestimates phi of a small pack.
///  - Shore Protection Manual (1984, ch. 7) / Coastal Engineering Manual (2006, VI-5) relations:
///    layer thickness t = n k_D Dn (n layers, k_D the layer coefficient) and units per area
///    N / A = n k_D (1 - P) / Dn^2, i.e. phi = n k_D (1 - P), P the layer porosity.
///  - Layer thickness: the mean slope-normal height of the units' highest points above the plane
///    of the frame (which must be the underlayer plane here), over the units in a window.
///  - Porosity per slab: 1 - V_solid / V_slab in slabs n0 <= n < n1 parallel to the slope, V_solid
///    estimated by deterministic Halton sampling (bases 2, 3, 5) of an inside(point) test.
///  - Contacts: per unit, the number of distinct neighbours it touches (units and supports, e.g.
///    underlayer rocks, counted apart; seed 000 Fig. 2b, 2 to 10), the largest pair force (seed 000
///    Fig. 2a), and the pack's mean coordination number 2 N_pairs / N over unit-unit pairs.

#include "analysis/Orientation.hpp"
#include "geometry/TriangleMesh.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <vector>

namespace armour::analysis {

// ---- Packing density -------------------------------------------------------------------------

/// A rectangle of the slope plane in frame coordinates (relative to frame.origin, see
/// SlopeFrame::toLocal): s0 <= s < s1 up-slope, t0 <= t < t1 along the trunk (half-open, so
/// adjacent windows tile without counting a unit twice).
struct SlopeWindow {
  double s0 = 0.0; ///< (unit: m)
  double s1 = 0.0; ///< (unit: m)
  double t0 = 0.0; ///< (unit: m)
  double t1 = 0.0; ///< (unit: m)
  [[nodiscard]] double area() const { return (s1 - s0) * (t1 - t0); } ///< (unit: m^2)
  /// True when the point's projection on the slope plane falls in the window.
  [[nodiscard]] bool contains(const SlopeFrame& frame, const Eigen::Vector3d& point) const;
  /// The same for a point already in frame coordinates (s, t, n).
  [[nodiscard]] bool containsLocal(const Eigen::Vector3d& local) const {
    return local.x() >= s0 && local.x() < s1 && local.y() >= t0 && local.y() < t1;
  }
};

/// phi = count Dn^2 / area. Throws core::InputError for a non-positive Dn or area.
[[nodiscard]] double packingDensity(std::size_t count, double dn, double area);

struct PackingDensity {
  double phi = 0.0;                ///< sum Dn_i^2 / A (unit: -)
  double area = 0.0;               ///< A, in the slope plane (unit: m^2)
  std::size_t count = 0;           ///< units counted (unit: -)
  std::vector<std::size_t> units;  ///< their indices
};

/// Packing density of the units whose centroids project into the window. `dn`: one value per
/// unit or a single value for all (m). Throws core::InputError for an empty or inverted window,
/// mismatched sizes, or a non-finite position / non-positive Dn (naming the unit).
[[nodiscard]] PackingDensity packingDensityInWindow(const std::vector<Eigen::Vector3d>& positions,
                                                    const std::vector<double>& dn, const SlopeFrame& frame,
                                                    const SlopeWindow& window);

/// Packing density over the convex hull of all centroids projected on the slope plane. Throws
/// core::InputError when the hull has no area (fewer than 3 units, or all in a line).
[[nodiscard]] PackingDensity packingDensityHull(const std::vector<Eigen::Vector3d>& positions,
                                                const std::vector<double>& dn, const SlopeFrame& frame);

/// Area of the convex hull of 2D points (unit: m^2); 0 for fewer than 3 or collinear points.
[[nodiscard]] double convexHullArea(std::vector<Eigen::Vector2d> points);

/// Layer coefficient k_D = t / (n Dn) (SPM 1984 / CEM VI-5) (unit: -).
[[nodiscard]] double layerCoefficient(double thickness, int layers, double dn);
/// Layer porosity from the packing density: P = 1 - phi / (n k_D) (unit: -).
[[nodiscard]] double porosityFromPackingDensity(double phi, int layers, double layerCoefficient);

// ---- Layer thickness -------------------------------------------------------------------------

/// Lowest and highest slope-normal coordinate (n, relative to the frame's origin) of a unit's
/// surface: its mesh (body frame) placed at `position` with `orientation` (body -> world). (m)
[[nodiscard]] Eigen::Vector2d normalExtent(const geometry::TriangleMesh& bodyMesh, const Eigen::Vector3d& position,
                                           const Eigen::Quaterniond& orientation, const SlopeFrame& frame);

struct LayerThickness {
  double thickness = 0.0;        ///< mean top height above the frame plane (unit: m)
  double layerCoefficient = 0.0; ///< thickness / (layers mean Dn) (unit: -)
  std::size_t count = 0;         ///< units averaged (unit: -)
};

/// Layer thickness from each unit's top (the max of normalExtent), averaged over the units whose
/// centroids project into the window; `frame` must be the underlayer plane. For a multi-layer
/// pack pass the top layer's units only (the lower ones' tops are not the layer's top). Throws
/// core::InputError for mismatched sizes, no unit in the window, or layers < 1.
[[nodiscard]] LayerThickness layerThickness(const std::vector<Eigen::Vector3d>& positions,
                                            const std::vector<double>& tops, const std::vector<double>& dn,
                                            const SlopeFrame& frame, const SlopeWindow& window, int layers = 1);

// ---- Porosity --------------------------------------------------------------------------------

/// True when a world point is inside solid (any unit). Plug in level sets, meshes, analytic solids.
using InsideTest = std::function<bool(const Eigen::Vector3d&)>;

/// The radical inverse of `index` in `base` (van der Corput): a Halton coordinate in [0, 1).
[[nodiscard]] double halton(std::uint64_t index, unsigned base);

struct SlabPorosity {
  double n0 = 0.0;            ///< lower face, slope-normal coordinate (unit: m)
  double n1 = 0.0;            ///< upper face (unit: m)
  double volume = 0.0;        ///< slab volume, window area x (n1 - n0) (unit: m^3)
  std::size_t samples = 0;    ///< points tested (unit: -)
  std::size_t solid = 0;      ///< points inside solid (unit: -)
  double porosity = 0.0;      ///< 1 - solid / samples (unit: -)
  /// Binomial standard error sqrt(p (1 - p) / samples) of independent random points (unit: -); the
  /// Halton points' error is usually well below it, so it is a conservative bound.
  double standardError = 0.0;
};

/// Porosity of `slabs` equal slabs between n0 and n1 (slope-normal coordinates relative to the
/// frame's origin) over the window, `samplesPerSlab` Halton points each (deterministic: the same
/// inputs give the same numbers). Throws core::InputError for n1 <= n0, an empty window, no slabs
/// or no samples.
[[nodiscard]] std::vector<SlabPorosity> porosityProfile(const InsideTest& inside, const SlopeFrame& frame,
                                                        const SlopeWindow& window, double n0, double n1,
                                                        std::size_t slabs, std::size_t samplesPerSlab);

/// 1 - count V_unit / V_slab, for units wholly inside a slab (unit: -).
[[nodiscard]] double porosityFromCount(double count, double unitVolume, double slabVolume);

/// Generalised winding number of a closed, outward mesh about a point (Jacobson et al. 2013: the
/// sum of the triangles' signed solid angles / 4 pi, each by Van Oosterom and Strackee 1983): 1
/// inside, 0 outside, robust to small defects, undefined on the surface.
[[nodiscard]] double windingNumber(const geometry::TriangleMesh& mesh, const Eigen::Vector3d& point);
/// windingNumber > 1/2.
[[nodiscard]] bool insideMesh(const geometry::TriangleMesh& mesh, const Eigen::Vector3d& point);

/// An InsideTest for placed units: unit i is shapes[shapeOfUnit[i]] (body frame) at positions[i]
/// with orientations[i] (body -> world). Copies what it needs. Cost per query: one bounding-sphere
/// test per unit, and a winding number (all triangles) for the units whose sphere holds the point.
[[nodiscard]] InsideTest insideAnyUnit(const std::vector<geometry::TriangleMesh>& shapes,
                                       const std::vector<std::size_t>& shapeOfUnit,
                                       const std::vector<Eigen::Vector3d>& positions,
                                       const std::vector<Eigen::Quaterniond>& orientations);

// ---- Contacts --------------------------------------------------------------------------------

/// One touching pair of bodies (a contact point or a whole pair; entries of the same pair merge).
struct Contact {
  std::size_t bodyA = 0; ///< body index (unit: -)
  std::size_t bodyB = 0; ///< body index (unit: -)
  double force = 0.0;    ///< magnitude of the contact force (unit: N)
};

/// What a body is for the contact count: an armour unit, or a support (underlayer rock, floor,
/// toe, wall: counted apart, and not analysed itself).
enum class BodyRole { unit, support };

struct UnitContacts {
  std::size_t unitNeighbours = 0;    ///< distinct units touched (unit: -)
  std::size_t supportNeighbours = 0; ///< distinct supports touched (unit: -)
  std::size_t contactNumber = 0;     ///< the sum: seed 000's contact number (unit: -)
  double maxForce = 0.0;             ///< largest pair force on the unit (unit: N)
};

struct PackContacts {
  std::vector<UnitContacts> bodies;  ///< per body (supports: zeros)
  std::size_t unitCount = 0;         ///< (unit: -)
  std::size_t unitUnitPairs = 0;     ///< distinct unit-unit pairs (unit: -)
  std::size_t unitSupportPairs = 0;  ///< distinct unit-support pairs (unit: -)
  double coordinationNumber = 0.0;   ///< 2 unitUnitPairs / unitCount (unit: -)
  double meanContactNumber = 0.0;    ///< mean contactNumber over units (unit: -)
  std::size_t minContactNumber = 0;  ///< over units (unit: -)
  std::size_t maxContactNumber = 0;  ///< over units (unit: -)
  double maxForce = 0.0;             ///< largest pair force touching a unit (unit: N)
};

/// Contact numbers from a contact list. Entries of the same pair (either order) are one neighbour
/// and their forces add up to the pair force (pass one entry per pair, or per contact point with
/// near-parallel normals). Pairs whose force is below minForce (N) are not contacts.
/// Support-support pairs are ignored. Throws core::InputError for a body index out of range, a
/// body touching itself, or a negative or non-finite force.
[[nodiscard]] PackContacts contactNumbers(const std::vector<Contact>& contacts, const std::vector<BodyRole>& roles,
                                          double minForce = 0.0);

} // namespace armour::analysis
