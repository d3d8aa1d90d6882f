// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/BodySeriesFile.hpp"
#include "io/BodySeriesReader.hpp"

#include "core/AtomicFile.hpp"
#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <netcdf.h>

#include <algorithm>
#include <cstdlib>
#include <array>
#include <ctime>
#include <stdexcept>
#include <system_error>

namespace armour::io {
namespace {

/// Largest chunk we ask HDF5 for. netCDF gives every variable its own chunk cache and enlarges
/// it to hold a chunk, but a chunk that is only partly filled when it leaves the cache is read
/// back, decompressed and recompressed on the next record: keeping chunks to 1 MiB keeps each
/// variable's working chunk resident (netCDF 4.9's default cache is 16 MiB) and the cost of a
/// flush small, while 64 records of a few hundred bodies still fit in one chunk.
constexpr std::size_t kMaxChunkBytes = std::size_t{1} << 20;
/// Records copied per read/write when a resumed file is rebuilt (bounded memory, few calls).
constexpr std::size_t kCopyBytes = std::size_t{8} << 20;
/// Records per chunk of the time coordinate: small and read whole by every tool, so uncompressed.
constexpr std::size_t kTimeChunk = 1024;

constexpr const char* kAxesComment =
    "world frame: x onshore (wave direction), y along the breakwater trunk, z up; vec index 0, 1, 2 = x, y, z";

/// The variables that grow along time, in the order a record is written (time last, so that a
/// record cut short by a kill shows the fill value as its time).
constexpr std::array<const char*, 8> kRecordVariables = {
    "position", "orientation", "velocity", "angular_velocity", "contact_count", "max_contact_force", "hydro_force", "time"};

struct Chunking {
  std::size_t records;
  std::size_t bodies;
};

/// Chunk shape (records x bodies) for a variable of `width` values of `bytes` each per body.
Chunking chunkShape(std::size_t requestedRecords, std::size_t bodies, std::size_t width, std::size_t bytes) {
  const std::size_t record = bodies * width * bytes;
  if (record >= kMaxChunkBytes) {
    return {1, std::max<std::size_t>(1, kMaxChunkBytes / (width * bytes))};
  }
  return {std::clamp<std::size_t>(kMaxChunkBytes / record, 1, std::max<std::size_t>(1, requestedRecords)), bodies};
}

/// Records per chunk that fill whole chunks when blocks of `block` records are written: a
/// multiple of `block` when a chunk holds more, a divisor of it when it holds fewer. At most
/// `records` (the byte limit), at least 1.
std::size_t alignedChunkRecords(std::size_t records, std::size_t block) {
  if (records >= block) {
    return records / block * block;
  }
  std::size_t r = records;
  while (r > 1 && block % r != 0) {
    --r;
  }
  return r;
}

std::string readTextAttribute(int ncid, int var, const char* name) {
  nc_type type = NC_NAT;
  std::size_t length = 0;
  if (nc_inq_att(ncid, var, name, &type, &length) != NC_NOERR || type != NC_CHAR) {
    return {};
  }
  std::string text(length, '\0');
  if (length > 0 && nc_get_att_text(ncid, var, name, text.data()) != NC_NOERR) {
    return {};
  }
  return text;
}

/// Closes a file opened for reading on every path out of the resume code.
struct ReadOnlyFile {
  int ncid = -1;
  ~ReadOnlyFile() {
    if (ncid >= 0) {
      nc_close(ncid);
    }
  }
};

} // namespace

void BodySeriesFile::check(int status, const char* what) const {
  if (status != NC_NOERR) {
    core::failInput(settings_.path.string(),
                    "netCDF could not {}: {}; check that the folder is writable and the disk is not full",
                    what, nc_strerror(status));
  }
}

void BodySeriesFile::create(const std::filesystem::path& file, const std::vector<SeriesBody>& bodies,
                            const std::string& history) {
  check(nc_create(file.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid_), "create the file");
  const std::size_t n = bodies.size();
  std::size_t nameLength = 1;
  for (const auto& b : bodies) {
    nameLength = std::max(nameLength, b.name.size());
  }

  const auto text = [&](int var, const char* name, const std::string& value) {
    check(nc_put_att_text(ncid_, var, name, value.size(), value.c_str()), "write an attribute");
  };
  text(NC_GLOBAL, "Conventions", "CF-1.8");
  text(NC_GLOBAL, "title", settings_.title);
  text(NC_GLOBAL, "source", "armour " + core::version());
  text(NC_GLOBAL, "history", history);
  for (const auto& [name, value] : settings_.textAttributes) text(NC_GLOBAL, name.c_str(), value);
  for (const auto& [name, value] : settings_.numberAttributes)
    check(nc_put_att_double(ncid_, NC_GLOBAL, name.c_str(), NC_DOUBLE, 1, &value), "write an attribute");
  text(NC_GLOBAL, "comment",
       "Rigid-body state of every body at each series output time (armour, docs/output-files.md). "
       "Axes: x onshore (wave direction), y along the breakwater trunk, z up. SI units.");

  int timeDim = -1, bodyDim = -1, vecDim = -1, quatDim = -1, strDim = -1;
  check(nc_def_dim(ncid_, "time", NC_UNLIMITED, &timeDim), "define the time dimension");
  check(nc_def_dim(ncid_, "body", n, &bodyDim), "define the body dimension");
  check(nc_def_dim(ncid_, "vec", 3, &vecDim), "define the vec dimension");
  check(nc_def_dim(ncid_, "quat", 4, &quatDim), "define the quat dimension");
  check(nc_def_dim(ncid_, "name_strlen", nameLength, &strDim), "define the name_strlen dimension");

  int timeVar = -1, positionVar = -1, orientationVar = -1, velocityVar = -1, angularVar = -1, contactCountVar = -1,
      maxForceVar = -1, externalForceVar = -1;
  check(nc_def_var(ncid_, "time", NC_DOUBLE, 1, &timeDim, &timeVar), "define time");
  const std::size_t timeChunk = kTimeChunk;
  check(nc_def_var_chunking(ncid_, timeVar, NC_CHUNKED, &timeChunk), "chunk time");
  text(timeVar, "units", "s");
  text(timeVar, "standard_name", "time");
  text(timeVar, "long_name", "simulated time");
  text(timeVar, "axis", "T");

  int idVar = -1, nameVar = -1;
  check(nc_def_var(ncid_, "body_id", NC_INT, 1, &bodyDim, &idVar), "define body_id");
  text(idVar, "long_name", "body id");
  text(idVar, "units", "1");
  const std::array<int, 2> nameDims{bodyDim, strDim};
  check(nc_def_var(ncid_, "body_name", NC_CHAR, 2, nameDims.data(), &nameVar), "define body_name");
  text(nameVar, "long_name", "body name");

  // Data variables (time, body[, vec|quat]), chunked along time and deflated.
  const auto define = [&](const char* name, nc_type type, int componentDim, std::size_t width, const char* units,
                          const char* longName, int& var) {
    std::array<int, 3> dims{timeDim, bodyDim, componentDim};
    const int ndims = componentDim >= 0 ? 3 : 2;
    check(nc_def_var(ncid_, name, type, ndims, dims.data(), &var), "define a variable");
    auto chunk = chunkShape(settings_.chunkRecords, n, width, type == NC_DOUBLE ? 8 : 4);
    // Whole chunks per flush (flush() writes syncEvery records into a reopened file): a chunk
    // rewritten by a later flush would leave its old copy as dead space in the file.
    chunk.records = alignedChunkRecords(chunk.records, settings_.syncEvery);
    const std::array<std::size_t, 3> chunks{chunk.records, chunk.bodies, width};
    check(nc_def_var_chunking(ncid_, var, NC_CHUNKED, chunks.data()), "set the chunking");
    if (settings_.deflateLevel > 0) {
      // Shuffle groups the bytes of equal significance, which is what lets zlib squeeze doubles.
      check(nc_def_var_deflate(ncid_, var, 1, 1, std::clamp(settings_.deflateLevel, 1, 9)), "set the compression");
    }
    text(var, "units", units);
    text(var, "long_name", longName);
    text(var, "coordinates", "body_name");
    if (componentDim == vecDim) {
      text(var, "comment", kAxesComment);
    }
  };
  define("position", NC_DOUBLE, vecDim, 3, "m", "centre of mass position", positionVar);
  define("orientation", NC_DOUBLE, quatDim, 4, "1", "orientation quaternion (w, x, y, z), body to world",
         orientationVar);
  define("velocity", NC_DOUBLE, vecDim, 3, "m s-1", "centre of mass velocity", velocityVar);
  define("angular_velocity", NC_DOUBLE, vecDim, 3, "rad s-1", "angular velocity", angularVar);
  define("contact_count", NC_INT, -1, 1, "1", "number of contacts acting on the body", contactCountVar);
  define("max_contact_force", NC_DOUBLE, -1, 1, "N", "largest contact force magnitude on the body", maxForceVar);
  define("hydro_force", NC_DOUBLE, vecDim, 3, "N",
         "hydrodynamic load on the body (pressure, drag, added mass; zero without hydro), last force evaluation",
         externalForceVar);
  check(nc_enddef(ncid_), "finish the header");

  std::vector<std::int32_t> ids(n);
  std::vector<char> names(n * nameLength, '\0');
  for (std::size_t i = 0; i < n; ++i) {
    ids[i] = bodies[i].id;
    std::copy(bodies[i].name.begin(), bodies[i].name.end(), names.begin() + static_cast<std::ptrdiff_t>(i * nameLength));
  }
  check(nc_put_var_int(ncid_, idVar, ids.data()), "write body_id");
  check(nc_put_var_text(ncid_, nameVar, names.data()), "write body_name");
}

BodySeriesFile::BodySeriesFile(BodySeriesSettings settings, const std::vector<SeriesBody>& bodies)
    : settings_(std::move(settings)) {
  if (bodies.empty()) {
    throw std::logic_error("BodySeriesFile: no bodies");
  }
  settings_.syncEvery = std::max<std::size_t>(1, settings_.syncEvery);
  settings_.chunkRecords = std::max<std::size_t>(1, settings_.chunkRecords);
  // flush() reopens the file for each block. With HDF5's file locking on, a reader that holds the
  // file open (ncdump, a Python session, ParaView) would make that open fail and stop the run: the
  // writer does not take the lock (HDF5 reads the variable at each open). A user's own setting wins.
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);
  const auto& path = settings_.path;
  const auto folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) {
    core::failInput(path.string(), "cannot create the folder '{}' ({}); choose a writable output folder",
                    folder.string(), ec.message());
  }
  ids_.reserve(bodies.size());
  for (const auto& b : bodies) {
    ids_.push_back(b.id);
  }

  std::string history = fmt::format("{:%Y-%m-%dT%H:%M:%SZ}: {}", fmt::gmtime(std::time(nullptr)),
                                    settings_.history.empty() ? std::string("armour") : settings_.history);

  // Resume: read what the old file holds before it is replaced.
  ReadOnlyFile old;
  std::size_t keep = 0;
  if (settings_.resumeTime && std::filesystem::exists(path)) {
    keep = openForResume(old.ncid, bodies, history);
  } else if (settings_.resumeTime) {
    core::logger("io")->warn("{}: no file to resume; starting a new one at t = {} s", path.string(),
                             *settings_.resumeTime);
  }

  const auto tmp = core::temporarySibling(path);
  try {
    create(tmp, bodies, history);
    if (keep > 0) {
      copyRecords(old.ncid, keep);
    }
    records_ = keep;
    closeOpenFile();
    // The file is complete (header, bodies, kept records) and closed: only now does it take the
    // path the user expects.
    core::commitAtomicFile(tmp, path);
  } catch (...) {
    if (ncid_ >= 0) {
      nc_close(ncid_);
      ncid_ = -1;
    }
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
  std::vector<double>().swap(oldTimes_); // only the resume's messages needed them
  const std::size_t n = bodies.size();
  const std::size_t block = settings_.syncEvery;
  pendingTime_.resize(block);
  pendingVec_.resize(block * n * 3 * 4); // position, velocity, angular velocity, hydro force
  pendingQuat_.resize(block * n * 4);
  pendingCount_.resize(block * n);
  pendingForce_.resize(block * n);
}

