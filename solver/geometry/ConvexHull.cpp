// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/ConvexHull.hpp"

#include "core/Error.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <unordered_map>

// Qhull's C headers define short macros (True, False, qh, FOREACH...): include them last.
#include <libqhull_r/qhull_ra.h>

namespace armour::geometry {
namespace {

/// One hull facet as Qhull reports it, in the caller's coordinates.
struct RawFacet {
  Vec3 normal;                        // unit, outward
  double offset = 0.0;                // normal . x = offset on the facet
  std::vector<std::int32_t> vertices; // input point indices, counter-clockwise from outside
};

/// One hull vertex and the facets around it.
struct RawVertex {
  std::int32_t point = 0;           // input point index
  std::vector<std::int32_t> facets; // indices into RawHull::facets, in cyclic order (either sense)
};

struct RawHull {
  std::vector<RawFacet> facets;
  std::vector<RawVertex> vertices;
};

/// Newell's normal of a polygon: robust for slightly non-planar merged facets, and its sign follows
/// the polygon's winding.
Vec3 newellNormal(const std::vector<Vec3>& points, const std::vector<std::int32_t>& polygon) {
  Vec3 n = Vec3::Zero();
  const std::size_t m = polygon.size();
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3& a = points[polygon[i]];
    const Vec3& b = points[polygon[(i + 1) % m]];
    n += a.cross(b);
  }
  return n;
}

/// Refuse point sets Qhull cannot make a 3-d hull of, with a message saying which case it is.
/// Qhull would also refuse them, but with a message about "initial simplex" that means little to a
/// user; thresholds are far below Qhull's own round-off tolerance so no valid input is refused here.
void checkPoints(const std::vector<Vec3>& points, const std::string& source) {
  if (points.size() < 4) {
    core::failInput(source, "{} point(s) given: a convex hull in 3-d needs at least 4 points not in one plane",
                    points.size());
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      core::failInput(source, "point {} = ({}, {}, {}) is not finite; check the generator or file", i,
                      points[i].x(), points[i].y(), points[i].z());
    }
  }
  Vec3 mean = Vec3::Zero();
  for (const auto& p : points) {
    mean += p;
  }
  mean /= static_cast<double>(points.size());
  Mat3 covariance = Mat3::Zero();
  double radius = 0.0;
  for (const auto& p : points) {
    covariance += (p - mean) * (p - mean).transpose();
    radius = std::max(radius, (p - mean).norm());
  }
  if (radius == 0.0) {
    core::failInput(source, "all {} points coincide at ({}, {}, {}): there is no solid to wrap", points.size(),
                    mean.x(), mean.y(), mean.z());
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(covariance);
  // Largest distance of a point from the best-fit plane, and from the best-fit line.
  double thickness = 0.0;
  double width = 0.0;
  for (const auto& p : points) {
    thickness = std::max(thickness, std::abs((p - mean).dot(eig.eigenvectors().col(0))));
    width = std::max(width, std::abs((p - mean).dot(eig.eigenvectors().col(1))));
  }
  if (width <= 1e-12 * radius) {
    core::failInput(source, "all {} points lie on one line (spread {:.3g} m across it, {:.3g} m along it): a hull "
                    "needs points spanning 3-d", points.size(), width, radius);
  }
  if (thickness <= 1e-12 * radius) {
    core::failInput(source, "all {} points lie in one plane (out-of-plane spread {:.3g} m for a size of {:.3g} m): "
                    "the hull would be flat, give points spanning 3-d", points.size(), thickness, radius);
  }
}

/// Run Qhull on points - shift (a shift near the points' middle keeps Qhull's relative round-off
/// small); the facet planes are returned in the unshifted frame.
RawHull runQhull(const std::vector<Vec3>& points, const Vec3& shift, bool wantVertexFacets, const std::string& source) {
  std::vector<coordT> coords;
  coords.reserve(3 * points.size());
  for (const auto& p : points) {
    coords.push_back(p.x() - shift.x());
    coords.push_back(p.y() - shift.y());
    coords.push_back(p.z() - shift.z());
  }
  // Qhull reports errors on a FILE*; collect them in memory so they can go into the exception.
  char* errorText = nullptr;
  std::size_t errorSize = 0;
  FILE* errorStream = open_memstream(&errorText, &errorSize);
  // "qhull" alone: 3-d hull with Qhull's default 'C-0' facet merging (coplanar facets merged).
  char options[] = "qhull";
  qhT qhStorage;
  qhT* qh = &qhStorage;
  qh_zero(qh, errorStream);
  const int status = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False, options, nullptr,
                                  errorStream);
  RawHull hull;
  if (status == 0) {
    std::unordered_map<const facetT*, std::int32_t> facetIndex;
    facetT* facet = nullptr;
    FORALLfacets {
      facetIndex[facet] = static_cast<std::int32_t>(hull.facets.size());
      RawFacet f;
      f.normal = Vec3(facet->normal[0], facet->normal[1], facet->normal[2]).normalized();
      // Qhull's plane is normal . y + offset = 0 in the shifted frame y = x - shift.
      f.offset = -facet->offset + f.normal.dot(shift);
      setT* ordered = qh_facet3vertex(qh, facet);
      vertexT* vertex = nullptr;
      vertexT** vertexp = nullptr;
      FOREACHvertex_(ordered) {
        f.vertices.push_back(static_cast<std::int32_t>(qh_pointid(qh, vertex->point)));
      }
      qh_settempfree(qh, &ordered);
      // qh_facet3vertex's winding depends on the facet's toporient flag; fix it against the
      // (outward) plane normal instead of relying on that convention.
      if (newellNormal(points, f.vertices).dot(f.normal) < 0.0) {
        std::reverse(f.vertices.begin(), f.vertices.end());
      }
      hull.facets.push_back(std::move(f));
    }
    if (wantVertexFacets) {
      qh_vertexneighbors(qh);
      vertexT* vertex = nullptr;
      FORALLvertices {
        qh_order_vertexneighbors(qh, vertex);
        RawVertex v;
        v.point = static_cast<std::int32_t>(qh_pointid(qh, vertex->point));
        facetT* neighbor = nullptr;
        facetT** neighborp = nullptr;
        FOREACHneighbor_(vertex) {
          v.facets.push_back(facetIndex.at(neighbor));
        }
        hull.vertices.push_back(std::move(v));
      }
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int currentLong = 0;
  int totalLong = 0;
  qh_memfreeshort(qh, &currentLong, &totalLong);
  std::fclose(errorStream);
  std::string message(errorText != nullptr ? errorText : "", errorSize);
  std::free(errorText);
  if (status != 0) {
    // Keep the first line: the rest is Qhull's option dump.
    message = message.substr(0, message.find('\n'));
    core::failInput(source, "Qhull could not build the convex hull of {} points (status {}): {}; the points are "
                    "probably (nearly) coplanar or duplicated", points.size(), status, message);
  }
  return hull;
}

Vec3 meanOf(const std::vector<Vec3>& points) {
  Vec3 mean = Vec3::Zero();
  for (const auto& p : points) {
    mean += p;
  }
  return mean / static_cast<double>(points.size());
}

/// Shape quality of triangle (a, b, c): minus the largest cosine of its angles, i.e. a monotone
/// function of its smallest angle (-1 for a degenerate triangle, -0.5 for an equilateral one).
/// Cosines need only + * / sqrt, which round identically everywhere, so the triangulation chosen
/// does not depend on the maths library (random rocks must be the same on every platform).
double shapeQuality(const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto cosine = [](const Vec3& u, const Vec3& v) {
    const double lengths = std::sqrt(u.squaredNorm() * v.squaredNorm());
    return lengths > 0.0 ? u.dot(v) / lengths : 1.0;
  };
  return -std::max({cosine(b - a, c - a), cosine(a - b, c - b), cosine(a - c, b - c)});
}

/// Max-min-angle triangulation of a convex polygon, appended to `out` with the polygon's winding.
void triangulatePolygon(const std::vector<Vec3>& vertices, const std::vector<std::int32_t>& polygon,
                        std::vector<Triangle>& out) {
  const std::size_t n = polygon.size();
  if (n < 3) {
    return;
  }
  if (n == 3) {
    out.push_back({polygon[0], polygon[1], polygon[2]});
    return;
  }
  // best[i][j]: best achievable worst shapeQuality when triangulating the sub-polygon i..j.
  // Any triangulation of a convex polygon is a tree of triangles (i, k, j), i < k < j, so the
  // optimum of the max-min criterion decomposes and the dynamic programme is exact.
  const double none = std::numeric_limits<double>::infinity();
  std::vector<double> best(n * n, none);
  std::vector<std::size_t> split(n * n, 0);
  for (std::size_t length = 2; length < n; ++length) {
    for (std::size_t i = 0; i + length < n; ++i) {
      const std::size_t j = i + length;
      double value = -2.0; // below any quality, so some k is always chosen
      for (std::size_t k = i + 1; k < j; ++k) {
        const double q = std::min({best[i * n + k], best[k * n + j],
                                   shapeQuality(vertices[polygon[i]], vertices[polygon[k]], vertices[polygon[j]])});
        if (q > value) {
          value = q;
          split[i * n + j] = k;
        }
      }
      best[i * n + j] = value;
    }
  }
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) {
      continue;
    }
    const std::size_t k = split[i * n + j];
    out.push_back({polygon[i], polygon[k], polygon[j]});
    stack.push_back({i, k});
    stack.push_back({k, j});
  }
}

} // namespace

