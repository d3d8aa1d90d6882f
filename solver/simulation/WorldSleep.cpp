// SPDX-License-Identifier: GPL-3.0-or-later
// Sleeping and waking (SleepSettings): rest timers, contact islands (union-find over the pairs in
// contact), waking by a moving neighbour or by a changed external load.
#include "simulation/World.hpp"

#include "simulation/WorldInternal.hpp"

#include <vector>

namespace armour::simulation {

using detail::kStaticBits;

void World::wakeAll() {
  bool woke = false;
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    if (bodies_.motionType(b) == dynamics::MotionType::Sleeping) {
      bodies_.wake(b);
      woke = true;
    }
    if (b < restTime_.size()) restTime_[b] = 0.0;
  }
  if (woke) energyWakeReset();
}

void World::energyWakeReset() {
  // The elastic energy of contacts between sleeping (or sleeping and static) bodies is not
  // evaluated while they sleep, so it leaves E when they fall asleep and comes back when they
  // wake: growth the energy guard would read as an instability (6e5 J, more than its tolerance,
  // when the settled 242-unit trunk was woken). A wake restarts the guard's reference instead.
  energyStarted_ = false;
}

void World::motionTypesChanged() {
  forcesReady_ = false;
  boxesValid_ = false;
  energyStarted_ = false;
  energyPeak_ = 0.0;
}

void World::updateSleep(double dt) {
  const SleepSettings& st = settings_.sleep;
  if (!st.enabled) {
    return;
  }
  const auto n = static_cast<BodyId>(bodies_.size());
  for (BodyId b : bodies_.awakeBodies()) {
    const bool resting = bodies_.velocity(b).norm() < st.linearSpeed &&
                         bodies_.worldAngularVelocity(b).norm() < st.angularSpeed;
    restTime_[b] = resting ? restTime_[b] + dt : 0.0;
  }
  // A sleeper whose external load has changed (a wave arrives) wakes: it was asleep under the old load.
  if (!externalForce_.empty()) {
    sleepLoad_.resize(n, Vec3::Zero());
    for (BodyId b = 0; b < n; ++b) {
      if (bodies_.motionType(b) == dynamics::MotionType::Sleeping &&
          (externalForce_[b] - sleepLoad_[b]).norm() >
              st.wakeLoadFraction * bodies_.info(b).mass * settings_.gravity.norm()) {
        bodies_.wake(b);
        restTime_[b] = 0.0;
        energyWakeReset();
      }
    }
  }
  // The pairs of movable bodies in contact: who touches whom, for waking and for the sleep rule.
  std::vector<std::pair<BodyId, BodyId>> touching;
  touching.reserve(history_.size());
  for (const auto& [key, h] : history_) {
    if ((key.second & kStaticBits) != 0 || h.empty()) continue;
    const BodyId a = key.first, b = key.second;
    if (bodies_.motionType(a) == dynamics::MotionType::Static || bodies_.motionType(b) == dynamics::MotionType::Static)
      continue;
    touching.emplace_back(a, b);
  }
  // What wakes a sleeper it touches. Island: a body that has not rested long enough (so a woken
  // body wakes its neighbours in turn, and the whole island wakes). Neighbours: a body that moved
  // in this step; a body just woken is not moving, so waking does not spread through a resting
  // pile, only motion does.
  const auto wakesOthers = [&](BodyId b) {
    return bodies_.isAwake(b) && (st.scope == SleepScope::Island ? restTime_[b] < st.time : restTime_[b] == 0.0);
  };
  std::vector<BodyId> toWake;
  for (const auto& [a, b] : touching) {
    if (bodies_.motionType(a) == dynamics::MotionType::Sleeping && wakesOthers(b)) toWake.push_back(a);
    if (bodies_.motionType(b) == dynamics::MotionType::Sleeping && wakesOthers(a)) toWake.push_back(b);
  }
  for (BodyId b : toWake) {
    bodies_.wake(b);
    restTime_[b] = 0.0;
  }
  if (!toWake.empty()) energyWakeReset();
  const std::vector<BodyId> toSleep =
      st.scope == SleepScope::Neighbours ? restedWithNeighbours(touching) : restedIslands(touching);
  for (BodyId b : toSleep) {
    bodies_.sleep(b);
    if (!externalForce_.empty()) {
      sleepLoad_.resize(n, Vec3::Zero());
      sleepLoad_[b] = externalForce_[b];
    }
  }
}

std::vector<BodyId> World::restedIslands(const std::vector<std::pair<BodyId, BodyId>>& touching) const {
  // SleepScope::Island: contact islands by union-find over the touching pairs; an island sleeps
  // when every awake member has rested long enough.
  const auto n = static_cast<BodyId>(bodies_.size());
  std::vector<BodyId> parent(n);
  for (BodyId b = 0; b < n; ++b) parent[b] = b;
  const auto find = [&](BodyId b) {
    while (parent[b] != b) {
      parent[b] = parent[parent[b]];
      b = parent[b];
    }
    return b;
  };
  for (const auto& [a, b] : touching) parent[find(a)] = find(b);
  std::vector<char> islandRestless(n, 0);
  for (BodyId b : bodies_.awakeBodies()) {
    if (restTime_[b] < settings_.sleep.time) islandRestless[find(b)] = 1;
  }
  std::vector<BodyId> toSleep;
  for (BodyId b : bodies_.awakeBodies()) {
    if (!islandRestless[find(b)]) toSleep.push_back(b);
  }
  return toSleep;
}

std::vector<BodyId> World::restedWithNeighbours(const std::vector<std::pair<BodyId, BodyId>>& touching) const {
  // SleepScope::Neighbours: an awake body that has rested long enough sleeps unless a body it
  // touches (asleep or not) is restless. The rested neighbours of a moving body stay awake as its
  // buffer; a sleeper touching one of them is not woken (they are at rest), and wakes when one of
  // them moves (the wake rule in updateSleep).
  const double time = settings_.sleep.time;
  std::vector<char> restless(bodies_.size(), 0);
  for (BodyId b : bodies_.awakeBodies()) restless[b] = restTime_[b] < time ? 1 : 0;
  std::vector<char> nextToRestless(bodies_.size(), 0);
  for (const auto& [a, b] : touching) {
    if (restless[b]) nextToRestless[a] = 1;
    if (restless[a]) nextToRestless[b] = 1;
  }
  std::vector<BodyId> toSleep;
  for (BodyId b : bodies_.awakeBodies()) {
    if (!restless[b] && !nextToRestless[b]) toSleep.push_back(b);
  }
  return toSleep;
}

} // namespace armour::simulation
