// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/DeformableBody.hpp"
#include "deformable/HalfSpaceFriction.hpp"

#include "core/Error.hpp"
#include "deformable/SurfaceLoads.hpp"

#include <chrono>
#include <cmath>
#include <cstddef>
#include <utility>

namespace armour::deformable {
namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// The largest mass_scaling accepted (unit: -), ours: beyond a tenth the added mass is no longer a
/// correction of a few elements.
constexpr double kMaxMassScaling = 0.1;

/// Share of the element mass per node: 4-node tets equal shares; 10-node HRZ (DeformableBody.hpp).
double massShare(ElementOrder order, int localNode) {
  if (order == ElementOrder::Linear) {
    return 0.25;
  }
  return localNode < 4 ? 1.0 / 36.0 : 4.0 / 27.0;
}

void validateSettings(const DeformableSettings& s, const std::string& source) {
  validateMaterial(s.material, source + ": material");
  for (int k = 0; k < 3; ++k) {
    core::requireFinite(s.gravity[k], source + ": gravity", "m/s^2");
  }
  core::requireFinite(s.massScaling, source + ": mass_scaling", "-");
  if (s.massScaling < 0.0 || s.massScaling > kMaxMassScaling) {
    core::failInput(source + ": mass_scaling",
                    "{}: the added mass must be between 0 (off) and {} of the body's mass; more changes the unit's "
                    "inertia, not only its smallest elements (0.01 is a usual choice)",
                    s.massScaling, kMaxMassScaling);
  }
  core::requireFinite(s.massDamping, source + ": mass_damping", "1/s");
  if (s.massDamping < 0.0) {
    core::failInput(source + ": mass_damping", "{} 1/s: must be 0 or positive; a negative damping adds energy",
                    s.massDamping);
  }
  core::requireFinite(s.contactGradient, source + ": contact_gradient", "Pa/m");
  if (s.contactGradient < 0.0) {
    core::failInput(source + ": contact_gradient", "{} Pa/m: must be positive, or 0 for 10 E / h", s.contactGradient);
  }
  for (std::size_t i = 0; i < s.halfSpaces.size(); ++i) {
    const double length = s.halfSpaces[i].normal.norm();
    if (!s.halfSpaces[i].point.allFinite() || !(std::abs(length - 1.0) < 1e-9)) {
      core::failInput(fmt::format("{}: half_spaces[{}]", source, i),
                      "normal of length {}, point ({}, {}, {}): the normal must be a unit vector and the point finite",
                      length, s.halfSpaces[i].point.x(), s.halfSpaces[i].point.y(), s.halfSpaces[i].point.z());
    }
  }
  core::requireFinite(s.friction, source + ": friction", "-");
  if (s.friction < 0.0) {
    core::failInput(source + ": friction", "{}: the Coulomb coefficient must be 0 (frictionless) or positive", s.friction);
  }
  if (!(s.frictionStiffnessRatio > 0.0 && s.frictionStiffnessRatio <= 1.0)) {
    core::failInput(source + ": friction_stiffness_ratio",
                    "{}: must be in (0, 1]; above 1 the stick springs are stiffer than the contact the stable step "
                    "allows for (default 8/9)", s.frictionStiffnessRatio);
  }
  core::requireFinite(s.contactPenalty, source + ": contact_penalty", "Pa");
  if (s.contactPenalty < 0.0) {
    core::failInput(source + ": contact_penalty", "{} Pa: must be positive, or 0 for 2 E", s.contactPenalty);
  }
  core::requireFinite(s.bodyFriction, source + ": body_friction", "-");
  if (s.bodyFriction < 0.0) {
    core::failInput(source + ": body_friction", "{}: the Coulomb coefficient must be 0 (frictionless) or positive",
                    s.bodyFriction);
  }
  if (s.bodyFriction > 0.0 && !s.bodyContact) {
    core::failInput(source + ": body_friction", "{}: acts between the bodies, and their contact is off; give two "
                                                "bodies or more, or remove it", s.bodyFriction);
  }
  core::requireFinite(s.contactDamping, source + ": contact_damping", "-");
  if (s.contactDamping < 0.0) {
    core::failInput(source + ": contact_damping", "{}: must be 0 or positive; a negative damping adds energy",
                    s.contactDamping);
  }
  if (!(s.stepSafety > 0.0 && s.stepSafety <= 1.0)) {
    core::failInput(source + ": step_safety", "{}: the safety factor on the stable step must be in (0, 1]",
                    s.stepSafety);
  }
}

} // namespace

