// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file AnvilDrop.hpp
/// Seed 002's drop test (Table 2, Figs. 3-4) as one deformable mesh: a unit (a shape of the
/// library, meshed by gmsh, 10-node tets) standing on one arm, its lowest face `gap` above the
/// top of a concrete anvil block (structured Kuhn cells graded toward the contact, 10-node tets) that rests on a rigid
/// frictionless floor (its base nodes held vertically, free to slide), both of one material, in
/// contact through BodyContact.hpp. The unit moves down at `speed`; the anvil starts at rest and
/// unstressed. Axes: z up; the anvil's top face is z = 0, centred on x = y = 0; the unit is centred
/// on the same vertical axis.

#include "deformable/DeformableBody.hpp"

#include <string>
#include <vector>

namespace armour::deformable {

struct AnvilDropSettings {
  std::string shape = "vcross";      ///< shape generator name (geometry/ShapeLibrary)
  double volume = 14.0;              ///< unit volume (unit: m^3); seed 002: Vcross 14, VRcross 18
  std::size_t unitTets = 2000;       ///< wanted tets in the unit, gmsh (unit: -)
  Vec3 anvilSize = Vec3(8.0, 8.0, 4.0); ///< anvil block (unit: m); seed 002 Table 2
  int anvilCells = 16;               ///< Kuhn cells along the anvil's x side; y alike, z in proportion (unit: -)
  /// Grading of the anvil's cells toward the impact point (unit: -): coordinates stretched by
  /// sinh, x = (L/2) sinh(beta s) / sinh(beta) for s in [-1, 1] (z alike from the top face down),
  /// so the cells at the contact are beta / sinh(beta) of the uniform size and those at the far
  /// sides beta / tanh(beta) of it (2.5: 0.41 and 2.5). 0: uniform. A coarse anvil under the
  /// contact is stiff at first: its few contact nodes are heavy, and the first pressure comes out
  /// near rho c v (a rigid anvil's) instead of rho c v / 2.
  double anvilGrading = 2.5;
  double speed = 0.5;                ///< impact speed, downwards (unit: m/s); seed 002: 0.5
  double gap = 0.0;                  ///< unit's lowest face above the anvil at t = 0 (unit: m)
  DeformableSettings body;           ///< material, gravity, damping; bodyContact is switched on
};

struct AnvilDrop {
  DeformableBody body;
  std::vector<std::size_t> unitElements; ///< elements of the unit (they come first), increasing
  double unitVolume = 0.0;  ///< meshed volume of the unit (unit: m^3)
  double baseArea = 0.0;    ///< area of the unit's faces on its lowest plane (unit: m^2)
  Vec3 unitCentre = Vec3::Zero(); ///< centre of the unit's bounding box at t = 0 (unit: m)
};

/// Throws core::InputError naming the key for a bad shape, count or size.
[[nodiscard]] AnvilDrop makeAnvilDrop(const AnvilDropSettings& settings);

} // namespace armour::deformable
