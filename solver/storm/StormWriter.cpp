// SPDX-License-Identifier: GPL-3.0-or-later
// StormWriter (StormFile.hpp): writes a storm file record by record to "<path>.partial" and moves
// it into place at finish().
#include "storm/StormFile.hpp"
#include "storm/StormFormat.hpp"

#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>

namespace armour::storm {

// The layout shared with the reader (StormFormat.hpp).
using namespace detail;

namespace {

/// Records per chunk of the time coordinate (8 KiB): read whole by every tool, so uncompressed.
constexpr std::size_t kTimeChunk = 1024;
/// Records per chunk of eta (100 KiB for nx = 100 floats), which the reader reads whole at open.
/// One record per chunk makes 72 000 chunks of 400 bytes for a one-hour storm, each with an HDF5
/// B-tree entry and a deflate header: bench_storm_io's open test measured 0.80 s CPU to read eta
/// (and 8 MB more on disk) against 0.15 s with 256 records and 0.13 s with 1024. 256 records stay
/// in the chunk cache while the writer appends them one by one.
constexpr std::size_t kEtaChunkRecords = 256;

constexpr const char* kAxesText = "x onshore (wave direction), y along the trunk, z up; SI units";
constexpr const char* kCellMethods = "y: mean";

std::string utcNow() { return fmt::format("{:%Y-%m-%dT%H:%M:%SZ}", fmt::gmtime(std::time(nullptr))); }

} // namespace

struct StormWriter::Impl {
  std::string path;
  std::string partial;
  StormHeader header;
  StormWriteOptions options;
  int ncid = -1;
  int timeVar = -1;
  int etaVar = -1;
  int dataVar[kDataVariables] = {-1, -1, -1, -1, -1};
  int shapeVar = -1, scaleVar = -1, ksVar = -1, countVar = -1, aboveVar = -1, pnVar = -1, anVar = -1;
  std::size_t records = 0;
  double lastTime = -std::numeric_limits<double>::infinity();
  bool finished = false;
  std::vector<float> floats;
  std::vector<double> doubles;

  bool created = false; ///< the .partial file exists with its header

  ~Impl() {
    if (ncid >= 0) nc_close(ncid);
    if (created && !finished) {
      core::logger("storm")->warn("{}: the storm file was not finished; {} records are kept in '{}'", path, records,
                                  partial);
    }
  }

  /// With syncEachRecord the file is closed between records (closeBetweenRecords): open it again.
  void reopen() {
    if (ncid < 0) check(nc_open(partial.c_str(), NC_WRITE, &ncid), "reopen the file");
  }
  /// With syncEachRecord: close the file after a record. HDF5 is not crash-safe while a file is
  /// open for writing (a kill inside a flush can leave it unreadable: 1 in 40 kills of a run
  /// writing bodies.nc, session 23); closed, it is whole, and other programs can read it.
  void closeBetweenRecords() {
    if (!options.syncEachRecord || ncid < 0) return;
    const int id = ncid;
    ncid = -1;
    check(nc_close(id), "close the file after a record");
  }

  void check(int status, const char* what) const {
    if (status != NC_NOERR) {
      core::failInput(path, "netCDF could not {} in '{}': {}; check that the folder is writable and the disk is not "
                            "full", what, partial, nc_strerror(status));
    }
  }
  void text(int var, const char* name, const std::string& value) const {
    check(nc_put_att_text(ncid, var, name, value.size(), value.c_str()), "write a text attribute");
  }
  void number(int var, const char* name, double value) const {
    check(nc_put_att_double(ncid, var, name, NC_DOUBLE, 1, &value), "write a numeric attribute");
  }
  void requireOpen(const char* call) const {
    if (finished) {
      throw std::logic_error(fmt::format("{}: StormWriter::{} after finish()", path, call));
    }
  }