DeformableBody::DeformableBody(DeformableMesh mesh, const DeformableSettings& settings, std::string source)
    : mesh_(std::move(mesh)), settings_(settings), source_(std::move(source)) {
  validateSettings(settings_, source_);
  if (mesh_.elementCount() == 0) {
    core::failInput(source_, "the mesh has no elements; give a tetrahedral mesh of the unit");
  }
  model_ = {lameConstants(settings_.material), settings_.material.viscosity, settings_.fBar};
  const int nen = mesh_.nodesPerElement();
  const std::size_t nodes = mesh_.nodeCount();
  geometry_.resize(mesh_.elementCount());
  masses_.assign(nodes, 0.0);
  for (std::size_t e = 0; e < mesh_.elementCount(); ++e) {
    NodeMatrix X(nen, 3);
    for (int a = 0; a < nen; ++a) {
      X.row(a) = mesh_.nodes[mesh_.element(e)[a]].transpose();
    }
    if (!elementGeometry(mesh_.order, X, geometry_[e])) {
      core::failInput(source_, "element {} (nodes {}, {}, {}, {}) is inverted or flat; remesh the unit", e,
                      mesh_.element(e)[0], mesh_.element(e)[1], mesh_.element(e)[2], mesh_.element(e)[3]);
    }
  }
  std::vector<double> volumes(mesh_.elementCount());
  for (std::size_t e = 0; e < volumes.size(); ++e) {
    volumes[e] = geometry_[e].volume;
  }
  massScaling_ = deformable::massScaling(mesh_, volumes, settings_.material.density, settings_.massScaling);
  for (std::size_t e = 0; e < mesh_.elementCount(); ++e) {
    for (int a = 0; a < nen; ++a) {
      masses_[mesh_.element(e)[a]] +=
          massShare(mesh_.order, a) * settings_.material.density * geometry_[e].volume * massScaling_.factor[e];
    }
  }
  for (std::size_t n = 0; n < nodes; ++n) {
    if (!(masses_[n] > 0.0)) {
      core::failInput(source_, "node {} belongs to no element; remove unused nodes from the mesh", n);
    }
  }
  double omegaContact = 0.0;
  if (!settings_.halfSpaces.empty() || settings_.rigidContact) {
    surface_ = surfaceTriangles(mesh_, boundaryFaces(mesh_));
    contactGradient_ = settings_.contactGradient;
    if (contactGradient_ == 0.0) {
      double edges = 0.0;
      for (const auto& t : surface_) {
        for (int i = 0; i < 3; ++i) {
          edges += (mesh_.nodes[t[(i + 1) % 3]] - mesh_.nodes[t[i]]).norm();
        }
      }
      contactGradient_ = 10.0 * settings_.material.youngModulus / (edges / (3.0 * static_cast<double>(surface_.size())));
    }
    omegaContact = contactFrequency(mesh_, surface_, masses_, contactGradient_);
    if (settings_.friction > 0.0) {
      frictionStiffness_ = tributaryAreas(mesh_, surface_);
      for (double& k : frictionStiffness_) {
        k *= settings_.frictionStiffnessRatio * contactGradient_;
      }
      state_.frictionAnchors.assign(settings_.halfSpaces.size() * nodes, Vec3::Zero());
      state_.frictionActive.assign(settings_.halfSpaces.size() * nodes, 0);
    }
  }
  if (settings_.bodyContact) {
    const auto triangles = surfaceTriangles(mesh_, boundaryFaces(mesh_));
    const double penalty =
        settings_.contactPenalty > 0.0 ? settings_.contactPenalty : 2.0 * settings_.material.youngModulus;
    const auto lame = lameConstants(settings_.material);
    const double impedance = std::sqrt((lame.lambda + 2.0 * lame.mu) * settings_.material.density);
    bodyContact_ = std::make_shared<BodyContact>(mesh_, triangles, penalty, settings_.contactDamping, impedance);
    // Both contacts press on a node at most as springs in parallel: frequencies add in squares.
    const double omegaBody = contactFrequency(mesh_, triangles, masses_, bodyContact_->gradientBound());
    omegaContact = std::sqrt(omegaContact * omegaContact + omegaBody * omegaBody);
    if (settings_.bodyFriction > 0.0) {
      bodyFrictionStiffness_ = tributaryAreas(mesh_, triangles);
      for (double& k : bodyFrictionStiffness_) {
        k *= settings_.frictionStiffnessRatio * bodyContact_->gradientBound();
      }
      state_.bodyFrictionTets.assign(nodes, -1);
      state_.bodyFrictionWeights.assign(nodes, std::array<double, 4>{});
    }
  }
  // Two rigorous bounds on the mesh's highest frequency: the element one (2 c_d / l over the
  // elements, with mass scaling's effective lengths) and Gershgorin's on the assembled mesh; the
  // lower sets the step.
  const double omegaMesh = meshFrequencyBound(mesh_, geometry_, model_, masses_);
  const double waveSpeed = dilatationalWaveSpeed(settings_.material);
  const bool meshBound = omegaMesh < 2.0 * waveSpeed / massScaling_.length;
  stable_ = deformable::stableStepForLength(meshBound ? 2.0 * waveSpeed / omegaMesh : massScaling_.length,
                                            massScaling_.element, settings_.material, settings_.stepSafety,
                                            omegaContact);
  stable_.meshBound = meshBound;
  stable_.meshFrequency = omegaMesh;
  fixedAxes_.assign(nodes, 0U);
  prescribedVelocity_.assign(nodes, Vec3::Zero());
  externalForces_.assign(nodes, Vec3::Zero());
  state_.positions = mesh_.nodes;
  state_.velocities.assign(nodes, Vec3::Zero());
  state_.accelerations.assign(nodes, Vec3::Zero());
  elementForces_.assign(mesh_.connectivity.size() * 3, 0.0);
  elementFailed_.assign(mesh_.elementCount(), 0);
  buildNodeElementTable();
}

