// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ProjectedArea.hpp
/// The area A of seed 000 eq. 2 (Morison drag): the silhouette of a unit seen along the relative
/// flow direction, as a table over directions built once per shape.
///
/// Silhouette area A(d) of a closed surface along the unit direction d:
///  - convex shape: exactly A(d) = 1/2 sum_t |n_t . d| a_t (each line of sight crosses the surface
///    twice, once through a front face and once through a back face);
///  - any shape: the area of the union of the projected front-facing triangles, rasterised on a
///    res x res grid over the projected bounds (a pixel counts when its centre lies in a projected
///    triangle, edges included). Error: a fraction of the boundary pixels, about 1e-3 of the area
///    at res = 256 (docs/theory.md, "Projected area").
/// A(d) = A(-d), so the table holds one hemisphere's worth of values.
///
/// A convex shape of at most kDirectTriangles triangles is not tabulated: the exact formula is
/// evaluated at each query (a cube: 12 dot products), because interpolation cannot follow the
/// conical minima of A(d) at face-on directions (a rotated cube seen face-on between nodes: 13 %
/// high with 386 directions). Other shapes use the table.
///
/// Directions: the nodes of an equi-angular cube map (the unit cube's faces, each parametrised by
/// two angles xi, eta in [-1, 1] with direction ~ (+-1, tan(pi xi / 4), tan(pi eta / 4)) and
/// nodesPerEdge nodes per parameter): 6 (n-1)^2 + 2 distinct directions (386 for n = 9, spaced by
/// 90/(n-1) = 11.25 degrees), near-uniform (cell areas within a factor 1.5 of each other). A query
/// is bilinear in (xi, eta) on the face the direction points through: O(1), exact at the nodes,
/// continuous across face edges (the edge nodes are shared), second-order accurate where A(d) is
/// smooth. The face centres (the body axes) and the cube corners (the diagonals) are nodes.

#include "geometry/TriangleMesh.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace armour::hydro {

using geometry::Vec3;

struct ProjectedAreaSettings {
  enum class Method {
    Automatic,  ///< exact formula for convex shapes, rasterisation otherwise
    Exact,      ///< 1/2 sum |n.d| a (only correct for convex shapes)
    Rasterised, ///< union of projected triangles on a grid
  };
  Method method = Method::Automatic;
  int nodesPerEdge = 9;       ///< cube-map nodes per face edge, odd (unit: -); 9 gives 386 directions
  int rasterResolution = 256; ///< pixels per side of the rasterisation grid (unit: -)
};

/// Silhouette area of a convex closed mesh along unit direction d (unit: m^2).
[[nodiscard]] double convexProjectedArea(const geometry::TriangleMesh& mesh, const Vec3& direction);

/// Silhouette area of any closed mesh along unit direction d, rasterised at `resolution` (unit: m^2).
[[nodiscard]] double rasterisedProjectedArea(const geometry::TriangleMesh& mesh, const Vec3& direction,
                                             int resolution);

/// True if every vertex lies behind (or within `tolerance` x the mesh size of) every triangle's plane.
[[nodiscard]] bool isConvex(const geometry::TriangleMesh& mesh, double relativeTolerance = 1e-9);

/// Projected areas of one shape (body frame, unscaled) over the cube-map directions.
class ProjectedAreaTable {
public:
  /// Convex shapes with at most this many triangles are evaluated exactly at every query (unit: -).
  static constexpr std::size_t kDirectTriangles = 2048;

  ProjectedAreaTable() = default;
  /// Throws core::InputError for an even or too small nodesPerEdge or a resolution below 16.
  explicit ProjectedAreaTable(const geometry::TriangleMesh& mesh, const ProjectedAreaSettings& settings = {});

  /// Interpolated silhouette area along `direction` (any non-zero length; zero gives 0) (unit: m^2).
  [[nodiscard]] double operator()(const Vec3& direction) const;

  [[nodiscard]] bool convex() const { return convex_; }
  /// Values from the exact convex formula (at the nodes, or at every query if direct()).
  [[nodiscard]] bool exact() const { return exact_; }
  /// Every query evaluates the exact formula (no interpolation).
  [[nodiscard]] bool direct() const { return !areaNormals_.empty(); }
  /// Distinct directions of the full sphere the table represents (unit: -).
  [[nodiscard]] std::size_t directions() const;
  [[nodiscard]] int nodesPerEdge() const { return n_; }

private:
  int n_ = 0;
  bool convex_ = false;
  bool exact_ = false;
  /// Values on the faces +x, +y, +z (the -x, -y, -z faces follow from A(d) = A(-d)), n x n each,
  /// index face * n^2 + j * n + i for parameters (xi_i, eta_j) over the other two axes in
  /// increasing order.
  std::vector<double> values_;
  /// direct(): the triangles' (b - a) x (c - a), A(d) = 1/4 sum |N . d|.
  std::vector<Vec3> areaNormals_;
};

} // namespace armour::hydro
