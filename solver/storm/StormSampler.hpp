// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StormSampler.hpp
/// Values of a storm file at any (x, z, t): exact linear interpolation in t between the two
/// records that bracket t, and bilinear in (x, z) between the four voxel centres around the point
/// (seed 000 section 2.3: "an exact linear interpolation in time and space from the netCDF file
/// cells to the surface element meshes"). A field linear in x, z and t is reproduced exactly.
///
/// Edges and gaps (docs/storm-file.md, "Sampling"):
///  - within half a voxel outside the outermost centres, the value of the edge is held;
///  - farther out the point is outside the grid: valid = false;
///  - corners in voxels without data (samples = 0) are dropped and the remaining weights
///    renormalised; with no corner left, valid = false;
///  - sampleExtended() / rateExtended() (the solver's loads) instead give every corner without
///    data the gap fill at its centre: still water under the column's free surface (hydrostatic
///    p, alpha 1; air above it) moving with the nearest wet voxel with data of the column. Files
///    sampled on the unit surfaces (seed 000's 3D tanks) have no data away from the armour layer,
///    where a displaced unit can go; the fill keeps the field continuous and exact in still water.
///    They also answer beyond the grid, where the water goes on: beyond the outermost columns the
///    flow of the edge column is held, beyond the outermost rows the pressure goes on
///    hydrostatically from the edge row.
///
/// Wave phase for the variability model: at each x column the zero crossings of eta(t) split the
/// record into half waves, numbered from 0; a half wave with eta > 0 is a crest, else a trough.
/// The column nearest to x is used.
///
/// Memory: two records at a time; moving forward in time reads at most one record per call.
/// Not thread-safe to setTime(); sample() and phase() are const and safe to call from many
/// threads between setTime() calls.

#include "storm/StormFile.hpp"

#include <cstdint>
#include <vector>

namespace armour::storm {

/// The flow at one point and time. Velocities in m/s, pressure in Pa (gauge), alpha in [0, 1].
struct FlowSample {
  double p = 0.0;
  double u = 0.0;
  double v = 0.0;
  double w = 0.0;
  double alpha = 0.0;
  bool valid = false;  ///< false: outside the grid or no data around the point (values are 0)
  bool filled = false; ///< sampleExtended()/rateExtended(): some weight fell on the gap fill
};

/// Where a point is in the wave cycle at its x.
struct WavePhase {
  bool crest = false;           ///< eta > 0 (above the still water level) in this half wave
  std::int64_t halfWave = 0;    ///< index of the half wave at this x since the first record (unit: -)
  double elevation = 0.0;       ///< eta(x, t): free surface above the still water level (unit: m)
};

class StormSampler {
public:
  /// The reader must outlive the sampler.
  explicit StormSampler(const StormReader& reader);

  /// Make t current: reads the records that bracket t if they are not held. Throws
  /// core::InputError if t is outside [first, last] record time (naming the file and the range).
  void setTime(double t);
  [[nodiscard]] double time() const { return time_; }

  /// Flow at (x, z) at the current time.
  [[nodiscard]] FlowSample sample(double x, double z) const;
  /// Time derivative of the velocity at (x, z): the slope between the two bracketing records
  /// (unit: m/s^2; the local derivative du/dt, not the material derivative).
  [[nodiscard]] FlowSample rate(double x, double z) const;
  /// The flow anywhere, for the solver's pressure integration (docs/theory.md, "Elements beyond
  /// the sampling box" and "Elements in voxels without data"):
  ///  - inside the outermost centres, sample(), but a corner without data takes the gap fill at its
  ///    voxel centre (x_i, z_k) instead of being dropped (filled = true when one with weight did):
  ///    with the column's free surface zs = still water level + eta_i(t), below zs alpha = 1,
  ///    p = rho g (zs - z_k) and the velocity of the nearest voxel with data of the column (in z)
  ///    that is wet (alpha >= 0.5; none: 0); above zs alpha = p = 0 and no velocity;
  ///  - beyond the outermost columns (any distance), the value at the edge column (x clamped);
  ///  - beyond the outermost rows, p(z) = p(z_edge) -/+ rho g (z - z_edge) with alpha and velocity
  ///    of the edge row (down: p grows; up: it falls, and where it reaches 0 the point is in air).
  /// valid = false only for a NaN coordinate. A file without gaps gives sample()'s values bit for
  /// bit inside the outermost centres.
  [[nodiscard]] FlowSample sampleExtended(double x, double z) const;
  /// rate() with the same rules: at a filled corner d/dt of the source voxel's velocity and
  /// rho g d(eta_i)/dt for p (alpha: 0); beyond the rows the edge row's rates (0 where the point
  /// is in air).
  [[nodiscard]] FlowSample rateExtended(double x, double z) const;