ConvexPolyhedron convexHullPolyhedron(const std::vector<Vec3>& points, const std::string& source) {
  checkPoints(points, source);
  const RawHull raw = runQhull(points, meanOf(points), false, source);
  ConvexPolyhedron hull;
  // Compact numbering: only hull vertices are kept, in order of first use.
  std::unordered_map<std::int32_t, std::int32_t> index;
  for (const auto& f : raw.facets) {
    std::vector<std::int32_t> face;
    face.reserve(f.vertices.size());
    for (auto p : f.vertices) {
      auto [it, inserted] = index.try_emplace(p, static_cast<std::int32_t>(hull.vertices.size()));
      if (inserted) {
        hull.vertices.push_back(points[p]);
        hull.vertexSource.push_back(p);
      }
      face.push_back(it->second);
    }
    hull.faces.push_back(std::move(face));
    hull.normals.push_back(f.normal);
    hull.offsets.push_back(f.offset);
  }
  return hull;
}

TriangleMesh triangulateFaces(const ConvexPolyhedron& polyhedron) {
  TriangleMesh mesh;
  mesh.vertices = polyhedron.vertices;
  for (const auto& face : polyhedron.faces) {
    triangulatePolygon(mesh.vertices, face, mesh.triangles);
  }
  return mesh;
}

