// SPDX-License-Identifier: GPL-3.0-or-later
#include "dynamics/RigidBodies.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <cmath>

namespace armour::dynamics {

namespace {

/// Relative slack in the triangle inequality of the principal moments: moments computed from a
/// mesh (geometry::computeMassProperties) satisfy it to round-off, and a thin rod or plate sits
/// exactly on the boundary (I_1 + I_2 = I_3 for a lamina).
constexpr double kTriangleSlack = 1e-9;

const char* motionName(MotionType type) {
  switch (type) {
  case MotionType::Static:
    return "static";
  case MotionType::Dynamic:
    return "dynamic";
  case MotionType::Sleeping:
    return "sleeping";
  }
  return "unknown";
}

std::string describeName(const std::string& name, std::size_t index) {
  return name.empty() ? fmt::format("body #{}", index) : fmt::format("body '{}'", name);
}

/// Mass and moments that make a body integrable; throws naming the body otherwise.
void requireMassProperties(const std::string& where, double mass, const Vec3& moments) {
  if (!std::isfinite(mass) || mass <= 0.0) {
    core::failInput(where, "mass = {}: a dynamic body needs a finite positive mass (kg); "
                           "give the mass (density x volume) or make the body static", mass);
  }
  if (!moments.allFinite() || (moments.array() <= 0.0).any()) {
    core::failInput(where, "principal moments = ({}, {}, {}): a dynamic body needs finite positive principal "
                           "moments of inertia (kg m^2) about its centre of mass; compute them from the shape "
                           "(density x geometry::computeMassProperties) or make the body static",
                    moments.x(), moments.y(), moments.z());
  }
  for (int c = 0; c < 3; ++c) {
    const double sumOthers = moments[(c + 1) % 3] + moments[(c + 2) % 3];
    if (moments[c] > sumOthers * (1.0 + kTriangleSlack)) {
      core::failInput(where, "principal moments = ({}, {}, {}): moment {} exceeds the sum of the other two, "
                             "which no rigid body can have (I_a + I_b >= I_c); check the inertia and its units",
                      moments.x(), moments.y(), moments.z(), c + 1);
    }
  }
}

} // namespace

BodyId RigidBodies::add(const BodyDefinition& def) {
  const std::size_t index = size();
  const std::string where = describeName(def.name, index);
  if (index >= kNotAwake) {
    core::failInput(where, "too many bodies: at most {} are supported", kNotAwake - 1);
  }

  const bool isStatic = def.motionType == MotionType::Static;
  if (isStatic) {
    // Mass properties are optional for a static body (0 = not given) but must not be garbage:
    // they are kept so that the body can be made dynamic later.
    if (!std::isfinite(def.mass) || def.mass < 0.0 || !def.principalMoments.allFinite() ||
        (def.principalMoments.array() < 0.0).any()) {
      core::failInput(where, "mass = {}, principal moments = ({}, {}, {}): must be finite and non-negative "
                             "(0 = not given for a static body)",
                      def.mass, def.principalMoments.x(), def.principalMoments.y(), def.principalMoments.z());
    }
  } else {
    requireMassProperties(where, def.mass, def.principalMoments);
  }
  if (!def.position.allFinite()) {
    core::failInput(where, "position = ({}, {}, {}): must be finite (m)", def.position.x(), def.position.y(),
                    def.position.z());
  }
  const double qNorm = def.orientation.norm();
  if (!def.orientation.coeffs().allFinite() || !(qNorm > 0.0)) {
    core::failInput(where, "orientation quaternion (w, x, y, z) = ({}, {}, {}, {}): must be finite and non-zero",
                    def.orientation.w(), def.orientation.x(), def.orientation.y(), def.orientation.z());
  }
  if (!def.velocity.allFinite() || !def.angularVelocity.allFinite()) {
    core::failInput(where, "velocity = ({}, {}, {}) m/s, angular velocity = ({}, {}, {}) rad/s: must be finite",
                    def.velocity.x(), def.velocity.y(), def.velocity.z(), def.angularVelocity.x(),
                    def.angularVelocity.y(), def.angularVelocity.z());
  }
  if (def.motionType != MotionType::Dynamic && (!def.velocity.isZero(0.0) || !def.angularVelocity.isZero(0.0))) {
    core::failInput(where, "a {} body is at rest but was given a velocity ({}, {}, {}) m/s or angular velocity "
                           "({}, {}, {}) rad/s; set them to zero or make the body dynamic",
                    motionName(def.motionType), def.velocity.x(), def.velocity.y(), def.velocity.z(),
                    def.angularVelocity.x(), def.angularVelocity.y(), def.angularVelocity.z());
  }

  const Quat q = def.orientation.normalized();
  position_.push_back(def.position);
  orientation_.push_back(q);
  velocity_.push_back(def.velocity);
  if (isStatic) {
    inverseMass_.push_back(0.0);
    inverseInertia_.push_back(Vec3::Zero());
    angularMomentum_.push_back(Vec3::Zero());
  } else {
    inverseMass_.push_back(1.0 / def.mass);
    inverseInertia_.push_back(def.principalMoments.cwiseInverse());
    // L = R diag(I) R^T omega.
    angularMomentum_.push_back(q * def.principalMoments.cwiseProduct(q.conjugate() * def.angularVelocity));
  }
  angularVelocity_.push_back(Vec3::Zero());
  force_.push_back(Vec3::Zero());
  torque_.push_back(Vec3::Zero());
  motionType_.push_back(def.motionType);
  awakeSlot_.push_back(kNotAwake);
  info_.push_back(BodyInfo{def.name, def.shapeId, def.userTag, def.mass, def.principalMoments});

  const auto id = static_cast<BodyId>(index);
  updateAngularVelocity(id);
  if (def.motionType == MotionType::Dynamic) {
    addToAwake(id);
  }
  return id;
}

Mat3 RigidBodies::inverseInertiaWorld(BodyId i) const {
  const Mat3 r = orientation_[i].toRotationMatrix();
  return r * inverseInertia_[i].asDiagonal() * r.transpose();
}

Vec3 RigidBodies::velocityAtPoint(BodyId i, const Vec3& worldPoint) const {
  return velocity_[i] + angularVelocity_[i].cross(worldPoint - position_[i]);
}

void RigidBodies::updateAngularVelocity(BodyId i) {
  // omega = R diag(1/I) R^T L: rotate L into the principal frame, scale, rotate back.
  const Quat& q = orientation_[i];
  angularVelocity_[i] = q * inverseInertia_[i].cwiseProduct(q.conjugate() * angularMomentum_[i]);
}

void RigidBodies::restoreState(BodyId i, MotionType type, const Vec3& x, const Quat& q, const Vec3& v, const Vec3& L) {
  setMotionType(i, type);
  position_[i] = x;
  orientation_[i] = q;
  if (type == MotionType::Dynamic) {
    velocity_[i] = v;
    angularMomentum_[i] = L;
  }
  updateAngularVelocity(i);
}

void RigidBodies::setOrientation(BodyId i, const Quat& q) {
  orientation_[i] = q.normalized();
  updateAngularVelocity(i);
}

void RigidBodies::setVelocity(BodyId i, const Vec3& v) {
  if (motionType_[i] == MotionType::Dynamic) {
    velocity_[i] = v;
  }
}

void RigidBodies::setWorldAngularVelocity(BodyId i, const Vec3& omega) {
  if (motionType_[i] != MotionType::Dynamic) {
    return;
  }
  const Quat& q = orientation_[i];
  angularMomentum_[i] = q * info_[i].principalMoments.cwiseProduct(q.conjugate() * omega);
  updateAngularVelocity(i);
}

void RigidBodies::clearForces() {
  for (auto& f : force_) {
    f.setZero();
  }
  for (auto& t : torque_) {
    t.setZero();
  }
}

void RigidBodies::applyForceAtPoint(BodyId i, const Vec3& force, const Vec3& worldPoint) {
  force_[i] += force;
  torque_[i] += (worldPoint - position_[i]).cross(force);
}

double RigidBodies::kineticEnergy(BodyId i) const {
  if (motionType_[i] != MotionType::Dynamic) {
    return 0.0;
  }
  return 0.5 * velocity_[i].squaredNorm() / inverseMass_[i] + 0.5 * angularVelocity_[i].dot(angularMomentum_[i]);
}

double RigidBodies::totalKineticEnergy() const {
  double sum = 0.0;
  for (std::size_t i = 0; i < size(); ++i) {
    sum += kineticEnergy(static_cast<BodyId>(i));
  }
  return sum;
}

void RigidBodies::makeAtRest(BodyId i) {
  velocity_[i].setZero();
  angularMomentum_[i].setZero();
  angularVelocity_[i].setZero();
}

void RigidBodies::setMotionType(BodyId i, MotionType type) {
  const MotionType old = motionType_[i];
  if (old == type) {
    return;
  }
  if (old == MotionType::Static) {
    // Restoring mass: the defined values must be usable now.
    requireMassProperties(describe(i), info_[i].mass, info_[i].principalMoments);
    inverseMass_[i] = 1.0 / info_[i].mass;
    inverseInertia_[i] = info_[i].principalMoments.cwiseInverse();
  }
  if (type == MotionType::Static) {
    inverseMass_[i] = 0.0;
    inverseInertia_[i].setZero();
  }
  if (type != MotionType::Dynamic || old == MotionType::Static) {
    makeAtRest(i);
  }
  if (old == MotionType::Dynamic) {
    removeFromAwake(i);
  }
  if (type == MotionType::Dynamic) {
    addToAwake(i);
  }
  motionType_[i] = type;
}

void RigidBodies::wake(BodyId i) {
  if (motionType_[i] == MotionType::Sleeping) {
    setMotionType(i, MotionType::Dynamic);
  }
}

void RigidBodies::sleep(BodyId i) {
  if (motionType_[i] == MotionType::Dynamic) {
    setMotionType(i, MotionType::Sleeping);
  }
}

void RigidBodies::addToAwake(BodyId i) {
  awakeSlot_[i] = static_cast<std::uint32_t>(awake_.size());
  awake_.push_back(i);
}

void RigidBodies::removeFromAwake(BodyId i) {
  const std::uint32_t slot = awakeSlot_[i];
  const BodyId last = awake_.back();
  awake_[slot] = last;
  awakeSlot_[last] = slot;
  awake_.pop_back();
  awakeSlot_[i] = kNotAwake;
}

std::string RigidBodies::describe(BodyId i) const { return describeName(info_[i].name, i); }

} // namespace armour::dynamics
