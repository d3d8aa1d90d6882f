// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/Tetrahedralizer.hpp"

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
#include <cstdio>
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

/// One gmsh run: the surface as a discrete surface bounding a volume, meshed with interior size h
/// (m; 0 = follow the surface triangles).
TetMesh meshVolume(const TriangleMesh& surface, double h, const std::string& source) {
  GmshSession session("tetrahedralize");
  const OptionGuard guard({"Mesh.Algorithm3D", "Mesh.MaxNumThreads3D", "Mesh.MeshSizeMax", "Mesh.MeshSizeMin",
                           "Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints", "Mesh.Optimize"});
  std::vector<std::size_t> nodeTags(surface.vertices.size());
  std::vector<double> coords;
  coords.reserve(3 * surface.vertices.size());
  for (std::size_t i = 0; i < surface.vertices.size(); ++i) {
    nodeTags[i] = i + 1; // gmsh tags start at 1: tag = index + 1 keeps the surface numbering
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
  try {
    gmsh::logger::start();
    // A discrete surface keeps its mesh as given; a discrete *volume* would not be meshed at all
    // in gmsh 4.8, so the volume is a built-in ("geo") volume bounded by the discrete surface.
    const int surfaceTag = gmsh::model::addDiscreteEntity(2);
    gmsh::model::mesh::addNodes(2, surfaceTag, nodeTags, coords);
    gmsh::model::mesh::addElementsByType(surfaceTag, 2, {}, triangleNodes);
    const int loop = gmsh::model::geo::addSurfaceLoop({surfaceTag});
    gmsh::model::geo::addVolume({loop});
    gmsh::model::geo::synchronize();

    // HXT: gmsh's 3-d Delaunay that honours MeshSizeMax inside a discrete boundary (the classic
    // Delaunay mesher, algorithm 1, inserts no interior point here). One thread: HXT's parallel
    // insertion order depends on scheduling, one thread makes the mesh reproducible.
    gmsh::option::setNumber("Mesh.Algorithm3D", 10);
    gmsh::option::setNumber("Mesh.MaxNumThreads3D", 1);
    gmsh::option::setNumber("Mesh.MeshSizeMin", 0.0);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", h > 0.0 ? 0 : 1);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", h > 0.0 ? 0 : 1);
    gmsh::option::setNumber("Mesh.MeshSizeMax", h > 0.0 ? h : 1e22);
    gmsh::option::setNumber("Mesh.Optimize", 1); // removes slivers by local swaps and smoothing
    std::fprintf(stderr, "DEBUG meshVolume %zu tris h=%.17g\n", surface.triangles.size(), h);
    gmsh::model::mesh::generate(3);

    std::vector<std::size_t> tags;
    std::vector<double> xyz, parametric;
    gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, true, false);
    // Surface nodes keep their index; new (interior) nodes follow in tag order.
    std::map<std::size_t, Vec3> extra;
    result.vertices = surface.vertices;
    for (std::size_t i = 0; i < tags.size(); ++i) {
      if (tags[i] > surface.vertices.size()) {
        extra.emplace(tags[i], Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]));
      }
    }
    std::unordered_map<std::size_t, std::int32_t> index;
    for (const auto& [tag, position] : extra) {
      index[tag] = static_cast<std::int32_t>(result.vertices.size());
      result.vertices.push_back(position);
    }
    const auto toIndex = [&](std::size_t tag) {
      return tag <= surface.vertices.size() ? static_cast<std::int32_t>(tag - 1) : index.at(tag);
    };
    std::vector<std::size_t> tetTags, tetNodes;
    gmsh::model::mesh::getElementsByType(4, tetTags, tetNodes); // 4-node tetrahedra
    result.tets.reserve(tetTags.size());
    for (std::size_t e = 0; e < tetTags.size(); ++e) {
      result.tets.push_back({toIndex(tetNodes[4 * e]), toIndex(tetNodes[4 * e + 1]), toIndex(tetNodes[4 * e + 2]),
                             toIndex(tetNodes[4 * e + 3])});
    }
    gmsh::logger::stop();
  } catch (const std::exception& e) {
    gmsh::logger::stop();
    core::failInput(source, "gmsh failed to tetrahedralise the surface ({} triangles): {} ({}); check that the "
                    "surface is closed and does not intersect itself", surface.triangles.size(), e.what(),
                    lastGmshError());
  } catch (...) {
    // gmsh 4.8 throws its error message as a std::string.
    const std::string error = lastGmshError();
    gmsh::logger::stop();
    core::failInput(source, "gmsh failed to tetrahedralise the surface ({} triangles): {}; check that the surface "
                    "is closed and does not intersect itself", surface.triangles.size(), error);
  }
  if (result.tets.empty()) {
    core::failInput(source, "gmsh made no tetrahedra from the surface ({} triangles): {}; check that the surface is "
                    "closed, outward and does not intersect itself", surface.triangles.size(), lastGmshError());
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
        const double angle = std::numbers::pi - std::atan2(normals[i].cross(normals[j]).norm(), normals[i].dot(normals[j]));
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
    core::failInput(source, "the surface has {} triangle(s): a closed solid needs at least 4", surface.triangles.size());
  }
  if (options.maxEdge < 0.0 || !std::isfinite(options.maxEdge)) {
    core::failInput(source, "maxEdge = {} m: give a positive element size, or 0 to follow the surface", options.maxEdge);
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
  // Interior size for a target count: a regular tet of edge h has volume h^3 / (6 sqrt 2).
  double h = options.maxEdge;
  if (options.targetTetCount > 0) {
    h = std::cbrt(volume * 6.0 * std::numbers::sqrt2 / static_cast<double>(options.targetTetCount));
  }
  const auto run = [&](double size) {
    if (options.keepSurface || size <= 0.0) {
      return meshVolume(surface, size, source);
    }
    return meshVolume(refineSurface(surface, size), size, source);
  };
  TetMesh mesh = run(h);
  if (options.targetTetCount > 0) {
    // A Delaunay mesh of size h is not made of regular tets, so the first count misses the target;
    // the count scales as 1 / h^3, which one correction captures well.
    const double target = static_cast<double>(options.targetTetCount);
    const double first = static_cast<double>(mesh.tets.size());
    if (std::abs(std::log(first / target)) > std::log(1.15)) {
      TetMesh second = run(h * std::cbrt(first / target));
      if (std::abs(std::log(static_cast<double>(second.tets.size()) / target)) < std::abs(std::log(first / target))) {
        mesh = std::move(second);
      }
    }
  }
  return mesh;
}

} // namespace armour::geometry
