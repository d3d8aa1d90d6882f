// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file FdemMesh.hpp
/// The contact-element mesh of one shape for the FDEM potential contact (Munjiza 2004, ch. 2;
/// docs/theory.md, "FDEM potential contact"): linear tetrahedra of the body (body frame, unscaled,
/// shared by every body of the shape like the level set), of which only the elements within reach
/// of the surface are kept, each carrying its potential, the boundary triangles that act as
/// contactor faces, and a bounding-volume hierarchy over the kept elements.
///
/// Potential of element e (barycentric coordinates lambda_k(x) = g_k . x + c_k, k = 0..3, lambda_k
/// = 0 on the face opposite vertex k):
///
///   psi_e(x) = 4 P_e min_k lambda_k(x)         (unit: m; zero on the faces, P_e at the centroid)
///
/// It is linear on each of the four sub-tetrahedra obtained by splitting e at its centroid (sub-tet
/// k = conv(centroid, face k) is exactly where lambda_k is the smallest), which is Munjiza's
/// potential. P_e is set so that psi_e grows at unit rate (1 m per m) with the depth below the
/// element's boundary face(s): P_e = mean over its boundary faces of the centroid's distance to the
/// face (r_k = h_k / 4). psi therefore measures depth below the body surface near the surface, and
/// the contact pressure of a flat overlap of depth d between two bodies is E_p d / L, the level-set
/// law's (FdemPotential.hpp).
///
/// Kept elements: those with a boundary face (the surface layer). The others carry no potential
/// (psi = 0 there): an element touching the surface at a vertex or an edge only has psi ~ 0 near it
/// and would add O(d / h) relative to the force at depth d; an overlap deeper than the surface layer
/// would see no push, and the run stops before that (the reach guard, FdemMesh::reach()).
///
/// Thread-safe: const member functions only read.

#include "geometry/Tetrahedralizer.hpp"
#include "geometry/TriangleMesh.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace armour::contact {

using geometry::Box3;
using geometry::Vec3;

/// How the contact-element mesh of a shape is made.
struct FdemMeshSettings {
  /// Wanted number of tetrahedra over the whole body, before the deep ones are dropped (unit: -).
  /// Seed 002 uses about 2500 per Core-Loc.
  std::size_t elementsPerUnit = 2500;
};

/// One kept tetrahedron.
struct FdemElement {
  std::array<Vec3, 4> lambdaGradient;  ///< g_k: gradient of barycentric coordinate k (unit: 1/m)
  std::array<double, 4> lambdaOffset{}; ///< c_k: lambda_k(x) = g_k . x + c_k (unit: -)
  double peak = 0.0;                    ///< P_e: psi at the centroid (unit: m)
  Vec3 centroid = Vec3::Zero();         ///< unit: m
  Box3 box;                             ///< bounds of the corners (unit: m)
  std::uint32_t firstFace = 0;          ///< its boundary faces are faces()[firstFace, firstFace + faceCount)
  std::uint32_t faceCount = 0;          ///< 0 to 4 boundary faces (unit: -)
  std::array<std::int32_t, 4> nodes{};  ///< vertex indices into FdemMesh::vertices()

  /// Barycentric coordinate k at x (unit: -).
  [[nodiscard]] double lambda(int k, const Vec3& x) const { return lambdaGradient[k].dot(x) + lambdaOffset[k]; }
  /// The potential psi_e at x (unit: m); meaningful inside the element (negative outside).
  [[nodiscard]] double psi(const Vec3& x) const;
};

/// A boundary triangle of the body: a contactor face.
struct FdemFace {
  std::array<Vec3, 3> corners; ///< counter-clockwise seen from outside (unit: m)
  Vec3 normal = Vec3::Zero();  ///< unit outward normal (unit: -)
  double area = 0.0;           ///< unit: m^2
  std::uint32_t element = 0;   ///< the kept element it bounds
};

/// Node of the element hierarchy: an inner node has two children, a leaf a range of elements.
struct FdemBvhNode {
  Box3 box;                 ///< bounds of its elements (unit: m)
  std::int32_t left = -1;   ///< first child, or -1 for a leaf
  std::int32_t right = -1;  ///< second child
  std::uint32_t first = 0;  ///< leaf: first entry of FdemMesh::bvhElements()
  std::uint32_t count = 0;  ///< leaf: number of elements
};

class FdemMesh {
public:
  /// Tetrahedralise `surface` (geometry::tetrahedralize, surface refined to the lattice spacing)
  /// at settings.elementsPerUnit and keep the surface layer.
  /// @pre `surface` is valid (closed, manifold, outward), in the body frame.
  /// @throws core::InputError naming `source` when meshing fails or the count is out of range.
  FdemMesh(const geometry::TriangleMesh& surface, const FdemMeshSettings& settings, const std::string& source);
  /// From a given tet mesh (tests, or a mesh made elsewhere); the surface layer is kept.
  FdemMesh(const geometry::TetMesh& tets, const std::string& source);

  [[nodiscard]] const std::vector<Vec3>& vertices() const { return vertices_; }
  [[nodiscard]] const std::vector<FdemElement>& elements() const { return elements_; }
  [[nodiscard]] const std::vector<FdemFace>& faces() const { return faces_; }
  [[nodiscard]] const std::vector<FdemBvhNode>& bvh() const { return nodes_; }
  [[nodiscard]] const std::vector<std::uint32_t>& bvhElements() const { return order_; }
  /// Tetrahedra of the full mesh before the deep ones were dropped (unit: -).
  [[nodiscard]] std::size_t totalTetCount() const { return totalTets_; }
  /// All tetrahedra of the body (indices into vertices()), kept or not: the body's solid, for the
  /// exact energy integral (fdemBodyPairEnergy).
  [[nodiscard]] const std::vector<geometry::Tet>& allTets() const { return tets_; }
  /// Volume of the full tet mesh (unit: m^3).
  [[nodiscard]] double volume() const { return volume_; }
  /// Reach of the potential: the median P_e over elements with a boundary face (unit: m). An
  /// overlap this deep has reached a typical surface element's centroid, past which its push fades.
  [[nodiscard]] double reach() const { return reach_; }
  /// Largest ratio of a sub-tetrahedron's potential gradient to the unit surface gradient,
  /// max over kept elements and k of P_e / r_k (unit: -): how much stiffer than a flat face a corner
  /// or edge contact can be locally.
  [[nodiscard]] double maxGradientRatio() const { return maxGradient_; }
  /// psi of the body at a body-frame point (the kept element holding it; 0 elsewhere) (unit: m).
  [[nodiscard]] double potential(const Vec3& x) const;

private:
  void build(const geometry::TetMesh& tets, const std::string& source);
  std::int32_t buildNode(std::uint32_t first, std::uint32_t count, std::vector<Vec3>& centres);

  std::vector<Vec3> vertices_;
  std::vector<FdemElement> elements_;
  std::vector<FdemFace> faces_;
  std::vector<FdemBvhNode> nodes_;
  std::vector<geometry::Tet> tets_;
  std::vector<std::uint32_t> order_;
  std::size_t totalTets_ = 0;
  double volume_ = 0.0;
  double reach_ = 0.0;
  double maxGradient_ = 0.0;
};

} // namespace armour::contact
