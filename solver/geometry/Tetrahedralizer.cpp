// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/Tetrahedralizer.hpp"

#include "geometry/ClosestPoint.hpp"

#include "core/Error.hpp"
#include "geometry/GmshSession.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/SurfaceRefinement.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <unordered_map>

namespace armour::geometry {

double TetMesh::volume(std::size_t t) const {
  const auto& k = tets[t];
  const Vec3& a = vertices[k[0]];
  return (vertices[k[1]] - a).dot((vertices[k[2]] - a).cross(vertices[k[3]] - a)) / 6.0;
}

double TetMesh::totalVolume() const {
  double sum = 0.0;
  for (std::size_t t = 0; t < tets.size(); ++t) {
    sum += volume(t);
  }
  return sum;
}

namespace {

/// The four faces of a positively oriented tet (a, b, c, d), each counter-clockwise seen from
/// outside: the normal of (a, b, c) points towards d, so that face is reversed, and so on.
constexpr std::array<std::array<int, 3>, 4> kOutwardFaces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};

/// gmsh options are global and outlive a session: put back the ones changed here, so that other
/// users of gmsh (GmshSession::meshSurface) see the values they expect.
class OptionGuard {
public:
  explicit OptionGuard(std::vector<std::string> names) : names_(std::move(names)) {
    for (const auto& n : names_) {
      double value = 0.0;
      gmsh::option::getNumber(n, value);
      saved_.push_back(value);
    }
  }
  ~OptionGuard() {
    for (std::size_t i = 0; i < names_.size(); ++i) {
      gmsh::option::setNumber(names_[i], saved_[i]);
    }
  }
  OptionGuard(const OptionGuard&) = delete;
  OptionGuard& operator=(const OptionGuard&) = delete;

private:
  std::vector<std::string> names_;
  std::vector<double> saved_;
};

std::string lastGmshError() {
  std::string error;
  gmsh::logger::getLastError(error);
  return error.empty() ? std::string("no message from gmsh") : error;
}

/// Crossings of lines parallel to x with the surface. Triangles are binned by their (y, z)
/// extent on a grid, so a line only visits the triangles whose projection covers its cell.
class ScanLines {
public:
  ScanLines(const TriangleMesh& surface, double cell) : surface_(surface), cell_(cell) {
    const Box3 box = surface.bounds();
    y0_ = box.min.y();
    z0_ = box.min.z();
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
      Box3 tb;
      for (auto v : surface.triangles[t]) {
        tb.extend(surface.vertices[v]);
      }
      const auto [j0, k0] = key(tb.min.y(), tb.min.z());
      const auto [j1, k1] = key(tb.max.y(), tb.max.z());
      for (auto j = j0; j <= j1; ++j) {
        for (auto k = k0; k <= k1; ++k) {
          bins_[{j, k}].push_back(static_cast<std::int32_t>(t));
        }
      }
    }
  }

  /// x-coordinates, sorted, where the line through (y, z) crosses the surface. A crossing
  /// through an edge or vertex shared by several triangles is counted once, by the rasteriser's
  /// "top-left" rule on the triangles projected onto the (y, z) plane; triangles seen edge-on
  /// are skipped. For a closed surface the count is even and the line is inside between
  /// crossings 1-2, 3-4, ...
  [[nodiscard]] std::vector<double> crossings(double y, double z) const {
    std::vector<double> xs;
    const auto it = bins_.find(key(y, z));
    if (it == bins_.end()) {
      return xs;
    }
    const auto orient = [](const Vec3& u, const Vec3& w, double py, double pz) {
      return (w.y() - u.y()) * (pz - u.z()) - (w.z() - u.z()) * (py - u.y());
    };
    for (auto t : it->second) {
      const auto& f = surface_.triangles[t];
      std::array<Vec3, 3> v{surface_.vertices[f[0]], surface_.vertices[f[1]], surface_.vertices[f[2]]};
      double area2 = orient(v[0], v[1], v[2].y(), v[2].z());
      if (area2 == 0.0) {
        continue;
      }
      if (area2 < 0.0) {
        std::swap(v[1], v[2]);
        area2 = -area2;
      }
      std::array<double, 3> weight{};
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        const Vec3& u = v[(k + 1) % 3];
        const Vec3& w = v[(k + 2) % 3];
        const double e = orient(u, w, y, z); // weight of the vertex opposite edge u -> w
        const double dy = w.y() - u.y();
        const double dz = w.z() - u.z();
        // An edge exactly through the point belongs to one of its two triangles only.
        inside = e > 0.0 || (e == 0.0 && (dz > 0.0 || (dz == 0.0 && dy < 0.0)));
        weight[k] = e;
      }
      if (inside) {
        xs.push_back((weight[0] * v[0].x() + weight[1] * v[1].x() + weight[2] * v[2].x()) / area2);
      }
    }
    std::sort(xs.begin(), xs.end());
    return xs;
  }

  /// Is p inside the closed surface? Parity of the crossings left of p on its line.
  [[nodiscard]] bool inside(const Vec3& p) const {
    const std::vector<double> xs = crossings(p.y(), p.z());
    const auto left = std::lower_bound(xs.begin(), xs.end(), p.x()) - xs.begin();
    return xs.size() % 2 == 0 && left % 2 == 1;
  }

