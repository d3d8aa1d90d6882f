// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableCoupling.hpp
/// A deformable body among the moving rigid bodies of a World (issue 26: "a deformable unit inside
/// a rigid pack"; docs/theory.md section 19, "Moving rigid bodies"). A load stage of the World
/// that advances the deformable body in lock step with the World and gives the rigid bodies the
/// reaction of its contact.
///
/// Both integrators are velocity Verlet ("kick-drift-kick") with the same step h. The World kicks
/// its bodies by h/2, drifts them to their poses at t + h and evaluates its forces there; this
/// stage is part of that evaluation: it hands the deformable body the rigid bodies' poses at
/// t + h and advances it by h (its own kick, drift to t + h, contact and element forces, kick),
/// and returns minus the contact forces and moments that the deformable body's nodes received,
/// which the World adds to the bodies before its second kick. The forces on both sides are
/// evaluated at the same configuration (deformable nodes and rigid poses at t + h) and enter
/// both integrators with the same weights, so action equals reaction in every step: momentum
/// is exchanged exactly (test_deformable_coupling measures it to round-off).
///
/// The step is the deformable body's (its stable step, far below the World's), so the rigid
/// bodies' contacts among themselves and with the floor run at it too: the World's penalty
/// contact is stable at any shorter step. Fixed rigid bodies may be in the list; their loads are
/// reported and ignored by the World.
///
/// The first force evaluation of a World (its step 0, or evaluateContacts) evaluates the body at
/// its current state without stepping it.

#include "deformable/DeformableBody.hpp"
#include "simulation/LoadStage.hpp"
#include "simulation/World.hpp"

#include <vector>

namespace armour::simulation {

class DeformableCoupling final : public LoadStage {
public:
  /// The deformable body touches the rigid bodies `rigid` (World ids) through their level sets;
  /// it must have rigid contact on (DeformableSettings::rigidContact). The body must outlive the
  /// stage; its stable step is the World's step (give WorldSettings::timeStep = it).
  DeformableCoupling(deformable::DeformableBody& body, std::vector<BodyId> rigid);

  [[nodiscard]] std::string name() const override { return "deformable"; }
  void apply(const World& world, double time, std::span<dynamics::Vec3> force,
             std::span<dynamics::Vec3> torque) override;

  /// The rigid bodies' obstacles at their current poses in `world`, in the order of `rigid`.
  [[nodiscard]] std::vector<deformable::RigidObstacle> obstacles(const World& world) const;
  [[nodiscard]] const std::vector<BodyId>& rigidBodies() const { return rigid_; }
  [[nodiscard]] std::string summary() const override;

private:
  deformable::DeformableBody& body_;
  std::vector<BodyId> rigid_;
  std::uint64_t steps_ = 0;
};

} // namespace armour::simulation
