// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RigidBodies.hpp
/// The state of every rigid body, stored as contiguous arrays indexed by a dense body index
/// (structure of arrays, after Box2D's b2BodySim): the integrator and the contact stage stream
/// through positions, orientations and velocities without touching names or other cold data,
/// which live in a separate table.
///
/// State variables and frames (docs/theory.md, "Rigid-body dynamics"):
///  - x: position of the centre of mass, world frame, double (m);
///  - q: orientation, unit quaternion mapping body to world (p_world = x + q p_body);
///  - v: linear velocity of the centre of mass, world frame (m/s);
///  - L: angular momentum about the centre of mass, world frame (kg m^2/s). This is the stored
///    rotational state: it is what the torque kick changes and what free rotation conserves, so
///    storing it makes conservation of L exact for a torque-free body (not just to round-off);
///  - omega: world angular velocity (rad/s), a cache kept equal to R diag(1/I) R^T L by every
///    integrator stage and setter, because the contact stage reads it at every contact point;
///  - 1/m and the inverse principal moments 1/I_k (body frame = principal frame);
///  - force F and torque tau accumulators (world, N and N m, torque about the centre of mass).
///
/// The body frame IS the principal frame: callers rotate a shape into its principal axes (and
/// centre it on its centroid) before defining the body (geometry::computeMassProperties gives the
/// axes), so the inertia tensor is diagonal in the body frame and its inverse is a Vec3.
///
/// Motion types: Static bodies never move (effective inverse mass and inertia are zero, so a
/// contact stage can treat them uniformly); Sleeping bodies keep their mass but are at rest and
/// skipped by the integrator; Dynamic bodies are awake and integrated. The list of awake bodies is
/// maintained on every change so that the integrator costs nothing for the others.
///
/// Bodies are never removed, so a BodyId stays valid for the life of the container.
/// Thread safety: const accessors may be called concurrently; the apply* functions and the
/// mutable force/torque spans are not synchronised (two threads must not add to the same body).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace armour::dynamics {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Dense body index: 0 .. size()-1, in the order bodies were added.
using BodyId = std::uint32_t;

enum class MotionType : std::uint8_t {
  Static,   ///< never moves; zero effective inverse mass and inertia
  Dynamic,  ///< awake: integrated every step
  Sleeping, ///< at rest and skipped by the integrator until woken
};

/// Everything needed to create a body. Velocities must be zero for Static and Sleeping bodies.
struct BodyDefinition {
  std::string name;                              ///< used in messages and output (unit: -)
  MotionType motionType = MotionType::Dynamic;   ///< see MotionType
  double mass = 0.0;                             ///< kg; required (> 0) unless Static
  Vec3 principalMoments = Vec3::Zero();          ///< about the centre of mass, body axes (unit: kg m^2); required unless Static
  Vec3 position = Vec3::Zero();                  ///< centre of mass, world (unit: m)
  Quat orientation = Quat::Identity();           ///< body -> world; normalised on add (unit: -)
  Vec3 velocity = Vec3::Zero();                  ///< of the centre of mass, world (unit: m/s)
  Vec3 angularVelocity = Vec3::Zero();           ///< world frame (unit: rad/s)
  std::int32_t shapeId = -1;                     ///< index into the caller's shape table, -1 for none (unit: -)
  std::uint64_t userTag = 0;                     ///< free for the caller (unit: -)
};

/// Cold per-body data: read for output and messages, never in the step loops.
struct BodyInfo {
  std::string name;                     ///< as defined (unit: -)
  std::int32_t shapeId = -1;            ///< as defined (unit: -)
  std::uint64_t userTag = 0;            ///< as defined (unit: -)
  double mass = 0.0;                    ///< as defined, also kept for Static bodies (unit: kg)
  Vec3 principalMoments = Vec3::Zero(); ///< as defined (unit: kg m^2)
};

class RigidBodies;
// The integrator stages (Integrator.hpp) write the state arrays directly.
void kick(RigidBodies& bodies, double h, const Vec3& gravity);
void drift(RigidBodies& bodies, double dt);