private:
  struct PairHash {
    std::size_t operator()(const std::pair<std::int64_t, std::int64_t>& k) const {
      return static_cast<std::size_t>(k.first * 73856093LL ^ k.second * 19349663LL);
    }
  };

  [[nodiscard]] std::pair<std::int64_t, std::int64_t> key(double y, double z) const {
    return {static_cast<std::int64_t>(std::floor((y - y0_) / cell_)),
            static_cast<std::int64_t>(std::floor((z - z0_) / cell_))};
  }

  const TriangleMesh& surface_;
  double cell_;
  double y0_ = 0.0;
  double z0_ = 0.0;
  std::unordered_map<std::pair<std::int64_t, std::int64_t>, std::vector<std::int32_t>, PairHash> bins_;
};

using CellKey = std::array<std::int64_t, 3>;

struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
  }
};

/// Distance queries against the surface: triangles binned on a grid of cell `cell` (m), each in
/// every cell its box grown by `reach` (m) touches, so a query point only needs the triangles of
/// its own cell to decide whether the surface is nearer than `reach`.
class SurfaceProximity {
public:
  SurfaceProximity(const TriangleMesh& surface, double cell, double reach)
      : surface_(surface), origin_(surface.bounds().min), cell_(cell) {
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
      Box3 box;
      for (auto v : surface.triangles[t]) {
        box.extend(surface.vertices[v]);
      }
      const CellKey lo = key(box.min - Vec3::Constant(reach));
      const CellKey hi = key(box.max + Vec3::Constant(reach));
      for (auto i = lo[0]; i <= hi[0]; ++i) {
        for (auto j = lo[1]; j <= hi[1]; ++j) {
          for (auto k = lo[2]; k <= hi[2]; ++k) {
            bins_[{i, j, k}].push_back(static_cast<std::int32_t>(t));
          }
        }
      }
    }
  }

  /// True if no surface point is nearer to p than r (m, r <= reach).
  [[nodiscard]] bool clear(const Vec3& p, double r) const {
    const auto it = bins_.find(key(p));
    if (it == bins_.end()) {
      return true;
    }
    for (auto t : it->second) {
      const auto& f = surface_.triangles[t];
      if (squaredDistanceToTriangle(p, surface_.vertices[f[0]], surface_.vertices[f[1]], surface_.vertices[f[2]]) <
          r * r) {
        return false;
      }
    }
    return true;
  }

private:
  [[nodiscard]] CellKey key(const Vec3& p) const {
    return {static_cast<std::int64_t>(std::floor((p.x() - origin_.x()) / cell_)),
            static_cast<std::int64_t>(std::floor((p.y() - origin_.y()) / cell_)),
            static_cast<std::int64_t>(std::floor((p.z() - origin_.z()) / cell_))};
  }

  const TriangleMesh& surface_;
  Vec3 origin_;
  double cell_;
  std::unordered_map<CellKey, std::vector<std::int32_t>, CellHash> bins_;
};

