// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/SurfaceElements.hpp"

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/SurfaceRefinement.hpp"

#include <algorithm>
#include <cmath>

namespace armour::hydro {

int patchIndex(const Vec3& point, const geometry::Box3& box, int patchesPerAxis) {
  const int n = patchesPerAxis;
  int cell[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    const double size = box.max[a] - box.min[a];
    if (size > 0.0 && n > 1) {
      const double f = std::floor((point[a] - box.min[a]) / size * n);
      cell[a] = static_cast<int>(std::clamp(f, 0.0, static_cast<double>(n - 1)));
    }
  }
  return cell[0] + n * (cell[1] + n * cell[2]);
}

SurfaceElements buildSurfaceElements(const geometry::TriangleMesh& bodyMesh, double maxEdgeLength,
                                     int patchesPerAxis) {
  // 40^3 = 64000 patches still fits the uint16_t index; more would be finer than the elements.
  if (patchesPerAxis < 1 || patchesPerAxis > 40) {
    core::failInput("hydro.storm.variability.patches_per_axis", "= {}: must be between 1 and 40 (2 = octants)",
                    patchesPerAxis);
  }
  const geometry::TriangleMesh mesh = geometry::refineSurface(bodyMesh, maxEdgeLength);
  SurfaceElements e;
  e.patchesPerAxis = patchesPerAxis;
  e.elementSize = maxEdgeLength;
  e.bounds = bodyMesh.bounds();
  e.volume = geometry::signedVolume(bodyMesh);
  const std::size_t n = mesh.triangleCount();
  e.centroid.reserve(n);
  e.normal.reserve(n);
  e.area.reserve(n);
  e.momentArm.reserve(n);
  e.patch.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto c = mesh.corners(t);
    const Vec3 doubleAreaNormal = mesh.doubleAreaNormal(t);
    const double twiceArea = doubleAreaNormal.norm();
    if (!(twiceArea > 0.0)) {
      continue; // a degenerate triangle carries no load
    }
    const Vec3 centroid = (c[0] + c[1] + c[2]) / 3.0;
    const double area = 0.5 * twiceArea;
    const Vec3 normal = doubleAreaNormal / twiceArea;
    e.centroid.push_back(centroid);
    e.normal.push_back(normal);
    e.area.push_back(area);
    e.momentArm.push_back(area * centroid.cross(normal));
    e.patch.push_back(static_cast<std::uint16_t>(patchIndex(centroid, e.bounds, patchesPerAxis)));
    e.totalArea += area;
  }
  return e;
}

} // namespace armour::hydro
