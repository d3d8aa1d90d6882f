// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Integrator.hpp
/// Explicit, second-order, symplectic time integration of rigid bodies: velocity Verlet
/// (kick-drift-kick) for translation and a splitting method for rotation
/// (docs/theory.md, "Time integration").
///
/// One step from t_n to t_{n+1} = t_n + dt, with the force stage run by the solver:
///
///   0. (before the first step only) clearForces, compute F_n, tau_n at (x_n, q_n, v_n, L_n)
///   1. kick(dt/2):   v_{n+1/2} = v_n + dt/2 (F_n / m + g),   L_{n+1/2} = L_n + dt/2 tau_n
///   2. drift(dt):    x_{n+1} = x_n + dt v_{n+1/2};  (q, L) advanced by the exact-flow splitting
///                    of the free rotation over dt (L in the world frame is unchanged by it)
///   3. forces:       clearForces, compute F_{n+1}, tau_{n+1} at (x_{n+1}, q_{n+1}) with the
///                    velocities v_{n+1/2}, omega_{n+1/2} (see below)
///   4. kick(dt/2):   v_{n+1} = v_{n+1/2} + dt/2 (F_{n+1} / m + g),  L_{n+1} = L_{n+1/2} + dt/2 tau_{n+1}
///
/// and the forces of stage 3 are reused by stage 1 of the next step: one force evaluation per
/// step. The accumulators must therefore not be cleared between steps, only at the start of the
/// force stage.
///
/// Where velocities live in time: after a complete step, positions, orientations and velocities
/// all refer to t_{n+1} (kick-drift-kick rather than leapfrog with half-step velocities), so that
/// output, kinetic energy, sleep tests and checkpoints see a consistent state without averaging.
/// The trajectory is the same as leapfrog's. Velocity-dependent forces (contact damping,
/// friction, drag) are evaluated in stage 3, where the velocities available are the half-step
/// ones v_{n+1/2} = v_n + dt/2 a_n and omega_{n+1/2} = R_{n+1} diag(1/I) R_{n+1}^T L_{n+1/2}:
/// this is the usual explicit treatment (as in LAMMPS' velocity Verlet), first-order accurate in
/// the dissipative part only, and stable for damping rates c/m below about 2/dt.
///
/// Rotation (stage 2): the kinetic energy T = sum_k L_k^2 / (2 I_k) (body components) is split as
///   T = |L|^2 / (2 I_r) + sum_{k != r} (1/I_k - 1/I_r) L_k^2 / 2
/// with r the axis of the intermediate moment. The first term commutes with everything (|L|^2 is
/// conserved by every rotation), and its flow is an exact rotation about L; each remaining term's
/// flow is an exact rotation about a body axis. The two axial flows are composed symmetrically
/// (Strang), so the method is second order, symplectic and time-reversible, conserves |L| and
/// the world vector L exactly, and is exact for axisymmetric (and isotropic, e.g. cube) bodies.
/// Dullweber, Leimkuhler & McLachlan 1997 (J. Chem. Phys. 107, 5840) for the axis splitting;
/// Fasso 2003 (J. Comput. Phys. 189, 527) for splitting off the isotropic part; Touma & Wisdom
/// 1994 (Astron. J. 107, 1189) for the symmetric-top flow.
///
/// Gravity enters the kicks as a body acceleration g (not through the accumulators).
/// Static and Sleeping bodies are never visited: every stage loops over awakeBodies() only.
/// Parallelism: OpenMP, static schedule, over awake bodies; each body's update reads and writes
/// only that body's entries, so the result is bit-identical for any thread count.

#include "dynamics/RigidBodies.hpp"

#include <cstddef>
#include <functional>

namespace armour::dynamics {

/// Below this many awake bodies the stages run serially: an OpenMP fork costs a few
/// microseconds, more than integrating a few dozen bodies.
inline constexpr std::size_t kParallelMinBodies = 64;

/// Half kick (stage 1 or 4): v += h (F/m + g), L += h tau for every awake body; refreshes omega.
/// @param h the kick length, dt/2 in velocity Verlet (s)
/// @param gravity acceleration of gravity (m/s^2), usually (0, 0, -9.81)
void kick(RigidBodies& bodies, double h, const Vec3& gravity);

/// Drift (stage 2): x += dt v, and the free rotation of (q, L) over dt; renormalises q and
/// refreshes omega for every awake body.
void drift(RigidBodies& bodies, double dt);

/// The force stage: add every force and torque at the current state to the accumulators
/// (step() has cleared them). Gravity is not part of it: the kicks add g.
using ForceStage = std::function<void(RigidBodies&)>;

/// One complete velocity Verlet step (stages 1-4 above): kick(dt/2), drift(dt), clearForces,
/// computeForces, kick(dt/2).
/// @pre the accumulators hold the forces at the current state: before the first step, call
/// clearForces and the force stage once (and again after any change of state made outside the
/// integrator, e.g. a teleport or a restart).
void step(RigidBodies& bodies, double dt, const Vec3& gravity, const ForceStage& computeForces);

/// The exact-flow splitting of torque-free rotation over dt for one body: advances the
/// orientation q (body -> world) and the body-frame angular momentum bodyL together; q is not
/// renormalised. Exposed for tests and for callers that integrate a single body.
/// @param inverseInertia the inverse principal moments (1/(kg m^2)), all positive
void freeRotation(Quat& q, Vec3& bodyL, const Vec3& inverseInertia, double dt);

} // namespace armour::dynamics
