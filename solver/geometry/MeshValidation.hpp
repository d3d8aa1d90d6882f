// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file MeshValidation.hpp
/// Checks that a triangle mesh bounds one solid: finite coordinates, valid indices, no degenerate
/// faces, watertight (every edge shared by exactly two faces), manifold, consistently oriented,
/// one connected piece, positive volume. Orientation is repaired where that is unambiguous
/// (a single orientable piece: faces are flipped to agree with their neighbours, then the whole
/// mesh is inverted if its volume is negative); anything else is refused with a MeshError that
/// names the source, the defect, example elements and the fix.

#include "core/Error.hpp"
#include "geometry/TriangleMesh.hpp"

#include <string>
#include <utility>
#include <vector>

namespace armour::geometry {

enum class MeshDefect {
  Empty,              ///< no triangles
  NonFinite,          ///< NaN or infinite coordinate
  BadIndex,           ///< a triangle refers to a vertex that does not exist
  DegenerateFace,     ///< repeated vertex or (near) zero area
  OpenEdges,          ///< edges used by one face only: not watertight
  NonManifoldEdges,   ///< edges used by more than two faces
  NonOrientable,      ///< no consistent orientation exists (Moebius-like)
  InconsistentOrientation, ///< neighbouring faces disagree (reported when repair is off)
  InwardOrientation,  ///< consistently oriented, but normals point inward (repair off)
  MultipleComponents, ///< more than one connected piece
  NonPositiveVolume,  ///< zero or negative enclosed volume
};

/// Short name of a defect ("open edges", ...).
const char* toString(MeshDefect defect);

using Edge = std::pair<std::int32_t, std::int32_t>; ///< vertex indices, first < second

/// Everything the inspection found; no exception, no change to the mesh.
struct MeshInspection {
  bool nonFinite = false;
  bool badIndex = false;
  std::vector<std::size_t> degenerateFaces;
  std::vector<Edge> openEdges;
  std::vector<Edge> nonManifoldEdges;
  std::size_t components = 0;
  bool orientable = true;
  bool consistentlyOriented = true;
  double volume = 0.0; ///< signed volume (m^3), meaningful only when watertight and consistent

  [[nodiscard]] bool watertight() const { return openEdges.empty() && nonManifoldEdges.empty(); }
  /// True when the mesh is a valid outward solid as it stands.
  [[nodiscard]] bool valid() const;
};

/// Inspect without changing anything. Degenerate faces are those with a repeated vertex or an area
/// below areaTolerance x (bounding-box diagonal)^2.
MeshInspection inspectMesh(const TriangleMesh& mesh, double areaTolerance = 1e-12);

/// Thrown for a mesh that cannot be used; `defect()` tells which check failed.
class MeshError : public core::InputError {
public:
  MeshError(MeshDefect defect, const std::string& message) : core::InputError(message), defect_(defect) {}
  [[nodiscard]] MeshDefect defect() const { return defect_; }

private:
  MeshDefect defect_;
};

struct ValidationOptions {
  bool repairOrientation = true; ///< flip faces / invert the mesh where unambiguous
  bool allowMultipleComponents = false;
  double areaTolerance = 1e-12;  ///< relative to the squared bounding-box diagonal (unit: -)
};

/// What validateMesh changed.
struct RepairReport {
  std::size_t flippedFaces = 0; ///< faces flipped to agree with their neighbours
  bool inverted = false;        ///< the whole mesh was turned outward
};

/// Validate and (optionally) repair orientation in place. `source` names the file or shape in
/// error messages. Throws MeshError naming the first defect found.
RepairReport validateMesh(TriangleMesh& mesh, const std::string& source, const ValidationOptions& options = {});

} // namespace armour::geometry