/// Accepts points that keep a minimum spacing from all points accepted before (hash grid).
class SpacedPoints {
public:
  explicit SpacedPoints(double spacing) : spacing_(spacing) {}

  bool tryAdd(const Vec3& p) {
    const CellKey c = key(p);
    for (auto i = c[0] - 1; i <= c[0] + 1; ++i) {
      for (auto j = c[1] - 1; j <= c[1] + 1; ++j) {
        for (auto k = c[2] - 1; k <= c[2] + 1; ++k) {
          const auto it = grid_.find({i, j, k});
          if (it == grid_.end()) {
            continue;
          }
          for (auto q : it->second) {
            if ((points_[q] - p).squaredNorm() < spacing_ * spacing_) {
              return false;
            }
          }
        }
      }
    }
    grid_[c].push_back(points_.size());
    points_.push_back(p);
    return true;
  }

  [[nodiscard]] const std::vector<Vec3>& points() const { return points_; }

private:
  [[nodiscard]] CellKey key(const Vec3& p) const {
    return {static_cast<std::int64_t>(std::floor(p.x() / spacing_)),
            static_cast<std::int64_t>(std::floor(p.y() / spacing_)),
            static_cast<std::int64_t>(std::floor(p.z() / spacing_))};
  }

  double spacing_;
  std::vector<Vec3> points_;
  std::unordered_map<CellKey, std::vector<std::size_t>, CellHash> grid_;
};

// Interior point placement, in units of the lattice spacing a (see interiorPoints). Chosen by
// trying layer depths 0.25-0.6 (and no layer), clearances 0.15-0.3 and spacings 0.45-0.55 on the
// cube and 5 seeds of each rock (keepSurface = false, 1000 and 5000 tets): depth 0.6 gave the best
// worst case on the cube (14 degrees) and about as few slivers as any on the rocks, where the
// layer halves the number of tets with a dihedral angle under 10 degrees (to 0.15 % for "rock",
// 0.8 % for "voronoi-rock").
constexpr double kLatticeClearance = 0.9; ///< lattice points at least this far from the surface
constexpr double kLayerDepth = 0.6;       ///< boundary-layer points this far inside, along the normal
constexpr double kLayerClearance = 0.2;   ///< ... and at least this far from any surface triangle
constexpr double kMinSpacing = 0.55;      ///< no two interior points closer than this

/// Interior points for the Delaunay mesher, spacing a (m): a body-centred cubic (BCC) lattice
/// filling the solid away from the surface, plus one boundary-layer point under each surface
/// vertex.
///  - The Delaunay tets of a BCC lattice are congruent (Sommerville's tetrahedron: two edges a,
///    four edges a sqrt(3)/2, dihedral angles 60 and 90 degrees, radius ratio 0.95), 12 per a^3, which sets count
///    and interior quality. The lattice is centred on the box and shifted by small irrational
///    fractions of a so its lines do not run exactly along faces or edges of typical inputs.
///  - Without the layer, the mesher joins surface vertices directly across the gap to the
///    lattice, and four surface vertices around a nearly flat ridge make a sliver tet. A point
///    below each vertex (along the area-weighted vertex normal) gives the surface triangles an
///    apex of their own and removes most of these slivers.
std::vector<Vec3> interiorPoints(const TriangleMesh& surface, double a) {
  const Box3 box = surface.bounds();
  const SurfaceProximity proximity(surface, a, kLatticeClearance * a);
  const ScanLines lines(surface, a);
  SpacedPoints accepted(kMinSpacing * a);

  // Boundary layer first: it matters more for quality than the lattice points it may displace.
  std::vector<Vec3> normals(surface.vertices.size(), Vec3::Zero());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const Vec3 n = surface.doubleAreaNormal(t);
    for (auto v : surface.triangles[t]) {
      normals[v] += n;
    }
  }
  for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
    if (normals[v].squaredNorm() == 0.0) {
      continue;
    }
    const Vec3 p = surface.vertices[v] - kLayerDepth * a * normals[v].normalized();
    if (proximity.clear(p, kLayerClearance * a) && lines.inside(p)) {
      accepted.tryAdd(p);
    }
  }

  const Vec3 shift = a * Vec3(0.5 * std::numbers::sqrt2 - 0.7, 0.1 * std::numbers::inv_pi, 0.01 * std::numbers::e);
  const Vec3 origin = box.centre() + shift;
  const auto range = [&](int axis, double offset) {
    const double lo = std::ceil((box.min[axis] - origin[axis]) / a - offset);
    const double hi = std::floor((box.max[axis] - origin[axis]) / a - offset);
    return std::pair<std::int64_t, std::int64_t>{static_cast<std::int64_t>(lo), static_cast<std::int64_t>(hi)};
  };
  for (const double offset : {0.0, 0.5}) { // the two simple cubic sublattices of BCC
    const auto [i0, i1] = range(0, offset);
    const auto [j0, j1] = range(1, offset);
    const auto [k0, k1] = range(2, offset);
    for (auto j = j0; j <= j1; ++j) {
      for (auto k = k0; k <= k1; ++k) {
        const double y = origin.y() + a * (static_cast<double>(j) + offset);
        const double z = origin.z() + a * (static_cast<double>(k) + offset);
        // One scan line serves all lattice points on it: inside between crossings 1-2, 3-4, ...
        const std::vector<double> crossings = lines.crossings(y, z);
        if (crossings.size() % 2 != 0) {
          continue; // cannot happen for a closed surface; skip the line rather than guess
        }
        std::size_t next = 0; // crossings left of the current x
        for (auto i = i0; i <= i1; ++i) {
          const Vec3 p(origin.x() + a * (static_cast<double>(i) + offset), y, z);
          while (next < crossings.size() && crossings[next] < p.x()) {
            ++next;
          }
          if (next % 2 == 1 && proximity.clear(p, kLatticeClearance * a)) {
            accepted.tryAdd(p);
          }
        }
      }
    }
  }
  return accepted.points();
}

