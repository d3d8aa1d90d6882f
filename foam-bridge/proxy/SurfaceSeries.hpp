// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SurfaceSeries.hpp
/// Reading the output of OpenFOAM's stock `surfaces` function object: one folder per sample time,
///     postProcessing/<function name>/<time>/<field>_<surface name>.raw  (`surfaceFormat raw`)
///     postProcessing/<function name>/<time>/<surface name>.vtk   (legacy, `legacy true`)
///     postProcessing/<function name>/<time>/<surface name>.vtp   (XML, v1912's default)
/// with the sampled fields as face values (the surfaces are sampled with `interpolate false`).
/// raw: per field, the face centres and values as text at the case's writePrecision (double
/// precision with 15 digits; no face geometry, so no areas). vtk/vtp: the polygons and the
/// values as cell data, stored as float by v1912's VTK writers (its ASCII writer too); read with
/// VTK 9 (IOLegacy, IOXML).

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
  std::vector<double> areaX, areaY, areaZ;        ///< face area vectors, OpenFOAM's rule (unit: m^2); empty from raw files
  std::map<std::string, std::vector<double>> fields; ///< per face, components interleaved
  std::map<std::string, int> components;          ///< 1 scalar, 3 vector

  std::size_t faces() const { return centreX.size(); }
  bool hasGeometry() const { return areaX.size() == centreX.size(); } ///< polygons and areas (vtk/vtp), not raw
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

/// Read the raw output of `surface` in a time folder: <field>_<surface>.raw for each of
/// `fieldNames` present (at least one), each "# <field>  FACE_DATA <n>", "# x  y  z  <columns>",
/// then per face its centre (OpenFOAM's face::centre of the surface points) and value(s).
/// The centres come from the first file and must repeat in the others. Throws core::InputError.
Surface readRawSurface(const std::filesystem::path& timeFolder, const std::string& surface,
                       const std::vector<std::string>& fieldNames);

/// The surface in a time folder in whichever format is there: raw files of `fieldNames` first
/// (double precision), then <surface>.vtk, then <surface>.vtp. Throws core::InputError if none.
Surface readSurfaceIn(const std::filesystem::path& timeFolder, const std::string& surface,
                      const std::vector<std::string>& fieldNames);

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
/// '_' in their names (p_rgh). With `needed` given, files holding none of those fields are not
/// read (the eta set needs alpha only, not the U file). Throws core::InputError if none is read.
PointSet readPointSet(const std::filesystem::path& timeFolder, const std::string& set,
                      const std::vector<std::string>& fieldNames, const std::vector<std::string>& needed = {});

/// The sample times under postProcessing/<function>: folder names that are numbers, sorted.
struct SampleTime {
  double time = 0.0;           ///< unit: s
  std::filesystem::path folder;
};
std::vector<SampleTime> listSampleTimes(const std::filesystem::path& functionFolder);

/// The file of `surface` in a time folder (.vtk preferred, then .vtp); throws if neither exists.
std::filesystem::path surfaceFile(const std::filesystem::path& timeFolder, const std::string& surface);

} // namespace armour::proxy
