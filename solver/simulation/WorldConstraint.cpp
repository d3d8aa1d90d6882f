// SPDX-License-Identifier: GPL-3.0-or-later
// The constraint solver's step (contact.solver: constraint; docs/theory.md, "The constraint
// solver"): loads at the step start -> boxes -> broad phase -> narrow phase with a speculative
// margin and contact reduction (parallel over pairs, each writing its own manifold) -> constraints
// with warm starts (serial, pair order) -> substeps of {integrate velocities, warm start, solve,
// integrate positions, relax} -> restitution -> history, contact records -> sleep and guard rails.
// The solve is serial Gauss-Seidel in constraint order: 1 and N threads give the same bits.
#include "simulation/World.hpp"

#include "core/Error.hpp"
#include "dynamics/Integrator.hpp"
#include "simulation/WorldInternal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace armour::simulation {

using detail::kPlaneBit;
using detail::kStaticBits;

namespace {

/// Hysteresis of the contact reduction (ContactReduction.hpp): a point kept in the previous step
/// stays unless another is deeper by this fraction of Dn (ours; 1 mm on a 1 m cube, ten times the
/// resting overlap at E_p = 1e8 Pa).
constexpr double kKeepDepthPerDn = 1e-3;

/// Depth over which a sample's area enters its kept point's spring: from 0 at this gap outside
/// the other body to all of it at the surface (ContactReduction.hpp). Ours, measured: with a step
/// at the surface the springs jump as samples cross it, and normal-force jumps ratchet a pack
/// downhill (the smoke trunk placed with this solver crept a median 0.34 mm in 4 s dry); with
/// 0.01 Dn the median creep is 0.06 mm (0.02 Dn: 0.02 mm, at a larger first settling).
constexpr double kStiffnessRampPerDn = 0.01;

/// A pair's contact history as the World holds it: (sample key, point history), sorted by key.
using PointHistories = std::vector<std::pair<std::uint32_t, contact::PointHistory>>;

/// The previous step's point of pair (a, b) nearest to `point` (world) within `radius` (m), or null.
/// A key is a sample index of A, or of B with the reverse bit; `samplePosition(owner, sample)` gives
/// that sample's world position now (or NaN when the index does not exist).
template <typename SamplePosition>
const contact::PointHistory* nearestPreviousPoint(const contact::BodyPair& key, const PointHistories& previous,
                                                  const Vec3& point, double radius, SamplePosition&& samplePosition) {
  const bool isStatic = (key.second & kStaticBits) != 0;
  const contact::PointHistory* nearest = nullptr;
  double closest = radius * radius;
  for (const auto& [k, h] : previous) {
    const bool ofB = (k & detail::kReverseBit) != 0;
    if (ofB && isStatic) continue;
    const Vec3 x = samplePosition(ofB ? key.second : key.first, k & ~detail::kReverseBit);
    if (const double d = (x - point).squaredNorm(); d < closest) {
      closest = d;
      nearest = &h;
    }
  }
  return nearest;
}

} // namespace

