// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/SurfaceLoads.hpp"

#include <algorithm>
#include <map>

namespace armour::deformable {
namespace {

/// Local mid-edge node (4..9) of the edge between local corners a and b.
int midEdgeLocal(int a, int b) {
  for (int e = 0; e < 6; ++e) {
    const auto& edge = kTet10Edges[e];
    if ((edge[0] == a && edge[1] == b) || (edge[0] == b && edge[1] == a)) {
      return 4 + e;
    }
  }
  return -1;
}

} // namespace

std::vector<BoundaryFace> boundaryFaces(const DeformableMesh& mesh) {
  // Face opposite local corner k: the other three corners.
  constexpr std::array<std::array<int, 3>, 4> kFaces{{{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};
  std::map<std::array<std::int32_t, 3>, std::pair<int, std::size_t>> uses; // sorted corners -> (count, element*4+face)
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    for (int f = 0; f < 4; ++f) {
      std::array<std::int32_t, 3> key{};
      for (int i = 0; i < 3; ++i) {
        key[i] = mesh.element(e)[kFaces[f][i]];
      }
      std::sort(key.begin(), key.end());
      auto& entry = uses[key];
      ++entry.first;
      entry.second = e * 4 + static_cast<std::size_t>(f);
    }
  }
  std::vector<std::size_t> keep;
  for (const auto& [key, entry] : uses) {
    if (entry.first == 1) {
      keep.push_back(entry.second);
    }
  }
  std::sort(keep.begin(), keep.end());
  std::vector<BoundaryFace> faces;
  faces.reserve(keep.size());
  for (const auto id : keep) {
    const std::size_t e = id / 4;
    const int f = static_cast<int>(id % 4);
    const auto* n = mesh.element(e);
    std::array<int, 3> local = kFaces[f];
    const Vec3& opposite = mesh.nodes[n[f]];
    Vec3 cross = (mesh.nodes[n[local[1]]] - mesh.nodes[n[local[0]]]).cross(mesh.nodes[n[local[2]]] - mesh.nodes[n[local[0]]]);
    if (cross.dot(opposite - mesh.nodes[n[local[0]]]) > 0.0) {
      std::swap(local[1], local[2]);
      cross = -cross;
    }
    BoundaryFace face;
    face.element = e;
    for (int i = 0; i < 3; ++i) {
      face.corners[i] = n[local[i]];
      face.midEdges[i] = mesh.order == ElementOrder::Quadratic ? n[midEdgeLocal(local[i], local[(i + 1) % 3])] : -1;
      face.centroid += mesh.nodes[face.corners[i]] / 3.0;
    }
    face.area = 0.5 * cross.norm();
    face.normal = cross.normalized();
    faces.push_back(face);
  }
  return faces;
}

namespace {

/// A face's consistent nodal forces under a uniform traction, added to `forces`.
void addFaceLoad(const DeformableMesh& mesh, const BoundaryFace& face, const Vec3& traction, std::vector<Vec3>& forces) {
  const Vec3 share = traction * (face.area / 3.0);
  for (int i = 0; i < 3; ++i) {
    forces[mesh.order == ElementOrder::Quadratic ? face.midEdges[i] : face.corners[i]] += share;
  }
}

} // namespace

std::vector<Vec3> tractionLoads(const DeformableMesh& mesh, const std::vector<BoundaryFace>& faces,
                                const std::function<bool(const BoundaryFace&)>& select, const Vec3& traction) {
  std::vector<Vec3> forces(mesh.nodeCount(), Vec3::Zero());
  for (const auto& face : faces) {
    if (select(face)) {
      addFaceLoad(mesh, face, traction, forces);
    }
  }
  return forces;
}

std::vector<Vec3> pressureLoads(const DeformableMesh& mesh, const std::vector<BoundaryFace>& faces,
                                const std::function<bool(const BoundaryFace&)>& select, double pressure) {
  std::vector<Vec3> forces(mesh.nodeCount(), Vec3::Zero());
  for (const auto& face : faces) {
    if (select(face)) {
      addFaceLoad(mesh, face, -pressure * face.normal, forces);
    }
  }
  return forces;
}

} // namespace armour::deformable
