// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file ContactLaw.hpp
/// The force law at one contact sample point: linear penalty normal force distributed as a
/// pressure, viscous damping set from a target coefficient of restitution, and Coulomb friction
/// with a real static regime: a tangential spring whose stretch is remembered from step to step
/// (Cundall and Strack 1979; the Y-code / FDEM lineage of seed 002), capped at mu_s |Fn| while
/// sticking and mu_d |Fn| while sliding. A viscous-only friction that lets blocks creep is not
/// used: a block held by friction stays put, to the elastic stretch of its springs.
///
/// Law (docs/theory.md, "Contact law"), for a sample point of tributary area a at depth d > 0,
/// outward normal n of the other body, relative velocity v = v_A - v_B at the point:
///   k      = E_p a / L                        normal stiffness (N/m); E_p penalty modulus (Pa),
///                                             L the pair's length scale (m)
///   Fn     = max(0, k d - beta k (v . n))     normal force on A along n (N)
///   beta   = 2 zeta sqrt(m_eff / K_pair)      (s); K_pair = sum of k over the pair's engaged points,
///            / (1 + zeta omega dt)            so the whole contact patch has damping ratio zeta;
///                                             omega = sqrt(K_pair / m_eff): the dashpot integrated
///                                             implicitly over the step dt (dampingTime)
///   zeta   from the coefficient of restitution e of the clamped (no-attraction) dashpot,
///          e = exp(-zeta t*) with t* the end of contact (Schwager and Poschel 2007; overdamped
///          for e < exp(-2) = 0.135), inverted by bisection
///   s     <- R(s) + v_t dt                    tangential spring stretch (m), R rotates the old
///                                             stretch into the current tangent plane
///   Ft     = -k_t s - beta k_t v_t,  k_t = r_t k
///   if |Ft| > mu Fn (mu = mu_s sticking, mu_d sliding): Ft <- mu Fn Ft/|Ft|, s <- -Ft / k_t, sliding

#include <Eigen/Core>

