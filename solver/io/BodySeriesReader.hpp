// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BodySeriesReader.hpp
/// Reads back the per-body time series an `armour run` writes (bodies.nc, BodySeriesFile,
/// docs/output-files.md): the body table, the times, the history attribute, and positions and
/// orientations record by record or in blocks (streaming: a one-hour series does not fit in
/// memory). Errors throw core::InputError naming the file, the variable and the fix.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace armour::io {

class BodySeriesReader {
public:
  explicit BodySeriesReader(const std::filesystem::path& path);
  ~BodySeriesReader();
  BodySeriesReader(const BodySeriesReader&) = delete;
  BodySeriesReader& operator=(const BodySeriesReader&) = delete;

  [[nodiscard]] std::size_t records() const { return records_; }
  [[nodiscard]] const std::vector<double>& times() const { return times_; } ///< unit: s
  [[nodiscard]] const std::vector<std::string>& names() const { return names_; }
  [[nodiscard]] const std::string& history() const { return history_; }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  /// A global text attribute (e.g. `scene_file`), or nothing if the file has none by that name.
  [[nodiscard]] std::optional<std::string> textAttribute(const char* name) const;
  /// A global number attribute (e.g. `storm_time_offset`), or nothing if absent. Throws
  /// core::InputError naming the file and the attribute if it is not one finite number.
  [[nodiscard]] std::optional<double> numberAttribute(const char* name) const;

  /// Positions of records [k0, k0 + n): (record, body, 3) (unit: m).
  void positions(std::size_t k0, std::size_t n, std::vector<double>& out) const;
  /// Orientations (w, x, y, z) of record k: (body, 4).
  void orientations(std::size_t k, std::vector<double>& out) const;

private:
  void check(int status, const char* what) const;
  std::filesystem::path path_;
  int ncid_ = -1;
  int timeDim_ = -1, timeVar_ = -1, positionVar_ = -1, orientationVar_ = -1;
  std::size_t records_ = 0, bodies_ = 0;
  std::vector<double> times_;
  std::vector<std::string> names_;
  std::string history_;
};

} // namespace armour::io
