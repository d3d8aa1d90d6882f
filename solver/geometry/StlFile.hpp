// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StlFile.hpp
/// STL (stereolithography) files. Binary: 80-byte header, uint32 triangle count, then 50 bytes
/// per triangle (normal, three corners as little-endian float32, uint16 attribute). ASCII:
/// "solid ... facet normal ... outer loop / vertex x y z (x3) / endloop / endfacet ... endsolid".
/// Corners are single precision in binary files: about 7 significant digits.

#include "geometry/TriangleMesh.hpp"

#include <filesystem>

namespace armour::geometry {

/// Read ASCII or binary STL (detected from the size and the first bytes); welds exact duplicates.
TriangleMesh readStl(const std::filesystem::path& path);
/// Write STL atomically; binary unless `ascii` (ASCII keeps 17 significant digits).
void writeStl(const TriangleMesh& mesh, const std::filesystem::path& path, bool ascii = false);

} // namespace armour::geometry
