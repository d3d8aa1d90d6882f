// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// bench_peers: a unit as convex pieces, for a physics engine that collides convex shapes only
// (Bullet's btCompoundShape of btConvexHullShape). Built from armour's own mesh of the unit, in
// its body (principal) frame, so the pieces sit where the level set's surface is.

#include "simulation/World.hpp"

#include <string>
#include <vector>

namespace armour::bench {

/// One convex piece: the corners of its hull (body frame, unit: m, at scale 1).
struct ConvexPiece {
  std::string name;
  std::vector<armour::simulation::Vec3> corners;
  std::vector<armour::simulation::Vec3> normals; ///< the hull's faces: normal . x <= offset inside (unit: -)
  std::vector<double> offsets;                   ///< (unit: m)
  double volume = 0.0; ///< volume of the hull (unit: m^3)
  double outside = 0.0; ///< sampled volume of the hull outside the mesh / mesh volume (unit: -)
};

/// The pieces of a shape and how well they fill it.
struct ConvexPieces {
  std::vector<ConvexPiece> pieces;
  double meshVolume = 0.0;   ///< armour's mesh (unit: m^3)
  double piecesVolume = 0.0; ///< sum of the pieces' hulls (unit: m^3)
  [[nodiscard]] double volumeError() const { return piecesVolume / meshVolume - 1.0; } ///< (-)
  /// Sampled on a grid of kSamples^3 points over the mesh's box: the union of the pieces outside
  /// the mesh, and the mesh outside every piece, as fractions of the mesh volume (unit: -). Each
  /// within about a grid cell's share of the surface layer (see bench_peers' report).
  double outside = 0.0;
  double missed = 0.0;
  static constexpr int kSamples = 96;
  std::string how;           ///< one line for the report
};

/// The convex hull of the whole shape as one piece (exact for a cube).
ConvexPieces wholeHull(const armour::simulation::ShapeModel& shape);

/// A Core-Loc (geometry/shapes/CoreLoc.cpp) split along its construction members, each piece the
/// convex hull of the mesh vertices that belong to it, found in the shape's natural frame (outer
/// members along z at x = -/+ x_outer, central member along x):
///  - 3 pieces: the two outer members (x <= -x_inner, x >= x_inner) and the central member with
///    its chamfers (|x| <= x_inner); the chamfers flare, so the central hull is a little too big;
///  - 5 pieces: the central member split where the chamfers start (|x| = x_inner - c), which makes
///    every piece convex: the decomposition is exact up to the mesh.
/// x_inner (the outer members' inner faces) is read from the mesh: the faces whose natural
/// normal is +-x; x_inner - c is the largest |x| of a vertex inside them.
/// @throws std::runtime_error when the mesh does not look like the Core-Loc construction.
ConvexPieces coreLocPieces(const armour::simulation::ShapeModel& shape, int pieces);

} // namespace armour::bench
