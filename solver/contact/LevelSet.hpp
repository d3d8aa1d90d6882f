// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file LevelSet.hpp
/// Signed distance of a closed triangle mesh: the exact distance (MeshDistance, a bounding-volume
/// tree over the triangles with angle-weighted pseudo-normals for the sign) and its sampled,
/// trilinearly interpolated form on a uniform grid (LevelSet), which contact queries use.
///
/// Sign convention: phi < 0 inside the solid, phi > 0 outside, |phi| = distance to the surface (m).
/// Frame: the mesh's own (body) frame; callers transform world points into it.
///
/// One LevelSet per shape, shared by every body of that shape: uniformly scaled instances query
/// with a scale factor s, phi_s(x) = s phi(x / s), since the distance to a mesh scaled by s about
/// the body origin is s times the distance of x / s to the unscaled mesh.
///
/// Method and error bounds: docs/theory.md, "Level sets and surface samples".

#include "geometry/ClosestPoint.hpp"
#include "geometry/TriangleMesh.hpp"
#include "geometry/TriangleTree.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace armour::contact {

using geometry::Box3;
using geometry::TriangleMesh;
using geometry::Vec3;

using geometry::TriangleFeature;

/// Closest point on a triangle mesh to a query point.
struct ClosestPoint {
  Vec3 point = Vec3::Zero();    ///< closest surface point (unit: m)
  double distance = 0.0;        ///< unsigned distance (unit: m)
  double signedDistance = 0.0;  ///< negative inside the solid (unit: m)
  std::int32_t triangle = -1;   ///< index of the triangle holding the closest point
  TriangleFeature feature = TriangleFeature::Face;
};

/// Exact signed distance to a closed, outward, manifold triangle mesh.
///
/// Distance: minimum over triangles of the distance to the closest point on the triangle
/// (Voronoi-region classification, Ericson 2005, section 5.1.5), found through an axis-aligned
/// bounding-box tree (median split, up to 4 triangles per leaf) searched nearest box first and
/// pruned when a box is farther than the best distance so far.
/// Sign: sign((x - c) . n) with c the closest point and n the angle-weighted pseudo-normal of the
/// feature holding c (face normal, sum of the two face normals at an edge, angle-weighted sum at
/// a vertex); exact for any point of a closed manifold surface (Baerentzen and Aanaes 2005).
///
/// Thread-safe: const member functions only read.
/// @pre the mesh passed geometry::validateMesh (closed, manifold, outward); the object keeps its
///      own copy of the triangles, so the mesh may be destroyed afterwards.
class MeshDistance {
public:
  explicit MeshDistance(const TriangleMesh& mesh);

  /// Closest point, distance and sign at `x` (unit: m).
  [[nodiscard]] ClosestPoint closest(const Vec3& x) const;
  /// Signed distance at `x`, negative inside (unit: m).
  [[nodiscard]] double signedDistance(const Vec3& x) const { return closest(x).signedDistance; }

  [[nodiscard]] std::size_t triangleCount() const { return corners_.size(); }
  /// Bytes held by the tree and the triangle data.
  [[nodiscard]] std::size_t memoryBytes() const;

private:
  using Node = geometry::TriangleTree::Node;

  std::vector<std::array<Vec3, 3>> corners_;   // triangle corners, tree order
  std::vector<Vec3> faceNormals_;              // unit normals, tree order
  std::vector<std::array<Vec3, 3>> edgeNormals_;   // pseudo-normals of edges 01, 12, 20
  std::vector<std::array<Vec3, 3>> vertexNormals_; // pseudo-normals of corners 0, 1, 2
  std::vector<std::int32_t> originalIndex_;    // tree order -> mesh triangle index
  std::vector<Node> nodes_;
};

