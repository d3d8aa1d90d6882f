// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/ContactSolver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace armour::contact {

namespace {

/// Which body of a constraint is the ground (index 0: no mass, at rest, never moved): static
/// geometry is B, a fixed body (a rock of the underlayer) may be either.
enum class Ground { None, A, B };

/// The two bodies of a constraint. With kGround set, the ground's terms are left out: they add
/// exact zeros (its velocities and motion are zero, its dq the identity, its inverse mass zero).
template <Ground kGround = Ground::None>
struct Pair {
  SolverBody* a;
  SolverBody* b;
  Pair(const ContactConstraint& c, std::vector<SolverBody>& bodies)
      : a(&bodies[static_cast<std::size_t>(c.bodyA)]), b(&bodies[static_cast<std::size_t>(c.bodyB)]) {}
  /// Impulse P on A at rA, -P on B at rB.
  void apply(const Vec3& P, const Vec3& rA, const Vec3& rB) const {
    if constexpr (kGround != Ground::A) {
      a->v += a->invMass * P;
      a->w += a->invInertia * rA.cross(P);
    }
    if constexpr (kGround != Ground::B) {
      b->v -= b->invMass * P;
      b->w -= b->invInertia * rB.cross(P);
    }
  }
  /// Relative velocity of A's material point at rA against B's at rB.
  [[nodiscard]] Vec3 relativeVelocity(const Vec3& rA, const Vec3& rB) const {
    if constexpr (kGround == Ground::B) {
      return a->v + a->w.cross(rA);
    } else if constexpr (kGround == Ground::A) {
      return -b->v - b->w.cross(rB);
    } else {
      return a->v + a->w.cross(rA) - b->v - b->w.cross(rB);
    }
  }
  /// How far A's anchor has moved against B's since the step start, plus rA - rB (the ground's
  /// anchor stays where it was).
  [[nodiscard]] Vec3 moved(const Vec3& rA, const Vec3& rB) const {
    if constexpr (kGround == Ground::B) {
      return a->dp + a->dq * rA - rB;
    } else if constexpr (kGround == Ground::A) {
      return -b->dp + rA - b->dq * rB;
    } else {
      return a->dp - b->dp + a->dq * rA - b->dq * rB;
    }
  }
};

double effectiveMass(const SolverBody& a, const SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& d) {
  const Vec3 ra = rA.cross(d), rb = rB.cross(d);
  const double k = a.invMass + b.invMass + ra.dot(a.invInertia * ra) + rb.dot(b.invInertia * rb);
  return k > 0.0 ? 1.0 / k : 0.0;
}

} // namespace

Softness makeSoftness(double stiffness, double zeta, double mass, double h) {
  if (!(stiffness > 0.0) || !(mass > 0.0)) {
    return {0.0, 1.0, 0.0};
  }
  // Cap the spring at a quarter of the substep rate: omega h <= pi / 2.
  const double omegaCap = 0.5 * std::numbers::pi / h;
  const double k = std::min(stiffness, mass * omegaCap * omegaCap);
  const double c = 2.0 * zeta * std::sqrt(k * mass);
  const double gamma = 1.0 / (h * (c + h * k));
  const double massScale = 1.0 / (1.0 + gamma * mass);
  return {k / (c + h * k), massScale, gamma * mass * massScale};
}

void tangentBasis(const Vec3& n, Vec3& t1, Vec3& t2) {
  // The axis least aligned with n, crossed with it (Frisvad-like choice, branch on the smallest
  // component so that the basis is continuous while n stays in one octant sector).
  const Vec3 a = std::abs(n.x()) < 0.57735 ? Vec3::UnitX() : (std::abs(n.y()) < 0.57735 ? Vec3::UnitY() : Vec3::UnitZ());
  t1 = n.cross(a).normalized();
  t2 = n.cross(t1);
}

void prepareConstraint(const ContactConstraint& c, std::span<ConstraintPoint> points,
                       const std::vector<SolverBody>& bodies, double h) {
  const SolverBody& a = bodies[static_cast<std::size_t>(c.bodyA)];
  const SolverBody& b = bodies[static_cast<std::size_t>(c.bodyB)];
  for (ConstraintPoint& p : points) {
    p.normalMass = effectiveMass(a, b, p.rA, p.rB, p.normal);
    p.softness = makeSoftness(p.stiffness, c.dampingRatio, p.normalMass, h);
    p.tangentMass[0] = effectiveMass(a, b, p.rA, p.rB, p.tangent1);
    p.tangentMass[1] = effectiveMass(a, b, p.rA, p.rB, p.tangent2);
    p.maxNormalImpulse = 0.0;
    p.approachSpeed = p.normal.dot(a.v + a.w.cross(p.rA) - b.v - b.w.cross(p.rB));
  }
}

void warmStart(const ConstraintSet& constraints, std::vector<SolverBody>& bodies) {
  for (const ContactConstraint& c : constraints.patches) {
    const Pair<> pair(c, bodies);
    for (const ConstraintPoint& p : constraints.pointsOf(c)) {
      const Vec3 P = p.normalImpulse * p.normal + p.tangentImpulse[0] * p.tangent1 + p.tangentImpulse[1] * p.tangent2;
      pair.apply(P, p.rA, p.rB);
    }
  }
}