std::size_t BodySeriesFile::openForResume(int& oldNcid, const std::vector<SeriesBody>& bodies, std::string& history) {
  const auto& path = settings_.path;
  // A damaged file can crash libhdf5 inside nc_open: the reader reads it in a child first
  // (core/ProbeInChild.hpp) and refuses it with the fix.
  (void)BodySeriesReader(path);
  check(nc_open(path.c_str(), NC_NOWRITE, &oldNcid), "open the file to resume it");
  int bodyDim = -1, strDim = -1, timeVar = -1, nameVar = -1, idVar = -1;
  if (nc_inq_dimid(oldNcid, "body", &bodyDim) != NC_NOERR || nc_inq_dimid(oldNcid, "name_strlen", &strDim) != NC_NOERR ||
      nc_inq_varid(oldNcid, "time", &timeVar) != NC_NOERR || nc_inq_varid(oldNcid, "body_name", &nameVar) != NC_NOERR ||
      nc_inq_varid(oldNcid, "body_id", &idVar) != NC_NOERR) {
    core::failInput(path.string(), "is not an armour body series file, so the run cannot be resumed from it; "
                                   "move it away or choose another output folder");
  }
  std::size_t oldBodies = 0, oldStrlen = 0, oldRecords = 0;
  int timeDim = -1;
  check(nc_inq_dimlen(oldNcid, bodyDim, &oldBodies), "read the body dimension");
  check(nc_inq_dimlen(oldNcid, strDim, &oldStrlen), "read the name_strlen dimension");
  check(nc_inq_vardimid(oldNcid, timeVar, &timeDim), "read the time dimension");
  check(nc_inq_dimlen(oldNcid, timeDim, &oldRecords), "read the time dimension");
  std::vector<char> names(oldBodies * oldStrlen);
  std::vector<std::int32_t> ids(oldBodies);
  if (oldBodies > 0) {
    check(nc_get_var_text(oldNcid, nameVar, names.data()), "read body_name");
    check(nc_get_var_int(oldNcid, idVar, ids.data()), "read body_id");
  }
  for (std::size_t i = 0; i < std::max(oldBodies, bodies.size()); ++i) {
    std::string oldName;
    if (i < oldBodies) {
      const auto* start = names.data() + i * oldStrlen;
      oldName.assign(start, std::find(start, start + oldStrlen, '\0'));
    }
    const bool same = i < oldBodies && i < bodies.size() && ids[i] == bodies[i].id && oldName == bodies[i].name;
    if (!same) {
      core::failInput(path.string(),
                      "lists {} bodies, the scene {}; body {} differs (file: '{}', scene: '{}'): the scene changed "
                      "since the run started. Resume with the original scene, or start a new run",
                      oldBodies, bodies.size(), i, oldName, i < bodies.size() ? bodies[i].name : std::string());
    }
  }
  oldTimes_.assign(oldRecords, 0.0);
  if (oldRecords > 0 && nc_get_var_double(oldNcid, timeVar, oldTimes_.data()) != NC_NOERR) {
    refuseDamaged(0, "time");
  }
  // Records are in increasing time; a record cut short by a kill has the (huge) fill value as
  // its time, so it is dropped here like any record after the resume time.
  std::size_t keep = 0;
  while (keep < oldRecords && oldTimes_[keep] <= *settings_.resumeTime &&
         (keep == 0 || oldTimes_[keep] > oldTimes_[keep - 1])) {
    ++keep;
  }
  if (keep > 0) {
    lastTime_ = oldTimes_[keep - 1];
  }
  const auto oldHistory = readTextAttribute(oldNcid, NC_GLOBAL, "history");
  if (!oldHistory.empty()) {
    history = oldHistory + "\n" + history + fmt::format(" (resumed at t = {} s)", *settings_.resumeTime);
  }
  core::logger("io")->info("{}: resuming at t = {} s: keeping {} of {} records", path.string(),
                           *settings_.resumeTime, keep, oldRecords);
  return keep;
}

