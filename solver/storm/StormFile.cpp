// SPDX-License-Identifier: GPL-3.0-or-later
#include "storm/StormFile.hpp"

#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <system_error>

namespace armour::storm {
namespace {

/// Relative tolerance of the uniform-spacing check of x and z. Coordinates written as x0 + i dx in
/// double differ from uniform by a few ulps of |x| (1e-13 relative to dx for |x| ~ 100 m, dx = 0.05 m);
/// a grid that is really non-uniform differs by far more than 1e-9.
constexpr double kUniformTolerance = 1e-9;
/// alpha outside [0, 1] by less than this is VOF round-off and is clamped; more is an error.
constexpr double kAlphaTolerance = 1e-6;
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

/// The voxel data variables in file order. v is optional (header.hasVelocityY).
struct DataVariableInfo {
  const char* name;
  const char* units;
  const char* standardName; ///< nullptr: none in the CF table
  const char* longName;
};
constexpr int kDataVariables = 5;
constexpr int kP = 0, kU = 1, kV = 2, kW = 3, kAlpha = 4;
constexpr DataVariableInfo kDataInfo[kDataVariables] = {
    {"p", "Pa", "sea_water_pressure_due_to_sea_water", "total pressure (hydrostatic + dynamic), gauge"},
    {"u", "m s-1", "sea_water_x_velocity", "velocity along x (onshore)"},
    {"v", "m s-1", "sea_water_y_velocity", "velocity along y (along the trunk)"},
    {"w", "m s-1", "upward_sea_water_velocity", "velocity along z (up)"},
    {"alpha", "1", nullptr, "water volume fraction (0 air, 1 water)"},
};

const std::vector<double>& recordArray(const StormRecord& r, int variable) {
  switch (variable) {
  case kP: return r.p;
  case kU: return r.u;
  case kV: return r.v;
  case kW: return r.w;
  default: return r.alpha;
  }
}

std::vector<double>& recordArray(StormRecord& r, int variable) {
  return const_cast<std::vector<double>&>(recordArray(static_cast<const StormRecord&>(r), variable));
}

/// Unit spellings a reader accepts besides the canonical one written (docs/storm-file.md, "Units").
const std::vector<std::string>& acceptedUnits(const std::string& canonical) {
  static const std::vector<std::string> metre{"m", "metre", "meter", "metres", "meters"};
  static const std::vector<std::string> second{"s", "second", "seconds", "sec"};
  static const std::vector<std::string> pascal{"Pa", "pascal", "pascals"};
  static const std::vector<std::string> velocity{"m s-1", "m/s", "m s^-1", "m.s-1"};
  static const std::vector<std::string> fraction{"1", "", "-", "m3 m-3", "m3/m3"};
  static const std::vector<std::string> none;
  if (canonical == "m") {
    return metre;
  }
  if (canonical == "s") {
    return second;
  }
  if (canonical == "Pa") {
    return pascal;
  }
  if (canonical == "m s-1") {
    return velocity;
  }
  if (canonical == "1") {
    return fraction;
  }
  return none;
}

std::string joinQuoted(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) {
    out += (out.empty() ? "'" : ", '") + s + "'";
  }
  return out;
}

/// Field names of the header checks: the C++ field for the writer, the netCDF name for the reader.
struct Naming {
  bool inFile;
  std::string operator()(const std::string& code, const std::string& file) const { return inFile ? file : code; }
};

void checkAxis(const std::string& where, const std::string& label, const std::vector<double>& c) {
  if (c.size() < 2) {
    core::failInput(where, "{} has {} value(s): at least 2 voxel centres are needed (values are interpolated "
                           "between neighbours)", label, c.size());
  }
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(c[i])) {
      core::failInput(where, "{}[{}] = {}: voxel centres must be finite (unit: m)", label, i, c[i]);
    }
  }
  const double d = c[1] - c[0];
  if (!(d > 0.0)) {
    core::failInput(where, "{}[0] = {} m, {}[1] = {} m: voxel centres must increase strictly; sort them", label, c[0],
                    label, c[1]);
  }
  for (std::size_t i = 1; i + 1 < c.size(); ++i) {
    const double di = c[i + 1] - c[i];
    if (!(std::abs(di - d) <= kUniformTolerance * d)) {
      core::failInput(where, "{}[{}] - {}[{}] = {} m but {}[1] - {}[0] = {} m: voxel centres must be uniformly "
                             "spaced (to 1e-9 relative); resample the fields onto a uniform grid",
                      label, i + 1, label, i, di, label, label, d);
    }
  }
}

