// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/Error.hpp"
#include "geometry/ConvexHull.hpp"
#include "geometry/shapes/Generators.hpp"
#include "geometry/shapes/RockSampling.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace armour::geometry::shapes {
namespace {

/// Facets smaller than this fraction of the mean facet area (total area / requested neighbours)
/// are removed (unit: -): a quarried block has facets of comparable size, and tiny ones only make
/// slivers for contact and meshing. 0.15 is 0.5 % of the area for the default 30 neighbours.
constexpr double kMinFacetAreaFraction = 0.15;
/// Edges shorter than this fraction of the mean facet size sqrt(total area / requested neighbours)
/// are removed with the smaller of their two facets (unit: -), for the same reason. 0.2 is about
/// 3.5 % of the bounding-box diagonal for the default rock.
constexpr double kMinEdgeFraction = 0.2;
/// Pruning stops at this many facets (unit: -), whatever their size: below it the cell would no
/// longer look like a rock (a cube has 6).
constexpr std::size_t kMinFacets = 10;

double polygonArea(const ConvexPolyhedron& cell, const std::vector<std::int32_t>& face) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < face.size(); ++i) {
    n += cell.vertices[face[i]].cross(cell.vertices[face[(i + 1) % face.size()]]);
  }
  return 0.5 * n.norm();
}

/// The face whose half-space should go next, or -1 when every facet and edge is large enough.
/// Faces of locked half-spaces (whose removal would unbound the cell) are never chosen.
int weakestFace(const ConvexPolyhedron& cell, const std::vector<char>& locked, std::size_t neighbours) {
  std::vector<double> areas;
  double total = 0.0;
  for (const auto& face : cell.faces) {
    areas.push_back(polygonArea(cell, face));
    total += areas.back();
  }
  int weakest = -1;
  const double meanArea = total / static_cast<double>(neighbours);
  double weakestArea = kMinFacetAreaFraction * meanArea;
  for (std::size_t f = 0; f < areas.size(); ++f) {
    if (areas[f] < weakestArea && locked[cell.faceSource[f]] == 0) {
      weakest = static_cast<int>(f);
      weakestArea = areas[f];
    }
  }
  if (weakest >= 0) {
    return weakest;
  }
  const double minEdge = kMinEdgeFraction * std::sqrt(meanArea);
  // Edge -> the faces on either side; the shortest too-short edge loses its smaller face.
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<int>> edgeFaces;
  for (std::size_t f = 0; f < cell.faces.size(); ++f) {
    const auto& face = cell.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const auto a = face[i];
      const auto b = face[(i + 1) % face.size()];
      edgeFaces[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(f));
    }
  }
  double shortest = minEdge;
  for (const auto& [edge, faces] : edgeFaces) {
    const double length = (cell.vertices[edge.first] - cell.vertices[edge.second]).norm();
    int smaller = -1;
    for (int f : faces) {
      if (locked[cell.faceSource[f]] == 0 && (smaller < 0 || areas[f] < areas[smaller])) {
        smaller = f;
      }
    }
    if (length < shortest && smaller >= 0) {
      shortest = length;
      weakest = smaller;
    }
  }
  return weakest;
}

} // namespace

