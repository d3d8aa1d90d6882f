// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableScene.hpp
/// A deformable-body scene file (`armour deform`, docs/deformable-file.md) as read: units and
/// blocks meshed into one deformable mesh, static half-spaces, material, contact and run settings.
/// Plain data; `armour deform` builds the deformable::DeformableBody from it (app/DeformCommands).

#include "geometry/TriangleMesh.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace armour::io {

/// One body of the mesh: a shape of the library or a surface mesh file meshed by gmsh, or a box of
/// Kuhn cells.
struct DeformablePart {
  std::string name;
  std::string shape;                  ///< library shape (geometry/ShapeLibrary); empty for a box or a mesh file
  std::filesystem::path meshFile;     ///< a closed surface mesh (absolute); empty for a library shape or a box
  double volume = 0.0;                ///< shape volume (unit: m^3); for a mesh file 0 = its own size
  std::uint64_t tets = 0;             ///< wanted tetrahedra of the shape (unit: -)
  std::uint64_t shapeSeed = 1;        ///< seed of a random shape (rock, voronoi-rock)
  std::map<std::string, double> params; ///< the shape generator's parameters (armour shape list)
  Eigen::Vector3d box = Eigen::Vector3d::Zero(); ///< box size (unit: m); zero for a shape
  std::array<std::uint64_t, 3> cells{1, 1, 1};   ///< box cells along x, y, z (6 tets each)
  Eigen::Vector3d position = Eigen::Vector3d::Zero(); ///< shape centroid or box centre (unit: m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< natural frame -> world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero(); ///< initial velocity of every node (unit: m/s)
};

/// A rigid body (`rigid_bodies:`): a library shape at a pose, felt through its level set
/// (deformable/RigidObstacleContact.hpp), fixed or moving (then a body of armour's rigid solver,
/// simulation/DeformableCoupling.hpp). Only shape, volume, shape_seed, params, position,
/// orientation and velocity of `part` are used.
struct RigidPart {
  DeformablePart part;
  double cellsPerDn = 24.0;           ///< level-set cells per Dn (unit: -)
  bool fixed = true;                  ///< false: it moves under gravity and its contacts
  double density = 0.0;               ///< of a moving body (unit: kg/m^3); the scene's material density when not given
};

/// The library surface of a part (shape, volume, shape_seed, params), centred on its centroid,
/// in the shape's natural frame. Throws core::InputError from the shape generator.
[[nodiscard]] geometry::TriangleMesh librarySurface(const DeformablePart& part);

struct DeformableHalfSpace {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< unit: m
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); ///< unit outward normal of the solid (normalised on reading)
};

struct DeformableScene {
  std::filesystem::path file;         ///< where it was read from
  // material (seed 002 Table 2 by default)
  double density = 2340.0;            ///< unit: kg/m^3
  double youngModulus = 26.6e9;       ///< unit: Pa
  double poissonRatio = 0.205;        ///< unit: -
  double viscosityFraction = 0.0;     ///< of 2 h sqrt(E rho), h = (V / N)^(1/3) of the mesh (unit: -)
  bool quadratic = true;              ///< element: tet10 (true) or tet4
  bool fBar = true;                   ///< F-bar on 10-node elements
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81); ///< unit: m/s^2
  std::vector<DeformablePart> parts;
  std::vector<RigidPart> rigidBodies; ///< rigid bodies, fixed or moving: a deformable unit in a rigid pack
  std::vector<DeformableHalfSpace> halfSpaces;
  double friction = 0.0;              ///< Coulomb mu on the half-spaces (unit: -)
  double contactGradient = 0.0;       ///< G of the half-spaces (unit: Pa/m); 0 = 10 E / h
  double contactPenalty = 0.0;        ///< body contact p (unit: Pa); 0 = 2 E
  double contactDamping = 0.0;        ///< body contact zeta (unit: -)
  double bodyFriction = 0.0;          ///< Coulomb mu between the deformable bodies (unit: -)
  double rigidPenaltyModulus = 1.0e9; ///< contact of moving rigid bodies with each other and the half-spaces (unit: Pa)
  double rigidRestitution = 0.05;     ///< the same contact's restitution (unit: -), seed 001
  double massDamping = 0.0;           ///< unit: 1/s
  double duration = 0.01;             ///< simulated time (unit: s)
  double stepSafety = 0.9;            ///< of the stable step (unit: -)
  double massScaling = 0.0;           ///< largest added mass over the mass, 0 = off (unit: -)
  double framesEvery = 0.0;           ///< VTU frame interval (unit: s); 0 = first and last only
  std::uint64_t stressEvery = 5;      ///< steps between stress samples (unit: -)
  double checkpointEvery = 600.0;     ///< wall time between checkpoints (unit: s)
  std::filesystem::path output = "deform-out"; ///< output folder (relative to the file)
};

/// Read a deformable scene. Throws core::InputError naming the file, line, key, value and fix.
[[nodiscard]] DeformableScene readDeformableScene(const std::filesystem::path& file);

} // namespace armour::io
