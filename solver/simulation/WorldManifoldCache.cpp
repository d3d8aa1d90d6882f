// SPDX-License-Identifier: GPL-3.0-or-later
// Manifold reuse of the constraint solver (contact.constraint.reuse_distance; docs/theory.md,
// "Manifold reuse"): a pair that has hardly moved against its partner since its last full narrow
// phase keeps that narrow phase's reduced patches, carried to the current poses, instead of
// querying its samples again. The same idea as Jolt's body-pair cache; our own code. The cache is
// part of the World's state (captureState / restoreState), so restarts stay bit-identical.
#include "simulation/World.hpp"

#include "core/Error.hpp"
#include "simulation/WorldInternal.hpp"

#include <algorithm>
#include <cmath>

namespace armour::simulation {

using detail::kStaticBits;

namespace {

/// Layout version of the flattened cache (saveManifoldCache): 2 adds each entry's margin. A
/// layout-1 cache (session 18) is read with margin = 2 r, its reuse rule then (travel < r).
constexpr double kCacheTag = 2.0;
constexpr double kCacheTagWithoutMargin = 1.0;

} // namespace

void World::relativePose(const contact::BodyPair& key, Vec3& p, Quat& q) const {
  const BodyId a = key.first;
  if ((key.second & kStaticBits) != 0) {
    p = bodies_.position(a);
    q = bodies_.orientation(a);
    return;
  }
  const Quat qb = bodies_.orientation(key.second);
  p = qb.conjugate() * (bodies_.position(a) - bodies_.position(key.second));
  q = qb.conjugate() * bodies_.orientation(a);
}

void World::clearManifoldCache() {
  manifoldCache_.clear();
  manifoldWalk_.clear();
}

void World::findCachedManifolds(const std::vector<contact::BodyPair>& keys, std::vector<CachedManifold*>& entries) {
  entries.assign(keys.size(), nullptr);
  static_assert(detail::kPlaneBit == 0x80000000u, "manifoldWalk_'s late bit is the plane bit");
  manifoldWalk_.cursor = 0;
  for (std::size_t w = 0; w < keys.size(); ++w) {
    const std::uint64_t k = pairKey(keys[w]);
    if (CachedManifold* walked = manifoldWalk_.find(k)) {
      entries[w] = walked;
    } else if (const auto it = manifoldCache_.find(k); it != manifoldCache_.end()) {
      entries[w] = &it->second;
    }
  }
}

bool World::reuseManifold(PairManifold& m, double travel, double turnedCos, const CachedManifold& cm) const {
  const BodyId a = m.key.first;
  const double limit = settings_.constraint.reuseDistance * bodyDn(a);
  Vec3 p;
  Quat q;
  relativePose(m.key, p, q);
  // Turned by angle: a point half a Dn from the centre moves by angle Dn / 2. A sample that was
  // outside the margin then is still more than margin - r away, so it cannot touch in this step
  // while travel + r < margin.
  // angle * Dn / 2 < r Dn  <=>  |q . q_then| = cos(angle / 2) > cos(r) = turnedCos, without an acos.
  if (!((p - cm.relP).squaredNorm() < limit * limit) || !(std::abs(q.dot(cm.relQ)) > turnedCos) ||
      !(travel + limit < cm.margin)) {
    return false;
  }
  const bool isStatic = (m.key.second & kStaticBits) != 0;
  const Vec3 pb = isStatic ? Vec3::Zero() : bodies_.position(m.key.second);
  const Quat qb = isStatic ? Quat::Identity() : bodies_.orientation(m.key.second);
  const Vec3& xa = bodies_.position(a);
  const Quat& qa = bodies_.orientation(a);
  m.patches = cm.patches;
  m.maxOverlap = cm.maxOverlap;
  for (std::size_t i = 0; i < m.patches.size(); ++i) {
    contact::ContactPatchPoints& patch = m.patches[i];
    patch.normal = qb * patch.normal;
    for (int k = 0; k < patch.count; ++k) {
      // The depth moves with the relative motion of the point's two material points along B's
      // normal (linear in the motion; the reuse distance bounds what is left out).
      const Vec3 onA = xa + qa * patch.points[k];
      const Vec3 onB = pb + qb * cm.pointsB[i][static_cast<std::size_t>(k)];
      const Vec3 n = qb * patch.normals[k];
      patch.depths[k] -= n.dot(onA - onB);
      patch.points[k] = onA;
      patch.normals[k] = n;
    }
  }
  return true;
}

void World::cacheManifolds(const std::vector<PairManifold>& manifolds, const std::vector<char>& reused,
                           const std::vector<CachedManifold*>& entries) {
  // In place: a reused entry keeps the pose of its full narrow phase, a new narrow phase
  // overwrites its pair's entry (keeping its vectors' storage), and the entries of pairs that are
  // no longer candidates go.
  const std::uint64_t stamp = ++manifoldCacheStamp_; // never 0, the stamp of a restored entry
  // The walk of the next step: these keys and entries (their nodes stay where they are while
  // other entries come and go).
  manifoldWalk_.keys.resize(manifolds.size());
  manifoldWalk_.entries.assign(entries.begin(), entries.end());
  for (std::size_t w = 0; w < manifolds.size(); ++w) {
    const PairManifold& m = manifolds[w];
    manifoldWalk_.keys[w] = pairKey(m.key);
    if (reused[w] != 0) {
      entries[w]->stamp = stamp;
      continue;
    }
    CachedManifold& cm = entries[w] != nullptr ? *entries[w] : manifoldCache_[pairKey(m.key)];
    manifoldWalk_.entries[w] = &cm;
    cm.stamp = stamp;
    relativePose(m.key, cm.relP, cm.relQ);
    const bool isStatic = (m.key.second & kStaticBits) != 0;
    const Vec3 pb = isStatic ? Vec3::Zero() : bodies_.position(m.key.second);
    const Quat qb = isStatic ? Quat::Identity() : bodies_.orientation(m.key.second);
    const Vec3& xa = bodies_.position(m.key.first);
    const Quat& qa = bodies_.orientation(m.key.first);
    cm.maxOverlap = m.maxOverlap;
    cm.margin = m.margin;
    cm.patches = m.patches;
    cm.pointsB.resize(m.patches.size());
    for (std::size_t i = 0; i < cm.patches.size(); ++i) {
      contact::ContactPatchPoints& patch = cm.patches[i];
      patch.normal = qb.conjugate() * patch.normal;
      for (int k = 0; k < patch.count; ++k) {
        cm.pointsB[i][static_cast<std::size_t>(k)] = qb.conjugate() * (patch.points[k] - pb);
        patch.points[k] = qa.conjugate() * (patch.points[k] - xa);
        patch.normals[k] = qb.conjugate() * patch.normals[k];
      }
    }
  }
  std::erase_if(manifoldCache_, [stamp](const auto& entry) { return entry.second.stamp != stamp; });
}

std::vector<double> World::saveManifoldCache() const {
  std::vector<double> flat;
  if (manifoldCache_.empty()) {
    return flat;
  }
  flat.push_back(kCacheTag);
  flat.push_back(static_cast<double>(manifoldCache_.size()));
  const auto vec = [&](const Vec3& v) { flat.insert(flat.end(), {v.x(), v.y(), v.z()}); };
  std::vector<std::uint64_t> keys;
  keys.reserve(manifoldCache_.size());
  for (const auto& entry : manifoldCache_) keys.push_back(entry.first);
  std::sort(keys.begin(), keys.end());
  for (const std::uint64_t key : keys) {
    const CachedManifold& cm = manifoldCache_.at(key);
    flat.push_back(static_cast<double>(key >> 32));
    flat.push_back(static_cast<double>(key & 0xffffffffu));
    vec(cm.relP);
    flat.insert(flat.end(), {cm.relQ.w(), cm.relQ.x(), cm.relQ.y(), cm.relQ.z()});
    flat.push_back(cm.maxOverlap);
    flat.push_back(cm.margin);
    flat.push_back(static_cast<double>(cm.patches.size()));
    for (std::size_t i = 0; i < cm.patches.size(); ++i) {
      const contact::ContactPatchPoints& patch = cm.patches[i];
      vec(patch.normal);
      flat.push_back(static_cast<double>(patch.count));
      for (int k = 0; k < patch.count; ++k) {
        flat.push_back(static_cast<double>(patch.keys[k]));
        vec(patch.points[k]);
        vec(cm.pointsB[i][static_cast<std::size_t>(k)]);
        vec(patch.normals[k]);
        flat.push_back(patch.depths[k]);
        flat.push_back(patch.areas[k]);
      }
    }
  }
  return flat;
}

void World::restoreManifoldCache(const std::vector<double>& flat) {
  clearManifoldCache();
  if (flat.empty()) {
    return;
  }
  std::size_t at = 0;
  const auto bad = [&](const char* what) {
    core::failInput("checkpoint", "variable 'manifold_cache' is damaged ({} at entry {} of {}): restart from an "
                                  "earlier checkpoint, or start the run again",
                    what, at, flat.size());
  };
  const auto next = [&]() {
    if (at >= flat.size()) bad("it ends early");
    if (!std::isfinite(flat[at])) bad("a value that is not finite");
    return flat[at++];
  };
  const auto count = [&](double limit) {
    const double v = next();
    if (!(v >= 0.0 && v <= limit && v == std::floor(v))) bad("a count out of range");
    return static_cast<std::size_t>(v);
  };
  const auto vec = [&]() {
    const double x = next(), y = next(), z = next();
    return Vec3(x, y, z);
  };
  const double tag = next();
  if (tag != kCacheTag && tag != kCacheTagWithoutMargin) bad("an unknown layout");
  const std::size_t pairs = count(static_cast<double>(flat.size()));
  for (std::size_t j = 0; j < pairs; ++j) {
    contact::BodyPair key;
    key.first = static_cast<std::uint32_t>(count(4294967295.0));
    key.second = static_cast<std::uint32_t>(count(4294967295.0));
    if (key.first >= bodies_.size()) bad("a body that is not in this scene");
    CachedManifold cm;
    cm.relP = vec();
    const double w = next(), x = next(), y = next(), z = next();
    cm.relQ = Quat(w, x, y, z);
    cm.maxOverlap = next();
    cm.margin = tag == kCacheTag ? next() : 2.0 * settings_.constraint.reuseDistance * bodyDn(key.first);
    const std::size_t patches = count(static_cast<double>(flat.size()));
    cm.patches.resize(patches);
    cm.pointsB.resize(patches);
    for (std::size_t i = 0; i < patches; ++i) {
      contact::ContactPatchPoints& patch = cm.patches[i];
      patch.normal = vec();
      patch.count = static_cast<int>(count(4.0));
      for (int k = 0; k < patch.count; ++k) {
        patch.keys[k] = static_cast<std::uint32_t>(count(4294967295.0));
        patch.points[k] = vec();
        cm.pointsB[i][static_cast<std::size_t>(k)] = vec();
        patch.normals[k] = vec();
        patch.depths[k] = next();
        patch.areas[k] = next();
      }
    }
    manifoldCache_.emplace(pairKey(key), std::move(cm));
  }
  if (at != flat.size()) bad("entries left over");
}

} // namespace armour::simulation
