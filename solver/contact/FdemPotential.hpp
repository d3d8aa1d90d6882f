// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file FdemPotential.hpp
/// The FDEM potential contact force between two bodies' contact-element meshes (FdemMesh), and
/// between a body and static geometry given as half-spaces (Munjiza 2004, ch. 2; seed 002 eq. 5;
/// derivation and algorithm in docs/theory.md, "FDEM potential contact").
///
/// Energy of a body pair, with phi = G psi (G: potential gradient, Pa/m):
///   E = integral over A n B of (phi_A + phi_B) dV
/// Its exact negative gradient for rigid motion is a traction on the boundary of the overlap,
/// n (phi_A - phi_B) (seed 002 eq. 5), which for rigid bodies reduces to the bodies' own surfaces:
///   force on A = - integral over (dA inside B) of n_A phi_B dS  +  integral over (dB inside A) of n_B phi_A dS
/// (faces shared by two elements of one body carry equal and opposite integrals and cancel). Each
/// surface triangle of A is clipped against each sub-tetrahedron of each element of B it meets, and
/// the linear phi_B integrated exactly over the clipped polygon; then the same with A and B swapped.
/// Every element pair (c of A, t of B) is taken once each way: c's faces in t and t's faces in c.
///
/// Penalty mapping: with G = E_p / (2 L) for each body (FdemMesh makes psi the depth below the
/// surface near the surface), a flat overlap of depth d is pressed by E_p d / L, as in the
/// level-set law (docs/theory.md, "Contact law"). A static half-space (plane, face of a static
/// convex piece) has psi = its exact depth and G = E_p / L, and only A's surface is integrated
/// against it (the static solid has no potential of its own): the same pressure E_p d / L.
///
/// Thread-safe: free functions, reading their arguments only.

#include "contact/FdemMesh.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace armour::contact {

/// Most faces a static convex piece may have under fdem (its cells are clipped in fixed-size
/// polygons); World::addConvex refuses more with an InputError (unit: -).
inline constexpr std::size_t kFdemMaxStaticFaces = 56;

using geometry::Mat3;

/// Where a body is: world = position + rotation (scale body), body frame unscaled.
struct FdemPose {
  Mat3 rotation = Mat3::Identity(); ///< body -> world (unit: -)
  Vec3 position = Vec3::Zero();     ///< world position of the body-frame origin (unit: m)
  double scale = 1.0;               ///< uniform scale of the shared mesh (unit: -)
};

/// The potential contact of one element pair (both directions summed), or of one contactor face of
/// A against static geometry.
struct FdemContact {
  std::uint32_t contactor = 0;   ///< element of A (body pair) or surface face of A (static)
  std::uint32_t target = 0;      ///< element of B (body pair); 0 for static geometry
  Vec3 force = Vec3::Zero();     ///< elastic potential force on A (unit: N, world); B gets minus it
  Vec3 torque = Vec3::Zero();    ///< torque of `force` on A about A's origin, exact (unit: N m)
  Vec3 point = Vec3::Zero();     ///< centre of the potential traction (unit: m, world)
  /// Contact normal pushing A: where the potentials fall fastest (out of the other body), weighted
  /// by the traction; for a face pressed flat it is the force's direction. Damping and friction use
  /// this frame, so the strip of a side face dipping below a surface is not taken for an impact
  /// against it when the body slides (unit: -, world).
  Vec3 normal = Vec3::Zero();
  /// k = G x the clipped faces' area projected on the potential gradient (faces facing the other
  /// body; a side face dipping in counts nothing, as the level-set law's projected areas) (unit: N/m)
  double stiffness = 0.0;
  double depth = 0.0;            ///< (force . normal) / k: the traction-weighted mean depth (unit: m)
  double maxDepth = 0.0;         ///< largest psi met on the clipped faces (unit: m)
  /// Elastic energy estimate G/2 x integral of psi^2 over the clipped faces (unit: J): the energy of
  /// columns along which psi grows at unit rate, exact for a flat overlap within the surface
  /// sub-tetrahedra; low in the strips along element edges, where psi is capped by the neighbouring
  /// face's coordinate (relative error O(d / h)). For the energy guard rail and reports; the exact
  /// volume integral (fdemBodyPairEnergy) is far too slow for every step.
  double energy = 0.0;
};

/// Potential contact of bodies A and B: one record per element pair with a non-zero force, in the
/// order of the hierarchy traversal (deterministic), appended to `out`.
/// @param gradient G of each body's potential phi = G psi (unit: Pa/m), E_p / (2 L) for the level-set pressure
/// @returns the deepest psi met (unit: m), also where the force is zero
double fdemBodyPair(const FdemMesh& a, const FdemPose& pa, const FdemMesh& b, const FdemPose& pb, double gradient,
                    std::vector<FdemContact>& out);

/// Potential contact of body A with the static convex solid {x : n_k . x <= d_k for all k} (one
/// plane: a half-space), psi = min_k (d_k - n_k . x), only where A's box meets `region` (world).
/// One record per surface face of A with a non-zero force, appended to `out`.
/// @param gradient G (unit: Pa/m), E_p / L for the level-set pressure
/// @pre at most 56 faces
/// @returns the deepest psi met (unit: m)
double fdemHalfSpaces(const FdemMesh& a, const FdemPose& pa, std::span<const Vec3> normals,
                      std::span<const double> offsets, const Box3& region, double gradient,
                      std::vector<FdemContact>& out);

/// E = G x integral over A n B of (psi_A + psi_B) dV, exact (each sub-tetrahedron of a kept element
/// clipped against every tetrahedron of the other body's solid): the energy whose negative gradient
/// fdemBodyPair returns. For tests; far slower than the force (unit: J).
double fdemBodyPairEnergy(const FdemMesh& a, const FdemPose& pa, const FdemMesh& b, const FdemPose& pb, double gradient);

/// E = G x integral over A n solid of psi_static dV, exact (every tetrahedron of A clipped against
/// the cells of the static solid): the energy of fdemHalfSpaces (unit: J).
double fdemHalfSpacesEnergy(const FdemMesh& a, const FdemPose& pa, std::span<const Vec3> normals,
                            std::span<const double> offsets, double gradient);

} // namespace armour::contact
