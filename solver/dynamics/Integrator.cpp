// SPDX-License-Identifier: GPL-3.0-or-later
#include "dynamics/Integrator.hpp"

#include <cmath>
#include <cstdlib>

namespace armour::dynamics {

namespace {

/// Exact flow of the Hamiltonian (c/2) L_a^2 (a = body axis 0, 1 or 2) over a time t, given as
/// the angle phi = c L_a t: the body turns by +phi about its axis e_a, so q <- q (cos phi/2,
/// sin phi/2 e_a), and the body-frame momentum turns by -phi about e_a (the world vector
/// L = R L_body is unchanged). L_a itself is constant along this flow.
void axialFlow(Quat& q, Vec3& bodyL, int a, double phi) {
  const int j = (a + 1) % 3;
  const int k = (a + 2) % 3;
  // One sine and cosine of the half angle serve both the quaternion and (by the double-angle
  // formulas) the momentum rotation: trigonometry is most of the cost of a drift.
  const double ch = std::cos(0.5 * phi);
  const double sh = std::sin(0.5 * phi);
  const double c = ch * ch - sh * sh;
  const double s = 2.0 * sh * ch;
  const double lj = bodyL[j];
  const double lk = bodyL[k];
  bodyL[j] = c * lj + s * lk;
  bodyL[k] = -s * lj + c * lk;
  Quat turn(ch, 0.0, 0.0, 0.0);
  turn.vec()[a] = sh;
  q = q * turn;
}

/// Exact flow of |L|^2 / (2 I_r) over dt: omega_body = L_body / I_r is parallel to L_body, so
/// L_body is constant and the body turns by |L| dt / I_r about L_body.
void isotropicFlow(Quat& q, const Vec3& bodyL, double inverseMomentR, double dt) {
  const double l = bodyL.norm();
  if (l == 0.0) {
    return;
  }
  const double half = 0.5 * l * inverseMomentR * dt;
  Quat turn;
  turn.w() = std::cos(half);
  turn.vec() = (std::sin(half) / l) * bodyL;
  q = q * turn;
}

/// Index of the intermediate value of v (ties resolved deterministically).
int intermediateAxis(const Vec3& v) {
  const int lo = v[0] <= v[1] ? (v[0] <= v[2] ? 0 : 2) : (v[1] <= v[2] ? 1 : 2);
  const int hi = v[0] > v[1] ? (v[0] > v[2] ? 0 : 2) : (v[1] > v[2] ? 1 : 2);
  return lo == hi ? 1 : 3 - lo - hi;
}

} // namespace

void freeRotation(Quat& q, Vec3& bodyL, const Vec3& inverseInertia, double dt) {
  // T = |L|^2/(2 I_r) + sum_{k != r} c_k L_k^2 / 2,  c_k = 1/I_k - 1/I_r, r = intermediate axis.
  // With r intermediate the Strang error term, proportional to c_j c_k, is smallest, and it
  // vanishes for any axisymmetric body (one of c_j, c_k is zero), where the method is exact.
  const int r = intermediateAxis(inverseInertia);
  int outer = (r + 1) % 3;
  int inner = (r + 2) % 3;
  double cOuter = inverseInertia[outer] - inverseInertia[r];
  double cInner = inverseInertia[inner] - inverseInertia[r];
  // The inner (full-step) flow carries the larger leading-error coefficient of the Strang
  // composition ([B,[A,B]]/12 against [A,[A,B]]/24), so the smaller coefficient goes inside.
  if (std::abs(cInner) > std::abs(cOuter)) {
    std::swap(outer, inner);
    std::swap(cOuter, cInner);
  }
  axialFlow(q, bodyL, outer, 0.5 * dt * cOuter * bodyL[outer]);
  axialFlow(q, bodyL, inner, dt * cInner * bodyL[inner]);
  axialFlow(q, bodyL, outer, 0.5 * dt * cOuter * bodyL[outer]);
  // Commutes exactly with the axial flows (|L|^2 is a Casimir), so its place is free.
  isotropicFlow(q, bodyL, inverseInertia[r], dt);
}

void kick(RigidBodies& bodies, double h, const Vec3& gravity) {
  const BodyId* awake = bodies.awake_.data();
  const auto count = static_cast<std::ptrdiff_t>(bodies.awake_.size());
  Vec3* velocity = bodies.velocity_.data();
  Vec3* angularMomentum = bodies.angularMomentum_.data();
  const Vec3* force = bodies.force_.data();
  const Vec3* torque = bodies.torque_.data();
  const double* inverseMass = bodies.inverseMass_.data();
  // Each iteration touches body i only: results do not depend on the thread count.
#pragma omp parallel for schedule(static) if (count >= static_cast<std::ptrdiff_t>(kParallelMinBodies))
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const BodyId i = awake[s];
    velocity[i] += h * (inverseMass[i] * force[i] + gravity);
    angularMomentum[i] += h * torque[i]; // world frame: exact for a torque constant over h
    bodies.updateAngularVelocity(i);
  }
}

void drift(RigidBodies& bodies, double dt) {
  const BodyId* awake = bodies.awake_.data();
  const auto count = static_cast<std::ptrdiff_t>(bodies.awake_.size());
  Vec3* position = bodies.position_.data();
  Quat* orientation = bodies.orientation_.data();
  const Vec3* velocity = bodies.velocity_.data();
  const Vec3* angularMomentum = bodies.angularMomentum_.data();
  const Vec3* inverseInertia = bodies.inverseInertia_.data();
#pragma omp parallel for schedule(static) if (count >= static_cast<std::ptrdiff_t>(kParallelMinBodies))
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const BodyId i = awake[s];
    position[i] += dt * velocity[i];
    Quat& q = orientation[i];
    Vec3 bodyL = q.conjugate() * angularMomentum[i];
    freeRotation(q, bodyL, inverseInertia[i], dt);
    // Five quaternion products drift off unit length by ~1e-16 per step; renormalising keeps q a
    // rotation. The world L is not touched: free rotation conserves it, so it stays exact.
    q.normalize();
    bodies.updateAngularVelocity(i);
  }
}

void step(RigidBodies& bodies, double dt, const Vec3& gravity, const ForceStage& computeForces) {
  kick(bodies, 0.5 * dt, gravity);
  drift(bodies, dt);
  bodies.clearForces();
  computeForces(bodies);
  kick(bodies, 0.5 * dt, gravity);
}

} // namespace armour::dynamics