/// Mesh size given to gmsh where it must not refine (m): larger than any model.
constexpr double kNoRefinement = 1e22;

/// One gmsh run: the surface as a discrete surface bounding a volume, the interior points embedded
/// in it, meshed by gmsh's Delaunay mesher (algorithm 1) and its default optimisation. Not HXT
/// (algorithm 10): in gmsh 4.8.4 HXT gave different meshes for the same input within one process
/// and crashed (segmentation fault in hxtRefineTetrahedra) on a coarse rock surface with a fine
/// interior size. Delaunay with the points given is repeatable. With no interior points, gmsh
/// refines by itself to the sizes of the surface triangles.
TetMesh meshVolume(const TriangleMesh& surface, const std::vector<Vec3>& interior, const std::string& source) {
  GmshSession session("tetrahedralize");
  const OptionGuard guard({"Mesh.Algorithm3D", "Mesh.MeshSizeMax", "Mesh.MeshSizeMin", "Mesh.Optimize",
                           "Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints"});
  std::vector<std::size_t> nodeTags(surface.vertices.size());
  std::vector<double> coords;
  coords.reserve(3 * surface.vertices.size());
  for (std::size_t i = 0; i < surface.vertices.size(); ++i) {
    nodeTags[i] = i + 1; // tags start at 1
    coords.insert(coords.end(), {surface.vertices[i].x(), surface.vertices[i].y(), surface.vertices[i].z()});
  }
  std::vector<std::size_t> triangleNodes;
  triangleNodes.reserve(3 * surface.triangles.size());
  for (const auto& f : surface.triangles) {
    for (auto v : f) {
      triangleNodes.push_back(static_cast<std::size_t>(v) + 1);
    }
  }
  TetMesh result;
  std::string failure;
  try {
    gmsh::logger::start();
    // A discrete surface keeps its mesh as given; a discrete *volume* would not be meshed at all
    // in gmsh 4.8, so the volume is a built-in ("geo") volume bounded by the discrete surface.
    const int surfaceTag = gmsh::model::addDiscreteEntity(2);
    gmsh::model::mesh::addNodes(2, surfaceTag, nodeTags, coords);
    gmsh::model::mesh::addElementsByType(surfaceTag, 2, {}, triangleNodes);
    const int loop = gmsh::model::geo::addSurfaceLoop({surfaceTag});
    const int volumeTag = gmsh::model::geo::addVolume({loop});
    std::vector<int> points;
    points.reserve(interior.size());
    for (const auto& p : interior) {
      points.push_back(gmsh::model::geo::addPoint(p.x(), p.y(), p.z(), kNoRefinement));
    }
    gmsh::model::geo::synchronize();
    if (!points.empty()) {
      gmsh::model::mesh::embed(0, points, 3, volumeTag);
    }
    gmsh::option::setNumber("Mesh.Algorithm3D", 1);
    gmsh::option::setNumber("Mesh.MeshSizeMin", 0.0);
    gmsh::option::setNumber("Mesh.MeshSizeMax", kNoRefinement);
    // With interior points given, sizes are huge everywhere so gmsh's Delaunay refinement inserts
    // nothing: it would otherwise split the thin tets of the boundary layer again and again (7x
    // the expected count on an L-shaped block). Without them, sizes follow the surface triangles.
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", interior.empty() ? 1 : 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", interior.empty() ? 1 : 0);
    gmsh::option::setNumber("Mesh.Optimize", 1); // removes slivers by local swaps and smoothing
    gmsh::model::mesh::generate(3);

    // After meshing gmsh renumbers all nodes (Mesh.Renumber; embedded points came first here), so the
    // surface nodes no longer have the tags given above: recognise them by their coordinates,
    // which gmsh copies bit for bit. (includeBoundary = false: each node listed once.)
    std::vector<std::size_t> tags;
    std::vector<double> xyz, parametric;
    gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, false, false);
    std::map<std::array<double, 3>, std::int32_t> surfaceIndex;
    for (std::size_t i = 0; i < surface.vertices.size(); ++i) {
      const auto& v = surface.vertices[i];
      surfaceIndex.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, static_cast<std::int32_t>(i));
    }
    // Surface nodes keep their index; new (interior) nodes follow in tag order.
    std::map<std::size_t, Vec3> extra;
    std::unordered_map<std::size_t, std::int32_t> index;
    std::vector<char> found(surface.vertices.size(), 0);
    result.vertices = surface.vertices;
    for (std::size_t i = 0; i < tags.size(); ++i) {
      const std::array<double, 3> p{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
      if (const auto it = surfaceIndex.find(p); it != surfaceIndex.end()) {
        index[tags[i]] = it->second;
        found[it->second] = 1;
      } else {
        extra.emplace(tags[i], Vec3(p[0], p[1], p[2]));
      }
    }
    for (const auto& [tag, position] : extra) {
      index[tag] = static_cast<std::int32_t>(result.vertices.size());
      result.vertices.push_back(position);
    }
    if (std::count(found.begin(), found.end(), 0) != 0) {
      failure = "some surface nodes are missing from gmsh's mesh (were they merged or moved?)";
    }
    if (index.size() != tags.size()) {
      failure = "gmsh returned duplicate node tags";
    }
    const auto toIndex = [&](std::size_t tag) { return index.at(tag); };
    std::vector<std::size_t> tetTags, tetNodes;
    gmsh::model::mesh::getElementsByType(4, tetTags, tetNodes); // 4-node tetrahedra
    result.tets.reserve(tetTags.size());
    for (std::size_t e = 0; e < tetTags.size(); ++e) {
      result.tets.push_back({toIndex(tetNodes[4 * e]), toIndex(tetNodes[4 * e + 1]), toIndex(tetNodes[4 * e + 2]),
                             toIndex(tetNodes[4 * e + 3])});
    }
    gmsh::logger::stop();
  } catch (const std::exception& e) {
    failure = std::string(e.what()) + " (" + lastGmshError() + ")";
    gmsh::logger::stop();
  } catch (...) {
    // gmsh 4.8 throws its error message as a std::string.
    failure = lastGmshError();
    gmsh::logger::stop();
  }
  if (!failure.empty() || result.tets.empty()) {
    core::failInput(source, "gmsh failed to tetrahedralise the surface ({} triangles, {} interior points): {}; check "
                    "that the surface is closed, outward and does not intersect itself", surface.triangles.size(),
                    interior.size(), failure.empty() ? lastGmshError() : failure);
  }
  // gmsh's tets are positive by its convention; enforce it rather than rely on it.
  for (std::size_t t = 0; t < result.tets.size(); ++t) {
    if (result.volume(t) < 0.0) {
      std::swap(result.tets[t][2], result.tets[t][3]);
    }
  }
  // The tets must fill exactly the solid: their volumes sum to the surface's volume (both are
  // exact for the same polyhedron). A mismatch means an inverted, open or self-intersecting input.
  const double expected = signedVolume(surface);
  const double obtained = result.totalVolume();
  if (!(std::abs(obtained - expected) <= 1e-6 * std::abs(expected))) {
    core::failInput(source, "the tetrahedra fill {:.9g} m^3 but the surface encloses {:.9g} m^3; the surface is "
                    "probably not a valid outward solid (run validateMesh) or intersects itself", obtained, expected);
  }
  return result;
}

} // namespace