void BodySeriesFile::refuseDamaged(std::size_t firstBad, const char* variable) const {
  const auto& path = settings_.path;
  const std::string from =
      firstBad < oldTimes_.size() ? fmt::format("record {} (t = {} s)", firstBad, oldTimes_[firstBad])
                                  : fmt::format("record {}", firstBad);
  core::failInput(path.string(),
                  "is damaged: its variable '{}' cannot be read from {} on, and the checkpoint needs its records "
                  "up to t = {} s (the run was killed while the file was being written). Move it away (e.g. "
                  "`mv {} {}.damaged`) and restart: the new file starts at the checkpoint, and the records before "
                  "are in the moved file as far as it can be read",
                  variable, from, *settings_.resumeTime, path.string(), path.filename().string());
}

void BodySeriesFile::copyRecords(int oldNcid, std::size_t keep) {
  // Rebuild rather than reopen: the records after the resume time cannot be removed from an
  // HDF5 file in place, and a file that says exactly what happened is worth one copy per restart.
  const auto& path = settings_.path;
  for (const char* name : kRecordVariables) {
    int from = -1, to = -1, ndims = 0;
    if (nc_inq_varid(oldNcid, name, &from) != NC_NOERR) {
      core::failInput(path.string(), "has no variable '{}', so the run cannot be resumed from it; move it away",
                      name);
    }
    check(nc_inq_varid(ncid_, name, &to), "find a variable");
    check(nc_inq_varndims(ncid_, to, &ndims), "read a variable's shape");
    int oldNdims = 0;
    nc_type oldType = NC_NAT, type = NC_NAT;
    check(nc_inq_varndims(oldNcid, from, &oldNdims), "read a variable's shape");
    check(nc_inq_vartype(oldNcid, from, &oldType), "read a variable's type");
    check(nc_inq_vartype(ncid_, to, &type), "read a variable's type");
    std::array<int, NC_MAX_VAR_DIMS> dims{};
    check(nc_inq_vardimid(ncid_, to, dims.data()), "read a variable's shape");
    std::array<std::size_t, 3> count{1, 1, 1};
    std::size_t recordValues = 1;
    for (int d = 1; d < ndims; ++d) {
      check(nc_inq_dimlen(ncid_, dims[static_cast<std::size_t>(d)], &count[static_cast<std::size_t>(d)]),
            "read a dimension");
      recordValues *= count[static_cast<std::size_t>(d)];
    }
    std::size_t valueBytes = 0;
    check(nc_inq_type(ncid_, type, nullptr, &valueBytes), "read a type");
    if (oldNdims != ndims || oldType != type) {
      core::failInput(path.string(), "variable '{}' has another shape or type than this version writes; "
                                     "the run cannot be resumed from it",
                      name);
    }
    const std::size_t block = std::max<std::size_t>(1, kCopyBytes / (recordValues * valueBytes));
    std::vector<unsigned char> buffer(std::min(block, keep) * recordValues * valueBytes);
    for (std::size_t first = 0; first < keep; first += block) {
      std::array<std::size_t, 3> start{first, 0, 0};
      count[0] = std::min(block, keep - first);
      if (nc_get_vara(oldNcid, from, start.data(), count.data(), buffer.data()) != NC_NOERR) {
        // Name the first record that cannot be read (a kill can damage HDF5's chunk index).
        std::size_t bad = first;
        count[0] = 1;
        for (; bad < first + std::min(block, keep - first); ++bad) {
          start[0] = bad;
          if (nc_get_vara(oldNcid, from, start.data(), count.data(), buffer.data()) != NC_NOERR) break;
        }
        refuseDamaged(bad, name);
      }
      check(nc_put_vara(ncid_, to, start.data(), count.data(), buffer.data()), "copy the records to keep");
    }
  }
}

