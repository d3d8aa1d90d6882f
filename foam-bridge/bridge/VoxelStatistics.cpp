// SPDX-License-Identifier: GPL-3.0-or-later
#include "bridge/VoxelStatistics.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace armour {
namespace bridge {

namespace {

void requirePositiveSetting(double value, const char* key, const char* unit) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream m;
    m << "= " << value << " " << unit << ": must be positive and finite";
    failSetting(key, m.str());
  }
}

} // namespace

VoxelStatistics::VoxelStatistics(const SamplerSettings& settings)
    : settings_(settings), grid_(settings.grid),
      etaPlaneY_(std::isnan(settings.etaPlaneY) ? grid_.trunkMiddle() : settings.etaPlaneY),
      etaHalfWidth_(std::isnan(settings.etaHalfWidth) ? 0.5 * settings.grid.dz : settings.etaHalfWidth),
      etaColumnHalfWidth_(std::isnan(settings.etaColumnHalfWidth) ? 0.5 * settings.grid.dx : settings.etaColumnHalfWidth),
      counts_(grid_.voxels(), 0), etaMin_(static_cast<std::size_t>(grid_.nx()), 0.0),
      etaMax_(static_cast<std::size_t>(grid_.nx()), 0.0) {
  requirePositiveSetting(settings.waterDensity, "waterDensity", "kg/m^3");
  requirePositiveSetting(settings.gravity, "gravity", "m/s^2");
  if (!std::isfinite(settings.stillWaterLevel)) failSetting("stillWaterLevel", "must be a finite z (m)");
  if (!(settings.wetAlpha > 0.0 && settings.wetAlpha <= 1.0)) {
    std::ostringstream m;
    m << "= " << settings.wetAlpha << ": must lie in (0, 1]; 0.5 marks the interface";
    failSetting("wetAlpha", m.str());
  }
  if (!(settings.normalisationAmplitude >= 0.0) || !std::isfinite(settings.normalisationAmplitude)) {
    std::ostringstream m;
    m << "= " << settings.normalisationAmplitude << " m: must be >= 0 (0 = from the eta range)";
    failSetting("normalisationAmplitude", m.str());
  }
  if (!std::isfinite(etaPlaneY_)) failSetting("etaPlaneY", "must be a finite y (m)");
  if (!(etaHalfWidth_ > 0.0) || !std::isfinite(etaHalfWidth_)) {
    std::ostringstream m;
    m << "= " << etaHalfWidth_ << " m: must be positive; the band |y - etaPlaneY| <= etaHalfWidth must hold a layer of cells";
    failSetting("etaHalfWidth", m.str());
  }
  if (!(etaColumnHalfWidth_ > 0.0) || !std::isfinite(etaColumnHalfWidth_)) {
    std::ostringstream m;
    m << "= " << etaColumnHalfWidth_ << " m: must be positive (at least half the width of the cells at the free surface)";
    failSetting("etaColumnHalfWidth", m.str());
  }
  if (settings.minimumSamples < 2) failSetting("minimumSamples", "must be >= 2: one sample has no deviation from its own mean");
  std::fill(etaMin_.begin(), etaMin_.end(), std::numeric_limits<double>::infinity());
  std::fill(etaMax_.begin(), etaMax_.end(), -std::numeric_limits<double>::infinity());
}

void VoxelStatistics::setSamplePoints(const std::vector<double>& x, const std::vector<double>& y,
                                      const std::vector<double>& z) {
  if (y.size() != x.size() || z.size() != x.size()) failSetting("setSamplePoints", "x, y and z differ in length");
  pointVoxel_.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) pointVoxel_[i] = grid_.voxel(x[i], y[i], z[i]);
  pointX_ = x;
  pointZ_ = z;
}

