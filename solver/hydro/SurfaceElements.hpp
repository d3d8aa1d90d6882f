// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SurfaceElements.hpp
/// The surface elements that carry the storm pressure on a unit (seed 000 section 2.3: "surface
/// pressures on each unit are integrated" over "some 4000 surface elements for each unit").
///
/// Built once per shape from the shape's closed mesh in its body (principal) frame, centroid at the
/// origin, and shared by every body of that shape: a body of uniform scale s sees positions
/// multiplied by s and areas by s^2. The mesh is split by longest-edge bisection
/// (geometry/SurfaceRefinement) until no edge exceeds the target size, so the surface does not move
/// and flat faces stay flat.
///
/// Quadrature: one point per flat triangle, at its centroid (the midpoint rule). It integrates any
/// pressure linear over the triangle exactly, so -sum p_e a_e n_e reproduces -grad(p) V for a linear
/// field (divergence theorem) to round-off: hydrostatic buoyancy comes out exact on any closed mesh.
///
/// Patches: each element also carries the index of the patch it belongs to, for the pressure
/// variability (Variability.hpp): the body-frame bounding box is divided into n x n x n cells
/// (octants for n = 2) and an element belongs to the cell holding its centroid.

#include "geometry/TriangleMesh.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace armour::hydro {

using geometry::Vec3;

/// Elements of one shape, body frame, unscaled (structure of arrays: the pressure loop streams
/// through them).
struct SurfaceElements {
  std::vector<Vec3> centroid;    ///< element centroid c_e (unit: m)
  std::vector<Vec3> normal;      ///< unit outward normal n_e (unit: -)
  std::vector<double> area;      ///< a_e (unit: m^2)
  /// a_e c_e x n_e: the element's moment arm times its vector area, so the pressure moment is
  /// -sum p_e (c_e x n_e) a_e without a cross product per element and update (unit: m^3).
  std::vector<Vec3> momentArm;
  std::vector<std::uint16_t> patch; ///< patch index, 0 .. patchesPerAxis^3 - 1 (unit: -)
  int patchesPerAxis = 1;        ///< n (unit: -)
  double elementSize = 0.0;      ///< the target edge length used (unit: m)
  double totalArea = 0.0;        ///< sum of a_e (unit: m^2)
  double volume = 0.0;           ///< volume enclosed by the mesh (unit: m^3)
  geometry::Box3 bounds;         ///< bounds of the mesh (unit: m)

  [[nodiscard]] std::size_t size() const { return area.size(); }
  [[nodiscard]] int patchCount() const { return patchesPerAxis * patchesPerAxis * patchesPerAxis; }
};

/// Patch of a point in the box split into n^3 cells: floor((c - box.min) / box.size * n) per axis,
/// clamped to 0 .. n-1, as ix + n (iy + n iz) (unit: -).
[[nodiscard]] int patchIndex(const Vec3& point, const geometry::Box3& box, int patchesPerAxis);

/// Split `bodyMesh` (closed, outward, body frame) until no edge exceeds `maxEdgeLength` (m) and
/// make one element per triangle. Throws core::InputError (from the refinement) for a size that is
/// not positive or that would make too many elements, and for patchesPerAxis outside 1 .. 40.
[[nodiscard]] SurfaceElements buildSurfaceElements(const geometry::TriangleMesh& bodyMesh, double maxEdgeLength,
                                                   int patchesPerAxis);

} // namespace armour::hydro
