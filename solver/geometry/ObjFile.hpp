// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ObjFile.hpp
/// Wavefront OBJ: "v x y z" vertex lines and "f i j k ..." faces (1-based; negative indices count
/// back from the last vertex; "i/t/n" forms accepted, texture and normal indices ignored). Faces
/// with more than three corners are split into a fan. Other statements (vn, vt, o, g, s, usemtl,
/// mtllib) are skipped.

#include "geometry/TriangleMesh.hpp"

#include <filesystem>

namespace armour::geometry {

TriangleMesh readObj(const std::filesystem::path& path);
/// Write OBJ atomically with 17 significant digits (round-trips doubles exactly).
void writeObj(const TriangleMesh& mesh, const std::filesystem::path& path);

} // namespace armour::geometry