TriangleMesh convexHull(const std::vector<Vec3>& points, const std::string& source) {
  return triangulateFaces(convexHullPolyhedron(points, source));
}

ConvexPolyhedron convexHalfspaceIntersection(const std::vector<Halfspace>& halfspaces, const Vec3& interiorPoint,
                                             const std::string& source) {
  if (halfspaces.size() < 4) {
    core::failInput(source, "{} half-space(s) given: a bounded solid needs at least 4", halfspaces.size());
  }
  // Polar dual about the interior point c: half-space n . x <= d becomes the point q = n / (d - n . c).
  std::vector<Vec3> dual;
  dual.reserve(halfspaces.size());
  for (std::size_t i = 0; i < halfspaces.size(); ++i) {
    const auto& h = halfspaces[i];
    const double margin = h.offset - h.normal.dot(interiorPoint);
    if (!(margin > 0.0) || !h.normal.allFinite() || h.normal.squaredNorm() == 0.0) {
      core::failInput(source, "half-space {} (normal ({}, {}, {}), offset {}) does not contain the interior point "
                      "({}, {}, {}) strictly (margin {:.3g}); choose a point inside every half-space", i,
                      h.normal.x(), h.normal.y(), h.normal.z(), h.offset, interiorPoint.x(), interiorPoint.y(),
                      interiorPoint.z(), margin);
    }
    dual.push_back(h.normal / margin);
  }
  try {
    checkPoints(dual, source);
  } catch (const core::InputError&) {
    // Dual points in one plane (or line) means a direction that no half-space limits.
    core::failInput(source, "the intersection of the {} half-spaces is unbounded: their normals do not surround the "
                    "interior point in 3-d; add half-spaces facing the open directions", halfspaces.size());
  }
  // The dual hull is taken about the origin (= the interior point): its facet offsets must stay in
  // that frame, so no shift here.
  const RawHull raw = runQhull(dual, Vec3::Zero(), true, source);

  ConvexPolyhedron cell;
  // Dual facet m . q = delta  <->  vertex y = m / delta of the intersection (relative to c). The
  // origin lies strictly inside the dual hull exactly when the intersection is bounded.
  double largestNormal = 0.0;
  for (const auto& q : dual) {
    largestNormal = std::max(largestNormal, q.norm());
  }
  for (const auto& f : raw.facets) {
    if (!(f.offset > 1e-12 * largestNormal)) {
      core::failInput(source, "the intersection of the {} half-spaces is unbounded (no half-space limits the "
                      "direction ({:.3f}, {:.3f}, {:.3f})); add half-spaces facing that way", halfspaces.size(),
                      f.normal.x(), f.normal.y(), f.normal.z());
    }
    cell.vertices.push_back(interiorPoint + f.normal / f.offset);
  }
  // Dual vertex i (a half-space that touches the solid) <-> face of the solid on plane i, whose
  // corners are the dual facets around the dual vertex.
  for (const auto& v : raw.vertices) {
    std::vector<std::int32_t> face = v.facets;
    const Halfspace& h = halfspaces[v.point];
    const Vec3 n = h.normal.normalized();
    if (newellNormal(cell.vertices, face).dot(n) < 0.0) {
      std::reverse(face.begin(), face.end());
    }
    cell.faces.push_back(std::move(face));
    cell.normals.push_back(n);
    cell.offsets.push_back(h.offset / h.normal.norm());
    cell.faceSource.push_back(v.point);
  }
  return cell;
}

} // namespace armour::geometry
