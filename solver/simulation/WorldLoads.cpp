// SPDX-License-Identifier: GPL-3.0-or-later
// The external-load stages (LoadStage.hpp): run after the contacts in every force evaluation and
// summed into the awake bodies' accumulators; their power, integrated by World::step, is the work
// the energy guard rail allows for.
#include "simulation/World.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

namespace armour::simulation {

void World::addLoadStage(std::shared_ptr<LoadStage> stage) {
  if (!stage) {
    throw std::invalid_argument("World::addLoadStage: null stage");
  }
  loadStages_.push_back(std::move(stage));
  forcesReady_ = false;
}

void World::applyLoadStages(double stateTime) {
  const std::size_t n = bodies_.size();
  if (loadStages_.empty()) {
    externalForce_.clear();
    externalTorque_.clear();
    return;
  }
  externalForce_.assign(n, Vec3::Zero());
  externalTorque_.assign(n, Vec3::Zero());
  for (const auto& stage : loadStages_) {
    stageForce_.assign(n, Vec3::Zero());
    stageTorque_.assign(n, Vec3::Zero());
    stage->apply(*this, stateTime, stageForce_, stageTorque_);
    for (std::size_t b = 0; b < n; ++b) {
      if (!stageForce_[b].allFinite() || !stageTorque_[b].allFinite()) {
        throw SimulationError(fmt::format("t = {:.6g} s: the '{}' loads on {} are not finite (force {}, {}, {}); "
                                          "check the load input (storm file, force model) at this time",
                                          stateTime, stage->name(), bodies_.describe(static_cast<BodyId>(b)),
                                          stageForce_[b].x(), stageForce_[b].y(), stageForce_[b].z()));
      }
      externalForce_[b] += stageForce_[b];
      externalTorque_[b] += stageTorque_[b];
    }
  }
  // Sleeping bodies get their load too (the integrator skips them): one that wakes after this
  // evaluation starts its next step with the load in its first half kick.
  auto forces = bodies_.forces();
  auto torques = bodies_.torques();
  for (BodyId b = 0; b < n; ++b) {
    if (bodies_.motionType(b) != dynamics::MotionType::Static) {
      forces[b] += externalForce_[b];
      torques[b] += externalTorque_[b];
    }
  }
}

double World::externalPower() const {
  double power = 0.0;
  if (externalForce_.empty()) {
    return power;
  }
  for (const BodyId b : bodies_.awakeBodies()) {
    power += externalForce_[b].dot(bodies_.velocity(b)) + externalTorque_[b].dot(bodies_.worldAngularVelocity(b));
  }
  return power;
}

} // namespace armour::simulation
