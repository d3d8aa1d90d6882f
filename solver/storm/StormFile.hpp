// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StormFile.hpp
/// The storm file: the contract between foam-bridge (writer) and the solver (reader), specified in
/// docs/storm-file.md. A y-averaged 2D (x, z) voxel slice of the breakwater with the time series of
/// total pressure, velocity and water fraction at the voxel centres, the free-surface elevation
/// eta(x, t), the samples per voxel m, the Weibull variability model of seed 000 and provenance.
///
/// netCDF-4 (HDF5), CF-1.8. Dimensions time (unlimited), z, x, class = 4, phase = 2. Data
/// variables are laid out (time, z, x), x fastest, chunked one time record per chunk so a writer
/// appends one record at a time and a reader reads one record at a time.
///
/// This header is deliberately plain C++11 (std::vector, std::array, std::string; no attributes,
/// no nested namespace definitions) so the foam-bridge function object, compiled with OpenFOAM's
/// -std=c++11 flags, can include it.
///
/// Axes: x in the wave direction (onshore), y along the trunk, z up. SI units. Pressure is gauge
/// (atmospheric = 0) and total: hydrostatic + dynamic.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armour {
namespace storm {

/// Version of the layout written (global attribute armour_storm_version). Readers accept
/// versions up to this one.
constexpr int kStormFormatVersion = 1;

/// The four variability classes of seed 000: crest or trough of the wave at the voxel's x, and a
/// sample above or below the voxel mean. Index into Variability::classes.
enum class VariabilityClass : int { CrestAbove = 0, CrestBelow = 1, TroughAbove = 2, TroughBelow = 3 };
constexpr int kVariabilityClasses = 4;
constexpr const char* kVariabilityClassNames[kVariabilityClasses] = {"crest_above", "crest_below", "trough_above",
                                                                     "trough_below"};

/// A two-parameter Weibull fit F(d) = 1 - exp(-(d/scale)^shape) of the normalised deviations
/// d = |p_sample - p_mean| / normalisation (docs/storm-file.md, "Variability").
struct WeibullFit {
  double shape = 1.0;        ///< k > 0 (unit: -)
  double scale = 0.0;        ///< lambda >= 0 (unit: -); 0 = no variability in this class
  double ksStatistic = -1.0; ///< Kolmogorov-Smirnov D of the fit; < 0 = not computed (unit: -)
  std::int64_t samples = 0;  ///< deviations the fit was made from; 0 = not fitted, given (unit: -)
};

/// The variability model (seed 000 section 2.2). A deviation drawn for a unit in class c has the
/// sign + with probability probabilityAbove[crest or trough] and magnitude
/// d ~ Weibull(classes[c]) x normalisationPressure x |eta| (eta is already above the still water level) / normalisationElevation.
struct Variability {
  bool present = false;                                ///< false: the file carries no variability model
  std::array<WeibullFit, kVariabilityClasses> classes; ///< by VariabilityClass
  /// Probability that a sample lies above the mean, in crests [0] and troughs [1] (unit: -).
  std::array<double, 2> probabilityAbove = {{0.5, 0.5}};
  double normalisationPressure = 0.0;  ///< P_n: deviations were divided by it (unit: Pa); rho g a_n for seed 000
  double normalisationElevation = 0.0; ///< a_n: the wave amplitude at which P_n was taken (unit: m)
  std::string source;                  ///< where the fits came from (run, command, date)
};

/// Who made the file and how (global attributes).
struct Provenance {
  std::string title;           ///< e.g. "Core-Loc trunk, 100-year storm, Hs 7 m, Tp 11 s"
  std::string sourceCase;      ///< OpenFOAM case directory or "synthetic: <model>"
  std::string openfoamVersion; ///< e.g. "v1912"; empty for synthetic files
  std::string software;        ///< writer's name and version, e.g. "armour 0.3.0 (git abc1234)"
  std::string command;         ///< the command line that created the file
  std::string comment;         ///< free text
};

/// Everything in a storm file except the time records.
struct StormHeader {
  std::vector<double> x;        ///< voxel centres in x, uniform spacing, increasing (unit: m)
  std::vector<double> z;        ///< voxel centres in z, uniform spacing, increasing (unit: m)
  double trunkOrigin = 0.0;     ///< y of the start of the extrusion (unit: m)
  double trunkLength = 0.0;     ///< length of the extrusion along y (unit: m); 44.5 in seed 000
  /// The fields hold at every y (a 2D tank, analytic waves): loads apply to units at any y;
  /// trunkOrigin/trunkLength then only record the y range averaged (unit: -). Global attribute
  /// uniform_along_y (0 or 1; absent = 0).
  bool uniformAlongY = false;
  double stillWaterLevel = 0.0; ///< z of the still water surface (unit: m)
  double waterDensity = 1025.0; ///< rho (unit: kg/m^3)
  double gravity = 9.81;        ///< |g| (unit: m/s^2)
  /// Samples averaged per voxel, m (z, x), x fastest; 0 = no data in the voxel (solid or empty):
  /// its data are _FillValue at every time. Synthetic files use 1 everywhere (unit: -).
  std::vector<std::int32_t> samples;
  bool hasVelocityY = false;    ///< the file carries v (sea_water_y_velocity); otherwise v = 0
  Variability variability;
  Provenance provenance;

