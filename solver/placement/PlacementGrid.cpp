// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/PlacementGrid.hpp"

#include "core/Error.hpp"

#include <algorithm>

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

namespace armour::placement {

GridSpacing gridSpacing(const GridSettings& grid, double dn, double wallWidth, const std::string& source) {
  GridSpacing g;
  if (grid.unitsPerRow.empty() || grid.unitsPerRow.front() < 1)
    core::failInput(source, "placement.grid.units_per_row: needs at least one positive count, e.g. [12, 11]");
  g.width = grid.width > 0.0 ? grid.width : wallWidth;
  if (!(g.width > 0.0))
    core::failInput(source, "placement.grid.width: not given and no pair of trunk walls (type: wall, axis: y) to take "
                            "it from; give width: <m>");
  g.dx = grid.dx > 0.0 ? grid.dx * dn : g.width / grid.unitsPerRow.front();
  // Units per row on average over a cycle of the row counts (11.5 for rows of 12 and 11).
  double mean = 0.0;
  for (int n : grid.unitsPerRow) mean += n;
  mean /= static_cast<double>(grid.unitsPerRow.size());
  if (grid.dy > 0.0) {
    g.dy = grid.dy * dn;
  } else if (grid.packingDensity > 0.0) {
    g.dy = mean * dn * dn / (grid.packingDensity * g.width);
  } else {
    core::failInput(source, "placement.grid: give dy (row spacing, Dn) or packing_density (e.g. 0.62 for Core-Loc)");
  }
  g.packingDensity = mean * dn * dn / (g.width * g.dy);
  const int widest = *std::max_element(grid.unitsPerRow.begin(), grid.unitsPerRow.end());
  if (widest * g.dx > g.width * (1.0 + 1e-9))
    core::failInput(source, "placement.grid: {} units at dx = {:.4g} m need {:.4g} m, more than the width {:.4g} m; "
                            "use fewer units per row or a smaller dx",
                    widest, g.dx, widest * g.dx, g.width);
  return g;
}

std::vector<GridPoint> generateGrid(const GridSettings& grid, const GridSlope& slope, double dn, double wallWidth,
                                    std::uint64_t seed, const std::string& source) {
  if (grid.rows < 1) core::failInput(source, "placement.grid.rows = {}: must be at least 1", grid.rows);
  if (grid.layers < 1) core::failInput(source, "placement.grid.layers = {}: must be at least 1", grid.layers);
  const GridSpacing g = gridSpacing(grid, dn, wallWidth, source);
  const double cosA = 1.0 / std::sqrt(1.0 + slope.tanAlpha * slope.tanAlpha);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  const auto jitter = [&] {
    return grid.jitter * dn * (2.0 * static_cast<double>(rng() >> 11) * 0x1.0p-53 - 1.0);
  };
  std::vector<GridPoint> points;
  for (int layer = 0; layer < grid.layers; ++layer) {
    for (int r = 0; r < grid.rows; ++r) {
      const int n = grid.unitsPerRow[static_cast<std::size_t>(r) % grid.unitsPerRow.size()];
      const double offset = (r * grid.stagger - std::floor(r * grid.stagger)) * g.dx;
      for (int c = 0; c < n; ++c) {
        GridPoint p;
        p.row = r;
        p.column = c;
        p.layer = layer;
        p.s = (grid.firstRow + layer * grid.layerShiftS) * dn + r * g.dy + jitter();
        double y = (c + 0.5) * g.dx + offset + layer * grid.layerShiftY * dn;
        y -= std::floor(y / g.width) * g.width; // parallelogram grids wrap around the trunk
        y += jitter();
        p.plan = Eigen::Vector2d(slope.originX + p.s * cosA, grid.yStart + y);
        points.push_back(p);
      }
    }
  }
  return points;
}

std::vector<GridPoint> readGridFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) core::failInput(path, "cannot open the grid file (placement.grid.file); give a CSV of x,y[,z] per line");
  std::vector<GridPoint> points;
  std::string line;
  int lineNo = 0;
  bool headerAllowed = true;
  while (std::getline(in, line)) {
    ++lineNo;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::vector<double> values;
    std::stringstream ss(line);
    std::string field;
    bool numeric = true;
    while (std::getline(ss, field, ',')) {
      try {
        std::size_t used = 0;
        const double v = std::stod(field, &used);
        if (field.find_first_not_of(" \t\r", used) != std::string::npos) numeric = false;
        values.push_back(v);
      } catch (const std::exception&) {
        numeric = false;
      }
    }
    if (!numeric && headerAllowed) {
      headerAllowed = false; // a line of column names
      continue;
    }
    headerAllowed = false;
    if (!numeric || (values.size() != 2 && values.size() != 3))
      core::failInput(fmt::format("{}:{}", path, lineNo), "'{}': expected x,y or x,y,z in metres", line);
    for (double v : values)
      if (!std::isfinite(v)) core::failInput(fmt::format("{}:{}", path, lineNo), "'{}': not a finite number", line);
    GridPoint p;
    p.plan = Eigen::Vector2d(values[0], values[1]);
    if (values.size() == 3) p.startZ = values[2];
    p.s = std::nan("");
    p.row = static_cast<int>(points.size());
    points.push_back(p);
  }
  if (points.empty()) core::failInput(path, "the grid file has no points; give one x,y[,z] line per unit");
  return points;
}

} // namespace armour::placement