class RigidBodies {
public:
  /// Add a body and return its index. Validation (always on): the name is used in messages
  /// ("body 'name'", or "body #index" when unnamed); a Dynamic or Sleeping body needs a finite
  /// positive mass and finite positive principal moments satisfying the triangle inequality
  /// I_a + I_b >= I_c (true of every real rigid body); position, orientation and velocities must
  /// be finite; the orientation must be non-zero (it is normalised); Static and Sleeping bodies
  /// must be given zero velocities.
  /// @throws core::InputError naming the body, the bad value and the fix.
  BodyId add(const BodyDefinition& definition);

  [[nodiscard]] std::size_t size() const { return position_.size(); }

  // --- Hot state (world frame unless stated) -------------------------------------------------
  [[nodiscard]] const Vec3& position(BodyId i) const { return position_[i]; }
  [[nodiscard]] const Quat& orientation(BodyId i) const { return orientation_[i]; }
  [[nodiscard]] const Vec3& velocity(BodyId i) const { return velocity_[i]; }
  /// World angular velocity omega = R diag(1/I) R^T L (rad/s); zero for Static and Sleeping.
  [[nodiscard]] const Vec3& worldAngularVelocity(BodyId i) const { return angularVelocity_[i]; }
  /// Angular momentum about the centre of mass, world frame (kg m^2/s).
  [[nodiscard]] const Vec3& angularMomentumWorld(BodyId i) const { return angularMomentum_[i]; }
  /// Angular momentum in the body (principal) frame: R^T L (kg m^2/s).
  [[nodiscard]] Vec3 angularMomentumBody(BodyId i) const { return orientation_[i].conjugate() * angularMomentum_[i]; }
  /// Effective inverse mass (1/kg): 0 for Static bodies.
  [[nodiscard]] double inverseMass(BodyId i) const { return inverseMass_[i]; }
  /// Effective inverse principal moments, body frame (1/(kg m^2)): 0 for Static bodies.
  [[nodiscard]] const Vec3& inverseInertiaBody(BodyId i) const { return inverseInertia_[i]; }
  /// World inverse inertia tensor R diag(1/I) R^T (1/(kg m^2)), for contact effective masses.
  [[nodiscard]] Mat3 inverseInertiaWorld(BodyId i) const;
  /// Velocity of the material point at `worldPoint`: v + omega x (p - x) (m/s).
  [[nodiscard]] Vec3 velocityAtPoint(BodyId i, const Vec3& worldPoint) const;
  /// Map a body-frame point (relative to the centre of mass) to the world: x + q p (m).
  [[nodiscard]] Vec3 toWorld(BodyId i, const Vec3& bodyPoint) const { return position_[i] + orientation_[i] * bodyPoint; }

  [[nodiscard]] std::span<const Vec3> positions() const { return position_; }
  [[nodiscard]] std::span<const Quat> orientations() const { return orientation_; }
  [[nodiscard]] std::span<const Vec3> velocities() const { return velocity_; }
  [[nodiscard]] std::span<const Vec3> angularVelocities() const { return angularVelocity_; }

  // --- Setters (placement, restarts). Each keeps the angular-velocity cache consistent. --------
  void setPosition(BodyId i, const Vec3& x) { position_[i] = x; }
  /// @pre q is non-zero; it is normalised. Keeps L (world) and recomputes omega.
  void setOrientation(BodyId i, const Quat& q);
  /// Ignored (kept at zero) unless the body is Dynamic.
  void setVelocity(BodyId i, const Vec3& v);
  /// Sets L = R diag(I) R^T omega. Ignored (kept at zero) unless the body is Dynamic.
  void setWorldAngularVelocity(BodyId i, const Vec3& omega);

  /// Restart from a checkpoint: set the raw state exactly (no normalisation, no conversion), so
  /// that a restored run continues bit for bit; the motion type is set first (see setMotionType)
  /// and omega is recomputed from L as the integrator does. L is the world angular momentum.
  void restoreState(BodyId i, MotionType type, const Vec3& x, const Quat& q, const Vec3& v, const Vec3& L);

