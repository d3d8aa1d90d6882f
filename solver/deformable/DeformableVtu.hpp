// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableVtu.hpp
/// A VTU frame of a deformable unit for ParaView: the current mesh (VTK_TETRA or
/// VTK_QUADRATIC_TETRA) with, on nodes, displacement (m), velocity (m/s) and the node-averaged
/// stress fields, and on elements the stress fields: cauchy_stress (9 components, Pa),
/// sigma_1, sigma_2, sigma_3 (tension positive), differential_stress (sigma_1 - sigma_3) and
/// von_mises (Pa). Written atomically (appended binary, zlib).

#include "deformable/DeformableBody.hpp"

#include <filesystem>

namespace armour::deformable {

/// Throws core::InputError naming the path if VTK cannot write it.
void writeDeformableVtu(const DeformableBody& body, const std::filesystem::path& path);

} // namespace armour::deformable
