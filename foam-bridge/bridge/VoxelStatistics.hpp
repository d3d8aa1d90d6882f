// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VoxelStatistics.hpp
/// The statistics of seed 000 (section 2.2, Fig. 3) that turn surface samples of a wave-tank run
/// into a storm file, record by record and without per-face time series. The same code runs in the
/// OpenFOAM function object armourSampler (online, per MPI rank) and in foam-proxy (offline, from
/// the `surfaces` function object's output), so both give the same numbers.
///
/// Per record (sample time):
///  1. sums(): per voxel, the sums of p, u, v, w, alpha over the sample points (faces of the armour
///     units, or the voxel centres in 2D runs) that fall in it. Reduce: sum over ranks.
///  2. addEtaCell(), in kEtaPasses passes over the cells whose centre lies in the band
///     |y - etaPlaneY| <= etaHalfWidth and within etaColumnHalfWidth of the column centre along x
///     (wider than dx/2 where the mesh is coarser than the voxels, or a column would catch no
///     cell): (0) the highest wet centre z_w (alpha >= wetAlpha) and the lowest centre of all;
///     (1) the lowest centre z_d above z_w and the alpha a_w at z_w; (2) the alpha a_d at z_d.
///     Reduce after each pass: max over ranks. (Cell centres, not cell extents: foam-proxy gets the
///     same cells, with their centres, from the stock `sets` function object, type cellCentre.)
///  3. finishRecord(): voxel means (p_mean = sum / m) and eta, where alpha crosses wetAlpha on the
///     straight line between (z_w, a_w) and (z_d, a_d), minus stillWaterLevel (docs/foam-bridge.md).
///  4. addDeviations(): for each sample point in a voxel with m >= minimumSamples, the deviation
///     p - p_mean into the DeviationHistogram of its class: crest if eta of its column > 0 (the
///     storm file's phase rule), above if the deviation is positive. Reduce at the end: sum.
///  5. observeEta(): the per-column range of eta, for the normalisation amplitude a_n.
/// At the end, variability() fits the four Weibull distributions of d = |p - p_mean| / (rho g a_n).
///
/// Plain C++11 (shared with the OpenFOAM function object).

#include "bridge/DeviationHistogram.hpp"
#include "bridge/VoxelGrid.hpp"
#include "storm/StormFile.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace armour {
namespace bridge {

/// Everything the sampler needs besides the run's fields.
struct SamplerSettings {
  VoxelGridSettings grid;
  double stillWaterLevel = 0.0;         ///< z of the still water surface, the datum of eta (unit: m)
  double waterDensity = 1000.0;         ///< rho of the water (unit: kg/m^3)
  double gravity = 9.81;                ///< |g| (unit: m/s^2)
  double wetAlpha = 0.5;                ///< a cell with alpha >= wetAlpha is wet (unit: -)
  /// y of the middle of the band of cells that gives eta (unit: m); NaN = the middle of the trunk.
  double etaPlaneY = std::numeric_limits<double>::quiet_NaN();
  /// Half width of that band (unit: m); NaN = dz / 2. It should hold one layer of cells (or a few).
  double etaHalfWidth = std::numeric_limits<double>::quiet_NaN();
  /// Cells count for a column if their centre is this close to the column centre along x (unit: m);
  /// NaN = dx / 2. At least half the width of the largest cell near the free surface.
  double etaColumnHalfWidth = std::numeric_limits<double>::quiet_NaN();
  /// a_n of the normalisation P_n = rho g a_n (unit: m); 0 = half the mean eta range over the
  /// columns with data (the amplitude of a regular wave), 1 m if that is 0 (calm water).
  double normalisationAmplitude = 0.0;
  double pressureReference = 0.0;       ///< subtracted from p to make it gauge (unit: Pa)
  int minimumSamples = 2;               ///< voxels with fewer sample points give no deviations (unit: -)
  /// The run's fields hold at every y (a 2D tank, one cell across): the storm file says so
  /// (uniform_along_y = 1) and the solver loads units at any y, not only on the trunk section
  /// (unit: -). Leave false for a 3D tank, whose section is the trunk the values stand for.
  bool uniformAlongY = false;
};

/// Values of one record at the local sample points, one array per component (length n).
struct SampleValues {
  std::vector<double> p;     ///< total pressure (unit: Pa)
  std::vector<double> u;     ///< x velocity (unit: m/s)
  std::vector<double> v;     ///< y velocity (unit: m/s)
  std::vector<double> w;     ///< z velocity (unit: m/s)
  std::vector<double> alpha; ///< water fraction (unit: -)
  void resize(std::size_t n) { p.resize(n); u.resize(n); v.resize(n); w.resize(n); alpha.resize(n); }
  std::size_t size() const { return p.size(); }
};

class VoxelStatistics {
public:
  /// Fields summed per voxel in sums(): p, u, v, w, alpha.
  static const int kSumFields = 5;