void checkPositive(const std::string& where, const std::string& field, double value, const char* unitAndHint) {
  if (!(std::isfinite(value) && value > 0.0)) {
    core::failInput(where, "{} = {}: must be positive and finite ({})", field, value, unitAndHint);
  }
}

void checkFinite(const std::string& where, const std::string& field, double value, const char* unit) {
  if (!std::isfinite(value)) {
    core::failInput(where, "{} = {}: must be finite (unit: {})", field, value, unit);
  }
}

void validateVariability(const std::string& where, const Variability& v, const Naming& name) {
  if (!v.present) {
    return;
  }
  for (int c = 0; c < kVariabilityClasses; ++c) {
    const auto& fit = v.classes[static_cast<std::size_t>(c)];
    const std::string cls = kVariabilityClassNames[c];
    const std::string code = fmt::format("variability.classes[{}]", cls);
    if (!(std::isfinite(fit.shape) && fit.shape > 0.0)) {
      core::failInput(where, "{} = {}: the Weibull shape k must be positive; refit the {} deviations",
                      name(code + ".shape", fmt::format("weibull_shape[{}]", cls)), fit.shape, cls);
    }
    if (!(std::isfinite(fit.scale) && fit.scale >= 0.0)) {
      core::failInput(where, "{} = {}: the Weibull scale must be >= 0 (0 = no variability in this class)",
                      name(code + ".scale", fmt::format("weibull_scale[{}]", cls)), fit.scale);
    }
    if (!std::isfinite(fit.ksStatistic)) {
      core::failInput(where, "{} = {}: must be finite (a negative value means 'not computed')",
                      name(code + ".ksStatistic", fmt::format("weibull_ks[{}]", cls)), fit.ksStatistic);
    }
    if (fit.samples < 0) {
      core::failInput(where, "{} = {}: the number of fitted deviations must be >= 0 (0 = given, not fitted)",
                      name(code + ".samples", fmt::format("weibull_samples[{}]", cls)), fit.samples);
    }
  }
  for (std::size_t i = 0; i < 2; ++i) {
    const double pa = v.probabilityAbove[i];
    if (!(pa >= 0.0 && pa <= 1.0)) {
      core::failInput(where, "{} = {}: a probability must lie in [0, 1]",
                      name(fmt::format("variability.probabilityAbove[{}]", i),
                           fmt::format("probability_above[{}]", i == 0 ? "crest" : "trough")),
                      pa);
    }
  }
  checkPositive(where, name("variability.normalisationPressure", "normalisation_pressure"), v.normalisationPressure,
                "unit: Pa; rho g a_n, the pressure the deviations were divided by");
  checkPositive(where, name("variability.normalisationElevation", "normalisation_elevation"),
                v.normalisationElevation, "unit: m; the wave amplitude a_n at which P_n was taken");
}

/// The checks shared by the writer (on the header given) and the reader (on the header read).
void validateHeader(const std::string& where, const StormHeader& h, const Naming& name) {
  checkAxis(where, name("header.x", "x"), h.x);
  checkAxis(where, name("header.z", "z"), h.z);
  if (h.samples.size() != h.voxels()) {
    core::failInput(where, "{} has {} values; expected nz * nx = {} * {} = {} ((z, x) order, x fastest)",
                    name("header.samples", "samples"), h.samples.size(), h.nz(), h.nx(), h.voxels());
  }
  for (std::size_t k = 0; k < h.samples.size(); ++k) {
    if (h.samples[k] < 0) {
      core::failInput(where, "{}[{}] = {} at voxel x = {} m, z = {} m: samples per voxel must be >= 0 (0 = no data)",
                      name("header.samples", "samples"), k, h.samples[k], h.x[k % h.nx()], h.z[k / h.nx()]);
    }
  }
  checkPositive(where, name("header.waterDensity", "global attribute water_density"), h.waterDensity,
                "unit: kg/m^3; sea water is about 1025");
  checkPositive(where, name("header.gravity", "global attribute gravity"), h.gravity, "unit: m/s^2; 9.81 on Earth");
  checkPositive(where, name("header.trunkLength", "global attribute trunk_length"), h.trunkLength,
                "unit: m; the length along y of the trunk the fields were averaged over");
  checkFinite(where, name("header.trunkOrigin", "global attribute trunk_origin"), h.trunkOrigin, "m");
  checkFinite(where, name("header.stillWaterLevel", "global attribute still_water_level"), h.stillWaterLevel, "m");
  validateVariability(where, h.variability, name);
}