/// Resolution of a level-set grid.
struct LevelSetSettings {
  /// Grid cells per nominal diameter Dn = V^(1/3) of the mesh (unit: -). 24 puts 8 cells across
  /// the thinnest member of the library (the Dolos fluke ends, 0.33 Dn across flats) and about 9
  /// across the Core-Loc member ends (0.38 Dn); docs/theory.md gives the measured figures.
  double cellsPerDn = 24.0;
  /// Explicit cell size; overrides cellsPerDn when positive (unit: m).
  double cellSize = 0.0;
  /// Grid nodes beyond the mesh bounding box on every side (unit: cells). At least 1; with m
  /// cells every node on the grid boundary is at least m h from the surface, so the outside
  /// extension of the distance starts from clearly positive values.
  int marginCells = 3;
  /// Largest number of grid nodes (unit: -). Guards against a cell size in the wrong unit.
  std::size_t maxNodes = 20'000'000;
};

/// Distance and direction at a point.
struct LevelSetQuery {
  double phi = 0.0;                ///< interpolated signed distance, negative inside (unit: m)
  Vec3 gradient = Vec3::Zero();    ///< exact gradient of the interpolant (unit: -); |g| <= sqrt(3)
  Vec3 normal = Vec3::Zero();      ///< gradient / |gradient|, or zero where |gradient| < kMinGradient
  /// Below this |gradient| the direction is not meaningful (a medial-axis point, where pushes to
  /// either side cancel); `normal` is then zero (unit: -).
  static constexpr double kMinGradient = 1e-3;
};

/// Signed distance of one shape sampled on a uniform grid, with trilinear interpolation.
///
/// Grid: nodes x_ijk = origin + h (i, j, k) covering the mesh bounding box plus marginCells on each
/// side; values are the exact signed distances at the nodes (MeshDistance), stored as float
/// (relative rounding 6e-8 of |phi|: at |phi| <= 2 Dn and h = Dn / 24 that is < 3e-6 h, far below
/// the interpolation error near edges and the 1e-3 h flatness the contact needs).
///
/// Inside the grid box: phi(x) = trilinear interpolant of the 8 nodes of the cell holding x;
/// exact for a linear field, so under a flat face, away from its edges, phi is the true depth.
/// gradient = exact gradient of that interpolant (continuous inside cells, jumps across cell
/// faces); a penalty force -k phi grad(phi) (outward where phi < 0) is then minus the gradient
/// of the continuous potential k phi^2 / 2 and does no net work around a closed path.
/// Outside the grid box: phi(x) = |x - c| + phi(c), c the nearest point of the box: positive
/// (the box boundary is >= marginCells h from the mesh), continuous across the box, cheap, and
/// never below the distance to the mesh bounding box nor below the true distance minus the
/// interpolation error at c (the path through c is not shorter than the shortest one), so a
/// far point is never reported inside, nor nearer than it is beyond that error.
///
/// Thread-safe: const member functions only read.
class LevelSet {
public:
  LevelSet() = default;
  /// Build from a closed, outward mesh in its body frame. `source` names the shape in errors.
  /// Throws core::InputError for a non-positive volume or an invalid resolution setting.
  LevelSet(const TriangleMesh& mesh, const LevelSetSettings& settings = {}, const std::string& source = "level set");

  /// Interpolated signed distance at body-frame point `local` (unit: m).
  [[nodiscard]] double distance(const Vec3& local) const;
  /// Same as distance(local): the value alone, without the gradient; equals query(local).phi
  /// (the narrow phase tests this first and queries only the samples found inside).
  [[nodiscard]] double value(const Vec3& local) const;
  /// A lower bound of the true distance from `local` to the surface (unit: m; negative inside):
  /// phi - sqrt(3) h inside the grid, the distance to the mesh's bounding box outside it (where
  /// value() can exceed the true distance). For culling: phi(x) < 0 needs this < sqrt(3) h at x.
  [[nodiscard]] double distanceLowerBound(const Vec3& local) const;
  /// Gradient of the interpolant at `local` (unit: -): the outward direction, not normalised.
  [[nodiscard]] Vec3 gradient(const Vec3& local) const;
  /// Unit outward direction at `local`, or zero at medial-axis points (see LevelSetQuery).
  [[nodiscard]] Vec3 normal(const Vec3& local) const { return query(local).normal; }
  /// Distance, gradient and normal at `local` in one lookup.
  [[nodiscard]] LevelSetQuery query(const Vec3& local) const;
  /// Where value() looked: the cell, the fractions in it, the step out of the grid box, and the
  /// value found. The narrow phase tests value(local, at) and finishes with query(at) only for the
  /// samples that pass, without a second lookup.
  struct Lookup {
    std::size_t base = 0; ///< index of the cell's node (0, 0, 0)
    double f[3] = {0.0, 0.0, 0.0};
    Vec3 away = Vec3::Zero(); ///< local minus its clamp to the grid box (unit: m)
    double phi = 0.0;         ///< value(local) (unit: m)
  };
  /// value(local), and where it was found.
  [[nodiscard]] double value(const Vec3& local, Lookup& at) const;
  /// query(local) for the point value(local, at) looked at: the same bits. `at` must come from
  /// this level set's value().
  [[nodiscard]] LevelSetQuery query(const Lookup& at) const;