void World::collideConstraint(std::vector<PairManifold>& manifolds) {
  std::vector<contact::BodyPair> keys;
  candidatePairs(keys);
  stepLists_ = sampleListsFor(keys);
  manifolds.resize(keys.size()); // each is reset below, keeping its patches' storage
  const ConstraintSettings& cs = settings_.constraint;
  contact::ReductionSettings reduction;
  reduction.patchAngle = cs.patchAngle;
  // How far a's surface can move towards b's within this step (b == a: towards static geometry):
  // the relative speed of the centres, the rim speeds |omega| R, and what gravity and the held
  // loads add over dt, with 10 % to spare. A pair that could close more than the speculative
  // margin in one step gets that much margin, so that a fast body is caught at the surface
  // instead of passing a thin wall between two steps (tunnelling).
  const double dt = timeStep();
  const auto rim = [&](BodyId b) {
    if (!bodies_.isAwake(b)) return 0.0;
    const double accel = settings_.gravity.norm() + bodies_.inverseMass(b) * bodies_.force(b).norm();
    return bodies_.worldAngularVelocity(b).norm() * shapes_[bodyShape_[b]]->radius * bodyScale_[b] + accel * dt;
  };
  const auto travel = [&](BodyId a, BodyId b) {
    const Vec3 va = bodies_.isAwake(a) ? bodies_.velocity(a) : Vec3::Zero();
    const Vec3 vb = (b != a && bodies_.isAwake(b)) ? bodies_.velocity(b) : Vec3::Zero();
    return 1.1 * dt * ((va - vb).norm() + rim(a) + (b != a ? rim(b) : 0.0));
  };
  const bool reuse = settings_.constraint.reuseDistance > 0.0;
  const double turnedCos = std::cos(settings_.constraint.reuseDistance);
  std::vector<char> reused(keys.size(), 0);
  std::vector<CachedManifold*> entries;
  if (reuse) {
    findCachedManifolds(keys, entries);
  } else {
    entries.assign(keys.size(), nullptr);
  }
#pragma omp parallel for schedule(dynamic, 1) if (keys.size() >= 16)
  for (std::size_t w = 0; w < keys.size(); ++w) {
    PairManifold& m = manifolds[w];
    m.key = keys[w];
    m.patches.clear();
    m.maxOverlap = 0.0;
    m.margin = 0.0;
    const BodyId a = m.key.first;
    if (entries[w] != nullptr &&
        reuseManifold(m, travel(a, (m.key.second & kStaticBits) != 0 ? a : m.key.second), turnedCos, *entries[w])) {
      reused[w] = 1;
      continue;
    }
    // One buffer per thread, kept from pair to pair and step to step (no allocation per pair).
    thread_local std::vector<contact::ContactPoint> points;
    points.clear();
    if ((m.key.second & kStaticBits) != 0) {
      const bool isPlane = (m.key.second & kPlaneBit) != 0;
      const detail::StaticTarget target =
          detail::staticTarget(planes_, convex_, isPlane, m.key.second & ~kStaticBits, boxes_[a]);
      const contact::HalfSpaces solid{target.normals, target.offsets(), target.region};
      m.margin = std::max(cs.speculativeMargin * bodyDn(a), travel(a, a));
      m.maxOverlap = contact::samplesInHalfSpaces(contactShape(a), contactPose(a), solid, m.margin, points);
    } else {
      const BodyId b = m.key.second;
      m.margin = std::max(cs.speculativeMargin * std::min(bodyDn(a), bodyDn(b)), travel(a, b));
      m.maxOverlap = contact::samplesInLevelSets(contactShape(a), contactPose(a), contactShape(b), contactPose(b),
                                                 m.margin, points, stepLists_[w], sampleListSlack(a, b));
    }
    // The keys this pair's patches held in the previous step (its history, sorted by key).
    std::vector<std::uint32_t> kept;
    if (const History* previous = findPairHistory(m.key)) {
      kept.reserve(previous->size());
      for (const auto& [key, h] : *previous) kept.push_back(key);
    }
    contact::ReductionSettings pairReduction = reduction;
    pairReduction.keepDepth = kKeepDepthPerDn * bodyDn(a);
    pairReduction.rampDepth = kStiffnessRampPerDn * bodyDn(a);
    contact::reduceContacts(points, pairReduction, kept, m.patches);
  }
  reusedPairs_ = static_cast<std::size_t>(std::count(reused.begin(), reused.end(), char{1}));
  if (reuse) {
    cacheManifolds(manifolds, reused, entries);
  } else {
    clearManifoldCache();
  }
}

void World::syncSolverBodies(bool inertia) {
  const auto awake = bodies_.awakeBodies();
  for (std::size_t s = 0; s < awake.size(); ++s) {
    const BodyId b = awake[s];
    contact::SolverBody& sb = solverBodies_[s + 1];
    sb.v = bodies_.velocity(b);
    sb.w = bodies_.worldAngularVelocity(b);
    sb.dp = bodies_.position(b) - stepStartPosition_[b];
    sb.dq = bodies_.orientation(b) * stepStartOrientation_[b].conjugate();
    if (inertia) {
      sb.invMass = bodies_.inverseMass(b);
      sb.invInertia = bodies_.inverseInertiaWorld(b);
    }
  }
}