std::string VoxelStatistics::gapWeightWarning(double meanGapWeight) {
  std::ostringstream s;
  s.precision(3);
  s << "at the unit faces, " << 100.0 * meanGapWeight << " % of the solver's interpolation weight falls on voxels "
    << "without data, which it fills with still water (more than " << 100.0 * kGapWeightWarning << " %): the voxel "
    << "grid's edges lie on or near flat unit faces. Measured on an axis-aligned box hit by a surge "
    << "(docs/foam-bridge.md, \"Where the voxels sit\"): 47 % gave a peak force 15 % low, 22 % 11 % low, 0 % "
    << "(voxel centres on the faces) 4 % low. Shift the grid (xMin, zMin) by a fraction of a voxel so that voxel "
    << "centres, not edges, fall on the units' flat faces";
  return s.str();
}

void VoxelStatistics::addGapWeight(double& weightSum, double& points) const {
  const VoxelGridSettings& g = grid_.settings();
  // The interpolation stencil of StormSampler: between the centres around the point, held (not
  // extrapolated) within half a voxel beyond the outermost centres.
  const auto stencil = [](double c, double c0, double d, int n, int& i0, double& r) {
    const double f = (c - c0) / d;
    i0 = static_cast<int>(std::floor(f));
    i0 = std::max(0, std::min(n - 2, i0));
    r = std::max(0.0, std::min(1.0, f - i0));
  };
  for (std::size_t i = 0; i < pointVoxel_.size(); ++i) {
    if (pointVoxel_[i] < 0) continue;
    int ix = 0, iz = 0;
    double r = 0.0, q = 0.0;
    stencil(pointX_[i], grid_.xCentre(0), g.dx, g.nx, ix, r);
    stencil(pointZ_[i], grid_.zCentre(0), g.dz, g.nz, iz, q);
    const double w[4] = {(1 - r) * (1 - q), r * (1 - q), (1 - r) * q, r * q};
    const std::size_t nx = static_cast<std::size_t>(g.nx), x0 = static_cast<std::size_t>(ix);
    const std::size_t z0 = static_cast<std::size_t>(iz);
    const std::size_t v[4] = {z0 * nx + x0, z0 * nx + x0 + 1, (z0 + 1) * nx + x0, (z0 + 1) * nx + x0 + 1};
    for (int k = 0; k < 4; ++k) {
      if (counts_[v[k]] == 0 && w[k] > 1e-9) weightSum += w[k]; // 1e-9: round-off of a point on a centre
    }
    points += 1.0;
  }
}

std::vector<double> VoxelStatistics::localCounts() const {
  std::vector<double> c(grid_.voxels(), 0.0);
  for (std::size_t i = 0; i < pointVoxel_.size(); ++i) {
    if (pointVoxel_[i] >= 0) c[static_cast<std::size_t>(pointVoxel_[i])] += 1.0;
  }
  return c;
}

void VoxelStatistics::setCounts(const std::vector<double>& counts) {
  if (counts.size() != grid_.voxels()) failSetting("setCounts", "one count per voxel expected");
  for (std::size_t i = 0; i < counts.size(); ++i) counts_[i] = static_cast<std::int32_t>(std::llround(counts[i]));
}

void VoxelStatistics::sums(const SampleValues& values, std::vector<double>& out) const {
  if (values.size() != pointVoxel_.size()) failSetting("sums", "one value per sample point expected");
  const std::size_t nv = grid_.voxels();
  out.assign(kSumFields * nv, 0.0);
  for (std::size_t i = 0; i < pointVoxel_.size(); ++i) {
    const long k = pointVoxel_[i];
    if (k < 0) continue;
    const std::size_t v = static_cast<std::size_t>(k);
    out[v] += values.p[i] - settings_.pressureReference;
    out[nv + v] += values.u[i];
    out[2 * nv + v] += values.v[i];
    out[3 * nv + v] += values.w[i];
    out[4 * nv + v] += values.alpha[i];
  }
}

void VoxelStatistics::initColumnLevels(std::vector<double>& levels) const {
  levels.assign(5 * static_cast<std::size_t>(grid_.nx()), -std::numeric_limits<double>::infinity());
}

