// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ContactSolver.hpp
/// The constraint-based contact solver (contact.solver: constraint): velocity-level contact
/// constraints on reduced contact points, solved by projected Gauss-Seidel with soft constraints,
/// substeps and a relax pass, warm-started from the previous step. Our own code after the soft step
/// of Box2D v3 (E. Catto, "Solver2D", 2024) and the TGS substepping of PhysX and Jolt: docs/theory.md,
/// "The constraint solver", derives every term. Per step of length dt with n substeps h = dt / n:
///
///   prepare: anchors r_A, r_B from the centres at the step start, the normal n and tangents t1, t2
///            (held over the step), effective masses, base separation s0 = -depth - n.(r_A - r_B)
///   for each substep:
///     integrate velocities (gravity, external loads)            (World)
///     warm start: apply the accumulated impulses
///     solve (bias on): normal impulses with the soft bias, then friction
///     integrate positions                                        (World)
///     relax (bias off): the same without the position bias
///   restitution: for points that approached faster than the threshold, an impulse to reach
///     -e times the approach speed
///
/// Current separation within the step: s = s0 + n.((dp_A + dq_A r_A) - (dp_B + dq_B r_B)), dp and
/// dq the body's motion since the step start. Normal impulse lambda >= 0 along n on A, per substep:
///   s > 0 (a speculative gap):  lambda += -m_n (v_n + s / h)   (may approach by s in this substep)
///   s <= 0, bias on:            lambda += -m_n S_m (v_n + max(b s, -v_push)) - S_i lambda
///   s <= 0, bias off:           lambda += -m_n v_n
/// with the soft constraint of a physical spring k and dashpot c at each point (Catto 2011, "Soft
/// constraints"): gamma = 1 / (h (c + h k)), b = k / (c + h k), S_m = 1 / (1 + gamma m_n),
/// S_i = gamma m_n / (1 + gamma m_n). k is the penalty law's stiffness E_p a / L of the tributary area
/// a the point stands for (ContactReduction), c = 2 zeta sqrt(k m_n). A point
/// whose k m_n^-1 exceeds (pi / (2 h))^2 gets that bound instead (Box2D's cap at a quarter of the
/// substep rate): stiffer than the substep can resolve, it behaves as rigid with Baumgarte-free push.
/// Friction: Coulomb, the tangential impulse (t1, t2) += -m_t (v_t + b u), clamped to the disk
/// mu lambda, mu = mu_d at a point that slid in the previous step, mu_s at one that stuck: a
/// velocity-level constraint, by default without a friction anchor (u = 0). With frictionAnchors
/// (contact.constraint.friction_anchors, off by default), u is the slip the point has made since it
/// stuck (carried from step to step, let go when it slides) and b the normal spring's bias rate, in
/// the solve only (the relax takes it out again); no impulse scale: the anchor corrects a position
/// error, it is not a spring that must stretch to carry a load (such a spring was tried in session
/// 14 and crept more). Measured in docs/theory.md, "Friction".
///
/// Determinism: serial Gauss-Seidel in constraint order; any thread count gives the same bits.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <span>
#include <vector>

