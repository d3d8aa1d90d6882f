// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file MeshFile.hpp
/// Read and write surface meshes by file format: STL (ASCII and binary), Wavefront OBJ and VTK
/// XML PolyData (.vtp). Reading welds coincident vertices (STL stores every corner separately)
/// and triangulates polygons; it does not validate: call validateMesh on the result.

#include "geometry/TriangleMesh.hpp"

#include <filesystem>
#include <string>

namespace armour::geometry {

enum class MeshFormat { Stl, StlAscii, Obj, Vtp };

/// "stl" (binary), "stl-ascii", "obj", "vtp"; throws InputError listing the valid names.
MeshFormat meshFormatFromName(const std::string& name);
/// From the file extension (.stl, .obj, .vtp, case-insensitive); throws InputError otherwise.
MeshFormat meshFormatFromPath(const std::filesystem::path& path);

/// Read a surface mesh; the format comes from the extension (STL: ASCII or binary detected).
TriangleMesh readMesh(const std::filesystem::path& path);

/// readMesh, then validateMesh (geometry/MeshValidation.hpp): throws core::InputError naming the
/// file and the defect; an orientation it repaired is logged as a warning by the `logModule`
/// logger ("geometry", "scene", "deform").
TriangleMesh readValidMesh(const std::filesystem::path& path, const std::string& logModule = "geometry");

/// Write a surface mesh atomically in the given format.
void writeMesh(const TriangleMesh& mesh, const std::filesystem::path& path, MeshFormat format);

} // namespace armour::geometry
