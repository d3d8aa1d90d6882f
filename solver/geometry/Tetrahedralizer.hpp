// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Tetrahedralizer.hpp
/// Volume meshes (linear tetrahedra) of closed triangle meshes, with gmsh.
///
/// The surface is handed to gmsh as a discrete surface (its nodes and triangles as given), bounded
/// into a volume, and meshed with gmsh's HXT Delaunay mesher on one thread (reproducible). The
/// surface triangles become the boundary faces of the tetrahedra unchanged (gmsh does not remesh a
/// discrete surface that has no parametrisation); interior points are inserted to reach the
/// requested size. To get smaller elements at the surface too, refine the surface first
/// (SurfaceRefinement.hpp, or keepSurface = false).

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
  /// Wanted number of tetrahedra (unit: -); 0 = not set. Sets the interior size h from the volume,
  /// then corrects h once from the count obtained. A surface that is fine compared with the
  /// requested size bounds the count from below.
  std::size_t targetTetCount = 0;
  /// Largest interior element edge (unit: m); 0 = not set. Ignored when targetTetCount is set.
  /// With neither set, the interior size follows the surface triangles.
  double maxEdge = 0.0;
  /// true: use the surface triangles as given. false: first refine the surface by longest-edge
  /// bisection to the interior size h (same geometry, smaller faces), so the elements are about
  /// uniform in size.
  bool keepSurface = true;
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
/// Throws core::InputError for bad options or when gmsh fails (e.g. self-intersecting surface).
TetMesh tetrahedralize(const TriangleMesh& surface, const TetrahedralizeOptions& options = {});

} // namespace armour::geometry
