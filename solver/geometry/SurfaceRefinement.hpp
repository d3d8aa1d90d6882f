// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SurfaceRefinement.hpp
/// Refine a closed triangle mesh to a target element size by longest-edge bisection.
///
/// Method: Rivara's longest-edge propagation path (LEPP) bisection. A triangle is only ever split
/// across its own longest edge, at that edge's midpoint; when the longest edge of the neighbour
/// across it is longer still, the neighbour is refined first, so the edge being split is the
/// longest edge of both triangles that share it and the mesh stays conforming (watertight) at
/// every step. Consequences:
///  - the surface does not move: new vertices are midpoints of existing straight edges, so flat
///    faces stay flat and a polyhedron's volume is unchanged (to round-off);
///  - angles stay bounded: in a plane, repeated longest-edge bisection never makes an angle smaller
///    than half the smallest angle of the input (Rosenberg and Stenger 1975; Rivara 1984), and only
///    finitely many similarity classes of triangles appear;
///  - the result depends only on the input and h: ties between equal edges are broken by vertex
///    index, never by memory address.
/// Only refinement: edges already shorter than h are left alone, nothing is coarsened.

#include "geometry/TriangleMesh.hpp"

#include <cstddef>

namespace armour::geometry {

/// Size and shape figures of a triangle mesh.
struct SurfaceMeshStats {
  std::size_t triangles = 0;
  std::size_t vertices = 0;
  double minEdge = 0.0;       ///< shortest edge (unit: m)
  double maxEdge = 0.0;       ///< longest edge (unit: m)
  double meanEdge = 0.0;      ///< mean over unique edges (unit: m)
  double minAngleDeg = 0.0;   ///< smallest triangle angle (unit: degree)
};

/// Statistics over the unique edges and all triangles of `mesh`.
SurfaceMeshStats surfaceMeshStats(const TriangleMesh& mesh);

struct SurfaceRefinementSettings {
  /// Largest number of triangles a refinement may produce (unit: -). Guards against a target size
  /// given in the wrong unit (e.g. mm for m) exhausting memory.
  std::size_t maxTriangles = 5'000'000;
};

/// Split edges until every edge is at most `maxEdgeLength` (m).
/// @pre `mesh` is a valid closed mesh (validateMesh); open edges are bisected too but only
///      closed meshes are covered by the guarantees above.
/// Throws core::InputError if maxEdgeLength is not positive and finite, or if it would make more
/// than settings.maxTriangles triangles (the message gives the smallest allowed size).
TriangleMesh refineSurface(const TriangleMesh& mesh, double maxEdgeLength,
                           const SurfaceRefinementSettings& settings = {});

/// Refine to about `targetTriangles` triangles (never fewer than the input has): picks the edge
/// size h from the surface area, refines, corrects h once from the count obtained and keeps the
/// result nearer the target. Bisection halves areas, so counts come in steps: expect the result
/// within a factor of about 1.5 of the target. Returns the mesh unchanged if it already has at
/// least targetTriangles triangles.
TriangleMesh refineToCount(const TriangleMesh& mesh, std::size_t targetTriangles,
                           const SurfaceRefinementSettings& settings = {});

} // namespace armour::geometry
