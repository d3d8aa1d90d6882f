// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/MeshValidation.hpp"

#include "geometry/MassProperties.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

namespace armour::geometry {

const char* toString(MeshDefect defect) {
  switch (defect) {
  case MeshDefect::Empty: return "empty mesh";
  case MeshDefect::NonFinite: return "non-finite coordinates";
  case MeshDefect::BadIndex: return "vertex index out of range";
  case MeshDefect::DegenerateFace: return "degenerate faces";
  case MeshDefect::OpenEdges: return "open edges";
  case MeshDefect::NonManifoldEdges: return "non-manifold edges";
  case MeshDefect::NonOrientable: return "non-orientable surface";
  case MeshDefect::InconsistentOrientation: return "inconsistent orientation";
  case MeshDefect::InwardOrientation: return "inward orientation";
  case MeshDefect::MultipleComponents: return "multiple components";
  case MeshDefect::NonPositiveVolume: return "non-positive volume";
  }
  return "unknown defect";
}

bool MeshInspection::valid() const {
  return !nonFinite && !badIndex && degenerateFaces.empty() && watertight() && orientable && consistentlyOriented &&
         components == 1 && volume > 0.0;
}

namespace {

/// One directed use of an edge by a face.
struct EdgeUse {
  std::size_t face;
  bool forward; // true if the face walks the edge from the smaller to the larger index
};

using EdgeMap = std::map<Edge, std::vector<EdgeUse>>;

EdgeMap buildEdgeMap(const TriangleMesh& mesh) {
  EdgeMap edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const auto a = f[k];
      const auto b = f[(k + 1) % 3];
      if (a == b) {
        continue;
      }
      edges[{std::min(a, b), std::max(a, b)}].push_back({t, a < b});
    }
  }
  return edges;
}

/// Breadth-first walk over faces across manifold edges. flip[t] says whether face t must be
/// reversed to agree with the first face of its component. Returns false if the walk meets a
/// contradiction (non-orientable surface).
bool propagateOrientation(const TriangleMesh& mesh, const EdgeMap& edges, std::vector<int>& component,
                          std::vector<char>& flip, std::size_t& componentCount) {
  const std::size_t n = mesh.triangles.size();
  std::vector<std::vector<std::pair<std::size_t, bool>>> neighbours(n); // (face, same direction)
  for (const auto& [edge, uses] : edges) {
    if (uses.size() != 2) {
      continue;
    }
    const bool same = uses[0].forward == uses[1].forward;
    neighbours[uses[0].face].push_back({uses[1].face, same});
    neighbours[uses[1].face].push_back({uses[0].face, same});
  }
  component.assign(n, -1);
  flip.assign(n, 0);
  componentCount = 0;
  bool orientable = true;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (component[seed] >= 0) {
      continue;
    }
    const int id = static_cast<int>(componentCount++);
    std::queue<std::size_t> queue;
    queue.push(seed);
    component[seed] = id;
    while (!queue.empty()) {
      const auto t = queue.front();
      queue.pop();
      for (const auto& [u, same] : neighbours[t]) {
        // Two faces agree when they walk their shared edge in opposite directions.
        const char required = static_cast<char>(flip[t] ^ (same ? 1 : 0));
        if (component[u] < 0) {
          component[u] = id;
          flip[u] = required;
          queue.push(u);
        } else if (flip[u] != required) {
          orientable = false;
        }
      }
    }
  }
  return orientable;
}

std::string listEdges(const TriangleMesh& mesh, const std::vector<Edge>& edges) {
  std::string out;
  const std::size_t shown = std::min<std::size_t>(edges.size(), 5);
  for (std::size_t i = 0; i < shown; ++i) {
    const auto& a = mesh.vertices[edges[i].first];
    const auto& b = mesh.vertices[edges[i].second];
    out += fmt::format("{}({}, {}) from ({:.6g}, {:.6g}, {:.6g}) to ({:.6g}, {:.6g}, {:.6g})", i ? "; " : "",
                       edges[i].first, edges[i].second, a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
  }
  if (edges.size() > shown) {
    out += fmt::format("; and {} more", edges.size() - shown);
  }
  return out;
}

} // namespace

MeshInspection inspectMesh(const TriangleMesh& mesh, double areaTolerance) {
  MeshInspection r;
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) {
      r.nonFinite = true;
    }
  }
  const auto nv = static_cast<std::int32_t>(mesh.vertices.size());
  for (const auto& f : mesh.triangles) {
    for (auto i : f) {
      if (i < 0 || i >= nv) {
        r.badIndex = true;
      }
    }
  }
  if (r.nonFinite || r.badIndex || mesh.triangles.empty()) {
    r.orientable = false;
    return r;
  }
  const double diag = mesh.bounds().size().norm();
  const double minDoubleArea = 2.0 * areaTolerance * diag * diag;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || mesh.doubleAreaNormal(t).norm() <= minDoubleArea) {
      r.degenerateFaces.push_back(t);
    }
  }
  const EdgeMap edges = buildEdgeMap(mesh);
  for (const auto& [edge, uses] : edges) {
    if (uses.size() == 1) {
      r.openEdges.push_back(edge);
    } else if (uses.size() > 2) {
      r.nonManifoldEdges.push_back(edge);
    } else if (uses[0].forward == uses[1].forward) {
      r.consistentlyOriented = false;
    }
  }
  std::vector<int> component;
  std::vector<char> flip;
  r.orientable = propagateOrientation(mesh, edges, component, flip, r.components);
  r.volume = signedVolume(mesh);
  return r;
}

