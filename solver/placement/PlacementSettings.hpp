// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacementSettings.hpp
/// Settings of `armour place`: the `placement:` block of a scene file (docs/placement.md). The
/// scene gives the underlayer (a slope with its toe, roughness and walls), the materials and the
/// shapes; the block says which units to add, where (a grid in the slope plane or a grid file),
/// in which orientations, how (crane: one at a time; grid: all lowered, then released together)
/// and, optionally, a rock underlayer to deposit first and freeze (seed 000).
///
/// Plain data, no dependencies: the scene reader (armour::io) fills it, the placement stage
/// (armour::placement) uses it. Axes: x onshore, y along the trunk, z up. SI units; lengths
/// given "in Dn" are multiples of the unit's nominal diameter.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace armour::placement {

/// How the units reach the pack.
enum class Method {
  Crane, ///< one at a time: lowered to first contact, released, next when the pack is at rest (seeds 001, 003)
  Grid,  ///< every unit lowered onto those below it, then all released together (seed 000's POSITIT)
};

/// How each unit is turned before it is lowered.
enum class OrientationMode {
  Perturbed, ///< the base orientation, then a rotation about the vertical by U(-max, max) (seed 000: +-20 deg)
  Tilted,    ///< the base orientation, then a rotation by U(0, max) about a random horizontal axis and U(-max, max) about z
  Random,    ///< uniformly random in SO(3)
};

/// Where the grid points are. Points are in the slope frame: s up the slope face from the slope's
/// origin (the foot of the face), y along the trunk; each is lowered vertically from above.
struct GridSettings {
  std::string file;                 ///< CSV of points "x,y" or "x,y,z" (m, world); empty = generated grid
  int rows = 0;                     ///< rows up the slope (unit: -)
  std::vector<int> unitsPerRow;     ///< units per row, repeated cyclically, e.g. {12, 11} (unit: -)
  double dx = 0.0;                  ///< spacing along the trunk (unit: Dn); 0 = width / unitsPerRow[0]
  double dy = 0.0;                  ///< row spacing up the slope, in the slope plane (unit: Dn); 0 = from packingDensity
  double packingDensity = 0.0;      ///< target phi = N Dn^2 / A = 1 / (dx dy) in Dn (unit: -); used when dy = 0
  double firstRow = 0.5;            ///< up-slope distance of row 0 from the slope origin (unit: Dn)
  double yStart = 0.0;              ///< trunk coordinate where the rows start (unit: m)
  double width = 0.0;               ///< trunk length covered by the rows (unit: m); 0 = from the walls
  double stagger = 0.5;             ///< row r is shifted along y by frac(r stagger) dx (unit: -); 0.5 alternates
  double jitter = 0.0;              ///< random shift of each point, U(-j, j) on both axes (unit: Dn)
  int layers = 1;                   ///< layers of the grid, each lowered onto the ones below (unit: -)
  double layerShiftS = 0.0;         ///< shift of each further layer up the slope (unit: Dn)
  double layerShiftY = 0.0;         ///< shift of each further layer along the trunk (unit: Dn)
};

/// How the best of an orientation's `tries` is chosen.
enum class OrientationSelect {
  Lowest, ///< the centroid that lands lowest (along the lowering direction)
  /// The lowest top (the unit's highest point along the lowering direction: the layer's thickness)
  /// among the candidates that touch the underlayer and key against a unit placed before, each
  /// rule broken at a cost (offUnderlayerCost, unkeyedCost). Issue 24: a crane operator keys each
  /// unit into the row below, on the underlayer, and keeps the layer thin.
  Keyed,
  /// Issue 24, session 28: a crane operator keying the unit into the gap of the row below. Every
  /// unit is lowered in `tries` attitudes, each at its grid point and at `offsets` small shifts
  /// around it along the face (within offsetRadius), and the least cost wins: a low top and
  /// centroid above the underlayer, contacts with the units below (keyed: two or more), members
  /// inside the envelopes (convex hulls) of the units below (interlocked), with penalties for a
  /// candidate off the underlayer, stacked on another unit, or shifted from its grid point
  /// (docs/theory.md section 15, "Interlocked").
  Interlocked,
};

