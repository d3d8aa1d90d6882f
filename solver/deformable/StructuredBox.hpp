// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StructuredBox.hpp
/// A box [0, size.x] x [0, size.y] x [0, size.z] split into nx x ny x nz cells of six tetrahedra
/// each (Kuhn's split along each cell's main diagonal, the same in every cell, so neighbouring
/// cells share their faces' diagonals and the mesh is conforming). For tests and benchmarks:
/// analytic solutions live on boxes and bars.

#include "geometry/Tetrahedralizer.hpp"

namespace armour::deformable {

/// Vertex (i, j, k) has index i + (nx + 1) * (j + (ny + 1) * k); tets are positively oriented.
/// Throws core::InputError when a size is not positive or a count is below 1 or above 1000.
geometry::TetMesh structuredBox(const geometry::Vec3& size, int nx, int ny, int nz);

} // namespace armour::deformable