ShapeGenerator voronoiRockGenerator() {
  ShapeGenerator g;
  g.name = "voronoi-rock";
  g.summary = "random angular rock: Voronoi cell of a seed among random neighbours (sharp planar facets, seeded)";
  g.proportions = "Voronoi cell of a seed at the centre among 30 neighbours placed so that the bisector planes "
                  "are tangent to an ellipsoid 1 : aspect_b : aspect_c (x : y : z, default 1 : 0.75 : 0.55, LT = 1.8) "
                  "at points spread evenly at random over it, plane distances jittered by +-20 %; facets under 0.15 x "
                  "the mean facet area (total / neighbours) or with an edge under 0.2 x the mean facet size are "
                  "dropped (down to 10 facets at least), leaving about 16 facets; finally stretched so the "
                  "bounding box is exactly 1 : aspect_b : aspect_c; longest axis along x";
  g.source = "shape measure LT from the Rock Manual (CIRIA, CUR, CETMEF 2007, section 3.4) and EN 13383-1 (typical "
             "LT about 1.5-2 for quarried armourstone, value recalled, not re-checked); Voronoi cells are a common way "
             "to make random convex polyhedral particles for DEM: a modelling choice giving sharp planar facets like "
             "blasted rock, not a measured rock";
  g.parameters = {
      {"neighbours", 30.0, 10.0, 120.0, "-",
       "number of neighbour seeds, i.e. candidate facets; nearer ones shadow others and tiny facets are dropped, "
       "so a rock has about 16 facets for 30 neighbours and 28 for 100 (spread 0.2)"},
      {"aspect_b", 0.75, 0.2, 1.0, "-", "b/a: semi-axis along y over the (longest) semi-axis along x"},
      {"aspect_c", 0.55, 0.2, 1.0, "-", "c/a: semi-axis along z over the semi-axis along x; LT about a/c"},
      {"spread", 0.2, 0.0, 0.5, "-",
       "random spread of the neighbours' distances: each facet's distance from the centre is scaled by a "
       "uniform factor in [1 - s, 1 + s]"},
  };
  g.random = true;
  g.build = [](const ShapeParameterValues& p) {
    const auto count = static_cast<std::size_t>(std::lround(p.get("neighbours")));
    const Vec3 axes(1.0, p.get("aspect_b"), p.get("aspect_c"));
    const double spread = p.get("spread");
    std::mt19937_64 rng(p.seed());
    // Tangent planes of the ellipsoid at points spread evenly at random over its surface (the same
    // spacing rule as the "rock" shape), so facets are of similar size all round instead of
    // crowding at the ends as uniformly random normals would. Plane i is the bisector between
    // the seed at the origin and a neighbour at 2 s_i (n_i . p_i) n_i: p_i is the point, n_i the
    // unit normal there, s_i the random spread factor.
    const double spacing = 0.6 * std::sqrt(rocks::ellipsoidAreaEstimate(axes.x(), axes.y(), axes.z()) /
                                           static_cast<double>(count));
    const auto onEllipsoid = [&](std::mt19937_64& r) -> Vec3 {
      return rocks::randomDirection(r).cwiseProduct(axes);
    };
    const std::vector<Vec3> points = rocks::spacedSample(rng, count, spacing, onEllipsoid);
    std::vector<Halfspace> planes;
    planes.reserve(count);
    for (const auto& q : points) {
      const Vec3 n = q.cwiseQuotient(axes.cwiseProduct(axes)).normalized(); // gradient of sum (x_k / a_k)^2
      planes.push_back({n, n.dot(q) * (1.0 + rocks::uniform(rng, -spread, spread))});
    }
    const std::string source = "shape 'voronoi-rock'";
    ConvexPolyhedron cell = convexHalfspaceIntersection(planes, Vec3::Zero(), source);
    // Drop the neighbours that make tiny facets or short edges, one at a time (each removal
    // enlarges the cell and changes its neighbours' facets). A removal that would unbound the cell
    // is undone and that neighbour kept.
    std::vector<char> removed(planes.size(), 0);
    std::vector<char> locked(planes.size(), 0);
    for (std::size_t iteration = 0; iteration < count; ++iteration) {
      const int face = cell.faces.size() > kMinFacets ? weakestFace(cell, locked, count) : -1;
      if (face < 0) {
        break;
      }
      const auto drop = cell.faceSource[face];
      removed[drop] = 1;
      std::vector<Halfspace> active;
      std::vector<std::int32_t> activeIndex;
      for (std::size_t i = 0; i < planes.size(); ++i) {
        if (removed[i] == 0) {
          active.push_back(planes[i]);
          activeIndex.push_back(static_cast<std::int32_t>(i));
        }
      }
      try {
        ConvexPolyhedron next = convexHalfspaceIntersection(active, Vec3::Zero(), source);
        for (auto& s : next.faceSource) {
          s = activeIndex[s];
        }
        cell = std::move(next);
      } catch (const core::InputError&) {
        removed[drop] = 0;
        locked[drop] = 1;
      }
    }
    TriangleMesh rock = triangulateFaces(cell);
    rocks::stretchToBox(rock.vertices, axes);
    return rock;
  };
  return g;
}

} // namespace armour::geometry::shapes
