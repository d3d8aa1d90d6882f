// SPDX-License-Identifier: GPL-3.0-or-later
#include "storm/StormSampler.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace armour::storm {
namespace {

/// The (up to four) voxel centres around a point and their bilinear weights, corners without data
/// dropped and the rest renormalised.
struct Stencil {
  std::size_t voxel[4] = {0, 0, 0, 0};
  double weight[4] = {0, 0, 0, 0};
  int corners = 0;
};

/// Cell index and fraction along one uniform axis (StormSampler::Axis); false when `c` is more
/// than half a spacing outside the outermost centres. Within that half spacing the fraction is
/// clamped so the edge value is held.
bool locate(const StormSampler::Axis& axis, double c, std::size_t& index, double& fraction) {
  const std::size_t n = axis.centres.size();
  const double f = (c - axis.centres.front()) * axis.inverseSpacing;
  // Written as a negated range test so a NaN coordinate is outside too.
  if (!(f >= -0.5 && f <= static_cast<double>(n - 1) + 0.5)) {
    return false;
  }
  const double cell = std::clamp(std::floor(f), 0.0, static_cast<double>(n - 2));
  index = static_cast<std::size_t>(cell);
  // The fraction from the stored centres (not from f) keeps a linear field exact on grids whose
  // centres are uniform only to round-off.
  fraction = std::clamp((c - axis.centres[index]) * axis.inverseWidth[index], 0.0, 1.0);
  return true;
}

/// The stencil of the cell (ix, iz) at fractions (tx, tz) (from locate).
bool stencilAt(const StormHeader& h, std::size_t ix, std::size_t iz, double tx, double tz, Stencil& s) {
  const std::size_t nx = h.nx();
  const std::size_t base = iz * nx + ix;
  const std::size_t voxels[4] = {base, base + 1, base + nx, base + nx + 1};
  const double weights[4] = {(1.0 - tx) * (1.0 - tz), tx * (1.0 - tz), (1.0 - tx) * tz, tx * tz};
  double total = 0.0;
  s.corners = 0;
  for (int c = 0; c < 4; ++c) {
    if (h.samples[voxels[c]] > 0 && weights[c] > 0.0) {
      s.voxel[s.corners] = voxels[c];
      s.weight[s.corners] = weights[c];
      total += weights[c];
      ++s.corners;
    }
  }
  // No weight left: the point is in the hold zone of, or exactly at the centre of, voxels without
  // data, with nothing to interpolate from.
  if (s.corners == 0) {
    return false;
  }
  const double inverse = 1.0 / total;
  for (int c = 0; c < s.corners; ++c) {
    s.weight[c] *= inverse;
  }
  return true;
}

} // namespace

StormSampler::Axis::Axis(const std::vector<double>& c) : centres(c) {
  inverseSpacing = 1.0 / (c[1] - c[0]);
  inverseWidth.resize(c.size() - 1);
  for (std::size_t i = 0; i + 1 < c.size(); ++i) {
    inverseWidth[i] = 1.0 / (c[i + 1] - c[i]);
  }
}

StormSampler::StormSampler(const StormReader& reader)
    : reader_(reader), axisX_(reader.header().x), axisZ_(reader.header().z) {
  const auto& h = reader.header();
  const auto& times = reader.times();
  const std::size_t nx = h.nx();
  dataLevels_.assign(nx, {});
  for (std::size_t iz = 0; iz < h.nz(); ++iz) {
    for (std::size_t ix = 0; ix < nx; ++ix) {
      if (h.samples[iz * nx + ix] > 0) {
        dataLevels_[ix].push_back(iz);
      } else {
        hasGaps_ = true;
      }
    }
  }
  crossings_.assign(nx, {});
  // Zero crossings of eta per column, the crossing time by linear interpolation between the two
  // records. A record with eta == 0 counts as trough (crest is eta > 0), so a crossing is a change
  // of that classification between consecutive records.
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    const double* e0 = reader.eta(k);
    const double* e1 = reader.eta(k + 1);
    const double t0 = times[k];
    const double t1 = times[k + 1];
    for (std::size_t i = 0; i < nx; ++i) {
      if ((e0[i] > 0.0) != (e1[i] > 0.0)) {
        const double s = e0[i] / (e0[i] - e1[i]);
        crossings_[i].push_back(t0 + s * (t1 - t0));
      }
    }
  }
  setTime(times.front());
}

void StormSampler::setTime(double t) {
  const auto& times = reader_.times();
  if (!(t >= times.front() && t <= times.back())) {
    core::failInput(reader_.path(), "time {} s is outside the storm's records [{}, {}] s; choose a time within the "
                                    "file (or a longer storm file)", t, times.front(), times.back());
  }
  // The record at or before t, limited so that lower + 1 exists (t = last time: weight 1).
  const std::size_t lower = reader_.intervalOf(t);
  const std::size_t upper = lower + 1;
  if (heldA_ != lower || heldB_ != upper) {
    if (heldB_ == lower || heldA_ == upper) {
      // One interval forward (as a time-stepping solver moves) or back: keep the shared record.
      std::swap(a_, b_);
      std::swap(heldA_, heldB_);
    }
    if (heldA_ != lower) {
      heldA_ = SIZE_MAX; // a failed read must not leave a stale record marked as held
      reader_.read(lower, a_);
      heldA_ = lower;
    }
    if (heldB_ != upper) {
      heldB_ = SIZE_MAX;
      reader_.read(upper, b_);
      heldB_ = upper;
    }
  }
  lower_ = lower;
  weight_ = (t - times[lower]) / (times[upper] - times[lower]);
  time_ = t;
  blendRecords();
}

