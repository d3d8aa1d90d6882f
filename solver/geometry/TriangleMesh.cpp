// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/TriangleMesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace armour::geometry {

double TriangleMesh::surfaceArea() const {
  double sum = 0.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    sum += area(t);
  }
  return sum;
}

Box3 TriangleMesh::bounds() const {
  Box3 box;
  for (const auto& v : vertices) {
    box.extend(v);
  }
  return box;
}

void TriangleMesh::append(const TriangleMesh& other) {
  const auto offset = static_cast<std::int32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& f : other.triangles) {
    triangles.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  }
}

void transform(TriangleMesh& mesh, const Mat3& rotation, const Vec3& translation) {
  for (auto& v : mesh.vertices) {
    v = rotation * v + translation;
  }
}

void translate(TriangleMesh& mesh, const Vec3& offset) {
  for (auto& v : mesh.vertices) {
    v += offset;
  }
}

void scale(TriangleMesh& mesh, double factor) {
  for (auto& v : mesh.vertices) {
    v *= factor;
  }
}

void flipOrientation(TriangleMesh& mesh) {
  for (auto& f : mesh.triangles) {
    std::swap(f[1], f[2]);
  }
}

namespace {

void renumber(TriangleMesh& mesh, const std::vector<std::int32_t>& map, std::size_t newCount,
              std::vector<Vec3> newVertices, bool dropCollapsed) {
  std::vector<Triangle> kept;
  kept.reserve(mesh.triangles.size());
  for (const auto& f : mesh.triangles) {
    const Triangle g{map[f[0]], map[f[1]], map[f[2]]};
    if (!dropCollapsed || (g[0] != g[1] && g[1] != g[2] && g[0] != g[2])) {
      kept.push_back(g);
    }
  }
  newVertices.resize(newCount);
  mesh.vertices = std::move(newVertices);
  mesh.triangles = std::move(kept);
}

} // namespace

std::size_t weldVertices(TriangleMesh& mesh, double tolerance) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::int32_t> map(n, -1);
  std::vector<Vec3> unique;
  unique.reserve(n);
  if (tolerance <= 0.0) {
    // Exact welding: STL stores each corner separately with bit-identical coordinates.
    std::map<std::array<double, 3>, std::int32_t> index;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = mesh.vertices[i];
      auto [it, inserted] = index.try_emplace({p.x(), p.y(), p.z()}, static_cast<std::int32_t>(unique.size()));
      if (inserted) {
        unique.push_back(p);
      }
      map[i] = it->second;
    }
  } else {
    // Tolerance welding on a hash grid of cell size `tolerance`: a vertex merges with the first
    // earlier representative within `tolerance` in its own or a neighbouring cell.
    struct KeyHash {
      std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
        return static_cast<std::size_t>(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
      }
    };
    std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::int32_t>, KeyHash> grid;
    auto cell = [&](const Vec3& p) {
      return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p.x() / tolerance)),
                                         static_cast<std::int64_t>(std::floor(p.y() / tolerance)),
                                         static_cast<std::int64_t>(std::floor(p.z() / tolerance))};
    };
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = mesh.vertices[i];
      const auto c = cell(p);
      std::int32_t found = -1;
      for (int dx = -1; dx <= 1 && found < 0; ++dx) {
        for (int dy = -1; dy <= 1 && found < 0; ++dy) {
          for (int dz = -1; dz <= 1 && found < 0; ++dz) {
            auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == grid.end()) {
              continue;
            }
            for (auto u : it->second) {
              if ((unique[u] - p).norm() <= tolerance) {
                found = u;
                break;
              }
            }
          }
        }
      }
      if (found < 0) {
        found = static_cast<std::int32_t>(unique.size());
        unique.push_back(p);
        grid[c].push_back(found);
      }
      map[i] = found;
    }
  }
  const std::size_t removed = n - unique.size();
  const std::size_t count = unique.size();
  renumber(mesh, map, count, std::move(unique), true);
  return removed;
}

void removeUnusedVertices(TriangleMesh& mesh) {
  std::vector<std::int32_t> map(mesh.vertices.size(), -1);
  std::vector<Vec3> used;
  for (const auto& f : mesh.triangles) {
    for (auto v : f) {
      if (map[v] < 0) {
        map[v] = static_cast<std::int32_t>(used.size());
        used.push_back(mesh.vertices[v]);
      }
    }
  }
  const std::size_t count = used.size();
  renumber(mesh, map, count, std::move(used), false);
}

} // namespace armour::geometry