std::string utcNow() { return fmt::format("{:%Y-%m-%dT%H:%M:%SZ}", fmt::gmtime(std::time(nullptr))); }

/// The command of a history line "2024-01-31T12:00:00Z: command" (the last line: tools such as NCO
/// prepend their own lines).
std::string commandFromHistory(const std::string& history) {
  std::string line = history;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\0')) {
    line.pop_back();
  }
  const auto nl = line.rfind('\n');
  if (nl != std::string::npos) {
    line = line.substr(nl + 1);
  }
  // "YYYY-MM-DDTHH:MM:SSZ: " is 22 characters.
  if (line.size() >= 22 && line[4] == '-' && line[10] == 'T' && line[19] == 'Z' && line[20] == ':') {
    return line.substr(22);
  }
  return line;
}

} // namespace

// ------------------------------------------------------------------------------------------------
// Writer
// ------------------------------------------------------------------------------------------------

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

  ~Impl() {
    if (ncid >= 0) {
      nc_close(ncid);
      core::logger("storm")->warn("{}: the storm file was not finished; {} records are kept in '{}'", path, records,
                                  partial);
    }
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
  void writeVariability(const Variability& v);
  /// Check one field of `record` and convert it to the stored type at `out` (fill in empty voxels).
  void convertField(int variable, const StormRecord& record, std::size_t offset);
};

void StormWriter::Impl::define() {
  const auto& h = header;
  const bool dbl = options.doublePrecision;
  const nc_type dataType = dbl ? NC_DOUBLE : NC_FLOAT;
  const int level = std::clamp(options.deflateLevel, 0, 9);

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
  text(NC_GLOBAL, "source_case", h.provenance.sourceCase);
  text(NC_GLOBAL, "openfoam_version", h.provenance.openfoamVersion);
  text(NC_GLOBAL, "comment", h.provenance.comment);
  text(NC_GLOBAL, "axes", kAxesText);
  text(NC_GLOBAL, "references", "docs/storm-file.md (armour); seed 000, sections 2.2-2.3");

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

  // Variability model (seed 000 section 2.2).
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

  check(nc_enddef(ncid), "finish the header");

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
  writeVariability(h.variability);
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
  m.check(nc_create(m.partial.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid), "create the file");
  m.ncid = ncid;
  m.define();
}

StormWriter::~StormWriter() = default;

void StormWriter::append(const StormRecord& record) {
  auto& m = *impl_;
  m.requireOpen("append");
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
}

void StormWriter::setVariability(const Variability& variability) {
  auto& m = *impl_;
  m.requireOpen("setVariability");
  validateVariability(m.path, variability, Naming{false});
  m.writeVariability(variability);
  m.header.variability = variability;
}

