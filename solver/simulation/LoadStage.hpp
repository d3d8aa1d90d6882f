// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file LoadStage.hpp
/// The "external loads" stage of the time step (docs/architecture.md): loads that do not come
/// from contacts or gravity — hydrodynamics replayed from a storm file, analytic wave forces.
/// The World runs every stage once per force evaluation, after the contact law, and sums their
/// loads into the bodies' accumulators. It also
///  - integrates the work of the loads (trapezoidal rule on F . v + T . omega), so the energy guard
///    rail does not take a wave's work for an instability;
///  - wakes a sleeping body whose load has moved by more than SleepSettings::wakeLoadFraction of
///    its weight since it fell asleep (a settled pack sleeps through still water and wakes when a
///    wave arrives).

#include "dynamics/RigidBodies.hpp"

#include <span>
#include <string>
#include <vector>

namespace armour::simulation {

class World;

class LoadStage {
public:
  virtual ~LoadStage() = default;

  /// Name for logs and checkpoints, e.g. "hydro".
  [[nodiscard]] virtual std::string name() const = 0;

  /// Write the load on every body: force (N, world) and torque about the centre of mass (N m,
  /// world), into arrays that come zeroed and sized to the body count. `time` is the time of the
  /// state being evaluated (unit: s). The contact forces of this evaluation are already in
  /// world.bodies().force(b) (a stage may read them, e.g. for added mass). Write loads for
  /// sleeping bodies too (they decide waking); static bodies' loads are ignored. Called from one
  /// thread; a stage may use OpenMP inside but must give the same result for any thread count.
  virtual void apply(const World& world, double time, std::span<dynamics::Vec3> force,
                     std::span<dynamics::Vec3> torque) = 0;

  /// The stage's own state (held loads, update times), for bit-identical restarts: saved in the
  /// checkpoint under name() and handed back to restoreState() before the first step.
  [[nodiscard]] virtual std::vector<double> saveState() const { return {}; }
  /// Throws core::InputError if the state does not fit (another scene).
  virtual void restoreState(const std::vector<double>& /*state*/) {}

  /// One line for the end of the run log: what the stage computed and what it skipped since it
  /// was made (a run's restart counts from the restart). Empty: nothing to say.
  [[nodiscard]] virtual std::string summary() const { return {}; }
};

} // namespace armour::simulation
