// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Exposure.hpp
/// Which units a wave "sees": parallel rays cast normal to the slope (seed 003 section 2.2, the
/// ray optics that decide where the shallow-wave force acts), counting per unit the rays that hit
/// it first and where. docs/theory.md, "Analytic wave forces", gives the algorithm and its error.
///
/// Also the selection of the bodies that take analytic loads (fixed bodies never do), shared by
/// the analytic load stages.

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

/// First intersection of a straight line with a closed triangle mesh, through an axis-aligned
/// bounding-box tree over the triangles (median split on the longest axis of the triangle
/// centroids, up to 4 triangles per leaf), searched nearest box first and pruned by the best hit.
///
/// Exact on the mesh (the exposed area of a unit is a property of its surface, not of the
/// level-set approximation the contact uses), and its cost does not depend on how closely a ray
/// grazes the surface; docs/theory.md says why this was preferred over sphere tracing.
/// Thread-safe: const member functions only read.
class MeshRayCaster {
public:
  /// @pre the mesh is closed (validated by the World when the shape was added).
  explicit MeshRayCaster(const geometry::TriangleMesh& mesh);

  /// Smallest t such that origin + t direction lies on the surface, over the whole line (t may be
  /// negative), or +infinity if the line misses the mesh. For a closed mesh that is where the line
  /// enters the solid, seen along `direction`. `direction` need not be unit; t is in its units.
  /// Triangles are tested with a small tolerance on the barycentric coordinates, so a line through
  /// a shared edge or vertex cannot slip between two triangles.
  [[nodiscard]] double firstHit(const Vec3& origin, const Vec3& direction) const;

  [[nodiscard]] std::size_t triangleCount() const { return v0_.size(); }

private:
  struct Node {
    Vec3 lo;                  // box of the node's triangles
    Vec3 hi;
    std::int32_t first = 0;   // leaf: first triangle; inner: index of the second child (the first follows)
    std::int32_t count = 0;   // leaf: number of triangles; inner: 0
  };
  std::int32_t build(std::int32_t begin, std::int32_t end, std::vector<std::int32_t>& order,
                     const std::vector<Vec3>& centroids, const geometry::TriangleMesh& mesh);

  std::vector<Vec3> v0_, e1_, e2_; // triangle corner 0 and edges 0->1, 0->2, in tree order
  std::vector<Node> nodes_;
};

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
