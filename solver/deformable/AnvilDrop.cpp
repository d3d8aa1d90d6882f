// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/AnvilDrop.hpp"

#include "core/Error.hpp"
#include "deformable/StructuredBox.hpp"
#include "deformable/SurfaceLoads.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <Eigen/Geometry>

#include <cmath>

namespace armour::deformable {

AnvilDrop makeAnvilDrop(const AnvilDropSettings& s) {
  if (s.unitTets < 10) {
    core::failInput("anvil drop: unit_tets", "{}: give at least 10 tets for the unit", s.unitTets);
  }
  if (s.anvilCells < 1 || !(s.anvilSize.minCoeff() > 0.0)) {
    core::failInput("anvil drop: anvil", "{} cells, size ({}, {}, {}) m: give at least one cell and positive sides",
                    s.anvilCells, s.anvilSize.x(), s.anvilSize.y(), s.anvilSize.z());
  }
  if (!(s.anvilGrading >= 0.0 && s.anvilGrading < 10.0)) {
    core::failInput("anvil drop: anvil_grading", "{}: give 0 (uniform) to 10", s.anvilGrading);
  }
  if (!(s.gap >= 0.0) || !std::isfinite(s.speed)) {
    core::failInput("anvil drop: gap", "{} m at {} m/s: the unit must start above the anvil (gap >= 0), speed finite",
                    s.gap, s.speed);
  }
  geometry::ShapeRequest request;
  request.volume = s.volume;
  const auto surface = geometry::makeShape(s.shape, request);
  geometry::TetrahedralizeOptions options;
  options.targetTetCount = s.unitTets;
  options.keepSurface = false;
  const auto unit = geometry::tetrahedralize(surface, options);
  Eigen::AlignedBox3d box;
  for (const auto& p : unit.vertices) {
    box.extend(p);
  }
  const Vec3 unitShift(-box.center().x(), -box.center().y(), s.gap - box.min().z());
  const int nz = std::max(1, static_cast<int>(std::lround(s.anvilCells * s.anvilSize.z() / s.anvilSize.x())));
  const int ny = std::max(1, static_cast<int>(std::lround(s.anvilCells * s.anvilSize.y() / s.anvilSize.x())));
  auto anvil = structuredBox(s.anvilSize, s.anvilCells, ny, nz);
  // A monotone map of each axis keeps every Kuhn tet positively oriented (each cell is scaled
  // along the axes only).
  const double beta = s.anvilGrading;
  const auto stretch = [beta](double u) { return beta > 0.0 ? std::sinh(beta * u) / std::sinh(beta) : u; };
  for (auto& p : anvil.vertices) {
    for (int k = 0; k < 2; ++k) {
      p[k] = 0.5 * s.anvilSize[k] * stretch(2.0 * p[k] / s.anvilSize[k] - 1.0);
    }
    p.z() = -s.anvilSize.z() * stretch(1.0 - p.z() / s.anvilSize.z());
  }
  const Vec3 anvilShift = Vec3::Zero();
  DeformableSettings settings = s.body;
  settings.bodyContact = true;
  AnvilDrop drop{DeformableBody(makeDeformableMesh(mergeTetMeshes({unit, anvil}, {unitShift, anvilShift}),
                                                   ElementOrder::Quadratic, "anvil drop"),
                                settings, "anvil drop " + s.shape),
                 {}, 0.0, 0.0, Vec3::Zero()};
  auto& body = drop.body;
  const auto& parts = body.bodyContact()->nodeParts();
  std::vector<Vec3> velocities(body.nodeCount(), Vec3::Zero());
  for (std::size_t n = 0; n < body.nodeCount(); ++n) {
    if (parts[n] == 0) {
      velocities[n] = Vec3(0.0, 0.0, -s.speed);
    } else if (body.mesh().nodes[n].z() < -s.anvilSize.z() + 1e-9) {
      body.fixNode(n, Vec3::Zero(), 4U); // the floor holds z only
    }
  }
  body.setVelocities(velocities);
  for (std::size_t e = 0; e < body.mesh().elementCount(); ++e) {
    if (parts[body.mesh().element(e)[0]] == 0) {
      drop.unitElements.push_back(e);
      drop.unitVolume += body.geometry()[e].volume;
    }
  }
  for (const auto& f : boundaryFaces(body.mesh())) {
    if (parts[f.corners[0]] == 0 && f.normal.z() < -0.999 && std::abs(f.centroid.z() - s.gap) < 1e-9) {
      drop.baseArea += f.area;
    }
  }
  drop.unitCentre = box.center() + unitShift;
  return drop;
}

} // namespace armour::deformable
