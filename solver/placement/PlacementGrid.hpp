// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacementGrid.hpp
/// The points units are lowered from, in placement order: a generated grid of rows in the slope
/// plane (staggered or parallelogram; spacing from a target packing density), or a user's grid
/// file. docs/placement.md, "Grids".
///
/// A generated grid lies in the plane of the slope face: s is the distance up the face from the
/// slope's origin (the foot of the face, on the toe), y runs along the trunk. Row r has
/// n_r = unitsPerRow[r mod k] units at y = yStart + frac((c + 1/2) dx + o_r, width), with the row
/// offset o_r = frac(r * stagger) dx, and s = firstRow + r dy. Its packing density, with the area
/// measured in the slope plane, is phi = n Dn^2 / (W dy) (seed 000: N Dn^2 / A), n the mean units
/// per row over a cycle of unitsPerRow and W the width, so a target phi gives
/// dy = n Dn^2 / (phi W); with equal rows filling the width, phi = Dn^2 / (dx dy). Order: rows from the toe up, along y within a row, layer by layer.

#include "placement/PlacementSettings.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace armour::placement {

struct GridPoint {
  Eigen::Vector2d plan = Eigen::Vector2d::Zero(); ///< (x, y) of the vertical the unit is lowered along (unit: m)
  std::optional<double> startZ;   ///< height to lower from (grid files with a z column); none = from above (unit: m)
  double s = 0.0;                 ///< up-slope distance in the slope plane (unit: m); NaN for grid-file points
  int row = 0, column = 0, layer = 0; ///< indices (unit: -)
};

/// The slope a generated grid lies on.
struct GridSlope {
  double originX = 0.0;  ///< x of the foot of the face (unit: m)
  double originZ = 0.0;  ///< z of the foot of the face (unit: m)
  double tanAlpha = 0.5; ///< gradient (unit: -)
};

/// The grid spacings actually used (unit: m) and the packing density they give, n Dn^2 / (W dy) (unit: -).
struct GridSpacing {
  double dx = 0.0, dy = 0.0, width = 0.0, packingDensity = 0.0;
};

/// Resolve dx, dy and the width from the settings (width 0: `wallWidth`, the distance between
/// the trunk walls). Throws core::InputError naming `source` and the key for impossible values.
GridSpacing gridSpacing(const GridSettings& grid, double dn, double wallWidth, const std::string& source);

/// The generated grid (no file): grid.layers copies, layer L shifted by L x (layerShiftS,
/// layerShiftY) Dn and lowered onto the layers below. Jitter is drawn from `seed`.
std::vector<GridPoint> generateGrid(const GridSettings& grid, const GridSlope& slope, double dn, double wallWidth,
                                    std::uint64_t seed, const std::string& source);

/// Points from a CSV grid file: one point per line, "x,y" or "x,y,z" (m, world), '#' comments and
/// a header line of names allowed. Throws core::InputError naming the file, the line and the fix.
std::vector<GridPoint> readGridFile(const std::string& path);

} // namespace armour::placement