  void define();
  /// The global attributes: conventions, provenance, water, trunk (define mode).
  void defineGlobalAttributes();
  /// The variability model's variables (seed 000 section 2.2) over the class and phase dimensions.
  void defineVariability(int classDim, int phaseDim);
  /// The coordinates, their bounds and the sample counts (data mode): x, z, y, x_bnds, z_bnds,
  /// y_bnds, samples.
  void writeCoordinates(const std::array<int, 7>& vars);
  void writeVariability(const Variability& v);
  /// Check one field of `record` and convert it to the stored type at `out` (fill in empty voxels).
  void convertField(int variable, const StormRecord& record, std::size_t offset);
};

void StormWriter::Impl::define() {
  const auto& h = header;
  const bool dbl = options.doublePrecision;
  const nc_type dataType = dbl ? NC_DOUBLE : NC_FLOAT;
  const int level = std::clamp(options.deflateLevel, 0, 9);

  defineGlobalAttributes();

  int timeDim = -1, zDim = -1, xDim = -1, classDim = -1, phaseDim = -1, nvDim = -1;
  check(nc_def_dim(ncid, "time", NC_UNLIMITED, &timeDim), "define the time dimension");
  check(nc_def_dim(ncid, "z", h.nz(), &zDim), "define the z dimension");
  check(nc_def_dim(ncid, "x", h.nx(), &xDim), "define the x dimension");
  check(nc_def_dim(ncid, "class", kVariabilityClasses, &classDim), "define the class dimension");
  check(nc_def_dim(ncid, "phase", 2, &phaseDim), "define the phase dimension");
  check(nc_def_dim(ncid, "nv", 2, &nvDim), "define the nv dimension");

  const auto compress = [&](int var) {
    if (level > 0) {
      // Shuffle groups the bytes of equal significance, which is what lets zlib squeeze floats.
      check(nc_def_var_deflate(ncid, var, options.shuffle ? 1 : 0, 1, level), "set the compression");
    }
  };

  // Coordinates.
  check(nc_def_var(ncid, "time", NC_DOUBLE, 1, &timeDim, &timeVar), "define time");
  check(nc_def_var_chunking(ncid, timeVar, NC_CHUNKED, &kTimeChunk), "chunk time");
  text(timeVar, "units", "s");
  text(timeVar, "standard_name", "time");
  text(timeVar, "axis", "T");
  text(timeVar, "long_name", "time since the start of the wave run");

  int xVar = -1, zVar = -1, yVar = -1, xb = -1, zb = -1, yb = -1;
  check(nc_def_var(ncid, "x", NC_DOUBLE, 1, &xDim, &xVar), "define x");
  text(xVar, "units", "m");
  text(xVar, "axis", "X");
  text(xVar, "long_name", "voxel centre along the wave direction (onshore)");
  text(xVar, "bounds", "x_bnds");
  check(nc_def_var(ncid, "z", NC_DOUBLE, 1, &zDim, &zVar), "define z");
  text(zVar, "units", "m");
  text(zVar, "axis", "Z");
  text(zVar, "positive", "up");
  text(zVar, "long_name", "voxel centre, elevation");
  text(zVar, "bounds", "z_bnds");
  // The extrusion along y as a scalar coordinate with bounds, so that cell_methods "y: mean" names
  // a coordinate (CF 7.3) and tools see over which y range the values were averaged.
  check(nc_def_var(ncid, "y", NC_DOUBLE, 0, nullptr, &yVar), "define y");
  text(yVar, "units", "m");
  text(yVar, "axis", "Y");
  text(yVar, "long_name", "middle of the trunk section the values are averaged over (along the trunk)");
  text(yVar, "bounds", "y_bnds");
  if (h.uniformAlongY) {
    text(yVar, "comment", "the fields hold at every y (global attribute uniform_along_y = 1); y_bnds is only the "
                          "range the values were averaged over");
  }
  const int xbDims[2] = {xDim, nvDim};
  const int zbDims[2] = {zDim, nvDim};
  check(nc_def_var(ncid, "x_bnds", NC_DOUBLE, 2, xbDims, &xb), "define x_bnds");
  check(nc_def_var(ncid, "z_bnds", NC_DOUBLE, 2, zbDims, &zb), "define z_bnds");
  check(nc_def_var(ncid, "y_bnds", NC_DOUBLE, 1, &nvDim, &yb), "define y_bnds");

  // Voxel data (time, z, x): one record per chunk so a record is written and read as one piece.
  const int dataDims[3] = {timeDim, zDim, xDim};
  const std::size_t dataChunk[3] = {1, h.nz(), h.nx()};
  for (int k = 0; k < kDataVariables; ++k) {
    if (k == kV && !h.hasVelocityY) {
      continue;
    }
    const auto& info = kDataInfo[k];
    int& var = dataVar[k];
    check(nc_def_var(ncid, info.name, dataType, 3, dataDims, &var), "define a data variable");
    check(nc_def_var_chunking(ncid, var, NC_CHUNKED, dataChunk), "chunk a data variable");
    compress(var);
    if (dbl) {
      const double fill = NC_FILL_DOUBLE;
      check(nc_def_var_fill(ncid, var, NC_FILL, &fill), "set _FillValue");
    } else {
      const float fill = NC_FILL_FLOAT;
      check(nc_def_var_fill(ncid, var, NC_FILL, &fill), "set _FillValue");
    }
    text(var, "units", info.units);
    if (info.standardName != nullptr) {
      text(var, "standard_name", info.standardName);
    }
    text(var, "long_name", info.longName);
    text(var, "cell_methods", kCellMethods);
    text(var, "coordinates", "y");
    if (k == kP) {
      text(var, "comment", "gauge pressure: atmospheric = 0 Pa; hydrostatic included");
    }
  }

  const int etaDims[2] = {timeDim, xDim};
  const std::size_t etaChunk[2] = {kEtaChunkRecords, h.nx()};
  check(nc_def_var(ncid, "eta", dataType, 2, etaDims, &etaVar), "define eta");
  check(nc_def_var_chunking(ncid, etaVar, NC_CHUNKED, etaChunk), "chunk eta");
  compress(etaVar);
  text(etaVar, "units", "m");
  text(etaVar, "standard_name", "sea_surface_height_above_mean_sea_level");
  text(etaVar, "long_name", "free-surface elevation above the still water level");
  text(etaVar, "cell_methods", kCellMethods);
  text(etaVar, "coordinates", "y");
  text(etaVar, "comment", "datum: the still water level (global attribute still_water_level)");

  int samplesVar = -1;
  const int samplesDims[2] = {zDim, xDim};
  check(nc_def_var(ncid, "samples", NC_INT, 2, samplesDims, &samplesVar), "define samples");
  compress(samplesVar);
  text(samplesVar, "units", "1");
  text(samplesVar, "long_name", "surface samples averaged per voxel (m of seed 000); 0 = no data");

  defineVariability(classDim, phaseDim);

  check(nc_enddef(ncid), "finish the header");

  writeCoordinates({xVar, zVar, yVar, xb, zb, yb, samplesVar});
  writeVariability(h.variability);
}

void StormWriter::Impl::defineGlobalAttributes() {
  const auto& h = header;
  text(NC_GLOBAL, "Conventions", "CF-1.8");
  text(NC_GLOBAL, "title", h.provenance.title);
  text(NC_GLOBAL, "source", h.provenance.software.empty() ? "armour " + core::version() : h.provenance.software);
  text(NC_GLOBAL, "history",
       utcNow() + ": " + (h.provenance.command.empty() ? std::string("armour storm writer") : h.provenance.command));
  const int version = kStormFormatVersion;
  check(nc_put_att_int(ncid, NC_GLOBAL, "armour_storm_version", NC_INT, 1, &version), "write armour_storm_version");
  number(NC_GLOBAL, "still_water_level", h.stillWaterLevel);
  number(NC_GLOBAL, "water_density", h.waterDensity);
  number(NC_GLOBAL, "gravity", h.gravity);
  number(NC_GLOBAL, "trunk_origin", h.trunkOrigin);
  number(NC_GLOBAL, "trunk_length", h.trunkLength);
  // Always written (0 or 1), so the file says which kind it is; readers treat an absent one as 0.
  const int uniform = h.uniformAlongY ? 1 : 0;
  check(nc_put_att_int(ncid, NC_GLOBAL, "uniform_along_y", NC_INT, 1, &uniform), "write uniform_along_y");
  text(NC_GLOBAL, "source_case", h.provenance.sourceCase);
  text(NC_GLOBAL, "openfoam_version", h.provenance.openfoamVersion);
  text(NC_GLOBAL, "comment", h.provenance.comment);
  text(NC_GLOBAL, "axes", kAxesText);
  text(NC_GLOBAL, "references", "docs/storm-file.md (armour); seed 000, sections 2.2-2.3");
}

void StormWriter::Impl::defineVariability(int classDim, int phaseDim) {
  const std::string classNames = fmt::format("{} {} {} {}", kVariabilityClassNames[0], kVariabilityClassNames[1],
                                             kVariabilityClassNames[2], kVariabilityClassNames[3]);
  const auto classVar = [&](const char* name, nc_type type, const char* units, const char* longName, int& var) {
    check(nc_def_var(ncid, name, type, 1, &classDim, &var), "define a variability variable");
    text(var, "units", units);
    text(var, "long_name", longName);
    text(var, "class_names", classNames);
  };
  classVar("weibull_shape", NC_DOUBLE, "1", "Weibull shape k of the normalised deviations", shapeVar);
  classVar("weibull_scale", NC_DOUBLE, "1", "Weibull scale lambda of the normalised deviations (0 = none)", scaleVar);
  classVar("weibull_ks", NC_DOUBLE, "1", "Kolmogorov-Smirnov statistic D of the fit (< 0 = not computed)", ksVar);
  classVar("weibull_samples", NC_INT64, "1", "deviations the fit was made from (0 = given, not fitted)", countVar);
  check(nc_def_var(ncid, "probability_above", NC_DOUBLE, 1, &phaseDim, &aboveVar), "define probability_above");
  text(aboveVar, "units", "1");
  text(aboveVar, "long_name", "probability that a sample lies above the voxel mean");
  text(aboveVar, "phase_names", "crest trough");
  check(nc_def_var(ncid, "normalisation_pressure", NC_DOUBLE, 0, nullptr, &pnVar), "define normalisation_pressure");
  text(pnVar, "units", "Pa");
  text(pnVar, "long_name", "pressure P_n the deviations were divided by (rho g a_n)");
  check(nc_def_var(ncid, "normalisation_elevation", NC_DOUBLE, 0, nullptr, &anVar), "define normalisation_elevation");
  text(anVar, "units", "m");
  text(anVar, "long_name", "wave amplitude a_n at which P_n was taken");
}

void StormWriter::Impl::writeCoordinates(const std::array<int, 7>& vars) {
  const auto& h = header;
  const auto [xVar, zVar, yVar, xb, zb, yb, samplesVar] = vars;
  check(nc_put_var_double(ncid, xVar, h.x.data()), "write x");
  check(nc_put_var_double(ncid, zVar, h.z.data()), "write z");
  const double y = h.trunkOrigin + 0.5 * h.trunkLength;
  const double ybounds[2] = {h.trunkOrigin, h.trunkOrigin + h.trunkLength};
  check(nc_put_var_double(ncid, yVar, &y), "write y");
  check(nc_put_var_double(ncid, yb, ybounds), "write y_bnds");
  const auto bounds = [](const std::vector<double>& c) {
    const double half = 0.5 * (c[1] - c[0]);
    std::vector<double> b(2 * c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      b[2 * i] = c[i] - half;
      b[2 * i + 1] = c[i] + half;
    }
    return b;
  };
  check(nc_put_var_double(ncid, xb, bounds(h.x).data()), "write x_bnds");
  check(nc_put_var_double(ncid, zb, bounds(h.z).data()), "write z_bnds");
  check(nc_put_var_int(ncid, samplesVar, h.samples.data()), "write samples");
}

void StormWriter::Impl::writeVariability(const Variability& v) {
  double shape[kVariabilityClasses], scale[kVariabilityClasses], ks[kVariabilityClasses];
  long long count[kVariabilityClasses];
  for (std::size_t c = 0; c < kVariabilityClasses; ++c) {
    shape[c] = v.classes[c].shape;
    scale[c] = v.classes[c].scale;
    ks[c] = v.classes[c].ksStatistic;
    count[c] = static_cast<long long>(v.classes[c].samples);
  }
  check(nc_put_var_double(ncid, shapeVar, shape), "write weibull_shape");
  check(nc_put_var_double(ncid, scaleVar, scale), "write weibull_scale");
  check(nc_put_var_double(ncid, ksVar, ks), "write weibull_ks");
  check(nc_put_var_longlong(ncid, countVar, count), "write weibull_samples");
  check(nc_put_var_double(ncid, aboveVar, v.probabilityAbove.data()), "write probability_above");
  check(nc_put_var_double(ncid, pnVar, &v.normalisationPressure), "write normalisation_pressure");
  check(nc_put_var_double(ncid, anVar, &v.normalisationElevation), "write normalisation_elevation");
  // netCDF-4 lets attributes change after nc_enddef (the library re-enters define mode itself).
  const int present = v.present ? 1 : 0;
  check(nc_put_att_int(ncid, NC_GLOBAL, "variability_present", NC_INT, 1, &present), "write variability_present");
  text(NC_GLOBAL, "variability_source", v.source);
}

void StormWriter::Impl::convertField(int variable, const StormRecord& record, std::size_t offset) {
  const auto& h = header;
  const auto& src = recordArray(record, variable);
  const char* name = kDataInfo[variable].name;
  const std::size_t n = h.voxels();
  const auto fail = [&](std::size_t i, double value, const char* rule) {
    core::failInput(path, "record at t = {} s: {} = {} at voxel x = {} m, z = {} m (ix {}, iz {}, samples {}): {}",
                    record.time, name, value, h.x[i % h.nx()], h.z[i / h.nx()], i % h.nx(), i / h.nx(),
                    h.samples[i], rule);
  };
  const bool isAlpha = variable == kAlpha;
  const auto value = [&](std::size_t i) {
    double x = src[i];
    if (!std::isfinite(x)) {
      fail(i, x, "values must be finite where the voxel has data (samples > 0); check the sampled CFD field");
    }
    if (isAlpha) {
      if (x < -kAlphaTolerance || x > 1.0 + kAlphaTolerance) {
        fail(i, x, "the water fraction must lie in [0, 1] (to 1e-6); check the VOF field sampled as alpha");
      }
      x = std::clamp(x, 0.0, 1.0);
    }
    return x;
  };
  if (options.doublePrecision) {
    double* out = doubles.data() + offset;
    for (std::size_t i = 0; i < n; ++i) {
      out[i] = h.samples[i] > 0 ? value(i) : NC_FILL_DOUBLE;
    }
  } else {
    float* out = floats.data() + offset;
    for (std::size_t i = 0; i < n; ++i) {
      if (h.samples[i] > 0) {
        const double x = value(i);
        if (std::abs(x) > static_cast<double>(FLT_MAX)) {
          fail(i, x, "the value exceeds the float range; write the file with doublePrecision");
        }
        out[i] = static_cast<float>(x);
      } else {
        out[i] = NC_FILL_FLOAT;
      }
    }
  }
}

StormWriter::StormWriter(const std::string& path, const StormHeader& header, const StormWriteOptions& options)
    : impl_(std::make_unique<Impl>()) {
  auto& m = *impl_;
  m.path = path;
  m.partial = path + ".partial";
  m.header = header;
  m.options = options;
  validateHeader(path, header, Naming{false});
  if (options.deflateLevel < 0 || options.deflateLevel > 9) {
    core::failInput(path, "deflateLevel = {}: must be 0 (none) to 9; 1 is the default", options.deflateLevel);
  }
  const std::filesystem::path p(path);
  if (p.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(p.parent_path(), ec);
    if (ec) {
      core::failInput(path, "cannot create the folder '{}' ({}); choose a writable folder", p.parent_path().string(),
                      ec.message());
    }
  }
  int ncid = -1;
  if (m.options.syncEachRecord) {
    // The file is reopened for each record: a reader holding it open (ncdump, Python) would make
    // that open fail with HDF5's file locking on. A user's own setting wins.
    ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  }
  m.check(nc_create(m.partial.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid), "create the file");
  m.ncid = ncid;
  m.define();
  m.created = true;
  m.closeBetweenRecords();
}

StormWriter::~StormWriter() = default;

void StormWriter::append(const StormRecord& record) {
  auto& m = *impl_;
  m.requireOpen("append");
  m.reopen();
  const auto& h = m.header;
  const std::size_t n = h.voxels();
  if (!std::isfinite(record.time)) {
    core::failInput(m.path, "record {}: time = {} s: record times must be finite", m.records, record.time);
  }
  if (m.records > 0 && !(record.time > m.lastTime)) {
    core::failInput(m.path, "record {}: time = {} s is not after the previous record's {} s: record times must "
                            "increase strictly", m.records, record.time, m.lastTime);
  }
  for (int k = 0; k < kDataVariables; ++k) {
    const auto& a = recordArray(record, k);
    if (k == kV && !h.hasVelocityY) {
      if (!a.empty()) {
        core::failInput(m.path, "record at t = {} s: v has {} values but header.hasVelocityY is false: leave v empty "
                                "or create the file with hasVelocityY = true", record.time, a.size());
      }
      continue;
    }
    if (a.size() != n) {
      core::failInput(m.path, "record at t = {} s: {} has {} values; expected nz * nx = {} * {} = {} ((z, x) order, "
                              "x fastest)", record.time, kDataInfo[k].name, a.size(), h.nz(), h.nx(), n);
    }
  }
  if (record.eta.size() != h.nx()) {
    core::failInput(m.path, "record at t = {} s: eta has {} values; expected nx = {} (one per x column)", record.time,
                    record.eta.size(), h.nx());
  }
  for (std::size_t i = 0; i < h.nx(); ++i) {
    if (!std::isfinite(record.eta[i])) {
      core::failInput(m.path, "record at t = {} s: eta = {} at x = {} m (ix {}): the free-surface elevation must be "
                              "finite in every column", record.time, record.eta[i], h.x[i], i);
    }
    if (!m.options.doublePrecision && std::abs(record.eta[i]) > static_cast<double>(FLT_MAX)) {
      core::failInput(m.path, "record at t = {} s: eta = {} at x = {} m exceeds the float range", record.time,
                      record.eta[i], h.x[i]);
    }
  }

  // Convert and check every field before writing any, so a refused record leaves no trace.
  // Time is written last: a record cut short by a kill shows the fill value as its time.
  const std::size_t start[3] = {m.records, 0, 0};
  const std::size_t count[3] = {1, h.nz(), h.nx()};
  std::size_t fields = 0;
  for (int k = 0; k < kDataVariables; ++k) {
    fields += m.dataVar[k] >= 0 ? 1 : 0;
  }
  if (m.options.doublePrecision) {
    m.doubles.resize(fields * n);
  } else {
    m.floats.resize(fields * n);
  }
  std::size_t offset = 0;
  for (int k = 0; k < kDataVariables; ++k) {
    if (m.dataVar[k] >= 0) {
      m.convertField(k, record, offset);
      offset += n;
    }
  }
  offset = 0;
  for (int k = 0; k < kDataVariables; ++k) {
    if (m.dataVar[k] < 0) {
      continue;
    }
    if (m.options.doublePrecision) {
      m.check(nc_put_vara_double(m.ncid, m.dataVar[k], start, count, m.doubles.data() + offset), "write a record");
    } else {
      m.check(nc_put_vara_float(m.ncid, m.dataVar[k], start, count, m.floats.data() + offset), "write a record");
    }
    offset += n;
  }
  const std::size_t etaStart[2] = {m.records, 0};
  const std::size_t etaCount[2] = {1, h.nx()};
  m.check(nc_put_vara_double(m.ncid, m.etaVar, etaStart, etaCount, record.eta.data()), "write eta");
  m.check(nc_put_var1_double(m.ncid, m.timeVar, &m.records, &record.time), "write time");
  m.lastTime = record.time;
  ++m.records;
  // With syncEachRecord the record and the new length of the time dimension reach the file now,
  // and the file is closed: a killed writer leaves them readable in the .partial file.
  m.closeBetweenRecords();
}

void StormWriter::setVariability(const Variability& variability) {
  auto& m = *impl_;
  m.requireOpen("setVariability");
  validateVariability(m.path, variability, Naming{false});
  m.reopen();
  m.writeVariability(variability);
  m.header.variability = variability;
  m.closeBetweenRecords();
}

void StormWriter::finish() {
  auto& m = *impl_;
  m.requireOpen("finish");
  if (m.records < 2) {
    core::failInput(m.path, "{} record(s) written: a storm file needs at least two records (a time interval); append "
                            "more before finish()", m.records);
  }
  m.reopen();
  const int ncid = m.ncid;
  m.ncid = -1;
  m.finished = true;
  m.check(nc_close(ncid), "close the file");
  std::error_code ec;
  std::filesystem::rename(m.partial, m.path, ec);
  if (ec) {
    core::failInput(m.path, "cannot move the finished file '{}' into place ({}); the data are intact: rename it by "
                            "hand or check the folder permissions", m.partial, ec.message());
  }
}

std::size_t StormWriter::records() const { return impl_->records; }

} // namespace armour::storm
