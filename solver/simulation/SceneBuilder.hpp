// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SceneBuilder.hpp
/// Turn a resolved scene file (io::Scene) into a World ready to step: materials, one World shape
/// per scene shape (shared by its bodies), bodies, the static boundary and the settings.
///
/// Sizes. A generator shape is built once at V = 1 m^3 (geometry::makeShape) and a mesh-file shape
/// at the file's own size; a body's size is a uniform scale of its shape: s = (V / V_shape)^(1/3)
/// when the body gives a volume (or dn), else the body's `scale` (mesh files only). Level sets and
/// sample spacings are relative to the shape's Dn, so one shape serves bodies of every size.
///
/// Static geometry (the solid is the union of the items, docs/scene-file.md):
///  - plane, wall: a World half-space (StaticPlane);
///  - slope with a toe: the seabed is a half-space z <= z_seabed (everything below the lowest
///    point of the profile is solid); above it the profile z(x) is cut where it turns upwards
///    (the foot of the face) into maximal runs over which it is concave, and the region under each
///    run, down to a base level below the seabed, is one convex prism extruded along y: the toe
///    (front face and top) and the face with the crest. Merging convex runs keeps internal seams
///    away from the convex edges (toe edge, crest edge) where units rest. A rough face (roughness)
///    replaces the cells' part of the face by the height-field pieces below;
///  - height field: each cell is an inverted pyramid (four triangles from its corners on the base
///    plane to its lowered centre). The surface over two triangles that share a cell edge (one in
///    each cell) is a ridge, so the region below them is convex: one prism per interior cell edge
///    (a diamond seen from above), one triangular prism per border edge, and four prisms with the
///    plain base plane as top around the field. Seams then lie along the valleys (corner to lowered
///    centre), where a touching body meets both faces anyway;
///  - fixed mesh: a World shape and a fixed body.
/// Items that are unbounded in the scene (a slope along y, the crest onshore, the plane around a
/// height field) are cut to the StaticDomain: the bounding box of the bodies, the items and the
/// walls, grown by a margin. A body that leaves it falls off the edge; walls prevent that.
///
/// Errors (core::InputError) name the scene file and the item, e.g.
///   "pile.yaml: shape 'unit' (mesh /case/unit.stl): 3 open edges, ...".

#include "io/Scene.hpp"
#include "simulation/World.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace armour::simulation {

/// A static convex piece: the convex hull of its corners (what World::addConvex takes).
struct ConvexPiece {
  std::string name;          ///< "<item>/<part>", e.g. "underlayer/toe", "bed/edge-x(3,4)"
  std::vector<Vec3> corners; ///< world (unit: m)
  MaterialId material = 0;
};

/// Where unbounded static items are cut, and how deep convex pieces reach.
struct StaticDomain {
  double xMin = -1.0, xMax = 1.0; ///< extent along x (unit: m)
  double yMin = -1.0, yMax = 1.0; ///< extent along y (unit: m)
  /// How far convex pieces reach below the lowest point of their surface (unit: m). Far deeper
  /// than any contact overlap (a fraction of Dn), so a body never feels a piece's bottom face.
  double depth = 1.0;
  /// The sides where a cut item ends above what lies beyond (an edge to fall off): x min, x max,
  /// y min, y max. A slope's crest onshore and its ends along y; every side of a height field's
  /// plane. Not a slope's offshore side: its seabed half-space continues there at the toe's foot.
  bool edge[4] = {false, false, false, false};

  /// A centroid past one of the edges (or NaN): off the scene's unbounded items.
  [[nodiscard]] bool beyondEdge(const Vec3& x) const {
    const bool inside[4] = {x.x() >= xMin, x.x() <= xMax, x.y() >= yMin, x.y() <= yMax};
    for (int k = 0; k < 4; ++k)
      if (edge[k] && !inside[k]) return true;
    return false;
  }
};

/// The World built from a scene, with the maps from scene items to World ids.
struct BuiltScene {
  std::unique_ptr<World> world;
  /// World body of scene body i (Scene::bodies order); static meshes come after them.
  std::vector<BodyId> bodyIndexOfSceneBody;
  /// World shape of scene shape i; empty for a shape no body uses (not built, with a warning).
  std::vector<std::optional<ShapeId>> shapeOfSceneShape;
  /// World material i = scene material i, as given to World (damping ratio -> restitution).
  std::vector<Material> materials;
  std::vector<StaticPlane> planes;        ///< every half-space added (planes, walls, seabeds)
  std::vector<ConvexPiece> convexPieces;  ///< every convex piece (slopes, height fields)
  std::vector<BodyId> staticMeshBodies;   ///< fixed bodies of the static meshes
  StaticDomain domain;                    ///< where unbounded items were cut
  double stableTimeStep = 0.0;            ///< World::stableTimeStep() (unit: s)
  double timeStep = 0.0;                  ///< World::timeStep(): the step a run uses (unit: s)
  std::vector<std::string> warnings;      ///< non-fatal notes from building (also logged)

  [[nodiscard]] std::size_t staticPieceCount() const {
    return planes.size() + convexPieces.size() + staticMeshBodies.size();
  }
};

/// The closed surface of a scene shape in its natural frame: a generator at V = 1 m^3, or a mesh
/// file at its own size, validated (orientation repaired where unambiguous, with a warning).
geometry::TriangleMesh shapeMesh(const io::ShapeSpec& spec);

/// The World settings a scene asks for (gravity, time step, contact resolution, guard rail, sleep).
WorldSettings worldSettings(const io::Scene& scene);

/// The World material of a scene material: a damping ratio zeta is turned into the restitution
/// e = contact::restitutionOfClampedDashpot(zeta) that World turns back into zeta.
/// @throws core::InputError naming `where` if zeta is so large that e underflows.
Material worldMaterial(const io::Material& material, const std::string& where);

/// The domain a scene's unbounded static items are cut to (after its shapes are known: `bodyRadius`
/// holds each scene body's bounding radius, m).
StaticDomain staticDomain(const io::Scene& scene, const std::vector<double>& bodyRadius);

/// The seabed half-space of a slope: z <= the lowest profile point (the toe's foot).
StaticPlane slopeSeabed(const io::StaticSlope& slope, MaterialId material);

/// Convex pieces of a slope above its seabed, extruded over the domain's y extent; with
/// roughness, the height-field pieces of the face cells included.
std::vector<ConvexPiece> slopePieces(const io::StaticSlope& slope, const StaticDomain& domain, MaterialId material);

/// Convex pieces of a height-field item: the cells and the plain plane around them within the
/// domain, down to `domain.depth` below the lowest point.
std::vector<ConvexPiece> heightFieldPieces(const io::StaticHeightField& item, const StaticDomain& domain,
                                           MaterialId material);

/// Build the World: materials, shapes (level sets and samples), bodies, static geometry, and
/// resolve the time step (a fixed step above the stability limit is an error).
/// @throws core::InputError naming the scene file and the item.
BuiltScene buildWorld(const io::Scene& scene);

/// A few lines for `armour check` and the run log: counts of bodies, shapes and static pieces,
/// the static domain, the stable and the used time step.
std::string describeBuild(const io::Scene& scene, const BuiltScene& built);

} // namespace armour::simulation
