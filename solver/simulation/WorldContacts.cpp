// SPDX-License-Identifier: GPL-3.0-or-later
// The contact stages of a force evaluation (World::computeForces): boxes -> broad phase ->
// narrow phase -> contact law (parallel over candidate pairs, each pair writing its own PairWork)
// -> accumulate (serial, in pair order, so any thread count gives the same bits), with the guard
// rails on overlap and tunnelling; then the external-load stages (WorldLoads.cpp).
#include "simulation/World.hpp"

#include "contact/FdemPotential.hpp"
#include "simulation/WorldInternal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace armour::simulation {

using detail::kConvexBit;
using detail::kPlaneBit;
using detail::kStaticBits;
using detail::findHistory;
using detail::StaticTarget;
using detail::staticTarget;

/// What one candidate pair produces in the force stage: written by one thread, read serially.
struct World::PairWork {
  contact::BodyPair key;
  Vec3 forceA = Vec3::Zero(), torqueA = Vec3::Zero();
  Vec3 forceB = Vec3::Zero(), torqueB = Vec3::Zero();
  History history;
  double maxPointForce = 0.0;
  double maxOverlap = 0.0;
  double elasticEnergy = 0.0; ///< J
  Vec3 weightedPoint = Vec3::Zero(); ///< sum of normal force x point (N m)
  Vec3 pointSum = Vec3::Zero();      ///< sum of the points (m)
  double normalForce = 0.0;          ///< sum of normal forces (N)
  /// Point forces on A (point, force, normal force) when the pair is traced (World::setTracedBodies).
  struct Traced {
    Vec3 point, force;
    double normalForce;
  };
  std::vector<Traced> traced;
  /// fdem, body pairs: median depth at which the potential of the pair's surface elements peaks
  /// (m); the overlap guard stops the run at 0.8 of it (infinite for static geometry: its depth
  /// never fades).
  double fdemReach = std::numeric_limits<double>::infinity();
};

contact::ContactParameters World::pairParameters(MaterialId a, MaterialId b, double lengthScale) const {
  const Material& ma = materials_[a];
  const Material& mb = materials_[b];
  contact::ContactParameters p;
  p.penaltyModulus = std::min(ma.penaltyModulus, mb.penaltyModulus);
  p.lengthScale = lengthScale;
  p.frictionStatic = std::min(ma.frictionStatic, mb.frictionStatic);
  p.frictionDynamic = std::min(ma.frictionDynamic, mb.frictionDynamic);
  // The smaller restitution: the larger damping ratio at every exponent.
  for (int i = 0; i < contact::DampingByExponent::kCount; ++i) {
    p.dampingByExponent.zeta[i] = std::max(materialDamping_[a].zeta[i], materialDamping_[b].zeta[i]);
  }
  p.dampingRatio = p.dampingByExponent.zeta[0];
  p.tangentialStiffnessRatio = std::min(ma.tangentialStiffnessRatio, mb.tangentialStiffnessRatio);
  return p;
}

const World::History* World::findPairHistory(const contact::BodyPair& key) const {
  const auto it = std::lower_bound(history_.begin(), history_.end(), key,
                                   [](const auto& e, const contact::BodyPair& k) { return e.first < k; });
  return it != history_.end() && it->first == key ? &it->second : nullptr;
}

contact::ContactShape World::contactShape(BodyId b) const {
  const ShapeModel& shape = *shapes_[bodyShape_[b]];
  return {shape.levelSet.get(), shape.samples.get(), &shape.buckets, shape.radius};
}

contact::ContactPose World::contactPose(BodyId b) const {
  contact::ContactPose p;
  p.position = bodies_.position(b);
  p.orientation = bodies_.orientation(b);
  p.rotation = p.orientation.toRotationMatrix();
  p.scale = bodyScale_[b];
  p.dn = bodyDn(b);
  return p;
}

