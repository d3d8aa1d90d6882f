// SPDX-License-Identifier: GPL-3.0-or-later
// Checkpoints: the complete dynamic state of a World (WorldState.hpp), captured and restored bit
// for bit.
#include "simulation/World.hpp"

#include "core/Error.hpp"
#include "simulation/WorldInternal.hpp"

#include <algorithm>
#include <map>
#include <utility>

namespace armour::simulation {

using detail::kConvexBit;
using detail::kPlaneBit;
using detail::kStaticBits;

WorldState World::captureState() const {
  WorldState s;
  s.time = time_;
  s.steps = steps_;
  s.forcesReady = forcesReady_;
  s.energyMinimum = energyMinimum_;
  s.externalWork = externalWork_;
  s.energyPeak = energyPeak_;
  s.energyStarted = energyStarted_;
  s.bodies.resize(bodies_.size());
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    BodyState& o = s.bodies[b];
    o.motion = bodies_.motionType(b);
    o.position = bodies_.position(b);
    o.orientation = bodies_.orientation(b);
    o.velocity = bodies_.velocity(b);
    o.angularMomentum = bodies_.angularMomentumWorld(b);
    o.force = bodies_.force(b);
    o.torque = bodies_.torque(b);
    o.restTime = restTime_[b];
    o.contactCount = contactCount(b);
    o.maxContactForce = maxContactForce(b);
    o.externalForce = externalForce(b);
    o.externalTorque = externalTorque(b);
    o.sleepLoad = b < sleepLoad_.size() ? sleepLoad_[b] : Vec3::Zero();
  }
  for (const auto& stage : loadStages_) {
    s.loadStages.emplace_back(stage->name(), stage->saveState());
  }
  for (const auto& [pair, points] : history_) {
    for (const auto& [key, h] : points) {
      s.contacts.push_back({pair.first, pair.second, key, h.stretch, h.sliding, h.normalImpulse, h.tangentImpulse});
    }
  }
  s.manifoldCache = saveManifoldCache();
  return s;
}

void World::restoreState(const WorldState& s) {
  if (s.bodies.size() != bodies_.size()) {
    core::failInput("checkpoint", "holds {} bodies but the scene builds {}: restart with the scene the run was "
                                  "started with", s.bodies.size(), bodies_.size());
  }
  const auto nBodies = static_cast<std::uint32_t>(bodies_.size());
  for (const ContactPointState& c : s.contacts) {
    const std::uint32_t index = c.second & ~kStaticBits;
    const bool ok = c.first < nBodies &&
                    ((c.second & kPlaneBit) != 0   ? index < planes_.size()
                     : (c.second & kConvexBit) != 0 ? index < convex_.size()
                                                    : c.second < nBodies && c.first < c.second);
    if (!ok) {
      core::failInput("checkpoint", "contact ({}, {:#x}) does not exist in this scene: restart with the scene the "
                                    "run was started with", c.first, c.second);
    }
  }
  time_ = s.time;
  steps_ = s.steps;
  energyMinimum_ = s.energyMinimum;
  externalWork_ = s.externalWork;
  energyPeak_ = s.energyPeak;
  energyStarted_ = s.energyStarted;
  contactCount_.assign(nBodies, 0);
  maxContactForce_.assign(nBodies, 0.0);
  bodies_.clearForces();
  auto forces = bodies_.forces();
  auto torques = bodies_.torques();
  for (BodyId b = 0; b < nBodies; ++b) {
    const BodyState& o = s.bodies[b];
    if ((o.motion == dynamics::MotionType::Static) != (bodies_.motionType(b) == dynamics::MotionType::Static)) {
      core::failInput("checkpoint", "{} is {} in the checkpoint but {} in the scene: restart with the scene the run "
                                    "was started with", bodies_.describe(b),
                      o.motion == dynamics::MotionType::Static ? "fixed" : "free",
                      o.motion == dynamics::MotionType::Static ? "free" : "fixed");
    }
    bodies_.restoreState(b, o.motion, o.position, o.orientation, o.velocity, o.angularMomentum);
    forces[b] = o.force;
    torques[b] = o.torque;
    restTime_[b] = o.restTime;
    contactCount_[b] = o.contactCount;
    maxContactForce_[b] = o.maxContactForce;
  }
  // Load stages: the same stages, in the same order, each given back its own state.
  if (s.loadStages.size() != loadStages_.size()) {
    core::failInput("checkpoint", "holds {} load stages but the scene has {}: restart with the scene the run was "
                                  "started with", s.loadStages.size(), loadStages_.size());
  }
  externalForce_.clear();
  externalTorque_.clear();
  sleepLoad_.clear();
  if (!loadStages_.empty()) {
    externalForce_.resize(nBodies);
    externalTorque_.resize(nBodies);
    sleepLoad_.resize(nBodies);
    for (BodyId b = 0; b < nBodies; ++b) {
      externalForce_[b] = s.bodies[b].externalForce;
      externalTorque_[b] = s.bodies[b].externalTorque;
      sleepLoad_[b] = s.bodies[b].sleepLoad;
    }
  }
  for (std::size_t k = 0; k < loadStages_.size(); ++k) {
    if (s.loadStages[k].first != loadStages_[k]->name()) {
      core::failInput("checkpoint", "load stage {} is '{}' in the checkpoint but '{}' in the scene: restart with the "
                                    "scene the run was started with", k, s.loadStages[k].first, loadStages_[k]->name());
    }
    loadStages_[k]->restoreState(s.loadStages[k].second);
  }
  std::map<contact::BodyPair, History> byPair;
  for (const ContactPointState& c : s.contacts) {
    byPair[{c.first, c.second}].emplace_back(c.key,
                                             contact::PointHistory{c.stretch, c.sliding, c.normalImpulse, c.tangentImpulse});
  }
  history_.clear();
  clearSampleLists(); // derived state: made anew from the restored poses
  for (auto& [pair, points] : byPair) {
    std::sort(points.begin(), points.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    history_.emplace_back(pair, std::move(points));
  }
  // The constraint solver's reused patches; a penalty run does not keep a cache it never reads
  // (a pack placed with the constraint solver and stormed with the penalty solver).
  if (settings_.solver == ContactSolverKind::Constraint) {
    restoreManifoldCache(s.manifoldCache);
  } else {
    clearManifoldCache();
  }
  forcesReady_ = s.forcesReady;
  boxesValid_ = false;
}

} // namespace armour::simulation
