// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ConvexHull.hpp
/// Convex hulls of point sets and intersections of half-spaces (Qhull, reentrant C API).
///
/// Both return a ConvexPolyhedron: planar convex polygons, each a whole face of the solid. Qhull
/// merges facets that are coplanar within its round-off estimate ('C-0', its default in 3-d), so a
/// face of a cube is one square, not two triangles at a slightly different angle. The polygons are
/// then triangulated here rather than with Qhull's 'Qt': 'Qt' fans each merged facet from one
/// vertex and so makes zero-area triangles wherever the facet has collinear vertices (points on an
/// edge of the hull); the max-min-angle triangulation below avoids such slivers whenever the polygon
/// allows it.
///
/// Precision: the points are shifted to their mean before Qhull sees them (Qhull's tolerances scale
/// with the largest coordinate), and the hull's vertices are the input points themselves, bit for bit.

#include "geometry/TriangleMesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace armour::geometry {

/// A convex solid as a list of planar faces.
struct ConvexPolyhedron {
  std::vector<Vec3> vertices;                   ///< positions (unit: m)
  std::vector<std::vector<std::int32_t>> faces; ///< convex polygons, counter-clockwise seen from outside
  std::vector<Vec3> normals;                    ///< unit outward normal of each face (unit: -)
  std::vector<double> offsets;                  ///< normal . x = offset on face i (unit: m)
  /// convexHullPolyhedron: index of the input point each vertex is. Otherwise empty.
  std::vector<std::int32_t> vertexSource;
  /// convexHalfspaceIntersection: index of the half-space each face lies on. Otherwise empty.
  std::vector<std::int32_t> faceSource;
};

/// Convex hull of `points` (at least 4, not all in one plane). `source` names the point set in
/// error messages. Throws core::InputError for too few, non-finite, coplanar or collinear points.
ConvexPolyhedron convexHullPolyhedron(const std::vector<Vec3>& points, const std::string& source = "convex hull");

/// Convex hull as a closed, outward triangle mesh whose vertices are the hull's vertices (points
/// inside the hull or inside a face are dropped). Same errors as convexHullPolyhedron.
TriangleMesh convexHull(const std::vector<Vec3>& points, const std::string& source = "convex hull");

/// Split every face of `polyhedron` into triangles, choosing for each polygon the triangulation
/// that maximises its smallest angle (dynamic programming over the O(n^3) triangulations of a
/// convex n-gon), so no zero-area triangle is made unless the polygon forces one. Unused vertices
/// are kept (none exist for the polyhedra made here).
TriangleMesh triangulateFaces(const ConvexPolyhedron& polyhedron);

/// The closed half-space { x : normal . x <= offset }.
struct Halfspace {
  Vec3 normal = Vec3::UnitZ(); ///< outward direction; need not be unit length (unit: -)
  double offset = 0.0;         ///< normal . x on the bounding plane (unit: m x |normal|)
};

/// Intersection of half-spaces that contain `interiorPoint` strictly (m). Computed as the polar
/// dual: each half-space becomes the point normal / (offset - normal . interiorPoint), whose hull
/// facets are the vertices of the intersection and whose hull vertices are its faces; half-spaces
/// that do not touch the intersection (redundant ones) make no face. faceSource tells which
/// half-space each face came from. Throws core::InputError if the point is not strictly inside
/// every half-space, if fewer than 4 half-spaces are given, or if the intersection is unbounded.
ConvexPolyhedron convexHalfspaceIntersection(const std::vector<Halfspace>& halfspaces, const Vec3& interiorPoint,
                                             const std::string& source = "half-space intersection");

} // namespace armour::geometry