namespace {

/// One constraint's Gauss-Seidel update (solveContacts). A point whose update is zero (a
/// speculative point that stays open, a friction impulse already at its clamp) applies nothing.
template <Ground kGround>
void solveConstraint(const ContactConstraint& c, std::span<ConstraintPoint> points, std::vector<SolverBody>& bodies,
                     double invH, const SolveSettings& settings, bool useBias) {
  const Pair<kGround> pair(c, bodies);
  for (ConstraintPoint& p : points) {
    const double s = p.baseSeparation + p.normal.dot(pair.moved(p.rA, p.rB));
    double bias = 0.0, massScale = 1.0, impulseScale = 0.0;
    if (s > 0.0) {
      bias = s * invH; // speculative: may close the gap in this substep, no more
    } else if (useBias) {
      bias = std::max(p.softness.biasRate * s, -settings.pushSpeed);
      massScale = p.softness.massScale;
      impulseScale = p.softness.impulseScale;
    }
    const double vn = p.normal.dot(pair.relativeVelocity(p.rA, p.rB));
    const double impulse = -p.normalMass * massScale * (vn + bias) - impulseScale * p.normalImpulse;
    const double updated = std::max(p.normalImpulse + impulse, 0.0);
    const double applied = updated - p.normalImpulse;
    p.normalImpulse = updated;
    p.maxNormalImpulse = std::max(p.maxNormalImpulse, updated);
    if (applied != 0.0) pair.apply(applied * p.normal, p.rA, p.rB);
  }
  for (ConstraintPoint& p : points) {
    const Vec3 vr = pair.relativeVelocity(p.rA, p.rB);
    double b0 = 0.0, b1 = 0.0; // the anchor's bias: pull the slip made since the point stuck back
    if (useBias && settings.frictionAnchors && p.softness.biasRate > 0.0) {
      const Vec3 step = pair.moved(p.rA, p.rB) - (p.rA - p.rB);
      const double cap = settings.pushSpeed;
      b0 = std::clamp(p.softness.biasRate * (p.slip[0] + p.tangent1.dot(step)), -cap, cap);
      b1 = std::clamp(p.softness.biasRate * (p.slip[1] + p.tangent2.dot(step)), -cap, cap);
    }
    const double old0 = p.tangentImpulse[0], old1 = p.tangentImpulse[1];
    double t0 = old0 - p.tangentMass[0] * (p.tangent1.dot(vr) + b0);
    double t1 = old1 - p.tangentMass[1] * (p.tangent2.dot(vr) + b1);
    const double limit = (p.sliding ? c.frictionDynamic : c.friction) * p.normalImpulse;
    const double length = std::sqrt(t0 * t0 + t1 * t1);
    p.slides = length > limit;
    if (p.slides) {
      const double scale = length > 0.0 ? limit / length : 0.0;
      t0 *= scale;
      t1 *= scale;
    }
    p.tangentImpulse[0] = t0;
    p.tangentImpulse[1] = t1;
    if (t0 != old0 || t1 != old1) pair.apply((t0 - old0) * p.tangent1 + (t1 - old1) * p.tangent2, p.rA, p.rB);
  }
}

} // namespace

void solveContacts(ConstraintSet& constraints, std::vector<SolverBody>& bodies, double h,
                   const SolveSettings& settings, bool useBias) {
  const double invH = 1.0 / h;
  for (const ContactConstraint& c : constraints.patches) {
    const std::span<ConstraintPoint> points = constraints.pointsOf(c);
    if (c.bodyB == 0) {
      solveConstraint<Ground::B>(c, points, bodies, invH, settings, useBias);
    } else if (c.bodyA == 0) {
      solveConstraint<Ground::A>(c, points, bodies, invH, settings, useBias);
    } else {
      solveConstraint<Ground::None>(c, points, bodies, invH, settings, useBias);
    }
  }
}

Vec3 slipAtEnd(const ContactConstraint& c, const ConstraintPoint& p, const std::vector<SolverBody>& bodies) {
  if (p.slides || p.normalImpulse == 0.0) {
    return Vec3::Zero();
  }
  const SolverBody& a = bodies[static_cast<std::size_t>(c.bodyA)];
  const SolverBody& b = bodies[static_cast<std::size_t>(c.bodyB)]; // the ground: dp 0, dq identity
  const Vec3 step = a.dp - b.dp + a.dq * p.rA - b.dq * p.rB - (p.rA - p.rB);
  return (p.slip[0] + p.tangent1.dot(step)) * p.tangent1 + (p.slip[1] + p.tangent2.dot(step)) * p.tangent2;
}

void applyRestitution(ConstraintSet& constraints, std::vector<SolverBody>& bodies,
                      const SolveSettings& settings) {
  // Gauss-Seidel passes: the points of a face impact share the body's rotation, and one pass leaves
  // a face landing 15 % short of e (measured: 0.77 for e = 0.9); the passes converge to the block
  // solution, each point reaching -e times its approach speed or leaving with no impulse.
  for (int pass = 0; pass < settings.restitutionPasses; ++pass) {
    for (const ContactConstraint& c : constraints.patches) {
      if (c.restitution == 0.0) {
        continue;
      }
      const Pair<> pair(c, bodies);
      for (ConstraintPoint& p : constraints.pointsOf(c)) {
        if (p.approachSpeed > -settings.restitutionThreshold || p.maxNormalImpulse == 0.0) {
          continue;
        }
        const double vn = p.normal.dot(pair.relativeVelocity(p.rA, p.rB));
        const double impulse = -p.normalMass * (vn + c.restitution * p.approachSpeed);
        const double updated = std::max(p.normalImpulse + impulse, 0.0);
        const double applied = updated - p.normalImpulse;
        p.normalImpulse = updated;
        p.maxNormalImpulse = std::max(p.maxNormalImpulse, updated);
        pair.apply(applied * p.normal, p.rA, p.rB);
      }
    }
  }
}

} // namespace armour::contact
