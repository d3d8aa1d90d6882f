// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/ConvexHull.hpp"
#include "geometry/shapes/Generators.hpp"
#include "geometry/shapes/RockSampling.hpp"

#include <algorithm>
#include <cmath>

namespace armour::geometry::shapes {
namespace {

/// Triangles with an angle below 8 degrees are "caps" to remove: the cosine of 8 degrees (unit: -).
/// Angles are compared by their cosines, which need only + * / sqrt (identical on every platform;
/// acos/atan2 are not), so a seed gives the same rock everywhere.
constexpr double kMaxCosine = 0.99026806874157036; // cos(8 degrees)

/// Cosine of the interior angle at corner k of triangle t (unit: -).
double cornerCosine(const TriangleMesh& mesh, std::size_t t, int k) {
  const auto c = mesh.corners(t);
  const Vec3 u = c[(k + 1) % 3] - c[k];
  const Vec3 v = c[(k + 2) % 3] - c[k];
  return u.dot(v) / std::sqrt(u.squaredNorm() * v.squaredNorm());
}

/// Convex hull of the points after removing "cap" vertices. Radial jitter can leave a hull vertex
/// just outside the edge joining two others: the hull then has a flat triangle with an angle near
/// 180 degrees at that vertex and two tiny ones (a sliver, bad for contact normals and for tet
/// meshing). Since the points are spaced (no short edges), every sliver is such a cap, and dropping
/// its obtuse vertex changes the rock by a sliver of volume. Worst first, one per hull.
TriangleMesh hullWithoutCaps(std::vector<Vec3> points, const std::string& source) {
  for (;;) {
    const ConvexPolyhedron hull = convexHullPolyhedron(points, source);
    TriangleMesh mesh = triangulateFaces(hull);
    double worst = kMaxCosine;
    std::int32_t cap = -1;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const std::array<double, 3> cosine{cornerCosine(mesh, t, 0), cornerCosine(mesh, t, 1), cornerCosine(mesh, t, 2)};
      const double sharpest = *std::max_element(cosine.begin(), cosine.end()); // smallest angle
      if (sharpest > worst) {
        worst = sharpest;
        const auto obtuse = std::min_element(cosine.begin(), cosine.end()) - cosine.begin(); // largest angle
        cap = hull.vertexSource[mesh.triangles[t][obtuse]];
      }
    }
    // Keep at least 8 points: a hull of fewer would no longer look like a rock at all.
    if (cap < 0 || points.size() <= 8) {
      return mesh;
    }
    points.erase(points.begin() + cap);
  }
}

} // namespace

ShapeGenerator rockGenerator() {
  ShapeGenerator g;
  g.name = "rock";
  g.summary = "random quarried rock: convex hull of random points on an ellipsoid (seeded)";
  g.proportions = "convex hull of 40 points spread evenly at random over an ellipsoid 1 : aspect_b : aspect_c "
                  "(x : y : z, default 1 : 0.75 : 0.55, i.e. length/thickness LT = 1.8), each point's radius jittered "
                  "by +-10 %; hull vertices that make sliver triangles (angle < 8 degrees) are dropped; finally "
                  "stretched so the bounding box is exactly 1 : aspect_b : aspect_c; longest axis along x, shortest "
                  "along z (lying on its flat side)";
  g.source = "shape measure from the Rock Manual (CIRIA, CUR, CETMEF 2007, section 3.4) and EN 13383-1: armourstone "
             "shape is given by the length-to-thickness ratio LT, and EN 13383-1 limits the share of pieces with "
             "LT > 3; "
             "LT about 1.5-2 is typical of well-produced quarried armourstone (value recalled, not re-checked "
             "against the text). b/a = 0.75 is an assumption placing the rock in Zingg's equant class. "
             "The hull-of-random-points construction is a modelling choice, not a measured rock";
  g.parameters = {
      {"points", 40.0, 8.0, 500.0, "-",
       "number of random points on the ellipsoid (about the number of hull vertices: more = rounder, smaller facets)"},
      {"aspect_b", 0.75, 0.2, 1.0, "-", "b/a: semi-axis along y over the (longest) semi-axis along x"},
      {"aspect_c", 0.55, 0.2, 1.0, "-", "c/a: semi-axis along z over the semi-axis along x; LT = a/c"},
      {"roughness", 0.1, 0.0, 0.4, "-",
       "radial jitter: each point's distance from the centre is scaled by a uniform factor in [1 - r, 1 + r]"},
  };
  g.random = true;
  g.build = [](const ShapeParameterValues& p) {
    const auto count = static_cast<std::size_t>(std::lround(p.get("points")));
    const Vec3 axes(1.0, p.get("aspect_b"), p.get("aspect_c"));
    const double roughness = p.get("roughness");
    std::mt19937_64 rng(p.seed());
    // Points spaced at about half the mean spacing sqrt(area / count): far enough apart that no hull
    // facet is a needle, loose enough that dart throwing always finds room (random sequential
    // packing jams near 0.83 x the mean spacing).
    const double spacing = 0.55 * std::sqrt(rocks::ellipsoidAreaEstimate(axes.x(), axes.y(), axes.z()) /
                                            static_cast<double>(count));
    const auto onEllipsoid = [&](std::mt19937_64& r) -> Vec3 {
      return rocks::randomDirection(r).cwiseProduct(axes);
    };
    std::vector<Vec3> points = rocks::spacedSample(rng, count, spacing, onEllipsoid);
    // Jitter after spacing, so roughness changes the facets' tilt without bringing points together.
    for (auto& q : points) {
      q *= 1.0 + rocks::uniform(rng, -roughness, roughness);
    }
    TriangleMesh rock = hullWithoutCaps(std::move(points), "shape 'rock'");
    rocks::stretchToBox(rock.vertices, axes);
    return rock;
  };
  return g;
}

} // namespace armour::geometry::shapes