TetMeshQuality tetMeshQuality(const TetMesh& mesh) {
  TetMeshQuality q;
  q.tets = mesh.tets.size();
  if (mesh.tets.empty()) {
    return q;
  }
  q.minDihedralDeg = 180.0;
  q.minRadiusRatio = std::numeric_limits<double>::infinity();
  q.minVolume = std::numeric_limits<double>::infinity();
  double sumRatio = 0.0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& k = mesh.tets[t];
    std::array<Vec3, 4> p{mesh.vertices[k[0]], mesh.vertices[k[1]], mesh.vertices[k[2]], mesh.vertices[k[3]]};
    std::array<Vec3, 4> normals; // outward, length = 2 x face area
    double area = 0.0;
    for (int f = 0; f < 4; ++f) {
      const auto& c = kOutwardFaces[f];
      normals[f] = (p[c[1]] - p[c[0]]).cross(p[c[2]] - p[c[0]]);
      area += 0.5 * normals[f].norm();
    }
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        // Interior dihedral angle between two faces = pi - angle between their outward normals.
        const double angle =
            std::numbers::pi - std::atan2(normals[i].cross(normals[j]).norm(), normals[i].dot(normals[j]));
        q.minDihedralDeg = std::min(q.minDihedralDeg, angle * 180.0 / std::numbers::pi);
        q.maxDihedralDeg = std::max(q.maxDihedralDeg, angle * 180.0 / std::numbers::pi);
      }
    }
    const double volume = mesh.volume(t);
    const Vec3 a = p[1] - p[0];
    const Vec3 b = p[2] - p[0];
    const Vec3 c = p[3] - p[0];
    // Circumradius: |a|^2 (b x c) + |b|^2 (c x a) + |c|^2 (a x b) = 12 V R (vector form).
    const double circumradius =
        (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) + c.squaredNorm() * a.cross(b)).norm() /
        (12.0 * std::abs(volume));
    const double inradius = 3.0 * std::abs(volume) / area;
    const double ratio = volume > 0.0 ? 3.0 * inradius / circumradius : 0.0;
    q.minRadiusRatio = std::min(q.minRadiusRatio, ratio);
    q.minVolume = std::min(q.minVolume, volume);
    sumRatio += ratio;
  }
  q.meanRadiusRatio = sumRatio / static_cast<double>(mesh.tets.size());
  return q;
}