RepairReport validateMesh(TriangleMesh& mesh, const std::string& source, const ValidationOptions& options) {
  const auto fail = [&](MeshDefect defect, const std::string& what) {
    throw MeshError(defect, fmt::format("{}: {}: {}", source, toString(defect), what));
  };
  if (mesh.triangles.empty()) {
    fail(MeshDefect::Empty, "the mesh has no triangles; check that the file holds a surface mesh");
  }
  MeshInspection r = inspectMesh(mesh, options.areaTolerance);
  if (r.nonFinite) {
    fail(MeshDefect::NonFinite, "a vertex has a NaN or infinite coordinate; re-export the mesh");
  }
  if (r.badIndex) {
    fail(MeshDefect::BadIndex, fmt::format("a triangle refers to a vertex outside 0..{}; the file is corrupt",
                                           mesh.vertices.size() - 1));
  }
  if (!r.degenerateFaces.empty()) {
    const auto t = r.degenerateFaces.front();
    const auto& f = mesh.triangles[t];
    fail(MeshDefect::DegenerateFace,
         fmt::format("{} face(s) with a repeated vertex or zero area, e.g. face {} = ({}, {}, {}) with area {:.3g} m^2; "
                     "remove slivers or weld vertices in the mesh tool",
                     r.degenerateFaces.size(), t, f[0], f[1], f[2], mesh.area(t)));
  }
  if (!r.nonManifoldEdges.empty()) {
    fail(MeshDefect::NonManifoldEdges,
         fmt::format("{} edge(s) shared by more than two faces: {}; the surface must bound a single solid, "
                     "separate touching parts or remove duplicate faces",
                     r.nonManifoldEdges.size(), listEdges(mesh, r.nonManifoldEdges)));
  }
  if (!r.openEdges.empty()) {
    fail(MeshDefect::OpenEdges,
         fmt::format("{} edge(s) used by one face only, the mesh is not watertight: {}; close the holes "
                     "(e.g. fill holes in MeshLab) or export the closed solid",
                     r.openEdges.size(), listEdges(mesh, r.openEdges)));
  }
  if (!r.orientable) {
    fail(MeshDefect::NonOrientable, "the faces cannot be oriented consistently; the surface is not a solid boundary");
  }
  if (r.components != 1 && !options.allowMultipleComponents) {
    fail(MeshDefect::MultipleComponents,
         fmt::format("the mesh has {} disconnected pieces; a body must be one closed surface, split the file into "
                     "one file per body",
                     r.components));
  }
  RepairReport report;
  if (!r.consistentlyOriented) {
    if (!options.repairOrientation) {
      fail(MeshDefect::InconsistentOrientation,
           "neighbouring faces have opposite orientations; enable orientation repair or fix the normals");
    }
    const EdgeMap edges = buildEdgeMap(mesh);
    std::vector<int> component;
    std::vector<char> flip;
    std::size_t count = 0;
    propagateOrientation(mesh, edges, component, flip, count);
    // Flip the minority within each component so that the repair changes as little as possible.
    std::vector<std::size_t> flips(count, 0), sizes(count, 0);
    for (std::size_t t = 0; t < flip.size(); ++t) {
      flips[component[t]] += flip[t];
      ++sizes[component[t]];
    }
    for (std::size_t t = 0; t < flip.size(); ++t) {
      const bool minorityFlipped = 2 * flips[component[t]] <= sizes[component[t]];
      if ((flip[t] != 0) == minorityFlipped) {
        std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
        ++report.flippedFaces;
      }
    }
    r.volume = signedVolume(mesh);
  }
  if (r.volume < 0.0) {
    if (!options.repairOrientation) {
      fail(MeshDefect::InwardOrientation,
           fmt::format("the normals point inward (volume {:.6g} m^3); enable orientation repair or flip the normals",
                       r.volume));
    }
    flipOrientation(mesh);
    report.inverted = true;
    r.volume = -r.volume;
  }
  const double diag = mesh.bounds().size().norm();
  if (!(r.volume > 1e-12 * diag * diag * diag)) {
    fail(MeshDefect::NonPositiveVolume,
         fmt::format("the enclosed volume is {:.6g} m^3 for a bounding-box diagonal of {:.6g} m; the surface "
                     "encloses nothing (flat or self-cancelling), check the export",
                     r.volume, diag));
  }
  return report;
}

} // namespace armour::geometry
