// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VtpFile.hpp
/// VTK XML PolyData (.vtp), read and written with VTK 9 so that ParaView opens what we write and
/// we read what ParaView writes. Polygons and triangle strips are triangulated on reading.

#include "geometry/TriangleMesh.hpp"

#include <filesystem>

namespace armour::geometry {

TriangleMesh readVtp(const std::filesystem::path& path);
/// Write a .vtp atomically (binary appended data, zlib-compressed).
void writeVtp(const TriangleMesh& mesh, const std::filesystem::path& path);

} // namespace armour::geometry
