// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BodySeriesFile.hpp
/// The per-body time series of a run (bodies.nc): netCDF-4, CF-1.8, one record per output time.
/// Also the plain `BodyFrame` the solver fills at each output time, shared with VtkFrameWriter:
/// the writers never see the World, only this snapshot.
///
/// File layout (docs/output-files.md): dimensions time (unlimited), body, vec = 3, quat = 4,
/// name_strlen; variables time, body_id, body_name, position, orientation, velocity,
/// angular_velocity, contact_count, max_contact_force. Axes: x onshore, y along the trunk, z up.
///
/// Crash safety: the file is created under a temporary name, given its header and body table,
/// closed, and only then renamed into place, so the path never holds a half-made header. Records
/// are staged in memory and written in blocks of `syncEvery`: flush() opens the file, appends the
/// block and closes it. Between flushes the file is closed and whole, so a killed run leaves a
/// readable file with every record up to the last flush, and other programs (ncdump, Python,
/// ParaView) can read it while the run goes on. HDF5 is not crash-safe while a file is open for
/// writing: a kill inside a flush (milliseconds per block) can damage the file; a resume from it
/// is then refused with the first unreadable record named and the fix.
///
/// Not thread-safe (nor is the netCDF-C library): use from one thread.

#include "geometry/TriangleMesh.hpp"

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace armour::io {

/// One body at one output time. World frame, SI units.
struct BodySnapshot {
  std::int32_t id = 0;                                         ///< stable body id (unit: -)
  geometry::Vec3 position = geometry::Vec3::Zero();            ///< centre of mass (unit: m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< unit, body to world (unit: -)
  geometry::Vec3 velocity = geometry::Vec3::Zero();            ///< centre-of-mass velocity (unit: m/s)
  geometry::Vec3 angularVelocity = geometry::Vec3::Zero();     ///< world frame (unit: rad/s)
  std::int32_t contactCount = 0;                               ///< contacts acting on the body (unit: -)
  double maxContactForce = 0.0;                                ///< largest contact force magnitude (unit: N)
  geometry::Vec3 externalForce = geometry::Vec3::Zero();       ///< hydrodynamic (load-stage) force, world (unit: N)
  /// For VtkFrameWriter only: the shape's surface in the body frame (centre of mass at the
  /// origin, principal or shape axes as the solver uses them). Not owned; must outlive the call
  /// that receives the frame. nullptr: the body is left out of the VTK frame.
  const geometry::TriangleMesh* surface = nullptr;
  double scale = 1.0;                                          ///< uniform scale of `surface` (unit: -)
  /// For VtkFrameWriter only: the body never moves (a scene body with `fixed: true`), so its
  /// surface is written once, not in every frame.
  bool fixed = false;
};

/// All bodies at one output time. BodySeriesFile wants the same bodies in the same order every
/// time; VtkFrameWriter accepts any set (bodies may appear, e.g. during placement).
struct BodyFrame {
  double time = 0.0;                 ///< simulated time (unit: s)
  std::vector<BodySnapshot> bodies;
};

/// The body table, written once.
struct SeriesBody {
  std::int32_t id = 0; ///< matches BodySnapshot::id (unit: -)
  std::string name;    ///< e.g. "unit_0042"; ASCII, any length
};

struct BodySeriesSettings {
  std::filesystem::path path;        ///< the file, e.g. "<output>/bodies.nc"; its folder is created
  std::string title = "armour body time series"; ///< global attribute `title`
  std::string history;               ///< the command line; recorded, with the UTC time, in `history`
  /// Further global attributes, e.g. what the run replayed (docs/output-files.md): text ones and
  /// numbers (their units are the documentation's; netCDF global attributes carry none).
  std::vector<std::pair<std::string, std::string>> textAttributes;
  std::vector<std::pair<std::string, double>> numberAttributes;
  /// Continue a run: keep the existing file's records with time <= *resumeTime and append after
  /// them (the later ones belonged to the abandoned run after the checkpoint). No file: start anew.
  std::optional<double> resumeTime;  ///< (unit: s)
  std::size_t syncEvery = 16;        ///< records between flushes to disk (unit: records); >= 1
  std::size_t chunkRecords = 64;     ///< records per HDF5 chunk, reduced for very many bodies (unit: records)
  int deflateLevel = 2;              ///< zlib level 1-9 of the data variables (unit: -); 0 = none
};

/// Writer of bodies.nc.
///
/// @code
///   BodySeriesSettings settings;
///   settings.path = out / "bodies.nc";
///   settings.history = commandLine;
///   BodySeriesFile series(settings, bodies);
///   series.append(frame);  // every series interval
///   series.close();        // or let the destructor do it
/// @endcode
class BodySeriesFile {
public:
  /// Create the file (or, with settings.resumeTime, reopen it and drop the records after that
  /// time). Throws core::InputError naming the path (and netCDF's message) if the file cannot be
  /// created, or, on resume, if the existing file is not ours or lists other bodies.
  BodySeriesFile(BodySeriesSettings settings, const std::vector<SeriesBody>& bodies);
  /// Closes the file if close() was not called (errors are logged, not thrown).
  ~BodySeriesFile();
  BodySeriesFile(const BodySeriesFile&) = delete;
  BodySeriesFile& operator=(const BodySeriesFile&) = delete;

  /// Append one record.
  /// @pre frame.bodies lists the constructor's bodies in the same order (ids are checked) and
  ///      frame.time is greater than the previous record's; std::logic_error otherwise.
  /// Throws core::InputError naming the file if netCDF cannot write (disk full, ...).
  void append(const BodyFrame& frame);

  /// Write the staged records into the file now (append() does it every syncEvery records).
  void flush();

  /// Flush and close. Afterwards append() throws std::logic_error. Idempotent.
  void close();

  /// Records in the file, including those kept on resume.
  [[nodiscard]] std::size_t recordCount() const { return records_; }
  [[nodiscard]] const std::filesystem::path& path() const { return settings_.path; }

private:
  void check(int status, const char* what) const;
  void create(const std::filesystem::path& file, const std::vector<SeriesBody>& bodies, const std::string& history);
  /// Open the old file for resume (checks its bodies), read its times; the records to keep.
  std::size_t openForResume(int& oldNcid, const std::vector<SeriesBody>& bodies, std::string& history);
  /// Copy the first `keep` records of every record variable from the old file.
  void copyRecords(int oldNcid, std::size_t keep);
  /// Refuse a resume from a file whose records cannot be read from `firstBad` on.
  [[noreturn]] void refuseDamaged(std::size_t firstBad, const char* variable) const;
  void closeOpenFile();

  BodySeriesSettings settings_;
  std::vector<std::int32_t> ids_;
  int ncid_ = -1;              ///< open only inside the constructor and flush()
  bool closed_ = false;
  std::size_t records_ = 0;    ///< in the file plus pending
  std::size_t pending_ = 0;    ///< staged records not yet in the file (< syncEvery)
  double lastTime_ = 0.0;
  std::vector<double> oldTimes_; ///< resume: the old file's record times (freed once it is rebuilt)
  // Staged records (syncEvery records): time; position, velocity, angular velocity and hydro
  // force (four blocks of syncEvery x bodies x 3); orientation; contact count; largest force.
  std::vector<double> pendingTime_, pendingVec_, pendingQuat_;
  std::vector<std::int32_t> pendingCount_;
  std::vector<double> pendingForce_;
};

} // namespace armour::io
