// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SurfaceSamples.hpp
/// Points on the surface of a shape, each with a tributary area and an outward normal: the points
/// of body A that contact tests against the level set of body B. A penetrating point carries a
/// force proportional to its depth and its area, so the contact force is a pressure integrated
/// over the surface with these points as the quadrature.
///
/// Construction: the mesh is refined by longest-edge bisection (geometry::refineSurface) until no
/// edge is longer than the spacing; the samples are the vertices of the refined mesh. So
///  - every vertex of the mesh (every corner) is a sample, and samples [0, mesh.vertexCount())
///    are the mesh vertices in their order;
///  - every edge of the mesh (every sharp edge) carries samples no more than `spacing` apart;
///  - every face carries samples on a triangulation with edges <= spacing, so every surface point
///    is within spacing / sqrt(3) of a sample;
///  - the order depends only on the mesh and the spacing (deterministic).
/// Tributary area of a sample: one third of the area of each refined triangle around it (the
/// consistent nodal load of a uniform pressure on linear triangles), so the areas sum to the
/// surface area to round-off. Normal: angle-weighted mean of the unit normals of the triangles
/// around it (Baerentzen and Aanaes 2005): the face normal inside a face, the bisector on an edge.
///
/// Area vector of a sample: one third of the area vector A_t n_t of each refined triangle around
/// it. They sum to zero over a closed surface (a uniform pressure has no resultant), and their
/// projection on a direction m is the tributary area seen along m: a penetrating sample on a
/// sharp edge or corner also carries area from the faces beside the contact face, and weighting
/// by max(0, -areaVector . m) instead of the scalar area removes that excess in flat-on-flat
/// contact (the bottom face of a cube then bears exactly its area).
///
/// Uniformly scaled bodies share one set: positions scale with s, areas with s^2, normals do not
/// change (scaled()).

#include "geometry/TriangleMesh.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace armour::contact {

struct SurfaceSampleSettings {
  /// Largest edge between neighbouring samples relative to the nominal diameter Dn = V^(1/3)
  /// (unit: -). Bisection makes the actual edges between spacing / 2 and spacing.
  double spacingOverDn = 0.1;
  /// Absolute spacing; overrides spacingOverDn when positive (unit: m).
  double spacing = 0.0;
  /// Largest number of samples (unit: -): guards against a spacing in the wrong unit.
  std::size_t maxSamples = 2'000'000;
};

class SurfaceSamples {
public:
  SurfaceSamples() = default;
  /// Sample a closed, outward mesh (body frame). `source` names the shape in errors.
  /// Throws core::InputError for a non-positive volume, a non-positive spacing or too many samples.
  SurfaceSamples(const geometry::TriangleMesh& mesh, const SurfaceSampleSettings& settings = {},
                 const std::string& source = "surface samples");

  [[nodiscard]] std::size_t size() const { return positions_.size(); }
  [[nodiscard]] const std::vector<geometry::Vec3>& positions() const { return positions_; } ///< unit: m
  [[nodiscard]] const std::vector<geometry::Vec3>& normals() const { return normals_; }     ///< unit vectors
  [[nodiscard]] const std::vector<double>& areas() const { return areas_; }                  ///< unit: m^2
  [[nodiscard]] const std::vector<geometry::Vec3>& areaVectors() const { return areaVectors_; } ///< unit: m^2
  /// Sum of the tributary areas = surface area of the mesh (unit: m^2).
  [[nodiscard]] double totalArea() const { return totalArea_; }
  /// The spacing used: no two neighbouring samples are farther apart (unit: m).
  [[nodiscard]] double spacing() const { return spacing_; }
  /// Samples [0, meshVertexCount()) are the mesh's own vertices.
  [[nodiscard]] std::size_t meshVertexCount() const { return meshVertices_; }
  /// Largest distance of a sample from the body origin (unit: m): a bounding sphere for culling.
  [[nodiscard]] double boundingRadius() const { return boundingRadius_; }
  /// The same samples for the shape scaled by s > 0 about the body origin.
  [[nodiscard]] SurfaceSamples scaled(double s) const;

private:
  std::vector<geometry::Vec3> positions_;
  std::vector<geometry::Vec3> normals_;
  std::vector<double> areas_;
  std::vector<geometry::Vec3> areaVectors_;
  double totalArea_ = 0.0;
  double spacing_ = 0.0;
  double boundingRadius_ = 0.0;
  std::size_t meshVertices_ = 0;
};

} // namespace armour::contact