TriangleMesh tetMeshBoundary(const TetMesh& mesh) {
  std::map<std::array<std::int32_t, 3>, std::pair<int, Triangle>> faces; // sorted corners -> (uses, face)
  for (const auto& k : mesh.tets) {
    for (const auto& c : kOutwardFaces) {
      const Triangle f{k[c[0]], k[c[1]], k[c[2]]};
      std::array<std::int32_t, 3> sorted = f;
      std::sort(sorted.begin(), sorted.end());
      auto& entry = faces[sorted];
      ++entry.first;
      entry.second = f;
    }
  }
  TriangleMesh boundary;
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& [corners, entry] : faces) {
    if (entry.first == 1) {
      boundary.triangles.push_back(entry.second);
      for (auto v : entry.second) {
        used[v] = 1;
      }
    }
  }
  // Drop interior vertices but keep the others in their order, so that a surface given to
  // tetrahedralize (whose vertices come first) comes back with its own numbering.
  std::vector<std::int32_t> index(mesh.vertices.size(), -1);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (used[i] != 0) {
      index[i] = static_cast<std::int32_t>(boundary.vertices.size());
      boundary.vertices.push_back(mesh.vertices[i]);
    }
  }
  for (auto& f : boundary.triangles) {
    f = {index[f[0]], index[f[1]], index[f[2]]};
  }
  return boundary;
}