void World::updateBoxes() {
  const std::size_t n = bodies_.size();
  const auto boxOf = [&](BodyId b) {
    const ShapeModel& shape = *shapes_[bodyShape_[b]];
    const double s = bodyScale_[b];
    const geometry::Box3 local = shape.levelSet->meshBounds();
    const geometry::Mat3 R = bodies_.orientation(b).toRotationMatrix();
    const Vec3 centre = bodies_.position(b) + R * (s * local.centre());
    const Vec3 half = R.cwiseAbs() * (0.5 * s * local.size()) + Vec3::Constant(settings_.boxMarginPerDn * bodyDn(b));
    boxes_[b].min = centre - half;
    boxes_[b].max = centre + half;
  };
  if (!boxesValid_ || boxes_.size() != n + convex_.size()) {
    // Everything: bodies first, then the static convex pieces (never active: they pair only
    // with awake bodies).
    boxes_.resize(n + convex_.size());
    active_.resize(n + convex_.size());
    for (std::size_t k = 0; k < convex_.size(); ++k) {
      boxes_[n + k] = convex_[k].box;
      active_[n + k] = 0;
    }
    for (BodyId b = 0; b < n; ++b) {
      boxOf(b);
      active_[b] = bodies_.isAwake(b) ? 1 : 0;
    }
    boxesValid_ = true;
    broadPhase_.invalidate();
    return;
  }
  // Only awake bodies move: a body's box stays valid while it is static or asleep (it fell
  // asleep at the position its box was last computed for).
  for (BodyId b = 0; b < n; ++b) {
    active_[b] = bodies_.isAwake(b) ? 1 : 0;
  }
  for (BodyId b : bodies_.awakeBodies()) {
    boxOf(b);
  }
}

double World::pairEffectiveMass(BodyId a, std::int64_t b, const contact::PatchSums& patch) const {
  double inverse = bodies_.inverseMass(a) + (b >= 0 ? bodies_.inverseMass(static_cast<BodyId>(b)) : 0.0);
  if (patch.weight > 0.0 && patch.normal.norm() >= 0.5 * patch.weight) {
    const Vec3 n = patch.normal.normalized();
    const Vec3 c = patch.centre / patch.weight;
    const Vec3 ra = (c - bodies_.position(a)).cross(n);
    inverse += ra.dot(bodies_.inverseInertiaWorld(a) * ra);
    if (b >= 0) {
      const auto bb = static_cast<BodyId>(b);
      const Vec3 rb = (c - bodies_.position(bb)).cross(n);
      inverse += rb.dot(bodies_.inverseInertiaWorld(bb) * rb);
    }
  }
  return inverse > 0.0 ? 1.0 / inverse : 0.0;
}