void World::writeSolverVelocities() {
  const auto awake = bodies_.awakeBodies();
  for (std::size_t s = 0; s < awake.size(); ++s) {
    const contact::SolverBody& sb = solverBodies_[s + 1];
    bodies_.setVelocity(awake[s], sb.v);
    bodies_.setWorldAngularVelocity(awake[s], sb.w);
  }
}

void World::buildConstraints(std::vector<PairManifold>& manifolds, double h) {
  // Serial: the guard rails (they throw, naming the pair) and where each pair's patches and points
  // go; then every pair fills its own slots, in parallel (any thread count gives the same bits).
  std::vector<std::size_t> patchStart(manifolds.size() + 1, 0), pointStart(manifolds.size() + 1, 0);
  for (std::size_t i = 0; i < manifolds.size(); ++i) {
    const PairManifold& m = manifolds[i];
    guardOverlap(m.key, m.maxOverlap, std::numeric_limits<double>::infinity());
    std::size_t points = 0;
    for (const auto& patch : m.patches) points += static_cast<std::size_t>(patch.count);
    patchStart[i + 1] = patchStart[i] + m.patches.size();
    pointStart[i + 1] = pointStart[i] + points;
  }
  constraints_.clear(); // the resizes below then start every point at its defaults (no impulses)
  constraints_.patches.resize(patchStart.back());
  constraints_.points.resize(pointStart.back());
  constraintPair_.resize(patchStart.back());
  std::vector<std::uint32_t> warm(manifolds.size(), 0);
  const auto n = static_cast<std::int64_t>(manifolds.size());
#pragma omp parallel for schedule(dynamic, 16) if (n >= 64)
  for (std::int64_t j = 0; j < n; ++j) {
    const auto i = static_cast<std::size_t>(j);
    if (!manifolds[i].patches.empty()) {
      warm[i] = buildPairConstraints(manifolds[i], static_cast<std::uint32_t>(i), patchStart[i], pointStart[i], h);
    }
  }
  std::size_t warmStarted = 0;
  for (const std::uint32_t w : warm) warmStarted += w;
  warmStarted_ = warmStarted;
}