TetMesh tetrahedralize(const TriangleMesh& surface, const TetrahedralizeOptions& options) {
  const std::string& source = options.source;
  if (surface.triangles.size() < 4) {
    core::failInput(source, "the surface has {} triangle(s): a closed solid needs at least 4",
                    surface.triangles.size());
  }
  if (options.maxEdge < 0.0 || !std::isfinite(options.maxEdge)) {
    core::failInput(source, "maxEdge = {} m: give a positive element size, or 0 to follow the surface",
                    options.maxEdge);
  }
  // gmsh given an open or inverted surface may crash, hang or fill the wrong side: check first.
  const MeshInspection inspection = inspectMesh(surface);
  if (!inspection.valid()) {
    core::failInput(source, "the surface is not a valid closed outward solid ({} open edges, {} non-manifold edges, "
                    "{} degenerate faces, {} components, {} orientation, volume {:.6g} m^3); run validateMesh on it "
                    "first", inspection.openEdges.size(), inspection.nonManifoldEdges.size(),
                    inspection.degenerateFaces.size(), inspection.components,
                    inspection.consistentlyOriented ? "consistent" : "inconsistent", inspection.volume);
  }
  const double volume = inspection.volume;
  // Lattice spacing: a BCC lattice of spacing a has 12 Delaunay tets per a^3 (see interiorPoints).
  const auto expectedCount = [&](double a) { return 12.0 * volume / (a * a * a); };
  double spacing = options.maxEdge;
  if (options.targetTetCount > 0) {
    spacing = std::cbrt(12.0 * volume / static_cast<double>(options.targetTetCount));
  }
  const auto run = [&](double a) {
    if (a <= 0.0) {
      return meshVolume(surface, {}, source);
    }
    if (expectedCount(a) > static_cast<double>(options.maxTetCount)) {
      core::failInput(source, "an interior element size of {:.4g} m would make about {:.3g} tetrahedra in {:.4g} m^3, "
                      "more than the limit of {}; use a size >= {:.4g} m or a smaller target count (check the unit: "
                      "metres)", a, expectedCount(a), volume, options.maxTetCount,
                      std::cbrt(12.0 * volume / static_cast<double>(options.maxTetCount)));
    }
    const TriangleMesh boundary = options.keepSurface ? surface : refineSurface(surface, a);
    return meshVolume(boundary, interiorPoints(boundary, a), source);
  };
  TetMesh mesh = run(spacing);
  if (options.targetTetCount > 0) {
    // The layer between lattice and surface does not follow the lattice count (it depends on the
    // surface triangles), so the first count misses. Correct the spacing from the counts
    // obtained, N ~ a^-p, with p = 3 at first and then measured from the last two runs; keep
    // the run nearest the target. Three corrections at most, stop within 10 %.
    const double target = static_cast<double>(options.targetTetCount);
    const auto miss = [&](double n) { return std::abs(std::log(n / target)); };
    double exponent = 3.0;
    double a = spacing;
    double n = static_cast<double>(mesh.tets.size());
    for (int pass = 0; pass < 3 && miss(n) > std::log(1.1); ++pass) {
      const double aNext = a * std::pow(n / target, 1.0 / exponent);
      TetMesh next = run(aNext);
      const double nNext = static_cast<double>(next.tets.size());
      if (nNext != n && aNext != a) {
        exponent = std::clamp(std::log(nNext / n) / std::log(a / aNext), 1.5, 6.0);
      }
      if (miss(nNext) < miss(static_cast<double>(mesh.tets.size()))) {
        mesh = std::move(next);
      }
      a = aNext;
      n = nNext;
    }
  }
  return mesh;
}

} // namespace armour::geometry