void StormSampler::blendRecords() {
  const std::size_t n = a_.p.size();
  const bool hasV = reader_.header().hasVelocityY;
  const auto& times = reader_.times();
  const double inv = 1.0 / (times[lower_ + 1] - times[lower_]);
  const double wa = 1.0 - weight_, wb = weight_;
  blended_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    FlowSample& v = blended_[i].now;
    v.p = wa * a_.p[i] + wb * b_.p[i];
    v.u = wa * a_.u[i] + wb * b_.u[i];
    v.v = hasV ? wa * a_.v[i] + wb * b_.v[i] : 0.0;
    v.w = wa * a_.w[i] + wb * b_.w[i];
    v.alpha = wa * a_.alpha[i] + wb * b_.alpha[i];
    FlowSample& r = blended_[i].slope;
    r.p = (b_.p[i] - a_.p[i]) * inv;
    r.u = (b_.u[i] - a_.u[i]) * inv;
    r.v = hasV ? (b_.v[i] - a_.v[i]) * inv : 0.0;
    r.w = (b_.w[i] - a_.w[i]) * inv;
    r.alpha = (b_.alpha[i] - a_.alpha[i]) * inv;
  }
}

FlowSample StormSampler::voxel(std::size_t i, bool rate) const {
  return rate ? blended_[i].slope : blended_[i].now;
}

void StormSampler::accumulate(FlowSample& out, double weight, const FlowSample& v) {
  out.p += weight * v.p;
  out.u += weight * v.u;
  out.v += weight * v.v;
  out.w += weight * v.w;
  out.alpha += weight * v.alpha;
}

FlowSample StormSampler::sample(double x, double z) const { return interpolate(x, z, false); }

FlowSample StormSampler::rate(double x, double z) const { return interpolate(x, z, true); }

FlowSample StormSampler::interpolate(double x, double z, bool rate) const {
  std::size_t ix = 0, iz = 0;
  double tx = 0.0, tz = 0.0;
  if (!locate(axisX_, x, ix, tx) || !locate(axisZ_, z, iz, tz)) {
    return {};
  }
  return interpolateCell(ix, iz, tx, tz, rate);
}

FlowSample StormSampler::interpolateCell(std::size_t ix, std::size_t iz, double tx, double tz, bool rate) const {
  FlowSample out;
  Stencil s;
  if (!stencilAt(reader_.header(), ix, iz, tx, tz, s)) {
    return out;
  }
  for (int c = 0; c < s.corners; ++c) {
    accumulate(out, s.weight[c], voxel(s.voxel[c], rate));
  }
  out.valid = true;
  return out;
}

FlowSample StormSampler::sampleExtended(double x, double z) const { return extended(locateExtended(x, z), false); }

FlowSample StormSampler::rateExtended(double x, double z) const { return extended(locateExtended(x, z), true); }

StormSampler::Located StormSampler::locateExtended(double x, double z) const {
  const auto& h = reader_.header();
  Located at;
  if (std::isnan(x) || std::isnan(z)) {
    return at;
  }
  // Beyond the outermost columns the edge column's flow; beyond the outermost rows the edge row's,
  // continued hydrostatically (extended()).
  const double cx = std::clamp(x, h.x.front(), h.x.back());
  const double cz = std::clamp(z, h.z.front(), h.z.back());
  at.rowOffset = z - cz;
  std::size_t ix = 0, iz = 0;
  double tx = 0.0, tz = 0.0;
  if (!locate(axisX_, cx, ix, tx) || !locate(axisZ_, cz, iz, tz)) {
    return at; // cannot happen for a clamped point; kept as sample() would answer
  }
  const std::size_t nx = h.nx();
  const std::size_t base = iz * nx + ix;
  const std::size_t voxels[4] = {base, base + 1, base + nx, base + nx + 1};
  const double weights[4] = {(1.0 - tx) * (1.0 - tz), tx * (1.0 - tz), (1.0 - tx) * tz, tx * tz};
  bool allData = true;
  for (int c = 0; c < 4; ++c) {
    allData = allData && (!(weights[c] > 0.0) || h.samples[voxels[c]] > 0);
  }
  if (allData) {
    // The file's values, bit for bit (as sample / rate): corners without weight dropped, the
    // rest renormalised.
    Stencil s;
    if (!stencilAt(h, ix, iz, tx, tz, s)) {
      return at;
    }
    at.corners = s.corners;
    for (int c = 0; c < s.corners; ++c) {
      at.voxel[c] = s.voxel[c];
      at.weight[c] = s.weight[c];
    }
    at.valid = true;
    return at;
  }
  // Gap fill at the corners without data (their weights kept, not renormalised).
  for (int c = 0; c < 4; ++c) {
    if (!(weights[c] > 0.0)) {
      continue;
    }
    at.voxel[at.corners] = voxels[c];
    at.weight[at.corners] = weights[c];
    at.gapFill[at.corners] = h.samples[voxels[c]] == 0;
    at.filled = at.filled || at.gapFill[at.corners];
    ++at.corners;
  }
  at.valid = true;
  return at;
}

