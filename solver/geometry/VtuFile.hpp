// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VtuFile.hpp
/// VTK XML UnstructuredGrid (.vtu) output of tetrahedral meshes, for ParaView.

#include "geometry/Tetrahedralizer.hpp"

#include <filesystem>

namespace armour::geometry {

/// Write a tet mesh atomically as linear tetrahedra (VTK_TETRA) with a cell field "volume" (m^3).
void writeVtu(const TetMesh& mesh, const std::filesystem::path& path);

} // namespace armour::geometry