BodySeriesFile::~BodySeriesFile() {
  try {
    close();
  } catch (const std::exception& e) {
    core::logger("io")->error("{}", e.what());
  }
}

void BodySeriesFile::append(const BodyFrame& frame) {
  if (closed_) {
    throw std::logic_error("BodySeriesFile::append after close");
  }
  const std::size_t n = ids_.size();
  if (frame.bodies.size() != n) {
    throw std::logic_error(fmt::format("BodySeriesFile::append: {} bodies, the file has {}", frame.bodies.size(), n));
  }
  if (records_ > 0 && !(frame.time > lastTime_)) {
    throw std::logic_error(fmt::format("BodySeriesFile::append: time {} s does not follow {} s", frame.time, lastTime_));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (frame.bodies[i].id != ids_[i]) {
      throw std::logic_error(
          fmt::format("BodySeriesFile::append: body {} has id {}, the file {}", i, frame.bodies[i].id, ids_[i]));
    }
  }
  // Stage the record; the file is opened only to take a block of syncEvery records.
  const std::size_t k = pending_;
  const std::size_t vecBlock = settings_.syncEvery * n * 3;
  const auto putVec = [&](std::size_t slot, auto member) {
    double* out = pendingVec_.data() + slot * vecBlock + k * n * 3;
    for (std::size_t i = 0; i < n; ++i) {
      const geometry::Vec3& v = frame.bodies[i].*member;
      out[3 * i] = v.x();
      out[3 * i + 1] = v.y();
      out[3 * i + 2] = v.z();
    }
  };
  putVec(0, &BodySnapshot::position);
  putVec(1, &BodySnapshot::velocity);
  putVec(2, &BodySnapshot::angularVelocity);
  putVec(3, &BodySnapshot::externalForce);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& q = frame.bodies[i].orientation;
    double* out = pendingQuat_.data() + (k * n + i) * 4;
    out[0] = q.w();
    out[1] = q.x();
    out[2] = q.y();
    out[3] = q.z();
    pendingCount_[k * n + i] = frame.bodies[i].contactCount;
    pendingForce_[k * n + i] = frame.bodies[i].maxContactForce;
  }
  pendingTime_[k] = frame.time;
  ++pending_;
  ++records_;
  lastTime_ = frame.time;
  if (pending_ >= settings_.syncEvery) {
    flush();
  }
}