void DeformableBody::buildNodeElementTable() {
  const std::size_t nodes = mesh_.nodeCount();
  nodeSlotStart_.assign(nodes + 1, 0);
  for (const auto n : mesh_.connectivity) {
    ++nodeSlotStart_[static_cast<std::size_t>(n) + 1];
  }
  for (std::size_t n = 0; n < nodes; ++n) {
    nodeSlotStart_[n + 1] += nodeSlotStart_[n];
  }
  nodeSlots_.resize(mesh_.connectivity.size());
  std::vector<std::int64_t> fill(nodeSlotStart_.begin(), nodeSlotStart_.end() - 1);
  // Slots in increasing order (element, then local node): the fixed order of every nodal sum.
  for (std::size_t slot = 0; slot < mesh_.connectivity.size(); ++slot) {
    nodeSlots_[static_cast<std::size_t>(fill[mesh_.connectivity[slot]]++)] = static_cast<std::int64_t>(slot);
  }
}

void DeformableBody::setPositions(const std::vector<Vec3>& positions) {
  if (positions.size() != nodeCount()) {
    core::failInput(source_, "{} positions given for {} nodes", positions.size(), nodeCount());
  }
  state_.positions = positions;
  state_.accelerationsReady = false;
}

void DeformableBody::setVelocities(const std::vector<Vec3>& velocities) {
  if (velocities.size() != nodeCount()) {
    core::failInput(source_, "{} velocities given for {} nodes", velocities.size(), nodeCount());
  }
  state_.velocities = velocities;
  state_.accelerationsReady = false;
}

