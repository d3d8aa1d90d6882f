// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableCheckpoint.hpp
/// The dynamic state of one deformable body (DeformableState) in a small binary file, so that a
/// stopped run continues bit for bit. Layout (little-endian, as the machine writes it):
///   8 bytes magic "ARMDEF01", uint32 format version, uint32 nodes-per-element,
///   uint64 nodes, uint64 elements, uint64 steps, double time, uint8 accelerations ready,
///   then nodes x 3 doubles each of positions, velocities and accelerations; from version 2, uint64
///   friction anchors A (0 without friction), A x 3 doubles of anchors and A bytes of their flags.
///   From version 3, uint64 length L and L bytes of text: setupIdentity() of the body that wrote
///   it. From version 4, uint64 body friction anchors B (0 without body friction), B int32 target
///   tets and B x 4 doubles of barycentric coordinates (BodyFriction.hpp). Version 1 to 3 files
///   (no anchors; no setup text; no body friction) are still read.
/// The mesh, material and boundary conditions are not stored: they come from the setup. The reader
/// refuses a file whose node and element counts or element order differ, and (version 3) one
/// whose setup text differs from the body's, naming the first line that changed. Boundary
/// conditions (fixed nodes, external forces, initial velocities) are not in the text. Written
/// atomically (core/AtomicFile.hpp).

#include "deformable/DeformableBody.hpp"

#include <filesystem>
#include <string>

namespace armour::deformable {

inline constexpr std::uint32_t kDeformableCheckpointVersion = 4;

/// The setup a checkpoint belongs to, one "key = value" line each: the mesh (counts and a hash of
/// its nodes and connectivity), the material, gravity, F-bar, damping, step safety, mass scaling,
/// half-spaces and contact settings (DeformableSettings), and the rigid obstacles: scale and level
/// set of each, with the pose of a fixed one (a moving one's pose is state, kept by its owner's
/// checkpoint: RigidObstacle::moving).
[[nodiscard]] std::string setupIdentity(const DeformableBody& body);

/// Throws core::InputError naming the path if it cannot be written.
void writeDeformableCheckpoint(const DeformableBody& body, const std::filesystem::path& path);

/// Read a checkpoint into `body`. Throws core::InputError naming the file and what is wrong (not
/// a checkpoint, another version, another mesh, truncated, non-finite values) and the fix.
void readDeformableCheckpoint(const std::filesystem::path& path, DeformableBody& body);

} // namespace armour::deformable
