// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/NarrowPhase.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace armour::contact {

double samplesInHalfSpaces(const ContactShape& a, const ContactPose& pa, const HalfSpaces& solid, double margin,
                           std::vector<ContactPoint>& out) {
  // A sample is inside when it is below all the faces, at the depth of the nearest face; within the
  // margin outside, the largest face distance is a lower bound of its gap (exact beside a face).
  const std::span<const Vec3> normals = solid.normals;
  const std::span<const double> offsets = solid.offsets;
  const double sA = pa.scale;
  const Quat& qA = pa.orientation;
  const Vec3& xA = pa.position;
  const Mat3& RA = pa.rotation;
  const auto& samplesA = *a.samples;
  const SampleBuckets& bk = *a.buckets;
  double maxOverlap = 0.0;
  // Near misses first: every sample lies within A's radius R of its centroid, so if that ball is
  // outside one face by more than the margin, no sample can come within it (phi >= that face's
  // distance > margin). The same result as the search, for one dot product per face: a unit
  // resting on a rock layer above a static core, whose huge box holds every unit of the trunk.
  const double ballRadius = a.radius * sA;
  for (std::size_t k = 0; k < normals.size(); ++k) {
    if (normals[k].dot(xA) - offsets[k] > ballRadius + margin) {
      return 0.0;
    }
  }
  // Visit only the buckets that reach into the region and below every face.
  const Mat3 toLocal = RA.transpose();
  const Vec3 regionCentre = toLocal * (solid.region.centre() - xA) / sA;
  const Vec3 regionHalf = toLocal.cwiseAbs() * (0.5 * solid.region.size() + Vec3::Constant(margin)) / sA;
  const Vec3 cellHalf = 0.5 * bk.cell;
  forBucketsNear(bk, regionCentre - regionHalf, regionCentre + regionHalf, [&](int cell, const Vec3& low) {
    const Vec3 worldCentre = xA + qA * (sA * (low + cellHalf));
    for (std::size_t k = 0; k < normals.size(); ++k) {
      const double reach = sA * cellHalf.dot((toLocal * normals[k]).cwiseAbs());
      if (normals[k].dot(worldCentre) - offsets[k] > reach + margin) {
        return; // the whole bucket is outside this face
      }
    }
    for (std::uint32_t j = bk.start[cell]; j < bk.start[cell + 1]; ++j) {
      const std::uint32_t i = bk.samples[j];
      const Vec3 X = xA + RA * (sA * samplesA.positions()[i]);
      double phi = -std::numeric_limits<double>::infinity();
      std::size_t nearest = 0;
      for (std::size_t k = 0; k < normals.size(); ++k) {
        const double d = normals[k].dot(X) - offsets[k];
        if (d > phi) {
          phi = d;
          nearest = k;
        }
      }
      if (phi < 0.0) {
        maxOverlap = std::max(maxOverlap, -phi); // engaged or not: the guard rails see every point inside
      }
      if (phi < margin) {
        // Projected tributary area: the pressure acts on the part of the sample's area that faces
        // the static surface, so a face pressed flat engages exactly its own area.
        const Vec3& n = normals[nearest];
        const double area = -sA * sA * (RA * samplesA.areaVectors()[i]).dot(n);
        if (area > 0.0) {
          out.push_back({i, X, n, -phi, area});
        }
      }
    }
  });
  return maxOverlap;
}