void DeformableBody::fixNode(std::size_t node, const Vec3& velocity, unsigned axes) {
  if (node >= nodeCount()) {
    core::failInput(source_, "fixed node {} does not exist ({} nodes)", node, nodeCount());
  }
  fixedAxes_[node] |= axes & 7U;
  for (int k = 0; k < 3; ++k) {
    if ((axes >> k) & 1U) {
      prescribedVelocity_[node][k] = velocity[k];
      state_.velocities[node][k] = velocity[k];
    }
  }
  state_.accelerationsReady = false;
}

void DeformableBody::setExternalForce(std::size_t node, const Vec3& force) {
  if (node >= nodeCount()) {
    core::failInput(source_, "loaded node {} does not exist ({} nodes)", node, nodeCount());
  }
  externalForces_[node] = force;
  state_.accelerationsReady = false;
}

void DeformableBody::gatherElement(std::size_t e, NodeMatrix& x, NodeMatrix& v) const {
  const int nen = mesh_.nodesPerElement();
  x.resize(nen, 3);
  v.resize(nen, 3);
  for (int a = 0; a < nen; ++a) {
    const auto n = static_cast<std::size_t>(mesh_.element(e)[a]);
    x.row(a) = state_.positions[n].transpose();
    v.row(a) = state_.velocities[n].transpose();
  }
}