namespace armour::contact {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Soft constraint coefficients for one substep (see the file comment).
struct Softness {
  double biasRate = 0.0;     ///< b (unit: 1/s)
  double massScale = 1.0;    ///< S_m (unit: -)
  double impulseScale = 0.0; ///< S_i (unit: -)
};

/// Softness of a point of effective mass `mass` (kg) on a spring `stiffness` (N/m) with damping
/// ratio `zeta` (-) over a substep h (s); stiffness 0: rigid, no position bias.
Softness makeSoftness(double stiffness, double zeta, double mass, double h);

/// What the solver reads and writes of a body. Solver body 0 is the ground: static geometry, fixed
/// and sleeping bodies, with zero inverse mass and inertia, so impulses never move it.
struct SolverBody {
  Vec3 v = Vec3::Zero();              ///< linear velocity (unit: m/s)
  Vec3 w = Vec3::Zero();              ///< angular velocity, world (unit: rad/s)
  Vec3 dp = Vec3::Zero();             ///< translation since the step start (unit: m)
  Quat dq = Quat::Identity();         ///< rotation since the step start (unit: -)
  double invMass = 0.0;               ///< unit: 1/kg
  Mat3 invInertia = Mat3::Zero();     ///< world inverse inertia (unit: 1/(kg m^2))
};

/// One point of a contact constraint.
struct ConstraintPoint {
  std::uint32_t key = 0;          ///< narrow-phase sample key (warm start)
  Vec3 normal = Vec3::UnitZ();    ///< unit, from B into A: the sample's own (its level-set gradient)
  Vec3 tangent1 = Vec3::UnitX(), tangent2 = Vec3::UnitY();
  Vec3 rA = Vec3::Zero();         ///< anchor from A's centre at the step start (unit: m)
  Vec3 rB = Vec3::Zero();         ///< anchor from B's centre (unit: m)
  double baseSeparation = 0.0;    ///< s0 (unit: m)
  double normalMass = 0.0;        ///< unit: kg
  double tangentMass[2] = {0, 0}; ///< unit: kg
  double normalImpulse = 0.0;     ///< accumulated per substep (unit: N s)
  double tangentImpulse[2] = {0, 0}; ///< along t1, t2 (unit: N s)
  double slip[2] = {0, 0};        ///< slip carried since the point stuck, along t1, t2 (unit: m; friction anchors)
  double maxNormalImpulse = 0.0;  ///< largest over the step's substeps (unit: N s)
  double approachSpeed = 0.0;     ///< normal relative velocity at prepare, < 0 approaching (unit: m/s)
  double stiffness = 0.0;         ///< the point's spring E_p a / L, a its tributary area (unit: N/m)
  Softness softness;              ///< of this point's spring (prepareConstraint)
  bool sliding = false;           ///< sliding at the end of the last step: mu_d holds it, else mu_s
  bool slides = false;            ///< the friction cap held in the last pass (the next step's `sliding`)
};

/// A reduced contact patch between bodies A (pushed along the normal) and B, as a constraint; its
/// points are ConstraintSet::points[first .. first + count).
struct ContactConstraint {
  int bodyA = 0, bodyB = 0;       ///< solver body indices, 0 for the ground
  double friction = 0.0;          ///< Coulomb mu_s, while sticking (unit: -)
  double frictionDynamic = 0.0;   ///< Coulomb mu_d, while sliding (unit: -)
  double restitution = 0.0;       ///< e (unit: -)
  double dampingRatio = 1.0;      ///< zeta of each point's spring (unit: -)
  std::uint32_t first = 0;        ///< index of its first point
  int count = 0;                  ///< its points (at most 4)
};

/// A step's constraints: the patches, and their points in one array in patch order, so that the
/// passes over them stream only the points that exist (a patch has 1 to 4).
struct ConstraintSet {
  std::vector<ContactConstraint> patches;
  std::vector<ConstraintPoint> points;
  void clear() {
    patches.clear();
    points.clear();
  }
  [[nodiscard]] std::span<ConstraintPoint> pointsOf(const ContactConstraint& c) {
    return {points.data() + c.first, static_cast<std::size_t>(c.count)};
  }
  [[nodiscard]] std::span<const ConstraintPoint> pointsOf(const ContactConstraint& c) const {
    return {points.data() + c.first, static_cast<std::size_t>(c.count)};
  }
};

/// Settings of the solve that do not belong to a constraint.
struct SolveSettings {
  double pushSpeed = 3.0;             ///< largest speed of the position correction (unit: m/s)
  double restitutionThreshold = 0.2;  ///< approach speed below which impacts are inelastic (unit: m/s)
  int restitutionPasses = 8;          ///< Gauss-Seidel passes of the restitution (unit: -)
  bool frictionAnchors = false;       ///< pull a sticking point's slip back (see the file comment)
};

/// Tangents t1, t2 completing the unit normal n to a right-handed frame (deterministic).
void tangentBasis(const Vec3& n, Vec3& t1, Vec3& t2);

/// Effective masses, softness and approach speeds from the bodies at the step start (anchors,
/// normal, stiffness and impulses already set). h: the substep (s).
void prepareConstraint(const ContactConstraint& c, std::span<ConstraintPoint> points,
                       const std::vector<SolverBody>& bodies, double h);

/// Apply the accumulated impulses (start of each substep).
void warmStart(const ConstraintSet& constraints, std::vector<SolverBody>& bodies);

/// One Gauss-Seidel pass over all constraints. useBias: the solve (true) or the relax (false).
void solveContacts(ConstraintSet& constraints, std::vector<SolverBody>& bodies, double h,
                   const SolveSettings& settings, bool useBias);

/// A point's slip at the end of the step (world, in its tangent plane; unit: m): the slip it carried
/// in plus the tangential motion of its anchors over the step; zero where it slid or carried no
/// normal impulse (its anchor is let go). Read after the substeps (bodies' dp, dq final).
Vec3 slipAtEnd(const ContactConstraint& c, const ConstraintPoint& p, const std::vector<SolverBody>& bodies);

/// Restitution after the substeps (see the file comment).
void applyRestitution(ConstraintSet& constraints, std::vector<SolverBody>& bodies,
                      const SolveSettings& settings);

} // namespace armour::contact
