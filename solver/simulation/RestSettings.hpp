// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RestSettings.hpp
/// How bodies come to rest: sleeping (`sleep:` in the scene file) and the viscous body damping
/// (`body_damping:`). Owned by the simulation stage and filled by io's scene reader directly (one
/// struct per concept, no twin in io). Header-only and free of the World, so io can include it.

namespace armour::simulation {

/// When bodies may sleep: a sleeping body is skipped by the integrator and its pairs with other
/// sleeping or static bodies are not examined, so a settled pack costs nothing until something
/// moving touches it (seed 001: the "sleep" that keeps resting packs from chattering). Every
/// default is ours.
/// Which bodies must be at rest for a body to sleep.
enum class SleepScope {
  /// Every body of its contact island (Box2D's and Jolt's rule): one unit creeping anywhere in a
  /// pile keeps the whole pile awake.
  Island,
  /// The body and the bodies it touches: a resting body next to a moving one stays awake, one two
  /// contacts away may sleep, and wakes as soon as a body it touches moves (ours; measured in
  /// docs/benchmarks.md, "Sleeping by neighbours").
  Neighbours,
};

struct SleepSettings {
  bool enabled = true;
  SleepScope scope = SleepScope::Island;
  double linearSpeed = 1.0e-3;  ///< centroid speed below which a body is at rest (unit: m/s)
  double angularSpeed = 1.0e-3; ///< angular speed below which a body is at rest (unit: rad/s)
  double time = 0.5;            ///< a whole contact island must rest this long to sleep (unit: s)
  /// A sleeping body wakes when its external load (LoadStage) differs from the load it fell asleep
  /// under by more than this fraction of its weight m |g| (unit: -).
  double wakeLoadFraction = 0.01;
};

/// Viscous damping of every dynamic body's motion, v and omega decaying as exp(-c t): the air and
/// water resistance of a physics engine's bodies (seed 001: PhysX linear and angular damping 0.9
/// 1/s, "to model air and water resistance"; docs/theory.md, "Body damping"). Off by default:
/// armour's storm loads model the water.
struct BodyDamping {
  double linear = 0.0;  ///< decay rate of the centroid velocity (unit: 1/s)
  double angular = 0.0; ///< decay rate of the angular velocity (unit: 1/s)
};

} // namespace armour::simulation