void DeformableBody::computeAccelerations() {
  const auto elements = static_cast<std::ptrdiff_t>(mesh_.elementCount());
  const int nen = mesh_.nodesPerElement();
  const double start = now();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t e = 0; e < elements; ++e) {
    const auto element = static_cast<std::size_t>(e);
    double x[30];
    double v[30];
    for (int a = 0; a < nen; ++a) {
      const auto n = static_cast<std::size_t>(mesh_.element(element)[a]);
      for (int k = 0; k < 3; ++k) {
        x[3 * a + k] = state_.positions[n][k];
        v[3 * a + k] = state_.velocities[n][k];
      }
    }
    const bool ok = deformable::internalForces(geometry_[element], model_, x, v, nen,
                                               elementForces_.data() + element * static_cast<std::size_t>(nen) * 3);
    elementFailed_[element] = ok ? 0 : 1;
  }
  const double forcesDone = now();
  times_.elementForces += forcesDone - start;
  for (std::size_t e = 0; e < mesh_.elementCount(); ++e) {
    if (elementFailed_[e] != 0) {
      throw DeformableStepError(fmt::format(
          "{}: element {} is inverted (J <= 0) at t = {} s, step {}: the step is too large for the loading, or the "
          "load crushes the element; reduce the step or refine the mesh",
          source_, e, state_.time, state_.steps));
    }
  }
  if (!surface_.empty() || bodyContact_) {
    // Serial over surface triangles, in order: the nodal sums do not depend on the threads.
    contactForces_.assign(nodeCount(), Vec3::Zero());
    if (frictionStiffness_.empty()) {
      for (const auto& halfSpace : settings_.halfSpaces) {
        addHalfSpaceContact(surface_, state_.positions, halfSpace, contactGradient_, contactForces_);
      }
    } else {
      // Friction needs each half-space's own normal forces: one at a time into the scratch.
      frictionTotal_ = Vec3::Zero();
      const std::size_t n = nodeCount();
      for (std::size_t h = 0; h < settings_.halfSpaces.size(); ++h) {
        halfSpaceScratch_.assign(n, Vec3::Zero());
        addHalfSpaceContact(surface_, state_.positions, settings_.halfSpaces[h], contactGradient_, halfSpaceScratch_);
        const FrictionAnchors anchors{std::span<Vec3>(state_.frictionAnchors).subspan(h * n, n),
                                      std::span<std::uint8_t>(state_.frictionActive).subspan(h * n, n)};
        frictionTotal_ += addHalfSpaceFriction(halfSpaceScratch_, state_.positions, settings_.halfSpaces[h],
                                               settings_.friction, frictionStiffness_, anchors, contactForces_);
        for (std::size_t a = 0; a < n; ++a) {
          contactForces_[a] += halfSpaceScratch_[a];
        }
      }
    }
    obstacleLoads_.assign(obstacles_.size(), ObstacleLoad{});
    for (std::size_t o = 0; o < obstacles_.size(); ++o) {
      if (frictionStiffness_.empty()) {
        obstacleLoads_[o] = addObstacleContact(surface_, state_.positions, obstacles_[o], contactGradient_, contactForces_);
        continue;
      }
      // With friction: this body's normal forces alone, then the stick-slip springs against it,
      // whose reaction the rigid body takes too. Anchors after the half-spaces' (setObstacles).
      const std::size_t n = nodeCount(), slot = settings_.halfSpaces.size() + o;
      halfSpaceScratch_.assign(n, Vec3::Zero());
      ObstacleLoad load = addObstacleContact(surface_, state_.positions, obstacles_[o], contactGradient_, halfSpaceScratch_);
      frictionScratch_.assign(n, Vec3::Zero());
      const FrictionAnchors anchors{std::span<Vec3>(state_.frictionAnchors).subspan(slot * n, n),
                                    std::span<std::uint8_t>(state_.frictionActive).subspan(slot * n, n)};
      const Vec3 friction = addObstacleFriction(halfSpaceScratch_, state_.positions, obstacles_[o].orientation,
                                                obstacles_[o].position, settings_.friction, frictionStiffness_, anchors,
                                                frictionScratch_);
      load.force -= friction;
      for (std::size_t a = 0; a < n; ++a) {
        if (frictionScratch_[a] != Vec3::Zero())
          load.torque -= (state_.positions[a] - obstacles_[o].position).cross(frictionScratch_[a]);
        contactForces_[a] += halfSpaceScratch_[a] + frictionScratch_[a];
      }
      obstacleLoads_[o] = load;
    }
    if (bodyContact_ && bodyFrictionStiffness_.empty()) {
      bodyContactStats_ = bodyContact_->add(state_.positions, state_.velocities, contactForces_);
    } else if (bodyContact_) {
      bodyContactStats_ = bodyContact_->add(state_.positions, state_.velocities, contactForces_, &contactorLoads_);
      const BodyFrictionAnchors anchors{std::span<std::int32_t>(state_.bodyFrictionTets),
                                        std::span<std::array<double, 4>>(state_.bodyFrictionWeights)};
      bodyFrictionTotal_ = addBodyFriction(*bodyContact_, contactorLoads_, state_.positions, settings_.bodyFriction,
                                           bodyFrictionStiffness_, anchors, contactForces_);
    }
  }
  const auto nodes = static_cast<std::ptrdiff_t>(nodeCount());
  const double alpha = settings_.massDamping;
  const bool contact = !surface_.empty() || bodyContact_;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t n = 0; n < nodes; ++n) {
    const auto node = static_cast<std::size_t>(n);
    Vec3 force = externalForces_[node] + masses_[node] * settings_.gravity;
    if (contact) {
      force += contactForces_[node];
    }
    for (auto s = nodeSlotStart_[node]; s < nodeSlotStart_[node + 1]; ++s) {
      const double* f = elementForces_.data() + nodeSlots_[static_cast<std::size_t>(s)] * 3;
      force -= Vec3(f[0], f[1], f[2]);
    }
    Vec3 a = force / masses_[node] - alpha * state_.velocities[node];
    for (int k = 0; k < 3; ++k) {
      if ((fixedAxes_[node] >> k) & 1U) {
        a[k] = 0.0;
      }
    }
    state_.accelerations[node] = a;
  }
  state_.accelerationsReady = true;
  times_.gather += now() - forcesDone;
}

