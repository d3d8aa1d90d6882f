// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/DeformableMesh.hpp"

#include "core/Error.hpp"

#include <numeric>
#include <unordered_map>

namespace armour::deformable {
namespace {

void checkTets(const geometry::TetMesh& tets, const char* source) {
  const auto count = static_cast<std::int64_t>(tets.vertices.size());
  for (std::size_t t = 0; t < tets.tets.size(); ++t) {
    for (const auto v : tets.tets[t]) {
      if (v < 0 || v >= count) {
        core::failInput(source, "tet {} refers to vertex {}, but there are {} vertices; the mesh is damaged", t, v,
                        count);
      }
    }
    const double volume = tets.volume(t);
    if (!(volume > 0.0)) {
      core::failInput(source,
                      "tet {} has volume {} m^3: elements must be positively oriented, (b-a).((c-a)x(d-a)) > 0; "
                      "swap two vertices of inverted tets and remove flat ones",
                      t, volume);
    }
  }
}

std::int32_t findRoot(std::vector<std::int32_t>& parent, std::int32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

} // namespace

DeformableMesh makeDeformableMesh(const geometry::TetMesh& tets, ElementOrder order, const char* source) {
  checkTets(tets, source);
  DeformableMesh mesh;
  mesh.order = order;
  mesh.nodes = tets.vertices;
  mesh.cornerCount = tets.vertices.size();
  const int nen = nodesPerElement(order);
  mesh.connectivity.reserve(tets.tets.size() * static_cast<std::size_t>(nen));
  // Key of an undirected edge: (smaller, larger) corner index packed into 64 bits. The map only
  // finds an edge's node; numbering comes from the loop order, so it is deterministic.
  std::unordered_map<std::uint64_t, std::int32_t> edgeNode;
  for (const auto& tet : tets.tets) {
    mesh.connectivity.insert(mesh.connectivity.end(), tet.begin(), tet.end());
    if (order == ElementOrder::Linear) {
      continue;
    }
    for (const auto& [a, b] : kTet10Edges) {
      const auto lo = static_cast<std::uint64_t>(std::min(tet[a], tet[b]));
      const auto hi = static_cast<std::uint64_t>(std::max(tet[a], tet[b]));
      const auto [it, inserted] = edgeNode.try_emplace((lo << 32U) | hi, static_cast<std::int32_t>(mesh.nodes.size()));
      if (inserted) {
        mesh.nodes.push_back(0.5 * (tets.vertices[lo] + tets.vertices[hi]));
      }
      mesh.connectivity.push_back(it->second);
    }
  }
  return mesh;
}

geometry::TetMesh mergeTetMeshes(const std::vector<geometry::TetMesh>& parts, const std::vector<Vec3>& offsets) {
  geometry::TetMesh out;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const auto base = static_cast<int>(out.vertices.size());
    const Vec3 offset = p < offsets.size() ? offsets[p] : Vec3::Zero();
    for (const auto& v : parts[p].vertices) {
      out.vertices.push_back(v + offset);
    }
    for (auto t : parts[p].tets) {
      for (auto& n : t) {
        n += base;
      }
      out.tets.push_back(t);
    }
  }
  return out;
}

std::vector<std::int32_t> nodeParts(const DeformableMesh& mesh, std::size_t& count) {
  const int nen = mesh.nodesPerElement();
  const std::size_t nodes = mesh.nodeCount();
  // Union-find over the elements' nodes.
  std::vector<std::int32_t> parent(nodes);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    for (int a = 1; a < nen; ++a) {
      const auto r0 = findRoot(parent, mesh.element(e)[0]);
      const auto r1 = findRoot(parent, mesh.element(e)[a]);
      parent[std::max(r0, r1)] = std::min(r0, r1);
    }
  }
  count = 0;
  std::vector<std::int32_t> part(nodes, -1);
  std::vector<std::int32_t> rootPart(nodes, -1);
  for (std::size_t n = 0; n < nodes; ++n) {
    const auto r = findRoot(parent, static_cast<std::int32_t>(n));
    if (rootPart[r] < 0) {
      rootPart[r] = static_cast<std::int32_t>(count++);
    }
    part[n] = rootPart[r];
  }
  return part;
}

} // namespace armour::deformable