struct OrientationSettings {
  OrientationMode mode = OrientationMode::Perturbed;
  /// The frame the base orientation and the perturbation are given in: false = the world (z up),
  /// true = the slope face (z along its outward normal, x up the face, y along the trunk), so a
  /// unit can lie on the face and be turned about its normal.
  bool slopeFrame = false;
  double phiDeg = 0.0, thetaDeg = 0.0, psiDeg = 0.0; ///< base orientation, Tait-Bryan x-y'-z'' (unit: deg)
  double maxAngleDeg = 20.0;        ///< perturbation bound (unit: deg); seed 000: +-20 deg about the vertical
  int tries = 1;                    ///< orientations tried per unit, the best by `select` kept (unit: -)
  OrientationSelect select = OrientationSelect::Lowest;
  /// With `keyed` or `interlocked`: the cost of a candidate that touches no underlayer stone (supports, the slope,
  /// the toe), in Dn of extra height of its top (unit: Dn). Ours: a unit off the underlayer is as
  /// bad as one standing this much higher.
  double offUnderlayerCost = 1.0;
  /// With `keyed`: the cost of a candidate that touches no unit placed before it (it does not key
  /// into the row below or its neighbours), in Dn (unit: Dn). Ours.
  double unkeyedCost = 0.25;
  /// With `keyed` or `interlocked`: the layer's design thickness k_t, from the underlayer's top to the units' tops
  /// (unit: Dn); candidates are judged by how far their top lies from it. 0: the lowest top wins.
  double layerThickness = 0.0;
  // `select: interlocked` (theory.md 15). All weights are ours (session 28), in Dn of cost.
  int offsets = 8;                  ///< shifted positions tried per attitude besides the grid point (unit: -)
  double offsetRadius = 0.35;       ///< the shifts are uniform in a disc of this radius along the face (unit: Dn)
  double centroidWeight = 1.0;      ///< weight of the centroid's height above the underlayer (unit: -)
  double keyReward = 0.15;          ///< reward per unit placed before that the candidate touches, up to two (unit: Dn)
  double envelopeReward = 1.0;      ///< reward for the share of its surface samples inside the hulls of the units near it (unit: Dn)
  double stackedCost = 2.0;         ///< cost of a stacked candidate: no support touched, centroid > 1 Dn above the underlayer (unit: Dn)
  double driftCost = 0.25;          ///< cost per Dn of shift from the grid point, along the face (unit: -)
  /// With `interlocked` and `settle_each`: the best this many candidates (each nested) are each
  /// settled alone from the same state and judged again where they rest; the best at rest is kept
  /// (a crane operator lifting a unit that did not key in and trying the next). 1: the best at
  /// first touch is settled, as with the other rules (unit: -).
  int settleCandidates = 1;
};

struct CraneSettings {
  double speed = 0.5;               ///< lowering speed, the velocity at release (unit: m/s); seed 001: 0.5
  /// The pack is at rest when its kinetic energy is below 1/2 M v_rest^2 (M the mass of the units
  /// placed so far): a root-mean-square speed (unit: m/s).
  double restSpeed = 0.01;
  double minTime = 0.2;             ///< simulated time after a release before the next unit (unit: s)
  double maxTime = 5.0;             ///< cap per unit: the next one goes anyway (and is counted) (unit: s)
};

/// A rock underlayer deposited before the units and then frozen (seed 000: 3436 rocks).
struct RockSettings {
  bool enabled = false;
  int count = 0;                    ///< rocks (unit: -)
  double dn50 = 0.0;                ///< median nominal diameter (unit: m)
  /// Grading: Dn85 / Dn15 (unit: -); nominal diameters are log-uniform between dn50 / sqrt(g) and dn50 sqrt(g).
  double grading = 1.25;
  int shapes = 12;                  ///< distinct rock shapes in the library, drawn at random (unit: -)
  std::string material;             ///< material name; empty = the units' material
  double sEnd = 0.0;                ///< rocks cover the face up to this up-slope distance (unit: m); 0 = up to the rows
  double toeLength = 0.0;           ///< and this far offshore of the slope origin along the toe (unit: m)
  double clearance = 0.002;         ///< gap left when a rock is lowered (unit: Dn50)
  int tries = 4;                    ///< orientations tried per rock, the lowest kept (unit: -)
};

/// The final settling: until every unit sleeps (the scene's sleep settings: at rest for the sleep
/// time) or no point of any unit has moved faster than restSpeed for the sleep time (a contact
/// island of hundreds of units may never sleep: one chattering contact keeps it awake), or, with
/// sleeping disabled, until the rms speed is below restSpeed.
struct SettleSettings {
  /// With sleeping: the speed no point of any unit (|v| + |omega| r) may exceed for the sleep time;
  /// without: the pack's rms speed (unit: m/s).
  double restSpeed = 0.005;
  double minTime = 0.5;             ///< at least this long after the last release (unit: s)
  double maxTime = 30.0;            ///< at most (unit: s); units still moving are reported
};

