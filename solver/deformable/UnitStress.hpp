// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file UnitStress.hpp
/// The stress in one unit of a rigid storm replay at each of its recorded load cases: the second
/// stage of `armour stress` (issue 26; docs/theory.md section 19, "Stress in a stormed pack").
/// The unit's surface (body frame, as the run recorded it) is meshed once by gmsh, its stiffness
/// factored once (QuasiStaticUnit), and each load case (the contact forces of one record, with
/// the unit's spin) is one back substitution and the element stresses.
///
/// Two maxima per case, because a rigid model gives a contact's force, not its pressure:
///  - sigma1: the largest principal stress (tension positive) of any element. Within about the
///    spread radius of a contact it depends on how the force is spread (QuasiStatic.hpp), so it
///    grows as the radius shrinks;
///  - sigma1Away: the same over elements whose centroid lies farther than `awayDistance` from
///    every load point: the bending and tension of the unit's body and legs, which is what breaks
///    Dolos and Core-Loc legs, and which does not depend on the spread radius.

#include "deformable/QuasiStatic.hpp"

#include "geometry/TriangleMesh.hpp"

#include <filesystem>
#include <memory>
#include <vector>

namespace armour::deformable {

struct UnitStressSettings {
  MaterialSettings material;        ///< E, nu, density (seed 002 Table 2's concrete by default)
  ElementOrder order = ElementOrder::Quadratic; ///< tet10 with F-bar, or tet4
  std::size_t tets = 4000;          ///< tetrahedra asked of gmsh (unit: -)
  double spreadRadius = 0.1;        ///< each contact force spread over the surface within this (unit: m)
  double awayDistance = 0.2;        ///< sigma1Away counts elements farther than this from every load (unit: m)
};

/// One load case: the contact forces on the unit and its spin, in its body frame.
struct UnitLoadCase {
  std::vector<PointLoad> loads;
  Vec3 angularVelocity = Vec3::Zero(); ///< (unit: rad/s)
};

/// The stress of one load case.
struct UnitStressResult {
  double sigma1 = 0.0;             ///< largest principal stress of any element (unit: Pa), tension positive
  Vec3 where = Vec3::Zero();       ///< centroid of that element, body frame (unit: m)
  double sigma1Away = 0.0;         ///< the same away from the loads (unit: Pa); 0 if no element is away
  Vec3 whereAway = Vec3::Zero();   ///< (unit: m)
  double differential = 0.0;       ///< largest sigma1 - sigma3 of any element (unit: Pa)
  double imbalance = 0.0;          ///< QuasiStaticResult::imbalance (unit: -)
};

class UnitStressModel {
public:
  /// Mesh `surface` (closed, body frame) and factor its stiffness. Throws core::InputError naming
  /// `source` when gmsh cannot mesh it or the mesh cannot be factored.
  UnitStressModel(const geometry::TriangleMesh& surface, const UnitStressSettings& settings, const std::string& source);
  ~UnitStressModel();

  [[nodiscard]] UnitStressResult evaluate(const UnitLoadCase& c) const;
  /// The stress field of a case, per element (for a VTU of the worst case).
  [[nodiscard]] QuasiStaticResult solve(const UnitLoadCase& c) const;

  /// A VTU of case `c` for ParaView (DeformableVtu.hpp): the unit in its body frame with its
  /// displacements and stress fields (principal stresses, von Mises: frame-free).
  void writeVtu(const UnitLoadCase& c, const std::filesystem::path& path);

  [[nodiscard]] const DeformableBody& body() const { return *body_; }
  [[nodiscard]] std::size_t elementCount() const;

private:
  UnitStressSettings settings_;
  std::unique_ptr<DeformableBody> body_;
  std::unique_ptr<QuasiStaticUnit> unit_;
  std::vector<Vec3> centroids_; ///< per element, body frame (unit: m)
};

} // namespace armour::deformable
