// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableMesh.hpp
/// The finite-element mesh of a deformable unit: 4-node (linear) or 10-node (quadratic)
/// tetrahedra in their reference (unstressed) configuration. Units: metres.
///
/// Node order inside an element follows VTK (VTK_TETRA, VTK_QUADRATIC_TETRA), so frames need no
/// permutation: corners 0-3, then the mid-edge nodes of edges (0,1), (1,2), (2,0), (0,3), (1,3),
/// (2,3). Quadratic meshes are built from linear ones with straight edges (mid-edge nodes at the
/// edge midpoints), which is exact for the polyhedral armour units.

#include "geometry/Tetrahedralizer.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace armour::deformable {

using Vec3 = geometry::Vec3;

enum class ElementOrder : int { Linear = 4, Quadratic = 10 };

[[nodiscard]] constexpr int nodesPerElement(ElementOrder order) { return static_cast<int>(order); }

/// The local corner pair of each mid-edge node 4..9 of a 10-node tet (VTK order).
inline constexpr std::array<std::array<int, 2>, 6> kTet10Edges{{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};

struct DeformableMesh {
  ElementOrder order = ElementOrder::Linear;
  std::vector<Vec3> nodes;               ///< reference positions (unit: m); corners first, then mid-edge nodes
  std::vector<std::int32_t> connectivity; ///< nodesPerElement(order) node indices per element

  [[nodiscard]] int nodesPerElement() const { return deformable::nodesPerElement(order); }
  [[nodiscard]] std::size_t elementCount() const {
    return connectivity.size() / static_cast<std::size_t>(nodesPerElement());
  }
  [[nodiscard]] std::size_t nodeCount() const { return nodes.size(); }
  [[nodiscard]] const std::int32_t* element(std::size_t e) const {
    return connectivity.data() + e * static_cast<std::size_t>(nodesPerElement());
  }
  /// Number of corner nodes (the nodes of the underlying linear mesh; they come first).
  std::size_t cornerCount = 0;
};

/// A mesh of the given order from a linear tet mesh (e.g. geometry::tetrahedralize). For
/// Quadratic, one mid-edge node per edge, shared by every tet around the edge, numbered after
/// the corners in the order the edges are first met (element by element, local edge by local
/// edge): the same input gives the same numbering.
/// Throws core::InputError naming `source` when a tet is not positively oriented (volume <= 0)
/// or refers to a missing vertex.
/// Several tet meshes as one, each shifted by its offset (unit: m), vertices and tets appended in
/// the order given: separate bodies in one mesh, touching through BodyContact.hpp.
geometry::TetMesh mergeTetMeshes(const std::vector<geometry::TetMesh>& parts, const std::vector<Vec3>& offsets);

DeformableMesh makeDeformableMesh(const geometry::TetMesh& tets, ElementOrder order, const char* source = "tet mesh");

/// The disconnected parts of a mesh (two nodes are in one part when an element links them): the
/// part of each node, parts numbered in the order of their lowest node; `count` gets their number.
std::vector<std::int32_t> nodeParts(const DeformableMesh& mesh, std::size_t& count);

} // namespace armour::deformable
