// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/BodySeriesReader.hpp"

#include "core/Error.hpp"
#include "core/ProbeInChild.hpp"

#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace armour::io {

namespace fs = std::filesystem;

BodySeriesReader::BodySeriesReader(const fs::path& path) : path_(path) {
  if (!fs::exists(path))
    core::failInput(path.string(), "missing: the run folder has no body series; give the output folder of a run "
                                   "(`armour run` writes bodies.nc there when output.series_interval > 0)");
  // A damaged file can crash libhdf5 inside nc_open: read it in a child first (core/ProbeInChild.hpp).
  core::probeInChild(path.string(), {"body series file", "move it away (a restart from the checkpoint then starts the series anew) or rerun the scene"}, [&] {
    const BodySeriesReader probe(path); // in the child: no second probe
    std::vector<double> values;
    probe.positions(probe.records() - 1, 1, values);
    probe.orientations(probe.records() - 1, values);
  });
  check(nc_open(path.c_str(), NC_NOWRITE, &ncid_),
        "open (not a readable netCDF file: cut short or damaged, so rerun the scene or restart it from its "
        "checkpoint; or locked by a run still writing it, so set HDF5_USE_FILE_LOCKING=FALSE)");
  std::size_t strlen = 0;
  check(nc_inq_dimid(ncid_, "time", &timeDim_), "dimension 'time'");
  check(nc_inq_dimlen(ncid_, timeDim_, &records_), "dimension 'time'");
  int dim = 0;
  check(nc_inq_dimid(ncid_, "body", &dim), "dimension 'body'");
  check(nc_inq_dimlen(ncid_, dim, &bodies_), "dimension 'body'");
  check(nc_inq_dimid(ncid_, "name_strlen", &dim), "dimension 'name_strlen'");
  check(nc_inq_dimlen(ncid_, dim, &strlen), "dimension 'name_strlen'");
  check(nc_inq_varid(ncid_, "time", &timeVar_), "variable 'time'");
  check(nc_inq_varid(ncid_, "position", &positionVar_), "variable 'position'");
  check(nc_inq_varid(ncid_, "orientation", &orientationVar_), "variable 'orientation'");
  int nameVar = 0;
  check(nc_inq_varid(ncid_, "body_name", &nameVar), "variable 'body_name'");
  if (records_ < 1)
    core::failInput(path_.string(), "holds no records: the run stopped before its first series output; run it "
                                    "longer or restart it");
  times_.resize(records_);
  check(nc_get_var_double(ncid_, timeVar_, times_.data()), "variable 'time'");
  std::vector<char> names(bodies_ * std::max<std::size_t>(strlen, 1), '\0');
  if (strlen > 0) check(nc_get_var_text(ncid_, nameVar, names.data()), "variable 'body_name'");
  for (std::size_t b = 0; b < bodies_; ++b) {
    std::string n(names.data() + b * strlen, strlen);
    n = n.substr(0, n.find('\0'));
    names_.push_back(n);
  }
  std::size_t length = 0;
  if (nc_inq_attlen(ncid_, NC_GLOBAL, "history", &length) == NC_NOERR) {
    std::string h(length, '\0');
    if (nc_get_att_text(ncid_, NC_GLOBAL, "history", h.data()) == NC_NOERR) history_ = h;
  }
}

std::optional<std::string> BodySeriesReader::textAttribute(const char* name) const {
  nc_type type = NC_NAT;
  std::size_t length = 0;
  if (nc_inq_att(ncid_, NC_GLOBAL, name, &type, &length) != NC_NOERR || type != NC_CHAR) return std::nullopt;
  std::string text(length, '\0');
  check(nc_get_att_text(ncid_, NC_GLOBAL, name, text.data()), name);
  return text.substr(0, text.find('\0'));
}

std::optional<double> BodySeriesReader::numberAttribute(const char* name) const {
  nc_type type = NC_NAT;
  std::size_t length = 0;
  if (nc_inq_att(ncid_, NC_GLOBAL, name, &type, &length) != NC_NOERR) return std::nullopt;
  double value = std::numeric_limits<double>::quiet_NaN();
  if (type == NC_CHAR || length != 1 || nc_get_att_double(ncid_, NC_GLOBAL, name, &value) != NC_NOERR ||
      !std::isfinite(value))
    core::failInput(path_.string(), "global attribute '{}' is not one finite number; the file was not written by "
                                    "`armour run` or was edited: run again, or give the setting on the command line",
                    name);
  return value;
}

BodySeriesReader::~BodySeriesReader() {
  if (ncid_ >= 0) nc_close(ncid_);
}

void BodySeriesReader::positions(std::size_t k0, std::size_t n, std::vector<double>& out) const {
  out.resize(n * bodies_ * 3);
  const std::size_t start[3] = {k0, 0, 0}, count[3] = {n, bodies_, 3};
  check(nc_get_vara_double(ncid_, positionVar_, start, count, out.data()), "variable 'position'");
}

void BodySeriesReader::orientations(std::size_t k, std::vector<double>& out) const {
  out.resize(bodies_ * 4);
  const std::size_t start[3] = {k, 0, 0}, count[3] = {1, bodies_, 4};
  check(nc_get_vara_double(ncid_, orientationVar_, start, count, out.data()), "variable 'orientation'");
}

void BodySeriesReader::check(int status, const char* what) const {
  if (status != NC_NOERR)
    core::failInput(path_.string(), "{}: {}; is it the bodies.nc of an `armour run`? (see docs/output-files.md)",
                    what, nc_strerror(status));
}

} // namespace armour::io
