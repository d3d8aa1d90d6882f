// SPDX-License-Identifier: GPL-3.0-or-later
#include "bridge/VoxelGrid.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace armour {
namespace bridge {

void failSetting(const std::string& where, const std::string& message) {
  throw std::invalid_argument(where + ": " + message);
}

namespace {

void requirePositive(double value, const char* key, const char* fix) {
  if (!(std::isfinite(value) && value > 0.0)) {
    std::ostringstream s;
    s << "= " << value << " m: must be a positive finite length; " << fix;
    failSetting(key, s.str());
  }
}

} // namespace

VoxelGrid::VoxelGrid(const VoxelGridSettings& settings) : settings_(settings) {
  if (!std::isfinite(settings.xMin)) failSetting("xMin", "must be a finite x (m) of the first voxel column's offshore face");
  if (!std::isfinite(settings.zMin)) failSetting("zMin", "must be a finite z (m) of the first voxel row's bottom face");
  if (!std::isfinite(settings.trunkOrigin)) failSetting("trunkOrigin", "must be a finite y (m)");
  requirePositive(settings.dx, "dx", "give the voxel width along x, e.g. 0.05");
  requirePositive(settings.dz, "dz", "give the voxel height along z, e.g. 0.05");
  requirePositive(settings.trunkLength, "trunkLength", "give the length of the trunk section along y that is averaged");
  if (settings.nx < 2) {
    std::ostringstream s;
    s << "= " << settings.nx << ": a storm file needs at least 2 voxel columns; widen the grid or reduce dx";
    failSetting("nx", s.str());
  }
  if (settings.nz < 2) {
    std::ostringstream s;
    s << "= " << settings.nz << ": a storm file needs at least 2 voxel rows; heighten the grid or reduce dz";
    failSetting("nz", s.str());
  }
}

std::vector<double> VoxelGrid::xCentres() const {
  std::vector<double> x(static_cast<std::size_t>(settings_.nx));
  for (int i = 0; i < settings_.nx; ++i) x[static_cast<std::size_t>(i)] = xCentre(i);
  return x;
}

std::vector<double> VoxelGrid::zCentres() const {
  std::vector<double> z(static_cast<std::size_t>(settings_.nz));
  for (int i = 0; i < settings_.nz; ++i) z[static_cast<std::size_t>(i)] = zCentre(i);
  return z;
}

int VoxelGrid::column(double x) const {
  const double s = std::floor((x - settings_.xMin) / settings_.dx + kBoundarySnap);
  if (!(s >= 0.0 && s < settings_.nx)) return -1; // also rejects NaN
  return static_cast<int>(s);
}

int VoxelGrid::row(double z) const {
  const double s = std::floor((z - settings_.zMin) / settings_.dz + kBoundarySnap);
  if (!(s >= 0.0 && s < settings_.nz)) return -1;
  return static_cast<int>(s);
}

bool VoxelGrid::inTrunk(double y) const {
  const double tolerance = kBoundarySnap * settings_.trunkLength;
  return y >= settings_.trunkOrigin - tolerance && y <= settings_.trunkOrigin + settings_.trunkLength + tolerance;
}

long VoxelGrid::voxel(double x, double y, double z) const {
  if (!inTrunk(y)) return -1;
  const int ix = column(x);
  const int iz = row(z);
  if (ix < 0 || iz < 0) return -1;
  return static_cast<long>(iz) * settings_.nx + ix;
}

void centreVoxelsOn(VoxelGridSettings& grid, double x, double z) {
  // The origin of the lattice x - dx/2 + k dx nearest to the given one: a shift of at most dx/2;
  // at a tie (the given edges lie exactly on X) downwards, so the grid still covers its lower end.
  // 1e-9: a tie computed with round-off is still a tie.
  const auto align = [](double& origin, double at, double d) {
    if (!std::isfinite(at) || !(d > 0.0)) return;
    const double first = at - 0.5 * d;
    origin = first - std::floor((first - origin) / d + 0.5 + 1e-9) * d;
  };
  align(grid.xMin, x, grid.dx);
  align(grid.zMin, z, grid.dz);
}

} // namespace bridge
} // namespace armour
