// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/shapes/PlanarLoft.hpp"

#include <gmsh.h>

#include <cmath>

namespace armour::geometry::shapes {

std::vector<Vec3> squareSection(const Vec3& centre, const Vec3& e1, const Vec3& e2, double side) {
  const double h = 0.5 * side;
  return {centre + h * (e1 - e2), centre + h * (e1 + e2), centre + h * (-e1 + e2), centre - h * (e1 + e2)};
}

std::vector<Vec3> octagonSection(const Vec3& centre, const Vec3& e1, const Vec3& e2, double width, double stretch) {
  const double h = 0.5 * width;
  const double q = h * (std::sqrt(2.0) - 1.0);
  const double s = stretch;
  const double a[8][2] = {{h, -q - s}, {h, q + s},   {q, h + s},   {-q, h + s},
                          {-h, q + s}, {-h, -q - s}, {-q, -h - s}, {q, -h - s}};
  std::vector<Vec3> corners;
  for (const auto& p : a) {
    corners.push_back(centre + p[0] * e1 + p[1] * e2);
  }
  return corners;
}

GmshEntity addPlanarLoft(const std::vector<std::vector<Vec3>>& sections) {
  namespace occ = gmsh::model::occ;
  const std::size_t n = sections.front().size();
  std::vector<std::vector<int>> points;
  for (const auto& polygon : sections) {
    std::vector<int> tags;
    for (const Vec3& p : polygon) {
      tags.push_back(occ::addPoint(p.x(), p.y(), p.z()));
    }
    points.push_back(tags);
  }
  std::vector<std::vector<int>> rings;  // edges of each section polygon
  std::vector<std::vector<int>> rails;  // edges from one section to the next
  for (std::size_t s = 0; s < points.size(); ++s) {
    std::vector<int> ring;
    for (std::size_t i = 0; i < n; ++i) {
      ring.push_back(occ::addLine(points[s][i], points[s][(i + 1) % n]));
    }
    rings.push_back(ring);
    if (s + 1 < points.size()) {
      std::vector<int> rail;
      for (std::size_t i = 0; i < n; ++i) {
        rail.push_back(occ::addLine(points[s][i], points[s + 1][i]));
      }
      rails.push_back(rail);
    }
  }
  std::vector<int> faces = {occ::addPlaneSurface({occ::addCurveLoop(rings.front())}),
                            occ::addPlaneSurface({occ::addCurveLoop(rings.back())})};
  for (std::size_t s = 0; s + 1 < points.size(); ++s) {
    for (std::size_t i = 0; i < n; ++i) {
      const int loop = occ::addCurveLoop({rings[s][i], rails[s][(i + 1) % n], rings[s + 1][i], rails[s][i]});
      faces.push_back(occ::addPlaneSurface({loop}));
    }
  }
  return {3, occ::addVolume({occ::addSurfaceLoop(faces)})};
}

} // namespace armour::geometry::shapes