namespace armour::contact {

using Vec3 = Eigen::Vector3d;

/// The damping ratios that give restitution e on contacts of exponent p = 1, 1.5, 2, 2.5 and 3
/// (zeta falls with p: a corner's contact, soft at first, loses more to the same damping ratio).
struct DampingByExponent {
  static constexpr int kCount = 5;
  double zeta[kCount] = {0, 0, 0, 0, 0}; ///< at p = 1 + 0.5 i (unit: -)
  /// Linear in p, p clamped to [1, 3].
  [[nodiscard]] double at(double p) const;
};

/// Material pair parameters of the law.
struct ContactParameters {
  double penaltyModulus = 1.0e9;      ///< E_p: normal pressure per unit relative depth (unit: Pa)
  double lengthScale = 1.0;           ///< L: depth is measured relative to it (unit: m)
  double frictionStatic = 0.75;       ///< mu_s, Coulomb coefficient while sticking (unit: -)
  double frictionDynamic = 0.75;      ///< mu_d, Coulomb coefficient while sliding (unit: -)
  double dampingRatio = 0.0;          ///< zeta of the contact patch (unit: -)
  /// zeta by the contact's exponent (dampingByExponentFromRestitution): dampingRatio is set from it
  /// per pair and step, with the exponent of its points (contactExponent).
  DampingByExponent dampingByExponent;
  double tangentialStiffnessRatio = 8.0 / 9.0; ///< r_t = k_t / k (unit: -): Mindlin 2(1-nu)/(2-nu), nu = 0.2 (concrete)
};

/// Restitution of a linear spring-dashpot with damping ratio zeta whose force is clamped at zero
/// (contact ends when the force vanishes; Schwager and Poschel 2007, Granular Matter 9, 465-469).
double restitutionOfClampedDashpot(double zeta);

/// Damping ratio giving restitution e (0 < e <= 1) for the clamped law (inverse of the above).
/// Small e needs zeta > 1 (e = 0.1: 1.24; e = 0.01: 4.81); integrated implicitly (dampingTime) it
/// lowers the stable step far less than an explicit dashpot would.
double dampingRatioFromRestitution(double restitution);

/// Restitution of the clamped law on a contact whose summed stiffness grows with the overlap d as
/// d^(p - 1), so that its force is F = K d / p: p = 1 a face, 2 an edge, 3 a corner (the contact
/// area grows as d^(p - 1)). In units of the impact speed and the mass, the overlap obeys
/// y'' + 2 zeta sqrt(p) y^((p - 1) / 2) y' + y^p = 0 with the force clamped at zero, whose rebound
/// does not depend on the impact speed (docs/validation.md, "Restitution at edges and corners";
/// utilities/restitution_power_law.py). RK4; p = 1 is restitutionOfClampedDashpot.
double restitutionOfGrowingContact(double zeta, double p);

DampingByExponent dampingByExponentFromRestitution(double restitution);

/// The exponent p of a pair's contact, F = C d^p, from its engaged points: with F the summed normal
/// elastic force, K the summed tangent stiffness and U the elastic energy, F^2 / (U K) = (p + 1) / p
/// (a face: 2, p = 1; a wedge of overlap, an edge: 3/2, p = 2; a cone, a corner: 4/3, p = 3). It
/// reads the overlap's shape, so a face tilted by a small angle theta over a patch of length L
/// reads p = 1 + O((L theta / d)^2): second order, where d_max K / F is first order. Readings up
/// to 1.2 count as a face (1), 1.2 to 1.5 map linearly onto 1 to 1.5; clamped to [1, 3]; 1 without
/// a force.
double contactExponent(double force, double stiffness, double energy);

/// What the penalty law needs of a pair's engaged points besides each point itself: the sums that
/// give its exponent (contactExponent) and, weighted by stiffness, its centre and normal (for the
/// effective mass at the contact). Both contact models fill it, point by point.
struct PatchSums {
  double stiffness = 0.0;      ///< K, summed over every point the model reports (unit: N/m)
  double force = 0.0;          ///< sum k d over the engaged points (unit: N)
  double energy = 0.0;         ///< elastic energy of the engaged points (unit: J)
  double weight = 0.0;         ///< sum k over the engaged points (unit: N/m)
  Vec3 centre = Vec3::Zero();  ///< sum k x (unit: N)
  Vec3 normal = Vec3::Zero();  ///< sum k n (unit: N/m)
  /// An engaged point of stiffness k, depth d > 0 and elastic energy u at `point`, normal `n`.
  void addEngaged(double k, double d, double u, const Vec3& point, const Vec3& n) {
    force += k * d;
    energy += u;
    weight += k;
    centre += k * point;
    normal += k * n;
  }
  [[nodiscard]] double exponent() const { return contactExponent(force, stiffness, energy); }
};

/// What a point remembers between steps.
/// The penalty law uses the spring; the constraint solver (ContactSolver.hpp) the impulses, its
/// warm start. Both live here so that sleep islands and checkpoints see one contact history.
struct PointHistory {
  Vec3 stretch = Vec3::Zero(); ///< tangential spring stretch s (unit: m), world frame
  bool sliding = false;        ///< true while the point slides (mu_d applies)
  double normalImpulse = 0.0;  ///< constraint solver: normal impulse per substep (unit: N s)
  Vec3 tangentImpulse = Vec3::Zero(); ///< constraint solver: friction impulse per substep, world (unit: N s)
};

/// One engaged sample point.
struct PointContact {
  Vec3 normal;           ///< unit normal, pointing from B into A (the direction A is pushed)
  double depth = 0.0;    ///< penetration d > 0 (unit: m)
  double area = 0.0;     ///< tributary area a of the sample point (unit: m^2)
  Vec3 relativeVelocity; ///< v_A - v_B at the point (unit: m/s)
};

struct PointForce {
  Vec3 force = Vec3::Zero(); ///< force on A (unit: N); B receives the opposite
  double normalForce = 0.0;  ///< |Fn| (unit: N)
  PointHistory history;      ///< state to keep for the next step
};

/// Normal stiffness k = E_p a / L of a point (unit: N/m).
inline double pointStiffness(const ContactParameters& p, double area) { return p.penaltyModulus * area / p.lengthScale; }

/// beta = 2 zeta sqrt(m_eff / K_pair) / (1 + zeta omega dt), omega = sqrt(K_pair / m_eff) (unit: s):
/// damping time of the pair's engaged patch, integrated implicitly over the step. The dashpot acts
/// on the mean of the step's velocity and the velocity the dashpot alone would leave at its end
/// (trapezoidal in the dashpot), which divides its rate by 1 + zeta omega dt: the explicit dashpot's
/// limit on the step (which vanishes as zeta grows) becomes omega dt < h(zeta) >= 0.87 for every
/// e >= 0.01 (stableStepOfImplicitDashpot; docs/theory.md section 6, "The dashpot over a step"). dt = 0
/// gives the explicit dashpot of the continuous law.
/// @param effectiveMass m_eff of the pair (kg); @param pairStiffness sum of k of engaged points (N/m);
/// @param dt the time step (s)
double dampingTime(const ContactParameters& p, double effectiveMass, double pairStiffness, double dt);

/// The largest omega dt at which the central-difference step of an undamped-mass spring of
/// frequency omega with the implicit dashpot of damping ratio zeta (dampingTime) is stable: the
/// root of h^2 (1 + zeta h) = 4 (2 at zeta = 0; 0.876 at zeta = 4.81, e = 0.01). The explicit
/// dashpot's is 2 (sqrt(1 + zeta^2) - zeta) (0.206 at e = 0.01).
double stableStepOfImplicitDashpot(double zeta);

/// Evaluate the law at one point. @param beta from dampingTime; @param dt time step (s).
PointForce evaluatePointContact(const ContactParameters& p, const PointContact& c, const PointHistory& previous,
                                double beta, double dt);

} // namespace armour::contact