void VoxelStatistics::addEtaCell(int pass, std::vector<double>& levels, double x, double z, double alpha) const {
  // Every column whose centre is within etaColumnHalfWidth of x (closed interval).
  const double s = (x - settings_.grid.xMin) / settings_.grid.dx - 0.5;
  const double h = etaColumnHalfWidth_ / settings_.grid.dx;
  const int first = std::max(0, static_cast<int>(std::ceil(s - h)));
  const int last = std::min(grid_.nx() - 1, static_cast<int>(std::floor(s + h)));
  const std::size_t nx = static_cast<std::size_t>(grid_.nx());
  const double sameHeight = 1e-6 * settings_.grid.dz;
  for (int ix = first; ix <= last; ++ix) {
    if (std::fabs(x - grid_.xCentre(ix)) > etaColumnHalfWidth_) continue; // round-off at the ends
    const std::size_t c = static_cast<std::size_t>(ix);
    double* zWet = &levels[c];
    double* negLow = &levels[nx + c];
    double* negAbove = &levels[2 * nx + c];
    double* aWet = &levels[3 * nx + c];
    double* aAbove = &levels[4 * nx + c];
    if (pass == 0) {
      *negLow = std::max(*negLow, -z);
      if (alpha >= settings_.wetAlpha) *zWet = std::max(*zWet, z);
    } else if (pass == 1) {
      // Centres at the same height compare equal to 1e-6 dz: OpenFOAM's cell centres of one mesh
      // row differ in the last bits, and the sets output prints them rounded.
      if (!std::isfinite(*zWet)) continue;
      if (z > *zWet + sameHeight) *negAbove = std::max(*negAbove, -z);
      if (std::fabs(z - *zWet) <= sameHeight) *aWet = std::max(*aWet, alpha);
    } else if (std::isfinite(*negAbove) && std::fabs(z + *negAbove) <= sameHeight) {
      *aAbove = std::max(*aAbove, alpha);
    }
  }
}

void VoxelStatistics::finishRecord(double time, const std::vector<double>& sums, const std::vector<double>& levels,
                                   bool hasVelocityY, storm::StormRecord& record) const {
  const std::size_t nv = grid_.voxels();
  const std::size_t nx = static_cast<std::size_t>(grid_.nx());
  if (sums.size() != kSumFields * nv || levels.size() != 5 * nx) failSetting("finishRecord", "sums or levels of the wrong size");
  record.time = time;
  record.p.assign(nv, 0.0);
  record.u.assign(nv, 0.0);
  record.w.assign(nv, 0.0);
  record.alpha.assign(nv, 0.0);
  if (hasVelocityY) record.v.assign(nv, 0.0); else record.v.clear();
  for (std::size_t v = 0; v < nv; ++v) {
    if (counts_[v] <= 0) continue;
    const double m = counts_[v];
    record.p[v] = sums[v] / m;
    record.u[v] = sums[nv + v] / m;
    if (hasVelocityY) record.v[v] = sums[2 * nv + v] / m;
    record.w[v] = sums[3 * nv + v] / m;
    // VOF round-off leaves alpha a little outside [0, 1]; the mean must not be.
    record.alpha[v] = std::min(1.0, std::max(0.0, sums[4 * nv + v] / m));
  }
  record.eta.assign(nx, 0.0);
  for (std::size_t c = 0; c < nx; ++c) {
    const double zWet = levels[c], zAbove = -levels[2 * nx + c], aWet = levels[3 * nx + c], aAbove = levels[4 * nx + c];
    if (std::isfinite(zWet)) {
      // The interface: where alpha crosses wetAlpha between the top wet centre and the centre
      // above it (cell values sit at the centres), on the straight line between them. Without a
      // cell above (top of the mesh, or a solid), the top wet centre.
      double level = zWet;
      const double a = std::min(aWet, 1.0); // VOF round-off above 1
      if (std::isfinite(zAbove) && std::isfinite(a) && std::isfinite(aAbove) && a > aAbove) {
        const double s = std::min(1.0, std::max(0.0, (a - settings_.wetAlpha) / (a - aAbove)));
        level = zWet + s * (zAbove - zWet);
      }
      record.eta[c] = level - settings_.stillWaterLevel;
    } else if (std::isfinite(levels[nx + c])) {
      // A dry column: the water is at most at its lowest cell centre (a trough), never a crest.
      record.eta[c] = std::min(0.0, -levels[nx + c] - settings_.stillWaterLevel);
    } else {
      record.eta[c] = 0.0; // no cell of the eta plane in this column (outside the mesh)
    }
  }
}