std::uint32_t World::buildPairConstraints(const PairManifold& m, std::uint32_t pairIndex, std::size_t patchAt,
                                          std::size_t pointAt, double h) {
  const ConstraintSettings& cs = settings_.constraint;
  std::uint32_t warmStarted = 0;
  const History* previous = findPairHistory(m.key);
  const BodyId a = m.key.first;
  const bool isStatic = (m.key.second & kStaticBits) != 0;
  MaterialId materialB = 0;
  if (isStatic) {
    const std::uint32_t index = m.key.second & ~kStaticBits;
    materialB = (m.key.second & kPlaneBit) != 0 ? planes_[index].material : convex_[index].material;
  } else {
    materialB = bodyMaterial_[m.key.second];
  }
  const Material& ma = materials_[bodyMaterial_[a]];
  const Material& mb = materials_[materialB];
  const Vec3& xA = bodies_.position(a);
  // The penalty law's stiffness (section 6 of docs/theory.md): E_p a / L for the area a each
  // kept point stands for.
  const double lengthScale = isStatic ? bodyDn(a) : std::min(bodyDn(a), bodyDn(m.key.second));
  const double modulus = std::min(ma.penaltyModulus, mb.penaltyModulus);
  const auto samplePosition = [&](BodyId owner, std::uint32_t sample) {
    const ShapeModel& shape = *shapes_[bodyShape_[owner]];
    if (sample >= shape.samples->size()) return Vec3(Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
    return Vec3(bodies_.toWorld(owner, bodyScale_[owner] * shape.samples->positions()[sample]));
  };
  for (const auto& patch : m.patches) {
    contact::ContactConstraint c;
    c.bodyA = solverIndex_[a];
    c.bodyB = isStatic ? 0 : solverIndex_[m.key.second];
    c.friction = std::min(ma.frictionStatic, mb.frictionStatic);
    c.frictionDynamic = std::min(ma.frictionDynamic, mb.frictionDynamic);
    c.restitution = std::min(ma.restitution, mb.restitution);
    c.count = patch.count;
    c.dampingRatio = cs.dampingRatio;
    c.first = static_cast<std::uint32_t>(pointAt);
    pointAt += static_cast<std::size_t>(patch.count);
    const std::span<contact::ConstraintPoint> points = constraints_.pointsOf(c);
    for (int k = 0; k < patch.count; ++k) {
      contact::ConstraintPoint& p = points[static_cast<std::size_t>(k)];
      p.key = patch.keys[k];
      p.normal = patch.normals[k];
      contact::tangentBasis(p.normal, p.tangent1, p.tangent2);
      p.rA = patch.points[k] - xA;
      p.rB = isStatic ? Vec3::Zero() : Vec3(patch.points[k] - bodies_.position(m.key.second));
      p.baseSeparation = -patch.depths[k] - p.normal.dot(p.rA - p.rB);
      p.stiffness = modulus * patch.areas[k] / lengthScale;
      const contact::PointHistory* old = detail::findHistory(previous, p.key);
      if (old == nullptr && previous != nullptr) {
        // A point new to the reduction takes over the nearest point of the previous step's
        // (within 0.15 Dn, one and a half sample spacings at the default): its impulses are not
        // lost when the reduction picks a neighbouring sample.
        old = nearestPreviousPoint(m.key, *previous, patch.points[k], 0.15 * lengthScale, samplePosition);
      }
      if (old != nullptr) {
        p.normalImpulse = old->normalImpulse;
        p.tangentImpulse[0] = old->tangentImpulse.dot(p.tangent1);
        p.tangentImpulse[1] = old->tangentImpulse.dot(p.tangent2);
        p.sliding = old->sliding;
        if (cs.frictionAnchors) {
          p.slip[0] = old->stretch.dot(p.tangent1); // the part in the new tangent plane
          p.slip[1] = old->stretch.dot(p.tangent2);
        }
        ++warmStarted;
      }
    }
    contact::prepareConstraint(c, points, solverBodies_, h);
    constraints_.patches[patchAt] = c;
    constraintPair_[patchAt] = pairIndex;
    ++patchAt;
  }
  return warmStarted;
}

void World::storeConstraintResults(const std::vector<PairManifold>& manifolds, double h) {
  const auto nBodies = static_cast<std::uint32_t>(bodies_.size());
  stats_ = {};
  stats_.candidatePairs = manifolds.size();
  countSampleLists(stepLists_);
  contactEnergy_ = 0.0; // the soft constraints' elastic energy is not tracked (docs/theory.md)
  patches_.clear();
  traced_.clear();
  contactCount_.assign(nBodies, 0);
  maxContactForce_.assign(nBodies, 0.0);
  for (const auto& m : manifolds) {
    stats_.maxOverlap = std::max(stats_.maxOverlap, m.maxOverlap);
  }
  stats_.warmStarted = warmStarted_;
  stats_.reusedPairs = reusedPairs_;
  auto forces = bodies_.forces();
  auto torques = bodies_.torques();
  PairHistories next;
  std::size_t c = 0;
  while (c < constraints_.patches.size()) {
    const std::uint32_t pairIndex = constraintPair_[c];
    const contact::BodyPair key = manifolds[pairIndex].key;
    const BodyId a = key.first;
    const bool isStatic = (key.second & kStaticBits) != 0;
    History history;
    ContactPatch record;
    record.bodyA = a;
    record.bodyB = isStatic ? -1 : static_cast<std::int64_t>(key.second);
    Vec3 weighted = Vec3::Zero();
    const bool traced = tracesPair(key);
    for (; c < constraints_.patches.size() && constraintPair_[c] == pairIndex; ++c) {
      const contact::ContactConstraint& k = constraints_.patches[c];
      for (const contact::ConstraintPoint& p : constraints_.pointsOf(k)) {
        contact::PointHistory ph;
        ph.sliding = p.slides;
        // The friction anchor's slip (ContactSolver.hpp), in the checkpoint's contact_stretch.
        if (settings_.constraint.frictionAnchors) ph.stretch = contact::slipAtEnd(k, p, solverBodies_);
        ph.normalImpulse = p.normalImpulse;
        ph.tangentImpulse = p.tangentImpulse[0] * p.tangent1 + p.tangentImpulse[1] * p.tangent2;
        history.emplace_back(p.key, ph);
        // Mean force over the last substep on A (B gets minus it).
        const Vec3 force = (p.normalImpulse * p.normal + ph.tangentImpulse) / h;
        const Vec3 point = bodies_.position(a) + p.rA;
        forces[a] += force;
        torques[a] += p.rA.cross(force);
        if (!isStatic) {
          forces[key.second] -= force;
          torques[key.second] -= (point - bodies_.position(key.second)).cross(force);
        }
        const double fn = p.normalImpulse / h;
        if (traced) traceContact(key, point, force, fn);
        record.force += force;
        record.normalForce += fn;
        weighted += fn * point;
        ++record.points;
        maxContactForce_[a] = std::max(maxContactForce_[a], force.norm());
        if (!isStatic) maxContactForce_[key.second] = std::max(maxContactForce_[key.second], force.norm());
      }
    }
    contactCount_[a] += record.points;
    if (!isStatic) contactCount_[key.second] += record.points;
    stats_.contactPoints += static_cast<std::size_t>(record.points);
    if (settings_.recordContacts && record.points > 0) {
      record.point = record.normalForce > 0.0 ? Vec3(weighted / record.normalForce) : bodies_.position(a);
      patches_.push_back(record);
    }
    std::sort(history.begin(), history.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    next.emplace_back(key, std::move(history));
  }
  keepSleepingHistory(next);
}

void World::stepConstraint() {
  const double dt = timeStep();
  const int substeps = std::max(1, settings_.constraint.substeps);
  const double h = dt / substeps;
  auto clock = StepProfile::Clock::now();
  // The external loads of the step's start state, held over its substeps.
  bodies_.clearForces();
  applyLoadStages(time_);
  const double powerBefore = externalPower();
  clock = profile_.add(Stage::Loads, clock);
  updateBoxes();
  clock = profile_.add(Stage::Boxes, clock);
  std::vector<PairManifold>& manifolds = stepManifolds_;
  collideConstraint(manifolds);
  clock = profile_.add(Stage::NarrowPhase, clock);

  const auto n = bodies_.size();
  stepStartPosition_.resize(n);
  stepStartOrientation_.resize(n);
  solverIndex_.assign(n, 0);
  const auto awake = bodies_.awakeBodies();
  solverBodies_.assign(awake.size() + 1, contact::SolverBody{});
  for (std::size_t s = 0; s < awake.size(); ++s) {
    solverIndex_[awake[s]] = static_cast<std::int32_t>(s + 1);
    stepStartPosition_[awake[s]] = bodies_.position(awake[s]);
    stepStartOrientation_[awake[s]] = bodies_.orientation(awake[s]);
  }
  syncSolverBodies(true);
  buildConstraints(manifolds, h);
  clock = profile_.add(Stage::Prepare, clock);

  contact::SolveSettings solve{settings_.constraint.pushSpeed, settings_.constraint.restitutionThreshold};
  solve.frictionAnchors = settings_.constraint.frictionAnchors;
  for (int i = 0; i < substeps; ++i) {
    dynamics::kick(bodies_, h, settings_.gravity);
    clock = profile_.add(Stage::Integrate, clock);
    syncSolverBodies(true);
    contact::warmStart(constraints_, solverBodies_);
    contact::solveContacts(constraints_, solverBodies_, h, solve, true);
    writeSolverVelocities();
    clock = profile_.add(Stage::Solve, clock);
    dynamics::drift(bodies_, h);
    clock = profile_.add(Stage::Integrate, clock);
    syncSolverBodies(true);
    contact::solveContacts(constraints_, solverBodies_, h, solve, false);
    writeSolverVelocities();
    clock = profile_.add(Stage::Solve, clock);
  }
  syncSolverBodies(false);
  contact::applyRestitution(constraints_, solverBodies_, solve);
  writeSolverVelocities();
  storeConstraintResults(manifolds, h);
  clock = profile_.add(Stage::Solve, clock);
  externalWork_ += 0.5 * dt * (powerBefore + externalPower());
  time_ += dt;
  ++steps_;
  forcesReady_ = false;
  finishStep(dt, clock);
}

} // namespace armour::simulation