void World::fdemPairForces(PairWork& pw, double dt) const {
  // The potential gives the elastic force of each element pair (or contactor face against static
  // geometry) with its stiffness k and mean depth d = |F| / k; the pair then goes through the same
  // law as a sample point (ContactLaw: dashpot, friction spring with history per element pair), so
  // the two models differ only in where the normal force comes from.
  const BodyId a = pw.key.first;
  const bool isStatic = (pw.key.second & kStaticBits) != 0;
  const History* previous = findPairHistory(pw.key);
  const ShapeModel& shapeA = *shapes_[bodyShape_[a]];
  contact::FdemPose pa;
  pa.rotation = bodies_.orientation(a).toRotationMatrix();
  pa.position = bodies_.position(a);
  pa.scale = bodyScale_[a];
  double lengthScale = bodyDn(a);
  contact::ContactParameters params;
  std::vector<contact::FdemContact> records;
  BodyId b = a;
  if (isStatic) {
    const bool isPlane = (pw.key.second & kPlaneBit) != 0;
    const std::uint32_t index = pw.key.second & ~kStaticBits;
    const StaticTarget target = staticTarget(planes_, convex_, isPlane, index, boxes_[a]);
    const std::span<const Vec3> normals = target.normals;
    const std::span<const double> offsets = target.offsets();
    const MaterialId staticMaterial = target.material;
    const geometry::Box3& region = target.region;
    params = pairParameters(bodyMaterial_[a], staticMaterial, lengthScale);
    // The static solid has no potential of its own: A's surface takes the whole E_p d / L.
    pw.maxOverlap = contact::fdemHalfSpaces(*shapeA.fdem, pa, normals, offsets, region,
                                            params.penaltyModulus / lengthScale, records);
  } else {
    b = pw.key.second;
    const ShapeModel& shapeB = *shapes_[bodyShape_[b]];
    contact::FdemPose pb;
    pb.rotation = bodies_.orientation(b).toRotationMatrix();
    pb.position = bodies_.position(b);
    pb.scale = bodyScale_[b];
    lengthScale = std::min(lengthScale, bodyDn(b));
    // Static geometry's potential is its exact depth and never fades; two bodies' element
    // potentials peak at their surface elements' centroids.
    pw.fdemReach = std::min(shapeA.fdem->reach() * pa.scale, shapeB.fdem->reach() * pb.scale);
    params = pairParameters(bodyMaterial_[a], bodyMaterial_[b], lengthScale);
    // Each body's potential carries half: E_p / (2 L) per body, E_p d / L for a flat overlap.
    pw.maxOverlap = contact::fdemBodyPair(*shapeA.fdem, pa, *shapeB.fdem, pb,
                                          0.5 * params.penaltyModulus / lengthScale, records);
  }
  if (records.empty()) {
    return;
  }
  contact::PatchSums patch;
  for (const auto& r : records) {
    patch.stiffness += r.stiffness;
    if (r.stiffness > 0.0 && r.depth > 0.0) {
      patch.addEngaged(r.stiffness, r.depth, r.energy, r.point, r.normal);
    }
  }
  // The damping ratio for how the contact stiffens with its overlap (a face, an edge, a corner),
  // and the effective mass at the contact, for an off-centre impact as for a central one.
  params.dampingRatio = params.dampingByExponent.at(patch.exponent());
  const double effectiveMass = pairEffectiveMass(a, isStatic ? -1 : static_cast<std::int64_t>(b), patch);
  const double beta = contact::dampingTime(params, effectiveMass, patch.stiffness, dashpotStep(dt));
  const Vec3& xA = pa.position;
  const Vec3& xB = bodies_.position(b);
  pw.history.reserve(records.size());
  const bool traced = tracesPair(pw.key);
  for (const auto& r : records) {
    // The elastic force splits into its part along the contact normal, which goes through the law
    // with the dashpot and the friction cap, and the rest (the pull of a side strip along the
    // surface), applied as it is: the sum stays the potential's exact, conservative force.
    const double elastic = r.force.dot(r.normal);
    const Vec3 elasticRest = r.force - elastic * r.normal;
    if (traced) pw.traced.push_back({r.point, r.force, std::max(elastic, 0.0)});
    if (!(elastic > 0.0) || !(r.stiffness > 0.0)) {
      pw.forceA += r.force;
      pw.torqueA += r.torque;
      if (!isStatic) {
        pw.forceB -= r.force;
        pw.torqueB -= r.torque + (xA - xB).cross(r.force);
      }
      pw.elasticEnergy += r.energy;
      continue;
    }
    // Key: the contactor face (static), or the element pair (16 bits each; World::addShape checks).
    const std::uint32_t key = isStatic ? r.contactor : ((r.contactor << 16) | r.target);
    const Vec3& n = r.normal;
    Vec3 vRel = bodies_.velocityAtPoint(a, r.point);
    if (!isStatic) {
      vRel -= bodies_.velocityAtPoint(b, r.point);
    }
    // The area that gives k = E_p a / L in the law: k d = the normal elastic force.
    const double area = r.stiffness * lengthScale / params.penaltyModulus;
    const contact::PointHistory* prev = findHistory(previous, key);
    const contact::PointForce f = contact::evaluatePointContact(params, {n, r.depth, area, vRel},
                                                                prev ? *prev : contact::PointHistory{}, beta, dt);
    const Vec3 total = f.force + elasticRest;
    // The elastic part keeps its exact torque (the potential's, conservative); the dashpot and
    // friction act at the traction centre.
    const Vec3 extra = total - r.force;
    if (traced) pw.traced.back() = {r.point, total, f.normalForce};
    pw.maxPointForce = std::max(pw.maxPointForce, total.norm());
    pw.weightedPoint += f.normalForce * r.point;
    pw.pointSum += r.point;
    pw.normalForce += f.normalForce;
    const double k = r.stiffness;
    const double kt = params.tangentialStiffnessRatio * k;
    const double holdable = kt > 0.0 ? params.frictionStatic * elastic / kt : 0.0;
    const double stretch = std::min(f.history.stretch.norm(), holdable);
    pw.elasticEnergy += r.energy + 0.5 * kt * stretch * stretch;
    pw.forceA += total;
    pw.torqueA += r.torque + (r.point - xA).cross(extra);
    if (!isStatic) {
      pw.forceB -= total;
      pw.torqueB -= r.torque + (xA - xB).cross(r.force) + (r.point - xB).cross(extra);
    }
    pw.history.emplace_back(key, f.history);
  }
  std::sort(pw.history.begin(), pw.history.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
}

void World::candidatePairs(std::vector<contact::BodyPair>& out) {
  broadPhase_.findPairs(boxes_, active_, pairs_);
  const auto nBodies = static_cast<std::uint32_t>(bodies_.size());
  out.clear();
  out.reserve(pairs_.size() + nBodies);
  for (const auto& p : pairs_) {
    out.push_back(p.second < nBodies ? p : contact::BodyPair{p.first, kConvexBit | (p.second - nBodies)});
  }
  for (BodyId b = 0; b < nBodies; ++b) {
    if (!active_[b]) {
      continue;
    }
    for (std::uint32_t k = 0; k < planes_.size(); ++k) {
      const auto& pl = planes_[k];
      // Lowest corner of the box along the normal.
      const Vec3 lowest(pl.normal.x() >= 0 ? boxes_[b].min.x() : boxes_[b].max.x(),
                        pl.normal.y() >= 0 ? boxes_[b].min.y() : boxes_[b].max.y(),
                        pl.normal.z() >= 0 ? boxes_[b].min.z() : boxes_[b].max.z());
      if ((lowest - pl.point).dot(pl.normal) < 0.0) {
        out.push_back({b, kPlaneBit | k});
      }
    }
  }
}

void World::clearSampleLists() {
  sampleLists_.clear();
  sampleWalk_.clear();
}

std::vector<contact::PairSampleCache*> World::sampleListsFor(const std::vector<contact::BodyPair>& keys) {
  std::vector<contact::PairSampleCache*> lists(keys.size(), nullptr);
  if (settings_.sampleListSlackPerDn <= 0.0 || settings_.contactModel != ContactModel::LevelSet) {
    clearSampleLists();
    return lists;
  }
  const std::uint64_t step = steps_ + 1; // never 0, the stamp of a new entry
  // The last step's entries by a walk (CacheWalk), the others by the hash; next step's walk.
  sampleWalk_.cursor = 0;
  CacheWalk<CachedSamples> next;
  next.keys.reserve(sampleWalk_.keys.size() + 16);
  next.entries.reserve(sampleWalk_.keys.size() + 16);
  for (std::size_t w = 0; w < keys.size(); ++w) {
    if ((keys[w].second & kStaticBits) != 0) continue;
    const std::uint64_t id = (std::uint64_t{keys[w].first} << 32) | keys[w].second;
    CachedSamples* walked = sampleWalk_.find(id);
    CachedSamples& entry = walked != nullptr ? *walked : sampleLists_[id];
    entry.step = step;
    for (contact::NearSampleList& direction : entry.cache.directions) direction.searches = direction.reuses = direction.listed = direction.lookups = 0;
    lists[w] = &entry.cache;
    next.keys.push_back(id);
    next.entries.push_back(&entry);
  }
  if (sampleLists_.size() > lists.size()) {
    std::erase_if(sampleLists_, [step](const auto& item) { return item.second.step != step; });
  }
  sampleWalk_ = std::move(next);
  return lists;
}

void World::countSampleLists(const std::vector<contact::PairSampleCache*>& lists) {
  for (const contact::PairSampleCache* list : lists) {
    if (list == nullptr) continue;
    for (const contact::NearSampleList& direction : list->directions) {
      stats_.sampleSearches += direction.searches;
      stats_.sampleListReuses += direction.reuses;
      stats_.sampleListListed += direction.listed;
      stats_.sampleListLookups += direction.lookups;
    }
  }
}

void World::computeForces(double dt, double stateTime) {
  auto clock = StepProfile::Clock::now();
  bodies_.clearForces();
  updateBoxes();
  clock = profile_.add(Stage::Boxes, clock);
  std::vector<contact::BodyPair> keys;
  candidatePairs(keys);
  const std::vector<contact::PairSampleCache*> lists = sampleListsFor(keys);
  clock = profile_.add(Stage::BroadPhase, clock);
  const auto nBodies = static_cast<std::uint32_t>(bodies_.size());
  std::vector<PairWork> work(keys.size());
  for (std::size_t w = 0; w < keys.size(); ++w) {
    work[w].key = keys[w];
  }

  // One pair can cost as much as a hundred (a concave unit on another versus a body on one
  // height-field cell): pairs are handed out one at a time.
#pragma omp parallel for schedule(dynamic, 1) if (work.size() >= 16)
  for (std::size_t w = 0; w < work.size(); ++w) {
    PairWork& pw = work[w];
    if (settings_.contactModel == ContactModel::Fdem) {
      fdemPairForces(pw, dt);
      continue;
    }
    const BodyId a = pw.key.first;
    const bool plane = (pw.key.second & kStaticBits) != 0; // any static geometry: plane or convex piece
    const History* previous = findPairHistory(pw.key);
    // One buffer per thread, kept from pair to pair and step to step (no allocation per pair).
    thread_local std::vector<contact::ContactPoint> engaged;
    engaged.clear();
    const Vec3& xA = bodies_.position(a);
    double lengthScale = bodyDn(a);
    contact::ContactParameters params;
    if (plane) {
      const bool isPlane = (pw.key.second & kPlaneBit) != 0;
      const StaticTarget target = staticTarget(planes_, convex_, isPlane, pw.key.second & ~kStaticBits, boxes_[a]);
      const contact::HalfSpaces solid{target.normals, target.offsets(), target.region};
      pw.maxOverlap = contact::samplesInHalfSpaces(contactShape(a), contactPose(a), solid, 0.0, engaged);
      params = pairParameters(bodyMaterial_[a], target.material, lengthScale);
    } else {
      const BodyId b = pw.key.second;
      lengthScale = std::min(lengthScale, bodyDn(b));
      pw.maxOverlap = contact::samplesInLevelSets(contactShape(a), contactPose(a), contactShape(b), contactPose(b), 0.0,
                                                  engaged, lists[w], sampleListSlack(a, b));
      params = pairParameters(bodyMaterial_[a], bodyMaterial_[b], lengthScale);
    }
    if (engaged.empty()) {
      continue;
    }
    contact::PatchSums patch;
    for (const auto& e : engaged) {
      const double k = contact::pointStiffness(params, e.area);
      const double d = std::max(e.depth, 0.0);
      patch.stiffness += k;
      patch.addEngaged(k, d, 0.5 * k * d * d, e.point, e.normal);
    }
    // The damping ratio for how the contact stiffens with its overlap (a face, an edge, a corner),
    // and the effective mass at the contact, for an off-centre impact as for a central one.
    params.dampingRatio = params.dampingByExponent.at(patch.exponent());
    const double effectiveMass = pairEffectiveMass(a, plane ? -1 : static_cast<std::int64_t>(pw.key.second), patch);
    const double beta = contact::dampingTime(params, effectiveMass, patch.stiffness, dashpotStep(dt));
    const BodyId b = plane ? a : pw.key.second;
    const Vec3& xB = bodies_.position(b);
    const bool traced = tracesPair(pw.key);
    pw.history.reserve(engaged.size());
    for (const auto& e : engaged) {
      // For B's samples (reverse bit) the normal was flipped to push A: the law always sees A
      // as the pushed body, so history and forces stay in one convention.
      Vec3 vRel = bodies_.velocityAtPoint(a, e.point);
      if (!plane) {
        vRel -= bodies_.velocityAtPoint(b, e.point);
      }
      const contact::PointHistory* prev = findHistory(previous, e.key);
      const contact::PointForce f = contact::evaluatePointContact(params, {e.normal, e.depth, e.area, vRel},
                                                                  prev ? *prev : contact::PointHistory{}, beta, dt);
      pw.maxPointForce = std::max(pw.maxPointForce, f.force.norm());
      pw.weightedPoint += f.normalForce * e.point;
      pw.pointSum += e.point;
      pw.normalForce += f.normalForce;
      // Elastic energy: the normal spring, and the friction spring up to the stretch its elastic
      // normal force can hold (after an impact the stored stretch carries the dashpot's share of
      // the cap too, which the spring can never give back).
      const double k = contact::pointStiffness(params, e.area);
      const double kt = params.tangentialStiffnessRatio * k;
      const double holdable = kt > 0.0 ? params.frictionStatic * k * e.depth / kt : 0.0;
      const double stretch = std::min(f.history.stretch.norm(), holdable);
      pw.elasticEnergy += 0.5 * (k * e.depth * e.depth + kt * stretch * stretch);
      pw.forceA += f.force;
      pw.torqueA += (e.point - xA).cross(f.force);
      if (traced) pw.traced.push_back({e.point, f.force, f.normalForce});
      if (!plane) {
        pw.forceB -= f.force;
        pw.torqueB -= (e.point - xB).cross(f.force);
      }
      pw.history.emplace_back(e.key, f.history);
    }
    std::sort(pw.history.begin(), pw.history.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  }

  clock = profile_.add(Stage::NarrowPhase, clock);

  // Serial, ordered accumulation: bit-identical for any thread count.
  stats_ = {};
  stats_.candidatePairs = work.size();
  countSampleLists(lists);
  contactEnergy_ = 0.0;
  patches_.clear();
  contactCount_.assign(nBodies, 0);
  maxContactForce_.assign(nBodies, 0.0);
  traced_.clear();
  PairHistories nextHistory;
  nextHistory.reserve(history_.size() + 16);
  for (auto& pw : work) {
    if (pw.history.empty() && pw.maxOverlap == 0.0) {
      continue;
    }
    const BodyId a = pw.key.first;
    auto forces = bodies_.forces();
    auto torques = bodies_.torques();
    forces[a] += pw.forceA;
    torques[a] += pw.torqueA;
    const auto points = static_cast<std::int32_t>(pw.history.size());
    contactCount_[a] += points;
    maxContactForce_[a] = std::max(maxContactForce_[a], pw.maxPointForce);
    if ((pw.key.second & kStaticBits) == 0) {
      forces[pw.key.second] += pw.forceB;
      torques[pw.key.second] += pw.torqueB;
      contactCount_[pw.key.second] += points;
      maxContactForce_[pw.key.second] = std::max(maxContactForce_[pw.key.second], pw.maxPointForce);
    }
    stats_.contactPoints += pw.history.size();
    contactEnergy_ += pw.elasticEnergy;
    for (const auto& t : pw.traced) traceContact(pw.key, t.point, t.force, t.normalForce);
    if (settings_.recordContacts && points > 0) recordPatch(pw, points);
    stats_.maxOverlap = std::max(stats_.maxOverlap, pw.maxOverlap);
    guardOverlap(pw.key, pw.maxOverlap, pw.fdemReach);
    if (!pw.history.empty()) {
      nextHistory.emplace_back(pw.key, std::move(pw.history));
    }
  }
  keepSleepingHistory(nextHistory);
  clock = profile_.add(Stage::Accumulate, clock);
  applyLoadStages(stateTime);
  profile_.add(Stage::Loads, clock);
}

void World::recordPatch(const PairWork& pw, std::int32_t points) {
  ContactPatch patch;
  patch.bodyA = pw.key.first;
  patch.bodyB = (pw.key.second & kStaticBits) == 0 ? static_cast<std::int64_t>(pw.key.second) : -1;
  patch.force = pw.forceA;
  patch.normalForce = pw.normalForce;
  patch.points = points;
  // A patch held only by friction and damping can have no normal force: plain mean then.
  patch.point = pw.normalForce > 0.0 ? Vec3(pw.weightedPoint / pw.normalForce) : Vec3(pw.pointSum / points);
  patches_.push_back(patch);
}

void World::setTracedBodies(const std::vector<BodyId>& bodies) {
  isTraced_.assign(bodies_.size(), 0);
  for (BodyId b : bodies) {
    if (b >= bodies_.size()) throw std::out_of_range(fmt::format("setTracedBodies: no body {}", b));
    isTraced_[b] = 1;
  }
  if (bodies.empty()) isTraced_.clear();
  traced_.clear();
}

bool World::tracesPair(const contact::BodyPair& key) const {
  if (isTraced_.empty()) return false;
  if (key.first < isTraced_.size() && isTraced_[key.first] != 0) return true;
  return (key.second & kStaticBits) == 0 && key.second < isTraced_.size() && isTraced_[key.second] != 0;
}

void World::traceContact(const contact::BodyPair& key, const Vec3& point, const Vec3& forceOnA, double normalForce) {
  const bool bodyPair = (key.second & kStaticBits) == 0;
  if (key.first < isTraced_.size() && isTraced_[key.first] != 0) {
    traced_.push_back({key.first, bodyPair ? static_cast<std::int64_t>(key.second) : -1, point, forceOnA, normalForce});
  }
  if (bodyPair && key.second < isTraced_.size() && isTraced_[key.second] != 0) {
    traced_.push_back({key.second, static_cast<std::int64_t>(key.first), point, -forceOnA, normalForce});
  }
}

void World::keepSleepingHistory(PairHistories& nextHistory) {
  // Pairs that were not examined because none of their bodies is awake keep their friction
  // springs: a sleeping pack wakes with the same contact state it fell asleep with.
  for (auto& [key, h] : history_) {
    const bool bodyPair = (key.second & kStaticBits) == 0;
    if (!bodies_.isAwake(key.first) && (!bodyPair || !bodies_.isAwake(key.second))) {
      nextHistory.emplace_back(key, std::move(h));
    }
  }
  // Sorted by pair, for the binary search of the next step (keys are unique: a pair is either
  // examined or kept).
  std::sort(nextHistory.begin(), nextHistory.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  history_ = std::move(nextHistory);
}


void World::guardOverlap(const contact::BodyPair& key, double maxOverlap, double fdemReach) const {
  const BodyId a = key.first;
  // Guard rails: an overlap this deep means the contact cannot hold (time step, stiffness or
  // speed), and the forces that follow are meaningless; past the middle of a thin part the
  // push would even turn and carry the body through (tunnelling).
  const BodyId other = key.second & ~kStaticBits;
  double dn = bodyDn(a);
  double inner = shapes_[bodyShape_[a]]->innerDepth * bodyScale_[a];
  if ((key.second & kStaticBits) == 0) {
    dn = std::min(dn, bodyDn(other));
    inner = std::min(inner, shapes_[bodyShape_[other]]->innerDepth * bodyScale_[other]);
  } else if ((key.second & kPlaneBit) == 0) {
    inner = std::min(inner, convex_[other].innerDepth);
  }
  // The other's name, only for a message (this runs for every candidate pair at every step).
  const auto otherName = [&]() -> std::string {
    if ((key.second & kStaticBits) == 0) return bodies_.describe(other);
    if ((key.second & kPlaneBit) != 0) return "plane '" + planes_[other].name + "'";
    return "static piece '" + convex_[other].name + "'";
  };
  const double overlapLimit = settings_.maxOverlapPerDn * dn;
  const double tunnelLimit = settings_.maxOverlapPerInnerDepth * inner;
  // fdem: the element potentials peak at the surface elements' centroids (median depth
  // fdemReach); past it a growing share of the engaged elements pushes less the deeper they go.
  constexpr double kFdemReachFraction = 0.8;
  if (maxOverlap > kFdemReachFraction * fdemReach) {
    throw SimulationError(fmt::format(
        "t = {:.6g} s: {} and {} overlap by {:.4g} m, {} x the median depth {:.4g} m at which the fdem potential "
        "of their surface elements peaks: deeper, the push fades; raise the penalty modulus, lower the speed, or "
        "use fewer, larger contact elements (contact.fdem.elements_per_unit)",
        time_, bodies_.describe(a), otherName(), maxOverlap, kFdemReachFraction, fdemReach));
  }
  if (maxOverlap > std::min(overlapLimit, tunnelLimit)) {
    if (tunnelLimit < overlapLimit) {
      throw SimulationError(fmt::format(
          "t = {:.6g} s: {} and {} overlap by {:.4g} m, more than {} x the inner depth {:.4g} m of the thinner "
          "part: it would pass through it (tunnel); make thin parts thicker, lower the speed, or raise the "
          "penalty modulus",
          time_, bodies_.describe(a), otherName(), maxOverlap, settings_.maxOverlapPerInnerDepth, inner));
    }
    throw SimulationError(fmt::format(
        "t = {:.6g} s: {} and {} overlap by {:.4g} m, more than {} x Dn = {:.4g} m; the contact cannot hold: "
        "lower the time step, raise the penalty modulus, or check the initial positions",
        time_, bodies_.describe(a), otherName(), maxOverlap, settings_.maxOverlapPerDn, overlapLimit));
  }
}

} // namespace armour::simulation
