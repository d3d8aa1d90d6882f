// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file WorldState.hpp
/// Everything a World needs to continue a run bit for bit: the raw body state, the forces of the
/// last evaluation (the velocity Verlet step starts with a half kick by them), the friction
/// springs of every contact point, the rest timers of the sleep logic and the energy monitor.
/// Shapes, materials, static geometry and settings are not part of it: they come from the scene,
/// which the checkpoint identifies by a fingerprint (io/CheckpointFile).

#include "dynamics/RigidBodies.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace armour::simulation {

/// One body, exactly as held in memory.
struct BodyState {
  dynamics::MotionType motion = dynamics::MotionType::Dynamic;
  dynamics::Vec3 position = dynamics::Vec3::Zero();        ///< centre of mass, world (m)
  dynamics::Quat orientation = dynamics::Quat::Identity(); ///< principal frame -> world (-)
  dynamics::Vec3 velocity = dynamics::Vec3::Zero();        ///< m/s
  dynamics::Vec3 angularMomentum = dynamics::Vec3::Zero(); ///< world frame (kg m^2/s)
  dynamics::Vec3 force = dynamics::Vec3::Zero();           ///< last evaluation (N)
  dynamics::Vec3 torque = dynamics::Vec3::Zero();          ///< last evaluation (N m)
  double restTime = 0.0;                                   ///< time at rest so far (s)
  std::int32_t contactCount = 0;                           ///< engaged points, last evaluation (-)
  double maxContactForce = 0.0;                            ///< largest point force, last evaluation (N)
  dynamics::Vec3 externalForce = dynamics::Vec3::Zero();   ///< load stages, last evaluation (N)
  dynamics::Vec3 externalTorque = dynamics::Vec3::Zero();  ///< load stages, last evaluation (N m)
  dynamics::Vec3 sleepLoad = dynamics::Vec3::Zero();       ///< external force when it fell asleep (N)
};

/// The friction spring of one contact point.
struct ContactPointState {
  std::uint32_t first = 0;  ///< body index
  std::uint32_t second = 0; ///< body index, or a flag bit | plane / static piece index
  std::uint32_t key = 0;    ///< direction bit | sample index
  dynamics::Vec3 stretch = dynamics::Vec3::Zero(); ///< tangential spring stretch, world (m)
  bool sliding = false;
  double normalImpulse = 0.0;                              ///< constraint solver's warm start (N s)
  dynamics::Vec3 tangentImpulse = dynamics::Vec3::Zero();  ///< constraint solver's warm start, world (N s)
};

struct WorldState {
  double time = 0.0;          ///< s
  std::uint64_t steps = 0;
  bool forcesReady = false;   ///< the forces below belong to the state (false before the first step)
  double energyMinimum = 0.0; ///< energy monitor: lowest E - W so far (J)
  double externalWork = 0.0;  ///< energy monitor: work of external loads so far (J)
  double energyPeak = 0.0;    ///< energy monitor: largest kinetic + elastic energy seen (J)
  bool energyStarted = false; ///< energy monitor: has a reference
  std::vector<BodyState> bodies;
  std::vector<ContactPointState> contacts; ///< sorted by (first, second, key)
  /// Each load stage's own state (LoadStage::saveState), in the order the stages were added.
  std::vector<std::pair<std::string, std::vector<double>>> loadStages;
  /// The constraint solver's reused manifolds (World::CachedManifold, flattened by
  /// World::saveManifoldCache; empty without reuse).
  std::vector<double> manifoldCache;
};

} // namespace armour::simulation
