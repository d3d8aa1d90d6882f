// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/SurfaceSamples.hpp"

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/SurfaceRefinement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace armour::contact {

using geometry::Vec3;

SurfaceSamples::SurfaceSamples(const geometry::TriangleMesh& mesh, const SurfaceSampleSettings& settings,
                               const std::string& source) {
  const double volume = geometry::signedVolume(mesh);
  if (!(volume > 0.0) || !std::isfinite(volume)) {
    core::failInput(source, "enclosed volume = {} m^3: surface samples need a closed, outward mesh with positive "
                    "volume (validate the mesh first)", volume);
  }
  const double dn = std::cbrt(volume);
  if (settings.spacing > 0.0) {
    spacing_ = settings.spacing;
  } else {
    if (!(settings.spacingOverDn > 0.0) || !std::isfinite(settings.spacingOverDn)) {
      core::failInput(source, "spacingOverDn = {}: must be positive and finite (default 0.1)", settings.spacingOverDn);
    }
    spacing_ = settings.spacingOverDn * dn;
  }
  if (!(spacing_ > 0.0) || !std::isfinite(spacing_)) {
    core::failInput(source, "spacing = {} m: must be positive and finite (or 0 to use spacingOverDn)",
                    settings.spacing);
  }
  // Bisection to edges <= h makes at most about 8.4 area / h^2 triangles (docs/theory.md,
  // section 3), i.e. about half as many vertices; refuse before spending the time.
  const double area = mesh.surfaceArea();
  const double expected = 4.2 * area / (spacing_ * spacing_);
  if (expected > static_cast<double>(settings.maxSamples)) {
    core::failInput(source, "spacing = {:.4g} m would give about {:.3g} samples, more than maxSamples = {}: use a "
                    "spacing of at least {:.4g} m (Dn = {:.4g} m)", spacing_, expected, settings.maxSamples,
                    std::sqrt(4.2 * area / static_cast<double>(settings.maxSamples)), dn);
  }
  geometry::SurfaceRefinementSettings refineSettings;
  refineSettings.maxTriangles = 2 * settings.maxSamples + mesh.triangleCount();
  const geometry::TriangleMesh refined = geometry::refineSurface(mesh, spacing_, refineSettings);

  // Bisection appends the new vertices after the original ones; the "every vertex is a sample at
  // its own index" contract rests on that.
  meshVertices_ = mesh.vertexCount();
  for (std::size_t v = 0; v < meshVertices_; ++v) {
    if (refined.vertices[v] != mesh.vertices[v]) {
      throw std::logic_error("SurfaceSamples: surface refinement renumbered the mesh vertices");
    }
  }

  positions_ = refined.vertices;
  areas_.assign(refined.vertexCount(), 0.0);
  normals_.assign(refined.vertexCount(), Vec3::Zero());
  areaVectors_.assign(refined.vertexCount(), Vec3::Zero());
  for (std::size_t t = 0; t < refined.triangleCount(); ++t) {
    const auto& f = refined.triangles[t];
    const auto p = refined.corners(t);
    const Vec3 doubleNormal = refined.doubleAreaNormal(t);
    const double third = doubleNormal.norm() / 6.0;
    const Vec3 unit = doubleNormal.normalized();
    for (int k = 0; k < 3; ++k) {
      areas_[static_cast<std::size_t>(f[k])] += third;
      areaVectors_[static_cast<std::size_t>(f[k])] += doubleNormal / 6.0;
      const Vec3 u = p[(k + 1) % 3] - p[k];
      const Vec3 v = p[(k + 2) % 3] - p[k];
      normals_[static_cast<std::size_t>(f[k])] += std::atan2(u.cross(v).norm(), u.dot(v)) * unit;
    }
  }
  totalArea_ = 0.0;
  boundingRadius_ = 0.0;
  for (std::size_t i = 0; i < positions_.size(); ++i) {
    normals_[i].normalize();
    totalArea_ += areas_[i];
    boundingRadius_ = std::max(boundingRadius_, positions_[i].norm());
  }
}

SurfaceSamples SurfaceSamples::scaled(double s) const {
  SurfaceSamples out = *this;
  for (auto& p : out.positions_) {
    p *= s;
  }
  for (auto& a : out.areas_) {
    a *= s * s;
  }
  for (auto& a : out.areaVectors_) {
    a *= s * s;
  }
  out.totalArea_ *= s * s;
  out.spacing_ *= s;
  out.boundingRadius_ *= s;
  return out;
}

} // namespace armour::contact