void BodySeriesFile::flush() {
  if (pending_ == 0) {
    return;
  }
  check(nc_open(settings_.path.c_str(), NC_WRITE, &ncid_), "open the file to append records (was it moved?)");
  try {
    const std::size_t n = ids_.size();
    const std::array<std::size_t, 3> start{records_ - pending_, 0, 0};
    const std::array<std::size_t, 3> vecCount{pending_, n, 3};
    const std::array<std::size_t, 3> quatCount{pending_, n, 4};
    const auto var = [&](const char* name) {
      int id = -1;
      check(nc_inq_varid(ncid_, name, &id), "find a variable");
      return id;
    };
    const std::size_t vecBlock = settings_.syncEvery * n * 3;
    const std::array<const char*, 4> vecNames{"position", "velocity", "angular_velocity", "hydro_force"};
    for (std::size_t slot = 0; slot < vecNames.size(); ++slot) {
      check(nc_put_vara_double(ncid_, var(vecNames[slot]), start.data(), vecCount.data(),
                               pendingVec_.data() + slot * vecBlock),
            "write records");
    }
    check(nc_put_vara_double(ncid_, var("orientation"), start.data(), quatCount.data(), pendingQuat_.data()),
          "write records");
    check(nc_put_vara_int(ncid_, var("contact_count"), start.data(), vecCount.data(), pendingCount_.data()),
          "write records");
    check(nc_put_vara_double(ncid_, var("max_contact_force"), start.data(), vecCount.data(), pendingForce_.data()),
          "write records");
    // Time last: a block cut short by a kill shows the fill value as its time.
    check(nc_put_vara_double(ncid_, var("time"), start.data(), vecCount.data(), pendingTime_.data()), "write records");
  } catch (...) {
    nc_close(ncid_);
    ncid_ = -1;
    throw;
  }
  pending_ = 0;
  closeOpenFile();
}

void BodySeriesFile::closeOpenFile() {
  if (ncid_ < 0) {
    return;
  }
  const int status = nc_close(ncid_);
  ncid_ = -1;
  check(status, "close the file");
}

void BodySeriesFile::close() {
  if (closed_) {
    return;
  }
  closed_ = true;
  flush();
}

} // namespace armour::io