  std::size_t nx() const { return x.size(); }
  std::size_t nz() const { return z.size(); }
  std::size_t voxels() const { return x.size() * z.size(); }
  double dx() const { return x.size() > 1 ? x[1] - x[0] : 0.0; }
  double dz() const { return z.size() > 1 ? z[1] - z[0] : 0.0; }
};

/// One time record. Voxel arrays are (z, x), x fastest, length nz * nx; eta has length nx.
/// In voxels with samples == 0 the values are ignored on write and NaN on read.
struct StormRecord {
  double time = 0.0;          ///< unit: s (since the start of the wave run)
  std::vector<double> p;      ///< total gauge pressure, hydrostatic included (unit: Pa)
  std::vector<double> u;      ///< x velocity (unit: m/s)
  std::vector<double> v;      ///< y velocity (unit: m/s); empty unless header.hasVelocityY
  std::vector<double> w;      ///< z velocity (unit: m/s)
  std::vector<double> alpha;  ///< water volume fraction, 0 = air, 1 = water (unit: -)
  std::vector<double> eta;    ///< free-surface elevation above the still water level, per x (unit: m)
};

/// How data variables are stored.
struct StormWriteOptions {
  bool doublePrecision = false; ///< NC_DOUBLE instead of NC_FLOAT for p, u, v, w, alpha, eta
  int deflateLevel = 1;         ///< 0 (none) to 9; 1 is nearly as small as 9 and several times faster
  bool shuffle = true;          ///< byte shuffle before deflate (smaller files for smooth fields)
  /// Close the file after every record and reopen it for the next, so a writer that is killed
  /// (SIGKILL, a crashed solver) leaves a whole "<path>.partial" holding every record appended so
  /// far, and other programs can read it meanwhile. Without it HDF5 keeps the records and the time
  /// dimension's length in its caches until the file is closed, and a killed writer leaves a file
  /// with 0 records; and a file open for writing can be left unreadable by a kill inside a flush.
  /// Costs an open and a close per record (docs/storm-file.md, "Writing"); the armourSampler
  /// function object sets it.
  bool syncEachRecord = false;
};

/// Writes a storm file record by record. The file is built under "<path>.partial" and renamed to
/// `path` by finish(), so a killed writer never leaves a file that looks complete.
/// Not thread-safe (nor is netCDF-C).
class StormWriter {
public:
  /// Validate the header (throws core::InputError naming the field and the fix) and create the file.
  StormWriter(const std::string& path, const StormHeader& header, const StormWriteOptions& options = {});
  ~StormWriter(); ///< an unfinished file is closed and left as "<path>.partial"
  StormWriter(const StormWriter&) = delete;
  StormWriter& operator=(const StormWriter&) = delete;

  /// Append one record. Times must increase strictly; arrays must have the header's sizes; values
  /// in data voxels (samples > 0) must be finite and alpha within [0, 1] (to 1e-6). Throws
  /// core::InputError naming the variable, the record time and the voxel (x, z).
  void append(const StormRecord& record);
  /// Replace the variability model written at creation (foam-proxy fits it after the records).
  void setVariability(const Variability& variability);
  /// Close and move into place. At least two records are required (a storm needs a time interval).
  void finish();
  std::size_t records() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads and validates a storm file. The constructor reads and checks the header, the time axis
/// and eta (small); records are read one at a time. Every error throws core::InputError naming
/// the file, the variable and the problem: missing, wrong units, wrong shape or dimension order,
/// non-monotonic time, non-uniform x or z, NaN where a voxel has data, a newer format version, or
/// not a netCDF file at all (truncated).
class StormReader {
public:
  explicit StormReader(const std::string& path);
  ~StormReader();
  StormReader(const StormReader&) = delete;
  StormReader& operator=(const StormReader&) = delete;

  const std::string& path() const;
  const StormHeader& header() const;
  const std::vector<double>& times() const;           ///< unit: s, strictly increasing
  /// eta of record k (unit: m above the still water level), length nx.
  const double* eta(std::size_t k) const;
  /// Read record k (0-based). Voxels without data are NaN; a NaN or infinity in a data voxel
  /// throws, naming variable, time and voxel.
  void read(std::size_t k, StormRecord& record) const;
  /// Read every record once (for `armour storm-file check`): throws on the first bad value.
  void validateAllRecords() const;
  /// The interval holding storm time t: the index k of the record at or before t, at most the
  /// last but one, so that records k and k + 1 are the pair a linear interpolation at t reads.
  /// @pre times().front() <= t <= times().back() (values outside are clamped to the first or last interval)
  std::size_t intervalOf(double t) const;
  /// Read every record an interpolation at storm times in [from, to] reads (for `armour check`:
  /// the records a run will use): throws on the first bad value, like read(). Returns how many
  /// records were read.
  std::size_t validateRecords(double from, double to) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace storm
} // namespace armour
