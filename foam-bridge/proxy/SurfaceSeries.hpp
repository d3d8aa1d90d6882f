// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SurfaceSeries.hpp
/// Reading the output of OpenFOAM's stock `surfaces` function object: one folder per sample time,
///     postProcessing/<function name>/<time>/<surface name>.vtk   (legacy, `legacy true`)
///     postProcessing/<function name>/<time>/<surface name>.vtp   (XML, v1912's default)
/// with the face (polygon) geometry and the sampled fields as cell data (face values: the
/// surfaces are sampled with `interpolate false`). Read with VTK 9 (IOLegacy, IOXML).

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace armour::proxy {

/// One sampled surface at one time.
struct Surface {
  std::vector<double> points;                     ///< 3 per point (unit: m)
  std::vector<long> offsets;                      ///< face f has points connectivity[offsets[f] .. offsets[f+1])
  std::vector<long> connectivity;                 ///< point indices
  std::vector<double> centreX, centreY, centreZ;  ///< face centres, OpenFOAM's rule (unit: m)
  std::vector<double> areaX, areaY, areaZ;        ///< face area vectors, OpenFOAM's rule (unit: m^2)
  std::map<std::string, std::vector<double>> fields; ///< per face, components interleaved
  std::map<std::string, int> components;          ///< 1 scalar, 3 vector

  std::size_t faces() const { return centreX.size(); }
  /// The field (components interleaved); throws InputError naming the file and the fields present.
  const std::vector<double>& field(const std::string& name, int expectedComponents) const;
  std::string source; ///< the file read
  /// z range and x range of face f's points (unit: m).
  void bounds(std::size_t f, double& xLo, double& xHi, double& yLo, double& yHi, double& zLo, double& zHi) const;
  /// True if the point (x, z) lies inside face f projected on the x-z plane.
  bool containsXZ(std::size_t f, double x, double z) const;
};

/// Read a .vtk (legacy, ASCII or binary) or .vtp file. Throws core::InputError.
Surface readSurface(const std::filesystem::path& file);

/// Values at points from OpenFOAM's stock `sets` function object (setFormat raw, axis xyz):
///     postProcessing/<function>/<time>/<set>_<scalar fields joined by _>.xy   x y z s1 s2 ...
///     postProcessing/<function>/<time>/<set>_<vector fields joined by _>.xy   x y z v1x v1y v1z ...
/// Points that lie in no cell are left out by OpenFOAM.
struct PointSet {
  std::vector<double> x, y, z;                       ///< unit: m
  std::map<std::string, std::vector<double>> fields; ///< components interleaved
  std::map<std::string, int> components;
  std::string source;                                ///< the folder and set name
  std::size_t size() const { return x.size(); }
  const std::vector<double>& field(const std::string& name, int expectedComponents) const;
};

/// Read the files of `set` in a time folder; `fieldNames` helps split file names of fields with
/// '_' in their names (p_rgh). Throws core::InputError if there are none.
PointSet readPointSet(const std::filesystem::path& timeFolder, const std::string& set,
                      const std::vector<std::string>& fieldNames);

/// The sample times under postProcessing/<function>: folder names that are numbers, sorted.
struct SampleTime {
  double time = 0.0;           ///< unit: s
  std::filesystem::path folder;
};
std::vector<SampleTime> listSampleTimes(const std::filesystem::path& functionFolder);

/// The file of `surface` in a time folder (.vtk preferred, then .vtp); throws if neither exists.
std::filesystem::path surfaceFile(const std::filesystem::path& timeFolder, const std::string& surface);

} // namespace armour::proxy
