// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CaseChecks.hpp
/// What foam-proxy checks in an OpenFOAM case before it samples it or writes its function objects
/// (docs/foam-bridge.md, "Cases the bridge refuses"): the same two refusals as the armourSampler
/// function object.
///  - The mesh must be static: the unit faces, their voxels and the samples per voxel of the storm
///    file are found once. constant/dynamicMeshDict naming any dynamicFvMesh other than
///    staticFvMesh (dynamicRefineFvMesh, dynamicMotionSolverFvMesh, ...) is refused.
///  - Gravity must point along -z (the storm file has z up, x along the waves, y along the trunk).

#include <array>
#include <filesystem>
#include <optional>
#include <string>

namespace armour::proxy {

/// The `dynamicFvMesh` entry of CASE/constant/dynamicMeshDict; "staticFvMesh" when the file or the
/// entry is absent (what OpenFOAM's solvers then build).
std::string dynamicMeshType(const std::filesystem::path& caseDir);

/// Throws core::InputError naming constant/dynamicMeshDict, the mesh type and the fix when the
/// case's mesh changes during the run.
void requireStaticMesh(const std::filesystem::path& caseDir);

/// The `value` of CASE/constant/g (m/s^2), or nothing when the file is absent.
std::optional<std::array<double, 3>> caseGravity(const std::filesystem::path& caseDir);

/// Throws core::InputError naming constant/g, its value and the fix (transformPoints) when g is not
/// along -z (sideways components above 1e-6 |g|, the armourSampler's tolerance). No file: no check.
void requireGravityAlongMinusZ(const std::filesystem::path& caseDir);

/// The storm file's source_case for a case folder, as the armourSampler function object writes it:
/// absolute, normalised, without a trailing separator ("--case ." gave "/runs/tank/").
std::string sourceCasePath(const std::filesystem::path& caseDir);

} // namespace armour::proxy