void DeformableBody::checkStep(double dt) const {
  if (!(dt > 0.0)) {
    core::failInput(source_, "time step {} s: must be positive", dt);
  }
  if (dt > stable_.dt) {
    core::failInput(source_,
                    "time step {} s is above the stable limit {} s = safety {} x {} / c_d {} m/s"
                    "{}{}; use a step of at most {} s",
                    dt, stable_.dt, stable_.safety,
                    stable_.meshBound
                        ? fmt::format("l = 2 c_d / omega_mesh = {} m (the mesh's Gershgorin bound, omega_mesh = {} rad/s)",
                                      stable_.lengthMin, stable_.meshFrequency)
                        : fmt::format("l_min {} m (element {})", stable_.lengthMin, stable_.element),
                    stable_.waveSpeed,
                    stable_.contactFrequency > 0.0
                        ? fmt::format(", lowered by the contact (omega_c = {} rad/s, G = {} Pa/m)",
                                      stable_.contactFrequency, contactGradient_)
                        : std::string(),
                    stable_.dampingRatio > 0.0 ? fmt::format(" x (sqrt(1 + xi^2) - xi), xi = {}", stable_.dampingRatio)
                                               : std::string(),
                    stable_.dt);
  }
  // The mass damping is explicit (it acts on the half-step velocity): alpha dt <= 1 keeps it from
  // overshooting (it is unstable from alpha dt = 2).
  if (settings_.massDamping * dt > 1.0) {
    core::failInput(source_ + ": mass_damping",
                    "{} 1/s with a step of {} s: mass_damping x dt = {} must be at most 1; use a step of at most {} s "
                    "or less damping (critical damping of the slowest mode is 2 omega_1)",
                    settings_.massDamping, dt, settings_.massDamping * dt, 1.0 / settings_.massDamping);
  }
}

void DeformableBody::step(double dt) {
  checkStep(dt);
  if (!state_.accelerationsReady) {
    computeAccelerations();
  }
  const auto nodes = static_cast<std::ptrdiff_t>(nodeCount());
  double start = now();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t n = 0; n < nodes; ++n) {
    auto& v = state_.velocities[static_cast<std::size_t>(n)];
    v += 0.5 * dt * state_.accelerations[static_cast<std::size_t>(n)];
    state_.positions[static_cast<std::size_t>(n)] += dt * v;
  }
  times_.update += now() - start;
  computeAccelerations();
  start = now();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t n = 0; n < nodes; ++n) {
    state_.velocities[static_cast<std::size_t>(n)] += 0.5 * dt * state_.accelerations[static_cast<std::size_t>(n)];
  }
  state_.time += dt;
  ++state_.steps;
  for (std::size_t n = 0; n < nodeCount(); ++n) {
    if (!state_.positions[n].allFinite() || !state_.velocities[n].allFinite()) {
      throw DeformableStepError(fmt::format("{}: node {} has a non-finite position or velocity at t = {} s, step {}",
                                            source_, n, state_.time, state_.steps));
    }
  }
  times_.update += now() - start;
}

void DeformableBody::prepare() {
  if (!state_.accelerationsReady) {
    computeAccelerations();
  }
}

std::vector<Vec3> DeformableBody::internalForces() {
  if (!state_.accelerationsReady) {
    computeAccelerations();
  }
  std::vector<Vec3> out(nodeCount(), Vec3::Zero());
  for (std::size_t n = 0; n < nodeCount(); ++n) {
    for (auto s = nodeSlotStart_[n]; s < nodeSlotStart_[n + 1]; ++s) {
      const double* f = elementForces_.data() + nodeSlots_[static_cast<std::size_t>(s)] * 3;
      out[n] += Vec3(f[0], f[1], f[2]);
    }
  }
  return out;
}

double DeformableBody::kineticEnergy() const {
  double sum = 0.0;
  for (std::size_t n = 0; n < nodeCount(); ++n) {
    sum += 0.5 * masses_[n] * state_.velocities[n].squaredNorm();
  }
  return sum;
}

template <typename T, typename F>
std::vector<T> DeformableBody::perElement(F&& f) const {
  std::vector<T> out(mesh_.elementCount());
  const auto elements = static_cast<std::ptrdiff_t>(mesh_.elementCount());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t e = 0; e < elements; ++e) {
    const auto k = static_cast<std::size_t>(e);
    NodeMatrix x;
    NodeMatrix v;
    gatherElement(k, x, v);
    out[k] = f(k, x, v);
  }
  return out;
}