void VoxelStatistics::addDeviations(const SampleValues& values, const storm::StormRecord& record,
                                    DeviationHistogram& histogram) const {
  const std::size_t nx = static_cast<std::size_t>(grid_.nx());
  for (std::size_t i = 0; i < pointVoxel_.size(); ++i) {
    const long k = pointVoxel_[i];
    if (k < 0) continue;
    const std::size_t v = static_cast<std::size_t>(k);
    if (counts_[v] < settings_.minimumSamples) continue;
    const bool crest = record.eta[v % nx] > 0.0;
    histogram.add(crest, values.p[i] - settings_.pressureReference - record.p[v]);
  }
}

void VoxelStatistics::observeEta(const std::vector<double>& eta) {
  for (std::size_t c = 0; c < eta.size() && c < etaMin_.size(); ++c) {
    etaMin_[c] = std::min(etaMin_[c], eta[c]);
    etaMax_[c] = std::max(etaMax_[c], eta[c]);
  }
}

double VoxelStatistics::normalisationAmplitude(std::string& how) const {
  if (settings_.normalisationAmplitude > 0.0) {
    how = "a_n given";
    return settings_.normalisationAmplitude;
  }
  const std::size_t nx = static_cast<std::size_t>(grid_.nx());
  double sum = 0.0;
  int columns = 0;
  for (std::size_t c = 0; c < nx; ++c) {
    bool data = false;
    for (int iz = 0; iz < grid_.nz() && !data; ++iz) data = counts_[static_cast<std::size_t>(iz) * nx + c] > 0;
    if (!data || !(etaMax_[c] >= etaMin_[c])) continue;
    sum += 0.5 * (etaMax_[c] - etaMin_[c]);
    ++columns;
  }
  const double a = columns > 0 ? sum / columns : 0.0;
  if (a > 1e-6) {
    std::ostringstream s;
    s << "a_n = half the eta range averaged over " << columns << " columns with data";
    how = s.str();
    return a;
  }
  how = "a_n = 1 m: eta did not vary (calm water); give normalisationAmplitude";
  return 1.0;
}

storm::Variability VoxelStatistics::variability(const DeviationHistogram& histogram, const std::string& source) const {
  double nonzero = 0.0;
  for (int c = 0; c < storm::kVariabilityClasses; ++c) nonzero += histogram.classCount(c);
  if (nonzero <= 0.0) {
    storm::Variability none;
    none.present = false;
    none.source = source + " (no voxel with two or more differing samples)";
    return none;
  }
  std::string how;
  const double an = normalisationAmplitude(how);
  return histogram.fit(settings_.waterDensity * settings_.gravity * an, an, source + "; " + how);
}

storm::StormHeader VoxelStatistics::header(bool hasVelocityY) const {
  storm::StormHeader h;
  h.x = grid_.xCentres();
  h.z = grid_.zCentres();
  h.trunkOrigin = settings_.grid.trunkOrigin;
  h.trunkLength = settings_.grid.trunkLength;
  h.uniformAlongY = settings_.uniformAlongY;
  h.stillWaterLevel = settings_.stillWaterLevel;
  h.waterDensity = settings_.waterDensity;
  h.gravity = settings_.gravity;
  h.samples = counts_;
  h.hasVelocityY = hasVelocityY;
  return h;
}

} // namespace bridge
} // namespace armour
