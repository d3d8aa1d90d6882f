// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VoxelGrid.hpp
/// The x-z voxel grid of seed 000 (section 2.2, Fig. 3): uniform rectangular voxels in the x-z
/// plane, each extruded along y over the trunk section [trunkOrigin, trunkOrigin + trunkLength].
/// A surface element (face) belongs to the voxel that holds its centre; faces outside the grid or
/// outside the trunk section belong to none.
///
/// Boundaries are widened by kBoundarySnap of a voxel towards lower indices: a centre on a voxel
/// boundary, or within round-off of it, belongs to the voxel above the boundary. Castellated
/// meshes put many faces exactly on mesh planes, and a grid aligned with the mesh puts those on
/// voxel boundaries (the 3D smoke case: 55 of 591 unit faces); the function object (mesh face
/// centres) and foam-proxy (centres recomputed from the written points, or a different but
/// equivalent formula) differ there in the last bits, and a plain floor() sent such faces to
/// different voxels (online vs offline voxel means 3.5e-3 apart). A face that is really 1e-6 of a
/// voxel below a boundary is moved by a distance no physical quantity of the storm file resolves.
///
/// Plain C++11: shared by the OpenFOAM function object (compiled with OpenFOAM's -std=c++11) and
/// foam-proxy. Bad settings throw std::invalid_argument naming the key, the value and the fix.

#include <cstddef>
#include <string>
#include <vector>

namespace armour {
namespace bridge {

/// Geometry of the voxel grid. Intervals are half-open: voxel ix covers [xMin + ix dx, xMin + (ix+1) dx),
/// both ends moved down by kBoundarySnap dx (see above).
struct VoxelGridSettings {
  double xMin = 0.0;        ///< x of the offshore face of the first voxel column (unit: m)
  double zMin = 0.0;        ///< z of the bottom face of the first voxel row (unit: m)
  double dx = 0.05;         ///< voxel width along x (unit: m); 0.05 in seed 000
  double dz = 0.05;         ///< voxel height along z (unit: m); 0.05 in seed 000
  int nx = 0;               ///< voxel columns (unit: -); >= 2 (a storm file needs 2)
  int nz = 0;               ///< voxel rows (unit: -); >= 2
  double trunkOrigin = 0.0; ///< y where the averaged trunk section starts (unit: m)
  double trunkLength = 0.0; ///< length of the section along y (unit: m); 44.5 in seed 000
};

/// Finds the voxel or column of a point by division (uniform grid), never by search.
class VoxelGrid {
public:
  /// Voxel boundaries (and the trunk ends) are moved this fraction of a voxel (of the trunk
  /// length) towards lower coordinates (unit: -). Larger than the round-off of face centres
  /// computed two ways in double (~1e-13 of a voxel) and than float rounding of points up to
  /// |x| ~ 16 dx; far below anything physical.
  static constexpr double kBoundarySnap = 1e-6;

  /// Validate (nx, nz >= 2, dx, dz, trunkLength > 0, all finite) and build.
  explicit VoxelGrid(const VoxelGridSettings& settings);

  const VoxelGridSettings& settings() const { return settings_; }
  int nx() const { return settings_.nx; }
  int nz() const { return settings_.nz; }
  std::size_t voxels() const { return static_cast<std::size_t>(settings_.nx) * static_cast<std::size_t>(settings_.nz); }

  double xCentre(int ix) const { return settings_.xMin + (ix + 0.5) * settings_.dx; } ///< unit: m
  double zCentre(int iz) const { return settings_.zMin + (iz + 0.5) * settings_.dz; } ///< unit: m
  std::vector<double> xCentres() const;
  std::vector<double> zCentres() const;
  double trunkMiddle() const { return settings_.trunkOrigin + 0.5 * settings_.trunkLength; } ///< unit: m

  /// Column index of x, or -1 outside [xMin, xMin + nx dx) (ends moved down by kBoundarySnap dx).
  int column(double x) const;
  /// Row index of z, or -1 outside [zMin, zMin + nz dz) (ends moved down by kBoundarySnap dz).
  int row(double z) const;
  /// True if y lies in the trunk section [trunkOrigin, trunkOrigin + trunkLength] widened by
  /// kBoundarySnap trunkLength at both ends (closed: a face on the end wall of a section counts).
  bool inTrunk(double y) const;
  /// Voxel index iz * nx + ix of the point, or -1 if it is outside the grid or the trunk section.
  long voxel(double x, double y, double z) const;

private:
  VoxelGridSettings settings_;
};

/// Move xMin and zMin by at most half a voxel (down at a tie) so that the lattice of voxel centres
/// passes through x (and z): put the centres, not the edges, on the flat faces of axis-aligned
/// units (docs/foam-bridge.md, "Where the voxels sit"). NaN leaves that axis as it is.
void centreVoxelsOn(VoxelGridSettings& grid, double x, double z);

/// Throw std::invalid_argument("<where>: <message>"): the C++11 core's input errors (foam-proxy
/// turns them into core::InputError, the function object into a FatalError).
void failSetting(const std::string& where, const std::string& message);

} // namespace bridge
} // namespace armour
