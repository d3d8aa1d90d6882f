// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StepSettings.hpp
/// The settings of the time step, owned by the simulation stage and filled by io's scene reader
/// directly (one struct per concept, no twin in io): the penalty solver's automatic step (a
/// fraction of the stability limit) and the constraint solver's step, substeps and contact
/// settings. Header-only and free of the World, so io can include it.

namespace armour::simulation {

/// The fraction of the penalty solver's stability limit that `time_step: auto` uses (unit: -).
/// Ours: measured on the fidelity ladder in ensembles (docs/fidelity.md, "The penalty step in
/// ensembles"): 0.4 and 0.8 move more units than 0.2 on every measure.
inline constexpr double kTimeStepSafety = 0.2;

/// The constraint solver's step range (unit: s): above 1/30 s a wave's 0.05 s records are skipped
/// and the speculative margin no longer covers a falling unit's travel; below 1e-6 s the penalty
/// solver is the better tool. Ours.
inline constexpr double kMaxConstraintStep = 1.0 / 30.0;
inline constexpr double kMinConstraintStep = 1.0e-6;

/// Settings of the constraint solver (contact.constraint in the scene file). Every default is
/// ours, chosen from the measurements in docs/benchmarks.md ("The constraint solver").
struct ConstraintSettings {
  double timeStep = 1.0 / 200.0;      ///< step with time_step: auto (unit: s); divides the storm record interval 0.05 s
  /// Substeps per step (unit: -): 3 since session 20, measured against 2 and 4 in docs/fidelity.md
  /// ("Substeps of the constraint solver").
  int substeps = 3;
  /// Damping ratio of each contact point's spring; the spring itself is the penalty law's E_p A / L
  /// (the materials' penalty modulus), capped at a quarter of the substep rate (unit: -).
  double dampingRatio = 10.0;
  double pushSpeed = 3.0;             ///< largest speed at which an overlap is pushed out (unit: m/s)
  double restitutionThreshold = 0.2;  ///< approach speed below which impacts are inelastic (unit: m/s)
  double speculativeMargin = 0.05;    ///< gap within which contacts are speculative, as a fraction of the pair's smaller Dn (unit: -)
  double patchAngle = 0.5;            ///< largest angle between normals of one contact patch (unit: rad)
  /// Friction anchors (ours, session 18): the slip a point makes while it sticks is carried from
  /// step to step and pulled back by the point's spring rate. Off by default: measured, they stop
  /// a tilted pack's slow creep sooner but neither change the storm damage nor help the 100:1
  /// stack or the Dolos pile (docs/theory.md, "Friction").
  bool frictionAnchors = false;
  /// Manifold reuse (ours, session 18; Jolt's body-pair cache is the same idea): a pair whose
  /// relative pose has moved less than this x Dn (and turned less than 2 x this rad) since its last
  /// full narrow phase, and cannot close that much in one step, keeps that narrow phase's patches,
  /// their depths moved with the relative motion (docs/theory.md, "Manifold reuse") (unit: Dn).
  double reuseDistance = 0.001;
};

} // namespace armour::simulation