  // --- Force accumulators (world frame) --------------------------------------------------------
  /// Zero every force and torque accumulator: the first thing the force stage does.
  void clearForces();
  /// Force through the centre of mass (N).
  void applyForce(BodyId i, const Vec3& force) { force_[i] += force; }
  /// Force applied at a world point: adds F and the torque (p - x) x F about the centre of mass.
  void applyForceAtPoint(BodyId i, const Vec3& force, const Vec3& worldPoint);
  /// Pure torque about the centre of mass (N m).
  void applyTorque(BodyId i, const Vec3& torque) { torque_[i] += torque; }
  [[nodiscard]] const Vec3& force(BodyId i) const { return force_[i]; }
  [[nodiscard]] const Vec3& torque(BodyId i) const { return torque_[i]; }
  /// Direct access for a force stage that writes per-body totals (e.g. after a deterministic
  /// reduction of contact forces).
  [[nodiscard]] std::span<Vec3> forces() { return force_; }
  [[nodiscard]] std::span<Vec3> torques() { return torque_; }

  // --- Energy -----------------------------------------------------------------------------------
  /// 1/2 m |v|^2 + 1/2 omega . L (J); zero for Static and Sleeping bodies.
  [[nodiscard]] double kineticEnergy(BodyId i) const;
  /// Sum over all bodies in index order (J): deterministic.
  [[nodiscard]] double totalKineticEnergy() const;

  // --- Motion type and sleeping -------------------------------------------------------------------
  [[nodiscard]] MotionType motionType(BodyId i) const { return motionType_[i]; }
  [[nodiscard]] bool isAwake(BodyId i) const { return motionType_[i] == MotionType::Dynamic; }
  /// Change the motion type. To Static or Sleeping: velocities and angular momentum are zeroed.
  /// To Dynamic from Static: the defined mass and moments are restored (the body starts at rest).
  /// @throws core::InputError if a Static body defined without valid mass or moments is made
  /// Dynamic or Sleeping.
  void setMotionType(BodyId i, MotionType type);
  /// Sleeping -> Dynamic (at rest); no effect on Static or Dynamic bodies.
  void wake(BodyId i);
  /// Dynamic -> Sleeping (velocities zeroed); no effect on Static or Sleeping bodies.
  void sleep(BodyId i);
  /// Indices of the Dynamic bodies: the only ones the integrator visits. The order is unspecified
  /// (it depends on the history of sleep/wake calls, deterministically) because removal swaps
  /// the last entry into the hole, keeping sleep and wake O(1).
  [[nodiscard]] std::span<const BodyId> awakeBodies() const { return awake_; }

  // --- Cold data ----------------------------------------------------------------------------------
  [[nodiscard]] const BodyInfo& info(BodyId i) const { return info_[i]; }
  /// "body 'name'" or "body #i": the prefix of every message about this body.
  [[nodiscard]] std::string describe(BodyId i) const;

private:
  friend void kick(RigidBodies& bodies, double h, const Vec3& gravity);
  friend void drift(RigidBodies& bodies, double dt);

  void updateAngularVelocity(BodyId i);
  void addToAwake(BodyId i);
  void removeFromAwake(BodyId i);
  void makeAtRest(BodyId i);

  static constexpr std::uint32_t kNotAwake = 0xffffffffu;

  // Hot arrays, all of length size().
  std::vector<Vec3> position_;
  std::vector<Quat> orientation_;
  std::vector<Vec3> velocity_;
  std::vector<Vec3> angularMomentum_; // world frame
  std::vector<Vec3> angularVelocity_; // world frame, cache of R diag(1/I) R^T L
  std::vector<double> inverseMass_;
  std::vector<Vec3> inverseInertia_;  // body frame diagonal
  std::vector<Vec3> force_;
  std::vector<Vec3> torque_;
  std::vector<MotionType> motionType_;
  std::vector<std::uint32_t> awakeSlot_; // position in awake_, or kNotAwake
  std::vector<BodyId> awake_;

  // Cold table.
  std::vector<BodyInfo> info_;
};

} // namespace armour::dynamics