/// The per-unit settle (`settle_each:`, both methods; POSITIT's sequential deposition): a unit
/// lowered to its first touch sits on one or two points and is not at rest, so released with the
/// others it falls and the rows ride down the face. With this block each unit, after its lowering
/// (and nesting), is simulated alone -- every unit before it and every rock held fixed, so one
/// body is awake -- under gravity with a viscous drag on its velocity and spin, until it rests,
/// and is then frozen where it rests; the next unit is lowered onto it. At the end all units are
/// released together and the pack settles as without it (SettleSettings).
struct SettleEachSettings {
  bool enabled = false;             ///< the `settle_each:` block is given
  /// Drag rate on the settling unit: its velocity and angular velocity decay as exp(-damping t)
  /// besides gravity and contacts (a drag force damping m v). It takes out the rebounds and the
  /// rocking that would otherwise make a lone unit slow to come to rest; a unit sliding on a face
  /// reaches at most a_net / damping (unit: 1/s).
  double damping = 2.0;
  /// At rest when the centroid speed and |omega| times the unit's radius (the speed of its farthest
  /// point) both stay below this for restTime (unit: m/s). With the drag a unit still sliding moves
  /// at a_net / damping: 0.02 m/s at 2/s leaves out-of-balance accelerations below 0.004 g.
  double restSpeed = 0.02;
  double restTime = 0.1;            ///< how long the speeds must stay below restSpeed (unit: s)
  double maxTime = 6.0;             ///< cap per unit: frozen where it is and counted (unit: s)
  /// Units whose settle takes their centroid farther than this from their first touch are
  /// reported (unit: Dn).
  double maxDrift = 1.0;
  /// Stop such a unit where it crosses maxDrift (frozen there, not at rest) instead of letting it
  /// slide on: the grid is kept, the unit may move again at the final release (unit: -).
  bool holdAtMaxDrift = false;
};

/// Nesting (both methods): after its lowering, each unit is slid and tilted geometrically into the
/// lowest nearby position it can reach without overlap (Deposit::slideDown), within maxDrift of its
/// grid point. It stands in for a crane operator working a unit into the hole between the units
/// below, so a dense staggered grid (whose rows overlap in plan) starts nested instead of
/// stacked: a stacked grid slumps as a whole when released on a steep face.
/// The direction a unit is lowered along to its first touch.
enum class Lowering {
  Vertical,    ///< along -z, as a crane does: a unit lands h tan(alpha) up-slope of its grid point on the face
  SlopeNormal, ///< along the slope's inward normal: the unit lands at its grid point's up-slope distance
};

struct NestSettings {
  bool enabled = false;             ///< the `nest:` block is given
  int moves = 24;                   ///< failed random moves in a row that end the slide (unit: -)
  double shift = 0.2;               ///< largest plan shift of one move (unit: Dn)
  double tiltDeg = 10.0;            ///< largest tilt of one move (unit: deg)
  double maxDrift = 0.75;           ///< farthest the centroid may go from its grid point, in plan (unit: Dn)
};

struct PlacementSettings {
  bool enabled = false;             ///< the scene has a `placement:` block
  std::string shape;                ///< shape name (from `shapes:` or a generator name)
  std::string material;             ///< material name
  double volume = 0.0;              ///< unit volume (unit: m^3)
  std::string namePrefix = "unit";  ///< units are called <prefix>_<i>, i from 0 in placement order
  std::string slope;                ///< the static slope the grid lies on; empty = the only slope
  Method method = Method::Crane;
  GridSettings grid;
  OrientationSettings orientation;
  CraneSettings crane;
  RockSettings rocks;
  /// A toe berm (placement.toe_berm): rocks laid on the underlayer in front of the first row, from
  /// toeLength offshore of the slope's foot to sEnd up the face (0: the foot), frozen like the
  /// underlayer; it holds the layer's foot, which otherwise rolls off the toe's edge in the
  /// downrush (docs/placement.md). Uses the underlayer's rock shapes: needs `rocks`.
  RockSettings toeBerm;
  SettleSettings settle;
  NestSettings nest;
  SettleEachSettings settleEach;
  Lowering lowering = Lowering::Vertical;
  double clearance = 0.002;         ///< gap left between a lowered unit and what it lands on (unit: Dn)
  std::uint64_t seed = 1;           ///< orientations, jitter and rocks (unit: -)
  std::string output = "placed.yaml"; ///< the placed scene, in the output folder
};

} // namespace armour::placement