  /// Queries of the same shape scaled uniformly by `scale` about the body origin:
  /// phi_s(x) = s phi(x / s), grad_s(x) = grad(x / s). @pre scale > 0.
  [[nodiscard]] double distance(const Vec3& local, double scale) const { return scale * distance(local / scale); }
  [[nodiscard]] LevelSetQuery query(const Vec3& local, double scale) const;

  /// False when no point of `localBox` can have phi < 0 (the box misses the grown mesh bounds, or
  /// the lower bound of the distance at its centre exceeds its half-diagonal plus sqrt(3) h).
  /// True means "look closer".
  [[nodiscard]] bool mayPenetrate(const Box3& localBox, double scale = 1.0) const;

  [[nodiscard]] bool empty() const { return values_.empty(); }
  [[nodiscard]] double cellSize() const { return h_; }                     ///< h (unit: m)
  [[nodiscard]] const Vec3& origin() const { return origin_; }             ///< node (0,0,0) (unit: m)
  [[nodiscard]] const std::array<int, 3>& nodeCounts() const { return n_; } ///< nodes per axis
  [[nodiscard]] const Box3& meshBounds() const { return meshBounds_; }     ///< unit: m
  [[nodiscard]] const Box3& gridBounds() const { return gridBounds_; }     ///< unit: m
  [[nodiscard]] double nominalDiameter() const { return dn_; }             ///< Dn of the mesh (unit: m)
  /// Node value (unit: m), i < nx, j < ny, k < nz.
  [[nodiscard]] double nodeValue(int i, int j, int k) const {
    const auto nx = static_cast<std::size_t>(n_[0]);
    const auto ny = static_cast<std::size_t>(n_[1]);
    return values_[static_cast<std::size_t>(i) + nx * (static_cast<std::size_t>(j) + ny * static_cast<std::size_t>(k))];
  }
  /// All node values, x fastest then y then z (unit: m).
  [[nodiscard]] const std::vector<float>& values() const { return values_; }
  /// Bytes held by the grid (the values; the object itself is a few hundred bytes).
  [[nodiscard]] std::size_t memoryBytes() const { return values_.size() * sizeof(float); }
  /// Wall time the build took (unit: s); for reports, not for logic.
  [[nodiscard]] double buildSeconds() const { return buildSeconds_; }

private:
  /// The interpolant of cell `base` at fractions f, and its gradient there.
  double interpolateAt(std::size_t base, const double f[3]) const;
  Vec3 gradientAt(std::size_t base, const double f[3]) const;
  /// Index of node (0,0,0) of the cell holding x (clamped to the grid) and x's fractions in it.
  std::size_t locate(const Vec3& x, double f[3]) const;
  /// The interpolant alone (no gradient): the cheap test most samples fail.
  double interpolateValue(const Vec3& x) const;

  Vec3 origin_ = Vec3::Zero();
  double h_ = 0.0;
  double invH_ = 0.0;
  std::array<int, 3> n_{0, 0, 0};
  Box3 meshBounds_;
  Box3 gridBounds_;
  double dn_ = 0.0;
  double buildSeconds_ = 0.0;
  std::vector<float> values_;
};

} // namespace armour::contact