void StormWriter::finish() {
  auto& m = *impl_;
  m.requireOpen("finish");
  if (m.records < 2) {
    core::failInput(m.path, "{} record(s) written: a storm file needs at least two records (a time interval); append "
                            "more before finish()", m.records);
  }
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

// ------------------------------------------------------------------------------------------------
// Reader
// ------------------------------------------------------------------------------------------------

struct StormReader::Impl {
  std::string path;
  int ncid = -1;
  StormHeader header;
  std::vector<double> times;
  std::vector<double> eta; ///< (time, x), x fastest
  int dataVar[kDataVariables] = {-1, -1, -1, -1, -1};
  double dataFill[kDataVariables] = {0, 0, 0, 0, 0};

  ~Impl() {
    if (ncid >= 0) {
      nc_close(ncid);
    }
  }

  [[noreturn]] void unreadable(const std::string& what, int status) const {
    core::failInput(path, "not a readable netCDF-4 file (truncated or not a storm file): {}: {}; copy or regenerate "
                          "the file", what, nc_strerror(status));
  }
  void checkRead(int status, const std::string& what) const {
    if (status != NC_NOERR) {
      unreadable(what, status);
    }
  }

  bool hasAttribute(int var, const char* name) const {
    int id = -1;
    return nc_inq_attid(ncid, var, name, &id) == NC_NOERR;
  }
  /// A text attribute, or `fallback` when it is absent. Throws when it exists but is not text.
  std::string text(int var, const std::string& varName, const char* name, const std::string& fallback = {}) const {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(ncid, var, name, &type, &length) != NC_NOERR) {
      return fallback;
    }
    if (type == NC_STRING && length == 1) {
      // netCDF-4 string attribute (some Python writers make these instead of char arrays).
      char* value = nullptr;
      checkRead(nc_get_att_string(ncid, var, name, &value), std::string("reading attribute ") + name);
      std::string out = value != nullptr ? value : "";
      nc_free_string(1, &value);
      return out;
    }
    if (type != NC_CHAR) {
      core::failInput(path, "{}attribute {} is not text (netCDF type {}); write it as a string",
                      varName.empty() ? "global " : varName + ": ", name, static_cast<int>(type));
    }
    std::string value(length, '\0');
    if (length > 0) {
      checkRead(nc_get_att_text(ncid, var, name, value.data()), std::string("reading attribute ") + name);
    }
    while (!value.empty() && value.back() == '\0') {
      value.pop_back();
    }
    return value;
  }
  double globalNumber(const char* name, const char* unit) const {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(ncid, NC_GLOBAL, name, &type, &length) != NC_NOERR) {
      core::failInput(path, "the global attribute {} ({}) is missing; a storm file carries it (docs/storm-file.md)",
                      name, unit);
    }
    if (type == NC_CHAR || type == NC_STRING || length != 1) {
      core::failInput(path, "the global attribute {} must be one number ({}); it has type {} and length {}", name,
                      unit, static_cast<int>(type), length);
    }
    double value = 0.0;
    checkRead(nc_get_att_double(ncid, NC_GLOBAL, name, &value), std::string("reading attribute ") + name);
    return value;
  }

  int dimension(const char* name) const {
    int id = -1;
    if (nc_inq_dimid(ncid, name, &id) != NC_NOERR) {
      core::failInput(path, "the dimension '{}' is missing; a storm file has dimensions time, z, x (docs/storm-file.md)",
                      name);
    }
    return id;
  }
  std::string dimName(int dim) const {
    char name[NC_MAX_NAME + 1] = {};
    nc_inq_dimname(ncid, dim, name);
    return name;
  }

  /// The id of variable `name` after checking its dimensions (in order), its type class and its units.
  int variable(const char* name, std::initializer_list<int> dims, bool floating, const std::string& units,
               bool required = true) const {
    int var = -1;
    if (nc_inq_varid(ncid, name, &var) != NC_NOERR) {
      if (!required) {
        return -1;
      }
      core::failInput(path, "the variable '{}' is missing; a storm file carries it (docs/storm-file.md)", name);
    }
    int ndims = 0;
    int varDims[NC_MAX_VAR_DIMS] = {};
    nc_type type = NC_NAT;
    checkRead(nc_inq_var(ncid, var, nullptr, &type, &ndims, varDims, nullptr), std::string("inquiring ") + name);
    const std::vector<int> expected(dims);
    bool same = ndims == static_cast<int>(expected.size());
    for (int i = 0; same && i < ndims; ++i) {
      same = varDims[i] == expected[static_cast<std::size_t>(i)];
    }
    if (!same) {
      std::string have, want, order;
      for (int i = 0; i < ndims; ++i) {
        have.append(i > 0 ? ", " : "").append(dimName(varDims[i]));
      }
      for (std::size_t i = 0; i < expected.size(); ++i) {
        want.append(i > 0 ? ", " : "").append(dimName(expected[i]));
        order.append(i > 0 ? "," : "").append(dimName(expected[i]));
      }
      core::failInput(path, "{} has dimensions ({}); expected ({}) in this order{}", name, have, want,
                      order.empty() ? std::string(" (a scalar)") : " (reorder with ncpdq -a " + order + ")");
    }
    if (floating && type != NC_FLOAT && type != NC_DOUBLE) {
      core::failInput(path, "{} has netCDF type {}; expected float or double", name, static_cast<int>(type));
    }
    if (!floating && !(type == NC_BYTE || type == NC_SHORT || type == NC_INT || type == NC_UBYTE ||
                       type == NC_USHORT || type == NC_UINT || type == NC_INT64 || type == NC_UINT64)) {
      core::failInput(path, "{} has netCDF type {}; expected an integer type", name, static_cast<int>(type));
    }
    if (hasAttribute(var, "scale_factor") || hasAttribute(var, "add_offset")) {
      core::failInput(path, "{} is packed (scale_factor/add_offset); unpack it first (ncpdq -U)", name);
    }
    if (!units.empty()) {
      const auto& accepted = acceptedUnits(units);
      if (!hasAttribute(var, "units")) {
        if (units != "1") {
          core::failInput(path, "{} has no units attribute; expected '{}'", name, units);
        }
      } else {
        const std::string have = text(var, name, "units");
        if (std::find(accepted.begin(), accepted.end(), have) == accepted.end()) {
          core::failInput(path, "{} has units '{}'; expected '{}' (accepted: {}); convert the values to SI", name, have,
                          units, joinQuoted(accepted));
        }
      }
    }
    return var;
  }

  std::vector<double> coordinate(const char* name, int dim, const std::string& units) const {
    const int var = variable(name, {dim}, true, units);
    nc_type type = NC_NAT;
    nc_inq_vartype(ncid, var, &type);
    if (type != NC_DOUBLE) {
      core::failInput(path, "{} is stored as float; coordinates must be double (float rounding breaks the uniform "
                            "spacing check and the interpolation)", name);
    }
    std::size_t n = 0;
    nc_inq_dimlen(ncid, dim, &n);
    std::vector<double> values(n);
    if (n > 0) {
      checkRead(nc_get_var_double(ncid, var, values.data()), std::string("reading ") + name);
    }
    return values;
  }

  double fillOf(int var) const {
    nc_type type = NC_NAT;
    nc_inq_vartype(ncid, var, &type);
    int noFill = 0;
    if (type == NC_FLOAT) {
      float fill = NC_FILL_FLOAT;
      nc_inq_var_fill(ncid, var, &noFill, &fill);
      return static_cast<double>(fill);
    }
    double fill = NC_FILL_DOUBLE;
    nc_inq_var_fill(ncid, var, &noFill, &fill);
    return fill;
  }

  void open();
  void readVariability();
};