  explicit VoxelStatistics(const SamplerSettings& settings);

  const SamplerSettings& settings() const { return settings_; }
  const VoxelGrid& grid() const { return grid_; }
  double etaPlaneY() const { return etaPlaneY_; }       ///< unit: m
  double etaHalfWidth() const { return etaHalfWidth_; } ///< unit: m
  double etaColumnHalfWidth() const { return etaColumnHalfWidth_; } ///< unit: m

  // ---- geometry (once) ---------------------------------------------------------------------
  /// The local sample points (face centres; voxel centres in 2D runs), unit: m.
  void setSamplePoints(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z);
  std::size_t samplePoints() const { return pointVoxel_.size(); }
  /// Voxel of each sample point, -1 if outside the grid or the trunk section.
  const std::vector<long>& pointVoxel() const { return pointVoxel_; }
  /// Sample points per voxel on this rank (reduce: sum), then setCounts() with the global counts.
  std::vector<double> localCounts() const;
  void setCounts(const std::vector<double>& counts);
  /// Where the voxels sit (docs/foam-bridge.md): at each sample point in the grid, the weight
  /// the solver's bilinear interpolation (StormSampler) puts on voxels without data (m = 0), which
  /// it fills with still water under the free surface. Adds this rank's sum of those weights and
  /// its number of points in the grid (reduce both: sum); call after setCounts(). Their ratio is
  /// ~0 when voxel centres lie on a unit's flat faces and 0.5 when voxel edges do.
  void addGapWeight(double& weightSum, double& points) const;
  /// Above this mean gap weight the sampler and foam-proxy warn (measured on the surge-box case:
  /// 0.47 gave a peak force 15 % low, 0.22 11 %, 0 4 %; docs/foam-bridge.md) (unit: -).
  static constexpr double kGapWeightWarning = 0.1;
  /// The warning both paths give when the mean gap weight exceeds kGapWeightWarning: what it is,
  /// what it cost on the measured case, and the fix.
  static std::string gapWeightWarning(double meanGapWeight);
  const std::vector<std::int32_t>& counts() const { return counts_; } ///< m per voxel (z, x)

  // ---- per record ---------------------------------------------------------------------------
  /// Local sums, kSumFields x voxels (field-major). Reduce: sum.
  void sums(const SampleValues& values, std::vector<double>& out) const;
  /// Passes of addEtaCell over the cells (each followed by a max-reduction of the levels).
  static const int kEtaPasses = 3;
  /// 5 nx column levels, all reduced by max: z_w, -(lowest centre), -z_d, a_w, a_d.
  void initColumnLevels(std::vector<double>& levels) const;
  /// True if a cell centre at y lies in the eta band (closed interval, as OpenFOAM's boundBox).
  bool inEtaBand(double y) const { return y >= etaPlaneY_ - etaHalfWidth_ && y <= etaPlaneY_ + etaHalfWidth_; }
  /// A cell of the eta band in pass 0, 1 or 2: centre x and z, alpha. Pass k reads the levels
  /// of the passes before it, reduced.
  void addEtaCell(int pass, std::vector<double>& levels, double x, double z, double alpha) const;
  /// Means and eta from the reduced sums and levels. v is filled when hasVelocityY.
  void finishRecord(double time, const std::vector<double>& sums, const std::vector<double>& levels, bool hasVelocityY,
                    storm::StormRecord& record) const;
  /// Local deviations of this record into `histogram` (uses record.p and record.eta).
  void addDeviations(const SampleValues& values, const storm::StormRecord& record, DeviationHistogram& histogram) const;
  /// Track the per-column range of eta (once per record, on the writing rank).
  void observeEta(const std::vector<double>& eta);

  // ---- end ----------------------------------------------------------------------------------
  /// a_n (unit: m) and how it was chosen.
  double normalisationAmplitude(std::string& how) const;
  /// The Weibull fits of the reduced histogram; present = false without any nonzero deviation.
  storm::Variability variability(const DeviationHistogram& histogram, const std::string& source) const;
  /// A storm header with the grid, the counts and the physical constants.
  storm::StormHeader header(bool hasVelocityY) const;

private:
  SamplerSettings settings_;
  VoxelGrid grid_;
  double etaPlaneY_;
  double etaHalfWidth_;
  double etaColumnHalfWidth_;
  std::vector<long> pointVoxel_;
  std::vector<double> pointX_, pointZ_; ///< the sample points' x and z (unit: m)
  std::vector<std::int32_t> counts_;
  std::vector<double> etaMin_, etaMax_;
};

} // namespace bridge
} // namespace armour
