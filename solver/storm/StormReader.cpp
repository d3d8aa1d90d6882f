// SPDX-License-Identifier: GPL-3.0-or-later
// StormReader (StormFile.hpp): opens a storm file, checks its layout, units and header, and reads
// and checks records one by one.
#include "storm/StormFile.hpp"
#include "storm/StormFormat.hpp"

#include "core/Error.hpp"
#include "core/ProbeInChild.hpp"

#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <system_error>

namespace armour::storm {

// The layout shared with the writer (StormFormat.hpp).
using namespace detail;

namespace {

std::string joinQuoted(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) {
    out += (out.empty() ? "'" : ", '") + s + "'";
  }
  return out;
}

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

  /// The optional global attribute uniform_along_y: absent = false (files written before it existed).
  bool readUniformAlongY() const;
  void open();
  void readVariability();
};

bool StormReader::Impl::readUniformAlongY() const {
  constexpr const char* kName = "uniform_along_y";
  nc_type type = NC_NAT;
  std::size_t length = 0;
  if (nc_inq_att(ncid, NC_GLOBAL, kName, &type, &length) != NC_NOERR) {
    return false; // bounded: loads only between trunk_origin and trunk_origin + trunk_length
  }
  const bool integer = type == NC_BYTE || type == NC_SHORT || type == NC_INT || type == NC_UBYTE ||
                       type == NC_USHORT || type == NC_UINT || type == NC_INT64 || type == NC_UINT64;
  if (!integer || length != 1) {
    const std::string have = type == NC_CHAR || (type == NC_STRING && length == 1)
                                 ? fmt::format("the text '{}'", text(NC_GLOBAL, "", kName))
                                 : fmt::format("of netCDF type {} with {} value(s)", static_cast<int>(type), length);
    core::failInput(path, "the global attribute {} is {}: it must be one integer, 0 (the fields hold only on the "
                          "trunk section trunk_origin .. trunk_origin + trunk_length) or 1 (they hold at every y, "
                          "e.g. a 2D tank); rewrite it, e.g. ncatted -a {},global,o,i,1 (a 2D tank) or ...,o,i,0 "
                          "(a 3D section)",
                    kName, have, kName);
  }
  long long value = 0;
  checkRead(nc_get_att_longlong(ncid, NC_GLOBAL, kName, &value), std::string("reading attribute ") + kName);
  if (value != 0 && value != 1) {
    core::failInput(path, "the global attribute {} = {}: must be 0 (the fields hold only on the trunk section "
                          "trunk_origin .. trunk_origin + trunk_length) or 1 (they hold at every y, e.g. a 2D tank); "
                          "rewrite it, e.g. ncatted -a {},global,o,i,1 (a 2D tank) or ...,o,i,0 (a 3D section)",
                    kName, value, kName);
  }
  return value == 1;
}

void StormReader::Impl::open() {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    core::failInput(path, "no such file; check the path (storm files are written by foam-bridge or `armour storm-file "
                          "synth`)");
  }
  // libhdf5 1.10 can crash inside nc_open on damaged metadata: read the header and the first and
  // last records in a child process first (core/ProbeInChild.hpp); a crash there refuses the file.
  core::probeInChild(path, {"storm file", "regenerate it (foam-proxy sample, or armour storm-file synth) or copy it "
                                          "again"},
                     [this] {
                       const StormReader probe(path); // in the child: no second probe
                       StormRecord record;
                       probe.read(0, record);
                       probe.read(probe.times().size() - 1, record);
                     });
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
  h.uniformAlongY = readUniformAlongY();

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

std::size_t StormReader::intervalOf(double t) const {
  const std::vector<double>& times = impl_->times;
  const auto it = std::upper_bound(times.begin(), times.end(), t);
  const std::size_t after = static_cast<std::size_t>(it - times.begin()); // first record after t
  return std::min(after == 0 ? 0 : after - 1, times.size() - 2);
}

std::size_t StormReader::validateRecords(double from, double to) const {
  const std::size_t first = intervalOf(from);
  const std::size_t last = intervalOf(to) + 1;
  StormRecord record;
  for (std::size_t k = first; k <= last; ++k) {
    read(k, record);
  }
  return last - first + 1;
}

} // namespace armour::storm