namespace {

/// Near misses first: in a rough pile most candidate pairs never touch (the boxes overlap, the
/// bodies do not: a rock under a Core-Loc's box but between its legs). A ball of radius R around a
/// body's centroid holds the body; if the other body's true distance at that centre exceeds
/// R + margin, they are apart (LevelSet::distanceLowerBound), for either body.
bool apart(const ContactShape& a, const ContactPose& pa, const ContactShape& b, const ContactPose& pb, double margin) {
  for (int dir = 0; dir < 2; ++dir) {
    const ContactPose& probe = dir == 0 ? pa : pb;
    const ContactPose& target = dir == 0 ? pb : pa;
    const ContactShape& ps = dir == 0 ? a : b;
    const ContactShape& ts = dir == 0 ? b : a;
    const double st = target.scale;
    const Vec3 centre = target.orientation.conjugate() * (probe.position - target.position) / st;
    if (ts.levelSet->distanceLowerBound(centre) > (ps.radius * probe.scale) / st + margin / st) {
      return true;
    }
  }
  return false;
}

/// How much the interpolated level-set value (LevelSet::value, inside and outside the grid) can
/// change when its argument moves by d: at most (1 + sqrt(3)) d. Inside the grid each partial
/// derivative of the trilinear interpolant is a weighted mean of node differences over h, at most 1
/// for node values that are exact distances; outside, the clamp to the grid moves no coordinate more
/// than the point and the distance to the grid box is 1-Lipschitz. With 0.01 % for the float nodes.
constexpr double kValueLipschitz = (1.0 + 1.7320508075688772) * 1.0001;

/// `value` as a float no larger than it (a listed sample's value, kept for the skip test).
float roundedDown(double value) {
  const auto f = static_cast<float>(value);
  return static_cast<double>(f) > value ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

/// One direction of a body pair: the probe's samples in the target's level set. With a list, the
/// list is used when it covers this call, and made anew (a full search with margin + slack) when not.
void probeSamples(const ContactShape& ps, const ContactPose& probe, const ContactShape& ts, const ContactPose& target,
                  double weight, std::uint32_t keyBit, bool flip, double margin, double slack, NearSampleList* list,
                  double& maxOverlap, std::vector<ContactPoint>& out) {
  const double sp = probe.scale;
  const double st = target.scale;
  const Mat3& Rp = probe.rotation;
  const Vec3& xp = probe.position;
  const Mat3& Rt = target.rotation;
  const Vec3& xt = target.position;
  const auto& samples = *ps.samples;
  const LevelSet& ls = *ts.levelSet;
  const double m = margin / st; // the margin in the target's unscaled frame
  // Probe frame (unscaled) -> target frame (unscaled): L = Rrel p + trel.
  const Mat3 Rrel = Rt.transpose() * Rp * (sp / st);
  const Vec3 trel = Rt.transpose() * (xp - xt) / st;
  // phi < m needs L within the target's mesh bounds grown by sqrt(3) h + m (LevelSet::mayPenetrate).
  const double h = ls.cellSize();
  const Vec3 grow = Vec3::Constant(std::sqrt(3.0) * h + m);
  const Vec3 targetLo = ls.meshBounds().min - grow;
  const Vec3 targetHi = ls.meshBounds().max + grow;
  const auto inBox = [](const Vec3& L, const Vec3& lo, const Vec3& hi) {
    return !((L.array() < lo.array()).any() || (L.array() > hi.array()).any());
  };
  // A sample within the margin (in the grown box, value below m): its contact point, if any.
  const auto emit = [&](std::uint32_t i, const LevelSet::Lookup& at) {
    const LevelSetQuery q = ls.query(at);
    if (q.phi < 0.0) {
      // Engaged or not, the guard rails see every point inside: past the other body's middle a
      // point faces the wrong way and is not engaged, but the overlap is real.
      maxOverlap = std::max(maxOverlap, -q.phi * st);
    }
    if (q.phi < m && q.normal.squaredNorm() > 0.0) {
      const Vec3 X = xp + Rp * (sp * samples.positions()[i]);
      const Vec3 n = Rt * q.normal; // out of the target: pushes the probe
      // The direction's weight scales the tributary area (k = E_p a / L is linear in a).
      const double area = -weight * sp * sp * (Rp * samples.areaVectors()[i]).dot(n);
      if (area > 0.0) {
        out.push_back({keyBit | i, X, flip ? Vec3(-n) : n, -q.phi * st, area});
      }
    }
  };
  const auto consider = [&](std::uint32_t i, const Vec3& L) {
    LevelSet::Lookup at;
    if (inBox(L, targetLo, targetHi) && ls.value(L, at) < m) {
      emit(i, at);
    }
  };
  if (list != nullptr && list->reach >= 0.0 && list->probe == ps.samples && list->target == ts.levelSet) {
    // How far any sample can have moved in the target frame since the list was made: the change of
    // the translation plus the change of the rotation (Frobenius norm, above the spectral one) times
    // the probe's radius; the list covers this call while its reach holds the margin plus what the
    // value can have changed over that distance.
    const double moved = (trel - list->translation).norm() + (Rrel - list->rotation).norm() * ps.radius;
    const double needed = m + kValueLipschitz * moved + 1e-6 * h;
    if (needed <= list->reach) {
      ++list->reuses;
      list->listed += static_cast<std::uint32_t>(list->samples.size());
      // A sample whose value at the search was at least `needed` still lies at or above m: its value
      // can have fallen by at most kValueLipschitz * moved since. The same points, bit for bit.
      // Else, a sample that has moved less than (its last value - m) / kValueLipschitz since its
      // last look-up is still at or above m. Exact too; a look-up refreshes the sample's record.
      const double fine = m + 1e-6 * h;
      for (std::size_t k = 0; k < list->samples.size(); ++k) {
        if (list->values[k] >= needed) continue;
        const std::uint32_t i = list->samples[k];
        const Vec3 L = Rrel * samples.positions()[i] + trel;
        const double bound = list->lastValues[k] - kValueLipschitz * (L - list->lastPoints[k]).norm();
        if (bound >= fine) continue;
        if (!inBox(L, targetLo, targetHi)) continue; // value >= m outside the grown box
        ++list->lookups;
        LevelSet::Lookup at;
        const double value = ls.value(L, at);
        list->lastValues[k] = value;
        list->lastPoints[k] = L;
        if (value < m) {
          emit(i, at);
        }
      }
      return;
    }
  }
  // A full search, with the reach of the list when one is made.
  const double reach = list != nullptr ? m + slack / st : m;
  if (list != nullptr) {
    ++list->searches;
    list->probe = ps.samples;
    list->target = ts.levelSet;
    list->rotation = Rrel;
    list->translation = trel;
    list->reach = reach;
    list->samples.clear();
    list->values.clear();
    list->lastValues.clear();
    list->lastPoints.clear();
  }
  const Vec3 reachLo = ls.meshBounds().min - Vec3::Constant(std::sqrt(3.0) * h + reach);
  const Vec3 reachHi = ls.meshBounds().max + Vec3::Constant(std::sqrt(3.0) * h + reach);
  // The target's grown mesh box (an oriented box) seen from the probe's unscaled body frame, as an
  // axis-aligned box there: tighter than the target's world box.
  const Mat3 toProbe = Rp.transpose() * Rt * (st / sp);
  const Vec3 centre = toProbe * (0.5 * (reachLo + reachHi)) + Rp.transpose() * (xt - xp) / sp;
  const Vec3 half = toProbe.cwiseAbs() * (0.5 * (reachHi - reachLo));
  const SampleBuckets& bk = *ps.buckets;
  forBucketsNear(bk, centre - half, centre + half, [&](int cell, const Vec3& /*low*/) {
    // Whole bucket first, by the sphere around its samples (radius r, centre c, in the target
    // frame): an interpolated phi < reach at x needs a true distance below sqrt(3) h + reach there,
    // and the true distance at x is at least that at c minus r; so a lower bound of the distance
    // at c above r + sqrt(3) h + reach rules out the whole bucket.
    const Vec3 bc = Rrel * bk.sphereCentre[cell] + trel;
    const double r = bk.sphereRadius[cell] * (sp / st);
    if (ls.distanceLowerBound(bc) - r > std::sqrt(3.0) * h + reach) {
      return;
    }
    for (std::uint32_t j = bk.start[cell]; j < bk.start[cell + 1]; ++j) {
      const std::uint32_t i = bk.samples[j];
      const Vec3 L = Rrel * samples.positions()[i] + trel;
      if (list == nullptr) {
        consider(i, L);
        continue;
      }
      // Listed: within the reach's box and value (a sample outside them stays beyond the margin
      // while the motion bound above holds: the box and the true distance are 1-Lipschitz).
      if (!inBox(L, reachLo, reachHi)) {
        continue;
      }
      LevelSet::Lookup at;
      const double value = ls.value(L, at);
      if (value < reach) {
        list->samples.push_back(i);
        list->values.push_back(roundedDown(value));
        list->lastValues.push_back(value);
        list->lastPoints.push_back(L);
      }
      if (value < m && inBox(L, targetLo, targetHi)) {
        emit(i, at);
      }
    }
  });
}

} // namespace

double samplesInLevelSets(const ContactShape& a, const ContactPose& pa, const ContactShape& b, const ContactPose& pb,
                          double margin, std::vector<ContactPoint>& out, PairSampleCache* cache, double slack) {
  double maxOverlap = 0.0;
  if (apart(a, pa, b, pb, margin)) {
    return maxOverlap;
  }
  // Both directions, so that both bodies' edges and corners are detected, each weighted by its
  // probe's sample density: w_A = h_B^2 / (h_A^2 + h_B^2), h = sample spacing (a fixed fraction of
  // Dn), so w_A + w_B = 1. Equal bodies get half each (symmetric in A and B); a unit on one 4.6
  // times its size (mass ratio 100) is measured mostly by its own fine samples, not by the few
  // coarse samples of the big one that fall on its small face. B's points are flipped to push A.
  const double hA2 = pa.dn * pa.dn, hB2 = pb.dn * pb.dn;
  NearSampleList* listA = cache != nullptr ? &cache->directions[0] : nullptr;
  NearSampleList* listB = cache != nullptr ? &cache->directions[1] : nullptr;
  probeSamples(a, pa, b, pb, hB2 / (hA2 + hB2), 0u, false, margin, slack, listA, maxOverlap, out);
  probeSamples(b, pb, a, pa, hA2 / (hA2 + hB2), kReverseSampleBit, true, margin, slack, listB, maxOverlap, out);
  return maxOverlap;
}

bool anySampleWithin(const ContactShape& probe, const ContactPose& pp, const ContactShape& target,
                     const ContactPose& pt, double clearance) {
  const auto& ls = *target.levelSet;
  const double reach = target.radius * pt.scale + clearance;
  const Vec3 grow = Vec3::Constant(clearance / pt.scale + std::sqrt(3.0) * ls.cellSize());
  const Vec3 lo = ls.meshBounds().min - grow, hi = ls.meshBounds().max + grow;
  const Mat3 toTarget = pt.rotation.transpose() * pp.rotation * (pp.scale / pt.scale);
  const Vec3 offset = pt.rotation.transpose() * (pp.position - pt.position) / pt.scale;
  const Vec3 probeInTarget = pp.position - pt.position;
  for (const Vec3& p : probe.samples->positions()) {
    const Vec3 X = probeInTarget + pp.rotation * (pp.scale * p);
    if (X.squaredNorm() > reach * reach) continue;
    const Vec3 L = toTarget * p + offset;
    if ((L.array() < lo.array()).any() || (L.array() > hi.array()).any()) continue;
    if (ls.value(L) * pt.scale < clearance) return true;
  }
  return false;
}

} // namespace armour::contact