FlowSample StormSampler::cornerSum(const Located& at, bool rate) const {
  FlowSample out;
  if (!at.valid) {
    return out;
  }
  const std::size_t nx = reader_.header().nx();
  for (int c = 0; c < at.corners; ++c) {
    const std::size_t i = at.voxel[c];
    accumulate(out, at.weight[c], at.gapFill[c] ? fill(i % nx, i / nx, rate) : voxel(i, rate));
  }
  out.valid = true;
  out.filled = at.filled;
  return out;
}

FlowSample StormSampler::extended(const Located& at, bool rate) const {
  FlowSample out = cornerSum(at, rate);
  if (!at.valid || at.rowOffset == 0.0) {
    return out;
  }
  const auto& h = reader_.header();
  const double rhoG = h.waterDensity * h.gravity;
  if (at.rowOffset < 0.0) {
    // Below the bottom row: deeper by -rowOffset in the same water; the added pressure does not
    // change in time.
    if (!rate) {
      out.p += rhoG * -at.rowOffset;
    }
    return out;
  }
  // Above the top row: the pressure falls by rho g per metre; where it is gone the point is in air.
  const FlowSample value = rate ? cornerSum(at, false) : out;
  if (value.p - rhoG * at.rowOffset <= 0.0) {
    FlowSample air;
    air.valid = true;
    air.filled = out.filled;
    return air;
  }
  if (!rate) {
    out.p -= rhoG * at.rowOffset;
  }
  return out;
}

FlowSample StormSampler::fill(std::size_t ix, std::size_t iz, bool rate) const {
  const auto& h = reader_.header();
  FlowSample out;
  const double etaA = reader_.eta(lower_)[ix];
  const double etaB = reader_.eta(lower_ + 1)[ix];
  const double surface = h.stillWaterLevel + (1.0 - weight_) * etaA + weight_ * etaB;
  const double z = h.z[iz];
  if (!(z < surface)) {
    return out; // above the free surface: air, gauge pressure 0
  }
  const auto& times = reader_.times();
  const double inv = 1.0 / (times[lower_ + 1] - times[lower_]);
  const double rhoG = h.waterDensity * h.gravity;
  if (rate) {
    out.p = rhoG * (etaB - etaA) * inv;
  } else {
    out.p = rhoG * (surface - z);
    out.alpha = 1.0;
  }
  // The flow: the wet voxel with data of this column nearest in z (the lower one at a tie).
  const std::size_t nx = h.nx();
  const auto& levels = dataLevels_[ix];
  const auto wet = [&](std::size_t k) {
    const std::size_t i = k * nx + ix;
    return blended_[i].now.alpha >= 0.5;
  };
  // Two cursors walking away from iz, down (lo - 1) and up (hi), the nearer one first.
  std::size_t hi = static_cast<std::size_t>(std::lower_bound(levels.begin(), levels.end(), iz) - levels.begin());
  std::size_t lo = hi;
  std::size_t source = SIZE_MAX;
  while (lo > 0 || hi < levels.size()) {
    const bool down = hi == levels.size() || (lo > 0 && iz - levels[lo - 1] <= levels[hi] - iz);
    const std::size_t k = down ? levels[--lo] : levels[hi++];
    if (wet(k)) {
      source = k * nx + ix;
      break;
    }
  }
  if (source == SIZE_MAX) {
    return out; // no wet voxel with data in the column: still water
  }
  const FlowSample flow = voxel(source, rate);
  out.u = flow.u;
  out.v = flow.v;
  out.w = flow.w;
  return out;
}

WavePhase StormSampler::phase(double x) const {
  WavePhase out;
  const auto& h = reader_.header();
  const double f = (x - h.x.front()) / h.dx();
  if (std::isnan(f)) {
    return out; // no column to speak of: still water, first half wave
  }
  const auto ix = static_cast<std::size_t>(std::clamp(std::round(f), 0.0, static_cast<double>(h.nx() - 1)));
  const double e0 = reader_.eta(lower_)[ix];
  const double e1 = reader_.eta(lower_ + 1)[ix];
  out.elevation = (1.0 - weight_) * e0 + weight_ * e1;
  out.crest = out.elevation > 0.0;
  const auto& c = crossings_[ix];
  out.halfWave = static_cast<std::int64_t>(std::upper_bound(c.begin(), c.end(), time_) - c.begin());
  return out;
}

} // namespace armour::storm