double DeformableBody::strainEnergy() const {
  const std::vector<double> energy = perElement<double>(
      [&](std::size_t e, const NodeMatrix& x, const NodeMatrix&) { return elementStrainEnergy(geometry_[e], model_, x); });
  double sum = 0.0;
  for (const double w : energy) {
    sum += w;
  }
  return sum;
}

double DeformableBody::gravityPotential() const {
  double sum = 0.0;
  for (std::size_t n = 0; n < nodeCount(); ++n) {
    sum -= masses_[n] * settings_.gravity.dot(state_.positions[n]);
  }
  return sum;
}

double DeformableBody::contactEnergy() const {
  double energy = 0.0;
  std::vector<Vec3> scratch(surface_.empty() ? 0 : nodeCount(), Vec3::Zero());
  for (const auto& halfSpace : settings_.halfSpaces) {
    energy += addHalfSpaceContact(surface_, state_.positions, halfSpace, contactGradient_, scratch);
  }
  for (const RigidObstacle& obstacle : obstacles_) {
    energy += addObstacleContact(surface_, state_.positions, obstacle, contactGradient_, scratch, true).energy;
  }
  return energy;
}

Vec3 DeformableBody::contactForce() const {
  std::vector<Vec3> forces(surface_.empty() ? 0 : nodeCount(), Vec3::Zero());
  for (const auto& halfSpace : settings_.halfSpaces) {
    addHalfSpaceContact(surface_, state_.positions, halfSpace, contactGradient_, forces);
  }
  Vec3 total = frictionTotal_;
  for (const auto& f : forces) {
    total += f;
  }
  for (const ObstacleLoad& load : obstacleLoads_) {
    total -= load.force;
  }
  return total;
}

void DeformableBody::setObstacles(std::vector<RigidObstacle> obstacles) {
  if (!settings_.rigidContact) {
    core::failInput(source_ + ": rigid_contact", "is off, so the stable step does not allow for rigid bodies; set "
                                                  "rigid_contact on to give obstacles");
  }
  obstacles_ = std::move(obstacles);
  if (!frictionStiffness_.empty()) {
    // One set of anchors per half-space, then per rigid body; a body added starts unanchored.
    const std::size_t size = (settings_.halfSpaces.size() + obstacles_.size()) * nodeCount();
    state_.frictionAnchors.resize(size, Vec3::Zero());
    state_.frictionActive.resize(size, 0);
  }
}

std::vector<Mat3> DeformableBody::elementStresses() const {
  return perElement<Mat3>([&](std::size_t e, const NodeMatrix& x, const NodeMatrix& v) {
    return elementCauchyStress(geometry_[e], model_, x, v);
  });
}

void DeformableBody::restore(const DeformableState& state, const std::string& source) {
  const std::size_t n = nodeCount();
  if (state.positions.size() != n || state.velocities.size() != n || state.accelerations.size() != n) {
    core::failInput(source, "the state holds {} nodes, this body has {}: the checkpoint is of another mesh; restart "
                            "with the mesh it was written for",
                    state.positions.size(), n);
  }
  if (state.frictionAnchors.size() != state_.frictionAnchors.size() ||
      state.frictionActive.size() != state_.frictionActive.size()) {
    core::failInput(source, "the state holds {} friction anchors, this body {} ({} half-spaces, friction {}): the "
                            "checkpoint was written with other friction settings; restart with those",
                    state.frictionAnchors.size(), state_.frictionAnchors.size(), settings_.halfSpaces.size(),
                    settings_.friction);
  }
  if (state.bodyFrictionTets.size() != state_.bodyFrictionTets.size() ||
      state.bodyFrictionWeights.size() != state_.bodyFrictionWeights.size()) {
    core::failInput(source, "the state holds {} body friction anchors, this body {} (body friction {}): the checkpoint "
                            "was written with other friction settings; restart with those",
                    state.bodyFrictionTets.size(), state_.bodyFrictionTets.size(), settings_.bodyFriction);
  }
  state_ = state;
}

} // namespace armour::deformable
