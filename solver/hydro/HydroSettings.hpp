// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file HydroSettings.hpp
/// Settings of the hydrodynamic loads on units: the `hydro:` block of a scene (docs/scene-file.md).
/// Plain data, no dependencies: the scene reader (armour::io) fills it, the load stages
/// (armour::hydro) use it. Axes: x onshore, y along the trunk, z up. SI units.

#include <cstdint>
#include <string>

namespace armour::hydro {

/// Which model gives the loads.
enum class HydroModel {
  Storm,        ///< pressure integration + Morison from a storm file (seed 000)
  Oscillating,  ///< seed 001 eq. 1-2: F0 [e_x cos(wt - kx) + e_z sin(wt - kx)] phi(z)
  ShallowWave,  ///< seed 003 eq. 2: onshore force by the shallow-water phase on a slope, exposed units only
};

/// How held loads behave between two updates.
enum class BetweenUpdates {
  Hold,        ///< the load of the last update until the next (seed 000)
  Interpolate, ///< linear from the last update's load to the next one's (computed one interval ahead)
};

struct VariabilitySettings {
  bool enabled = true;              ///< add the storm file's Weibull variability (if the file has a model)
  std::uint64_t seed = 1;           ///< reproducible draws: same seed, same deviations (unit: -)
  /// Each unit's surface is split into patches_per_axis^3 patches in its body frame, each with its own
  /// deviation per half wave (unit: -); 1 = one deviation per unit (which a closed surface integrates to
  /// no net force), 2 = octants.
  int patchesPerAxis = 2;
};

struct DragSettings {
  bool enabled = true;
  double coefficient = 1.0;         ///< C_d of seed 000 eq. 2 (unit: -)
};

struct AddedMassSettings {
  bool enabled = false;             ///< the inertia option of seed 000 eq. 1
  double coefficient = 1.0;         ///< C_a (unit: -)
};

/// What lies under a unit that rests on the bed (docs/foam-bridge.md, "A unit on an impermeable bed").
enum class BedKind {
  Porous,      ///< water under the unit at the pressure of its surroundings: every element takes pressure (seed 000's
               ///< units on a rock underlayer; the tank's convention when units sit on a porous layer)
  Impermeable, ///< a tank floor or a slab: elements lying on the bed and facing down into it take no pressure
};

/// The bed under the units, for the pressure integration (hydro.storm.bed*, docs/scene-file.md).
struct BedSettings {
  BedKind kind = BedKind::Porous;
  /// z of the bed in the scene's coordinates (unit: m). The scene reader fills it from
  /// hydro.storm.bed_level, or from the scene's one horizontal static plane.
  double level = 0.0;
  /// An element lies on the bed when its centroid is at most this far above it (or anywhere below
  /// it), as a fraction of its unit's Dn (unit: Dn). 0.01 is ours: a unit resting on the bed sinks
  /// into it by the contact overlap, ~1e-5 Dn at the default penalty (docs/scene-file.md), and a
  /// rocking unit's lifted edge, which water reaches, leaves the band after a tilt of ~1 degree.
  double toleranceDn = 0.01;
};

struct StormLoadSettings {
  std::string file;                 ///< storm file; relative paths are relative to the scene file
  double timeOffset = 0.0;          ///< storm time at simulation time 0 (unit: s)
  /// Where the scene's origin lies in the storm file's (x, z): storm x = scene x + offsetX, storm
  /// z = scene z + offsetZ. A tank has its own origin (its inlet, its floor); a placed scene its
  /// own (the foot of the face): this puts one on the other without placing again (unit: m).
  double offsetX = 0.0, offsetZ = 0.0;
  double updateInterval = 0.1;      ///< loads recomputed every this much simulated time (unit: s); seed 000: 0.1
  /// The loads rise from zero over the first rampTime of simulated time by the half cosine
  /// r(t) = (1 - cos(pi t / rampTime)) / 2, so that water put on a pack placed dry does not hit it
  /// at once; 0 = full loads from the first step (unit: s).
  double rampTime = 0.0;
  BetweenUpdates betweenUpdates = BetweenUpdates::Hold;
  double wetAlpha = 0.5;            ///< below this water fraction an element feels atmospheric pressure (unit: -)
  /// Target edge length of the surface elements that carry pressure, as a fraction of the unit's Dn
  /// (unit: -); the shape's triangles are split until no edge is longer. 0.1 gives 4640 elements
  /// on a Core-Loc (seed 000 integrates over ~4000); 0.05 gives 18 256.
  double elementSizePerDn = 0.1;
  bool pressure = true;             ///< form force and moment by pressure integration (buoyancy included)
  BedSettings bed;                  ///< porous (every element loaded) or impermeable (elements on it are not)
  VariabilitySettings variability;
  DragSettings drag;
  AddedMassSettings addedMass;
};

/// Seed 001 eq. 1-2 in this project's axes (seed 001 has y up): a force on each unit's centre of mass
/// F = F0 [e_x cos(w t - k x) + e_z sin(w t - k x)] phi(z), 0 <= t <= n T, with phi rising linearly
/// from 0 at zMin to 1 at zSwl and falling back to 0 at zMax.
struct OscillatingForceSettings {
  double amplitude = 0.0;           ///< F0 (unit: N)
  double period = 10.0;             ///< T (unit: s)
  double waveNumber = 0.0;          ///< k (unit: 1/m)
  double zMin = 0.0;                ///< unit: m (seed 001: 5.658)
  double zSwl = 0.0;                ///< unit: m (seed 001: 15.568)
  double zMax = 0.0;                ///< unit: m (seed 001: 23.568)
  double waves = 0.0;               ///< n: number of waves; 0 = for the whole run (unit: -)
};

/// Seed 003 eq. 2 in this project's axes: F = e_x F sin[w t + 2w/(sqrt(g) tan th) (sqrt(d0 - s tan th) - sqrt(d0))]
/// with s = x - toeX the distance from the toe. A positive (onshore) force acts only on units exposed to
/// rays cast down-slope-normal from the sea side; a negative one only on units exposed from behind.
struct ShallowWaveForceSettings {
  double amplitude = 0.0;           ///< F (unit: N)
  double angularFrequency = 3.14159265358979323846; ///< w (unit: rad/s); seed 003: pi
  double slopeAngle = 0.0;          ///< theta_0 of the slope (unit: rad)
  double toeX = 0.0;                ///< x of the toe, where s = 0 (unit: m)
  double depthAtToe = 0.0;          ///< d0 (unit: m)
  double raySpacing = 0.0;          ///< exposure rays' spacing on the slope; 0 = Dn / 4 of the smallest unit (unit: m)
  double exposureInterval = 0.5;    ///< exposure recomputed every this much simulated time (unit: s)
};

struct HydroSettings {
  bool enabled = false;             ///< a `hydro:` block was given
  HydroModel model = HydroModel::Storm;
  StormLoadSettings storm;
  OscillatingForceSettings oscillating;
  ShallowWaveForceSettings shallowWave;
  /// Bodies that take loads: fixed bodies never do; "all" or a name prefix such as "unit_".
  std::string bodies = "all";
};

} // namespace armour::hydro
