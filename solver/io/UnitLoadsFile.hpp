// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file UnitLoadsFile.hpp
/// The contact loads on chosen units of a rigid run (`output.unit_loads`), in the folder
/// `<output>/unit_loads/`, for `armour stress` (issue 26; docs/output-files.md, "Unit loads"):
///  - units.csv: one row per unit: unit, name, scene_body, mass_kg, volume_m3, dn_m, surface;
///  - `<name>.vtp`: the unit's surface in its body frame (centre of mass at the origin, the axes
///    of the orientation in records.csv), at its size: ParaView opens it, `armour stress` meshes it;
///  - records.csv: one row per unit and record: record, unit, time, window_end, the unit's pose
///    (x, y, z, qw, qx, qy, qz: body to world), velocity (vx, vy, vz, world), angular velocity
///    (wx, wy, wz, body frame), contact_force (sum of the point force magnitudes, N) and loads
///    (its rows in loads.csv);
///  - loads.csv: one row per load: record, unit, other (the other body's name, or "static"),
///    px, py, pz (body frame, m), fx, fy, fz (body frame, N).
/// Plain CSV, so that Python (numpy.genfromtxt, pandas), ParaView and a spreadsheet read it.
///
/// Crash safety and restart: rows are appended and flushed record by record. A checkpoint stores
/// the row counts (UnitLoadsRows); a resumed run keeps that many rows of each file (rewritten
/// atomically) and appends after them, so its files equal those of an uninterrupted run. A file
/// shorter than the checkpoint says is refused, naming the file and the fix.

#include "geometry/TriangleMesh.hpp"

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace armour::io {

/// One contact load on a unit, in the unit's body frame.
struct UnitLoad {
  std::string other = "static";                     ///< the other body's name, or "static"
  geometry::Vec3 point = geometry::Vec3::Zero();    ///< (unit: m), body frame
  geometry::Vec3 force = geometry::Vec3::Zero();    ///< on the unit (unit: N), body frame
};

/// The loads on one unit at one step: the step of largest total contact force in its window.
struct UnitLoadRecord {
  std::int32_t unit = 0;         ///< row of units.csv (unit: -)
  double time = 0.0;             ///< time of the step held (unit: s)
  double windowEnd = 0.0;        ///< the record's scheduled time: the window is (previous, this] (unit: s)
  geometry::Vec3 position = geometry::Vec3::Zero();             ///< centre of mass, world (unit: m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< body to world (unit: -)
  geometry::Vec3 velocity = geometry::Vec3::Zero();             ///< world (unit: m/s)
  geometry::Vec3 angularVelocity = geometry::Vec3::Zero();      ///< body frame (unit: rad/s)
  double contactForce = 0.0;     ///< sum of the contact point force magnitudes (unit: N)
  std::vector<UnitLoad> loads;
};

/// One traced unit.
struct UnitLoadsUnit {
  std::string name;
  std::int32_t sceneBody = 0;       ///< index in the scene's bodies (unit: -)
  double mass = 0.0;                ///< (unit: kg)
  double volume = 0.0;              ///< of the surface (unit: m^3)
  double dn = 0.0;                  ///< volume^(1/3) (unit: m)
  geometry::TriangleMesh surface;   ///< body frame, at size (unit: m)
};

/// How many rows each file holds (headers excluded): what a checkpoint needs to resume.
struct UnitLoadsRows {
  std::size_t records = 0;
  std::size_t loads = 0;
};

/// Writer of `<folder>/unit_loads/`.
class UnitLoadsWriter {
public:
  /// Create the folder and its files (units.csv, the surfaces, headers), or with `resume` keep the
  /// first resume->records and resume->loads rows of the existing files. Throws core::InputError
  /// naming the file if it cannot be written, or, on resume, if a file is missing, lists other
  /// units, or is shorter than the checkpoint says.
  UnitLoadsWriter(const std::filesystem::path& folder, const std::vector<UnitLoadsUnit>& units,
                  const std::optional<UnitLoadsRows>& resume = std::nullopt);

  /// Append records (flushed to disk before returning).
  void append(const std::vector<UnitLoadRecord>& records);

  [[nodiscard]] const UnitLoadsRows& rows() const { return rows_; }
  [[nodiscard]] const std::filesystem::path& folder() const { return folder_; }

private:
  std::filesystem::path folder_;
  UnitLoadsRows rows_;
  std::size_t nextRecord_ = 0;
};

/// Everything in a unit-loads folder.
struct UnitLoads {
  std::vector<UnitLoadsUnit> units;
  std::vector<UnitLoadRecord> records; ///< in file order (by record)
};

/// Read `<run folder>/unit_loads/`. Throws core::InputError naming the file, the line and the
/// column when a file is missing or a value is not what it should be, with the fix.
[[nodiscard]] UnitLoads readUnitLoads(const std::filesystem::path& runFolder);

} // namespace armour::io
