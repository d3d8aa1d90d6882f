// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VtpFile.hpp
/// VTK XML PolyData (.vtp), read and written with VTK 9 so that ParaView opens what we write and
/// we read what ParaView writes. Polygons and triangle strips are triangulated on reading.

#include "geometry/TriangleMesh.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace armour::geometry {

TriangleMesh readVtp(const std::filesystem::path& path);
/// Write a .vtp atomically (binary appended data, zlib-compressed).
void writeVtp(const TriangleMesh& mesh, const std::filesystem::path& path);

/// A named value per triangle (VTK cell data), e.g. a stress for colouring in ParaView.
struct CellArray {
  std::string name;           ///< e.g. "max_sigma1_Pa"
  std::vector<double> values; ///< one per triangle
};
/// writeVtp with cell data. @pre every array has one value per triangle (std::invalid_argument).
void writeVtp(const TriangleMesh& mesh, const std::filesystem::path& path, const std::vector<CellArray>& cells);

} // namespace armour::geometry
