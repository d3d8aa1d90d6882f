// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Tetrahedralizer.hpp
/// Volume meshes (linear tetrahedra) of closed triangle meshes, with gmsh.
///
/// Method: the interior is seeded with points: a body-centred cubic (BCC) lattice of spacing a,
/// clipped to the solid and kept 0.9 a from its surface, plus a boundary layer of one point 0.6 a
/// below each surface vertex. The surface goes to gmsh as a discrete surface (its nodes and
/// triangles as given) bounding a volume with these points embedded, and gmsh's Delaunay mesher
/// (algorithm 1, with its default optimisation, no further refinement) connects them. Why: the
/// Delaunay tets of a BCC lattice are congruent and well shaped (12 per a^3), which sets count and
/// interior quality directly; gmsh 4.8's own interior refinement either ignores the requested
/// size inside a discrete surface (Delaunay) or is not repeatable and crashed (HXT). The result is
/// repeatable: same input, same mesh, in any order of calls.
///
/// Quality (tetMeshQuality, keepSurface = false): box-like solids have no dihedral angle below
/// 14 degrees; the rock shapes keep a few slivers (0.15-0.8 % of tets under 10 degrees, worst
/// about 1 degree) at nearly flat ridges and thin surface triangles, which gmsh's optimiser cannot
/// remove without moving surface nodes.
///
/// The surface triangles become the boundary faces of the tets unchanged (keepSurface), so a
/// coarse surface with a fine interior gives poorly shaped tets along the surface: refine the
/// surface first (SurfaceRefinement.hpp, or keepSurface = false) when quality matters.

#include "geometry/TriangleMesh.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace armour::geometry {

using Tet = std::array<std::int32_t, 4>; ///< vertex indices; (b-a) . ((c-a) x (d-a)) > 0

/// A linear tetrahedral mesh. Units: metres.
struct TetMesh {
  std::vector<Vec3> vertices; ///< positions (unit: m); the surface mesh's vertices come first, in order
  std::vector<Tet> tets;      ///< positively oriented

  [[nodiscard]] double volume(std::size_t t) const; ///< signed volume of tet t (unit: m^3)
  [[nodiscard]] double totalVolume() const;         ///< sum of the tet volumes (unit: m^3)
};

struct TetrahedralizeOptions {
  /// Wanted number of tetrahedra (unit: -); 0 = not set. Sets the lattice spacing from the volume
  /// (spacing^3 = 12 V / N), then corrects it once from the count obtained. A surface that is
  /// fine compared with the spacing bounds the count from below.
  std::size_t targetTetCount = 0;
  /// Interior lattice spacing = longest interior edge (unit: m); 0 = not set. Ignored when
  /// targetTetCount is set. With neither set there are no lattice points and the interior follows
  /// the surface triangles (gmsh's Delaunay refinement from the surface sizes).
  double maxEdge = 0.0;
  /// true: use the surface triangles as given. false: first refine the surface by longest-edge
  /// bisection to the spacing (same geometry, smaller faces), so elements are about uniform.
  bool keepSurface = true;
  /// Refuse requests that would make more tetrahedra than this (unit: -): guards against a size
  /// given in the wrong unit.
  std::size_t maxTetCount = 5'000'000;
  /// Name of the body in error messages.
  std::string source = "tetrahedralisation";
};

/// Quality figures of a tet mesh.
struct TetMeshQuality {
  std::size_t tets = 0;
  double minDihedralDeg = 0.0;   ///< smallest dihedral angle (unit: degree; 70.53 for a regular tet)
  double maxDihedralDeg = 0.0;   ///< largest dihedral angle (unit: degree)
  double minRadiusRatio = 0.0;   ///< smallest 3 r_in / r_circ (unit: -; 1 regular, 0 flat)
  double meanRadiusRatio = 0.0;  ///< mean 3 r_in / r_circ (unit: -)
  double minVolume = 0.0;        ///< smallest tet volume (unit: m^3)
};

TetMeshQuality tetMeshQuality(const TetMesh& mesh);

/// The triangles on the boundary of a tet mesh (faces used by one tet), outward.
TriangleMesh tetMeshBoundary(const TetMesh& mesh);

/// Tetrahedralise the solid bounded by `surface`.
/// @pre `surface` is valid (validateMesh): closed, manifold, outward, one piece, no self-intersection.
/// @post tets positive; their volumes sum to the surface's volume within 1e-6 (checked); the
///       surface's vertices are the first vertices, in order.
/// Throws core::InputError for an invalid surface, bad options, a request above maxTetCount, or
/// when gmsh fails (e.g. a self-intersecting surface).
TetMesh tetrahedralize(const TriangleMesh& surface, const TetrahedralizeOptions& options = {});

} // namespace armour::geometry