  /// Where sampleExtended() and rateExtended() read for one point: its (up to four) corners with
  /// their weights and which of them take the gap fill, and how far the point lies beyond the
  /// outermost rows. Locate once, then ask for the value and, where needed, the rate: the same
  /// numbers as the two calls, without finding the cell twice.
  struct Located {
    bool valid = false;          ///< false only for a NaN coordinate
    bool filled = false;         ///< some weight falls on the gap fill
    int corners = 0;
    std::size_t voxel[4] = {0, 0, 0, 0};
    double weight[4] = {0, 0, 0, 0};
    bool gapFill[4] = {false, false, false, false}; ///< the corner takes the gap fill (no data)
    double rowOffset = 0.0;      ///< z minus the z clamped to the outermost rows (unit: m)
  };
  [[nodiscard]] Located locateExtended(double x, double z) const;
  [[nodiscard]] FlowSample sampleExtended(const Located& at) const { return extended(at, false); }
  [[nodiscard]] FlowSample rateExtended(const Located& at) const { return extended(at, true); }
  /// Does the file have voxels without data (samples = 0)? (Then the gap fill can apply.)
  [[nodiscard]] bool hasGaps() const { return hasGaps_; }
  /// Free-surface elevation and wave phase at x, current time. Outside the x range: the edge column.
  [[nodiscard]] WavePhase phase(double x) const;

  [[nodiscard]] const StormReader& reader() const { return reader_; }

  /// One axis of the grid's voxel centres with the reciprocals a lookup multiplies by.
  struct Axis {
    explicit Axis(const std::vector<double>& centres);
    std::vector<double> centres;
    double inverseSpacing = 0.0;       ///< 1 / (c_1 - c_0) (unit: 1/m)
    std::vector<double> inverseWidth;  ///< 1 / (c_(i+1) - c_i) per cell (unit: 1/m)
  };

private:
  const StormReader& reader_;
  Axis axisX_, axisZ_;
  double time_ = 0.0;
  std::size_t lower_ = 0;      ///< index of the record at or before time_
  double weight_ = 0.0;        ///< weight of record lower_ + 1 (unit: -)
  StormRecord a_, b_;          ///< records lower_ and lower_ + 1
  /// The file's values at every voxel at time_ (blended from a_ and b_) and their time derivative,
  /// computed once per setTime() so that a sample reads one voxel's values from one place.
  struct VoxelFlows {
    FlowSample now, slope;
  };
  std::vector<VoxelFlows> blended_;
  std::size_t heldA_ = SIZE_MAX, heldB_ = SIZE_MAX;
  /// Per x column, the times of the zero crossings of eta (increasing).
  std::vector<std::vector<double>> crossings_;
  /// Per x column, the z indices of its voxels with data (increasing): the gap fill's sources.
  std::vector<std::vector<std::size_t>> dataLevels_;
  bool hasGaps_ = false;

  /// The gap fill at the centre of voxel (ix, iz); `rate`: its time derivative instead.
  [[nodiscard]] FlowSample fill(std::size_t ix, std::size_t iz, bool rate) const;
  /// sampleExtended() (rate = false) and rateExtended() at a located point.
  [[nodiscard]] FlowSample extended(const Located& at, bool rate) const;
  /// The located corners' bilinear sum (fill corners: the gap fill at their centre).
  [[nodiscard]] FlowSample cornerSum(const Located& at, bool rate) const;
  /// sample() (rate = false) and rate().
  [[nodiscard]] FlowSample interpolate(double x, double z, bool rate) const;
  /// interpolate() in the cell (ix, iz) at fractions (tx, tz), as locate() found them.
  [[nodiscard]] FlowSample interpolateCell(std::size_t ix, std::size_t iz, double tx, double tz, bool rate) const;
  /// The file's values at voxel i, current time (rate: their time derivative).
  [[nodiscard]] FlowSample voxel(std::size_t i, bool rate) const;
  /// Fill blended_ for the held records and weight_.
  void blendRecords();
  static void accumulate(FlowSample& out, double weight, const FlowSample& v);
};

} // namespace armour::storm