void StormReader::Impl::open() {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    core::failInput(path, "no such file; check the path (storm files are written by foam-bridge or `armour storm-file "
                          "synth`)");
  }
  int id = -1;
  const int status = nc_open(path.c_str(), NC_NOWRITE, &id);
  if (status != NC_NOERR) {
    unreadable("nc_open", status);
  }
  ncid = id;

  // Version first: a newer layout may differ in everything below.
  {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(ncid, NC_GLOBAL, "armour_storm_version", &type, &length) != NC_NOERR) {
      core::failInput(path, "not a storm file: the global attribute armour_storm_version is missing "
                            "(docs/storm-file.md)");
    }
    int version = 0;
    if (type == NC_CHAR || type == NC_STRING || length != 1 ||
        nc_get_att_int(ncid, NC_GLOBAL, "armour_storm_version", &version) != NC_NOERR) {
      core::failInput(path, "the global attribute armour_storm_version must be one integer");
    }
    if (version > kStormFormatVersion) {
      core::failInput(path, "armour_storm_version = {}: this file is newer than this armour reads (up to version {}); "
                            "update armour", version, kStormFormatVersion);
    }
    if (version < 1) {
      core::failInput(path, "armour_storm_version = {}: invalid (versions start at 1)", version);
    }
  }

  const int timeDim = dimension("time");
  const int zDim = dimension("z");
  const int xDim = dimension("x");
  auto& h = header;
  h.x = coordinate("x", xDim, "m");
  h.z = coordinate("z", zDim, "m");
  times = coordinate("time", timeDim, "s");

  // samples (z, x)
  {
    const int var = variable("samples", {zDim, xDim}, false, "1");
    h.samples.assign(h.voxels(), 0);
    if (h.voxels() > 0) {
      checkRead(nc_get_var_int(ncid, var, h.samples.data()), "reading samples");
    }
  }
  h.stillWaterLevel = globalNumber("still_water_level", "m");
  h.waterDensity = globalNumber("water_density", "kg m-3");
  h.gravity = globalNumber("gravity", "m s-2");
  h.trunkOrigin = globalNumber("trunk_origin", "m");
  h.trunkLength = globalNumber("trunk_length", "m");

  auto& prov = h.provenance;
  prov.title = text(NC_GLOBAL, "", "title");
  prov.software = text(NC_GLOBAL, "", "source");
  prov.command = commandFromHistory(text(NC_GLOBAL, "", "history"));
  prov.sourceCase = text(NC_GLOBAL, "", "source_case");
  prov.openfoamVersion = text(NC_GLOBAL, "", "openfoam_version");
  prov.comment = text(NC_GLOBAL, "", "comment");

  readVariability();
  validateHeader(path, h, Naming{true});

  // Time axis: every record must have a time, in strictly increasing order.
  const std::size_t nt = times.size();
  if (nt < 2) {
    core::failInput(path, "{} record(s): a storm file needs at least two records (a time interval)", nt);
  }
  const int timeVar = variable("time", {timeDim}, true, "s");
  const double timeFill = fillOf(timeVar);
  for (std::size_t k = 0; k < nt; ++k) {
    if (times[k] == timeFill) {
      core::failInput(path, "time[{}] is the fill value: record {} was never completed (was the writer killed?); "
                            "regenerate the file", k, k);
    }
    if (!std::isfinite(times[k])) {
      core::failInput(path, "time[{}] = {}: record times must be finite", k, times[k]);
    }
    if (k > 0 && !(times[k] > times[k - 1])) {
      core::failInput(path, "time[{}] = {} s is not after time[{}] = {} s: record times must increase strictly", k,
                      times[k], k - 1, times[k - 1]);
    }
  }

  // Voxel data variables: checked here, read record by record.
  for (int k = 0; k < kDataVariables; ++k) {
    const int var = variable(kDataInfo[k].name, {timeDim, zDim, xDim}, true, kDataInfo[k].units, k != kV);
    dataVar[k] = var;
    if (var >= 0) {
      dataFill[k] = fillOf(var);
    }
  }
  h.hasVelocityY = dataVar[kV] >= 0;

  // eta (time, x): small, read whole.
  {
    const int var = variable("eta", {timeDim, xDim}, true, "m");
    const double fill = fillOf(var);
    eta.assign(nt * h.nx(), 0.0);
    checkRead(nc_get_var_double(ncid, var, eta.data()), "reading eta");
    for (std::size_t i = 0; i < eta.size(); ++i) {
      const double e = eta[i];
      if (e == fill || !std::isfinite(e)) {
        const std::size_t k = i / h.nx();
        const std::size_t ix = i % h.nx();
        core::failInput(path, "eta = {} at t = {} s (record {}), x = {} m (ix {}): the free-surface elevation must be "
                              "finite in every column and record; regenerate the file",
                        e == fill ? std::string("_FillValue") : fmt::format("{}", e), times[k], k, h.x[ix], ix);
      }
    }
  }
}

