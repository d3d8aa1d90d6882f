// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Exposure.hpp
/// Which units a wave "sees": parallel rays cast normal to the slope (seed 003 section 2.2, the
/// ray optics that decide where the shallow-wave force acts), counting per unit the rays that hit
/// it first and where. docs/theory.md, "Analytic wave forces", gives the algorithm and its error.
///
/// Also the selection of the bodies that take analytic loads (fixed bodies never do), shared by
/// the analytic load stages.

#include "geometry/MeshRayCaster.hpp"
#include "hydro/LoadedBodies.hpp"
#include "simulation/World.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace armour::hydro {

using dynamics::BodyId;
using geometry::Vec3;

using geometry::MeshRayCaster;

/// Which way the rays travel.
enum class ExposureSide {
  FromSea,    ///< along -n: from the sea side into the slope (surfaces an onshore push reaches)
  FromBehind, ///< along +n: from behind the units out of the slope (surfaces a seaward pull reaches)
};

struct ExposureQuery {
  /// Unit normal out of the slope, pointing up and seaward: (-sin th, 0, cos th) for a slope of
  /// angle th rising onshore (unit: -). Normalised by compute(); must be finite and non-zero.
  Vec3 slopeNormal = Vec3::UnitZ();
  double spacing = 0.25;        ///< distance between neighbouring rays on the slope plane (unit: m)
  ExposureSide side = ExposureSide::FromSea;
};

/// What the rays found on one loaded body.
struct BodyExposure {
  std::int32_t hits = 0;          ///< rays whose first body hit is this one (unit: -)
  Vec3 meanPoint = Vec3::Zero();  ///< mean of those first-hit points, world; zero without hits (unit: m)
  /// Exposed area projected on the slope plane: hits x spacing^2 (unit: m^2).
  [[nodiscard]] double area(double spacing) const { return hits * spacing * spacing; }
};

/// Counters of the last compute(), for logs and benchmarks.
struct ExposureStatistics {
  std::size_t rays = 0;           ///< rays cast (unit: -)
  std::size_t candidates = 0;     ///< ray-body tests that reached the triangle tree (unit: -)
  std::size_t hits = 0;           ///< rays whose first hit is a loaded body (unit: -)
};

/// Ray-cast exposure of a set of loaded bodies.
///
/// Ray grid: with n the slope normal, v the trunk direction e_y made orthogonal to n (e_x if n is
/// along e_y) and u = v x n (up the slope), ray (i, j) is the line through
/// ((i + 1/2) h) u + ((j + 1/2) h) v, h = spacing, travelling along -n (FromSea) or +n
/// (FromBehind). The grid is fixed in the world (not re-anchored on the bodies), so a body that
/// does not move keeps its count between updates. Only the rays that pass within a loaded body's
/// bounding sphere are cast: they cover the loaded bodies' projected extent on the slope plane.
///
/// Each ray is a whole line: the first body it enters, seen along its direction, takes it. Every
/// body of the World blocks rays: loaded ones, other dynamic ones and fixed (static) ones; only
/// loaded bodies receive. Static planes and convex pieces (the impermeable slope, the toe) do not
/// block: the rays from behind start inside them. Candidates for a ray are found on a 2D grid of
/// the bodies' bounding circles in the slope plane (the sphere pre-test), then tested exactly on
/// the shape's triangles (MeshRayCaster, one per shape, built on first use).
///
/// Determinism: rays run in parallel (OpenMP), each writing its own slot; the per-body sums are
/// then formed serially in ray order, so the result is the same for any thread count. A ray that
/// enters two bodies at the same distance goes to the lower body index.
class Exposure {
public:
  /// Exposure of `loaded` bodies: result[k] belongs to loaded[k]. Static bodies in `loaded` get no
  /// hits (they only block). Throws core::InputError for a non-positive spacing or a bad normal
  /// (naming `where`).
  [[nodiscard]] std::vector<BodyExposure> compute(const simulation::World& world, std::span<const BodyId> loaded,
                                                  const ExposureQuery& query, const std::string& where = "exposure");

  [[nodiscard]] const ExposureStatistics& lastStatistics() const { return stats_; }

private:
  const MeshRayCaster& caster(const simulation::World& world, simulation::ShapeId shape);

  std::vector<std::unique_ptr<MeshRayCaster>> casters_; // by shape id, built on first use
  ExposureStatistics stats_;
};

} // namespace armour::hydro