void StormReader::Impl::readVariability() {
  auto& v = header.variability;
  v = Variability{};
  nc_type type = NC_NAT;
  std::size_t length = 0;
  if (nc_inq_att(ncid, NC_GLOBAL, "variability_present", &type, &length) != NC_NOERR) {
    return; // no model: the solver adds no variability
  }
  int present = 0;
  if (type == NC_CHAR || type == NC_STRING || length != 1 ||
      nc_get_att_int(ncid, NC_GLOBAL, "variability_present", &present) != NC_NOERR) {
    core::failInput(path, "the global attribute variability_present must be 0 or 1");
  }
  v.source = text(NC_GLOBAL, "", "variability_source");
  if (present == 0) {
    return;
  }
  if (present != 1) {
    core::failInput(path, "variability_present = {}: must be 0 or 1", present);
  }
  v.present = true;
  const int classDim = dimension("class");
  const int phaseDim = dimension("phase");
  std::size_t nClass = 0, nPhase = 0;
  nc_inq_dimlen(ncid, classDim, &nClass);
  nc_inq_dimlen(ncid, phaseDim, &nPhase);
  if (nClass != kVariabilityClasses || nPhase != 2) {
    core::failInput(path, "dimensions class = {}, phase = {}: expected 4 variability classes and 2 phases", nClass,
                    nPhase);
  }
  double shape[kVariabilityClasses], scale[kVariabilityClasses], ks[kVariabilityClasses];
  long long count[kVariabilityClasses];
  checkRead(nc_get_var_double(ncid, variable("weibull_shape", {classDim}, true, "1"), shape), "reading weibull_shape");
  checkRead(nc_get_var_double(ncid, variable("weibull_scale", {classDim}, true, "1"), scale), "reading weibull_scale");
  checkRead(nc_get_var_double(ncid, variable("weibull_ks", {classDim}, true, "1"), ks), "reading weibull_ks");
  checkRead(nc_get_var_longlong(ncid, variable("weibull_samples", {classDim}, false, "1"), count),
            "reading weibull_samples");
  checkRead(nc_get_var_double(ncid, variable("probability_above", {phaseDim}, true, "1"), v.probabilityAbove.data()),
            "reading probability_above");
  checkRead(nc_get_var_double(ncid, variable("normalisation_pressure", {}, true, "Pa"), &v.normalisationPressure),
            "reading normalisation_pressure");
  checkRead(nc_get_var_double(ncid, variable("normalisation_elevation", {}, true, "m"), &v.normalisationElevation),
            "reading normalisation_elevation");
  for (std::size_t c = 0; c < kVariabilityClasses; ++c) {
    v.classes[c].shape = shape[c];
    v.classes[c].scale = scale[c];
    v.classes[c].ksStatistic = ks[c];
    v.classes[c].samples = static_cast<std::int64_t>(count[c]);
  }
}

StormReader::StormReader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->open();
}

StormReader::~StormReader() = default;

const std::string& StormReader::path() const { return impl_->path; }
const StormHeader& StormReader::header() const { return impl_->header; }
const std::vector<double>& StormReader::times() const { return impl_->times; }

const double* StormReader::eta(std::size_t k) const {
  if (k >= impl_->times.size()) {
    throw std::out_of_range(fmt::format("{}: eta of record {} requested; the file has {} records", impl_->path, k,
                                        impl_->times.size()));
  }
  return impl_->eta.data() + k * impl_->header.nx();
}

void StormReader::read(std::size_t k, StormRecord& record) const {
  const auto& m = *impl_;
  const auto& h = m.header;
  if (k >= m.times.size()) {
    throw std::out_of_range(fmt::format("{}: record {} requested; the file has {} records", m.path, k, m.times.size()));
  }
  const std::size_t n = h.voxels();
  const std::size_t start[3] = {k, 0, 0};
  const std::size_t count[3] = {1, h.nz(), h.nx()};
  record.time = m.times[k];
  for (int var = 0; var < kDataVariables; ++var) {
    auto& out = recordArray(record, var);
    if (m.dataVar[var] < 0) {
      out.clear();
      continue;
    }
    const char* name = kDataInfo[var].name;
    out.resize(n);
    m.checkRead(nc_get_vara_double(m.ncid, m.dataVar[var], start, count, out.data()),
                fmt::format("reading {} at record {}", name, k));
    const double fill = m.dataFill[var];
    for (std::size_t i = 0; i < n; ++i) {
      if (h.samples[i] <= 0) {
        out[i] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      const double value = out[i];
      const bool isFill = value == fill;
      const bool bad = isFill || !std::isfinite(value) ||
                       (var == kAlpha && (value < -kAlphaTolerance || value > 1.0 + kAlphaTolerance));
      if (bad) {
        core::failInput(m.path, "{} = {} at t = {} s (record {}), voxel x = {} m, z = {} m (ix {}, iz {}) which has "
                                "samples = {}: {}; the file is damaged or its writer is faulty: regenerate it",
                        name, isFill ? std::string("_FillValue") : fmt::format("{}", value), m.times[k], k,
                        h.x[i % h.nx()], h.z[i / h.nx()], i % h.nx(), i / h.nx(), h.samples[i],
                        var == kAlpha && std::isfinite(value) && !isFill
                            ? "the water fraction must lie in [0, 1]"
                            : "a voxel with data must hold a finite value");
      }
      if (var == kAlpha) {
        out[i] = std::clamp(value, 0.0, 1.0); // round-off of an external writer (within 1e-6)
      }
    }
  }
  const double* e = eta(k);
  record.eta.assign(e, e + h.nx());
}

void StormReader::validateAllRecords() const {
  StormRecord record;
  for (std::size_t k = 0; k < impl_->times.size(); ++k) {
    read(k, record);
  }
}

} // namespace armour::storm
