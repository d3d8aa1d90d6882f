// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/UnitLoadsFile.hpp"

#include "core/AtomicFile.hpp"
#include "core/CsvText.hpp"
#include "core/Error.hpp"
#include "geometry/MeshFile.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace armour::io {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUnitsHeader = "unit,name,scene_body,mass_kg,volume_m3,dn_m,surface";
constexpr const char* kRecordsHeader =
    "record,unit,time,window_end,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,contact_force,loads";
constexpr const char* kLoadsHeader = "record,unit,other,px,py,pz,fx,fy,fz";

/// A unit's surface file: "<index>-<name>.vtp".
std::string surfaceFileName(const UnitLoadsUnit& unit, std::size_t index) {
  return std::to_string(index) + "-" + core::fileSafeName(unit.name) + ".vtp";
}

/// Keep the header and the first `rows` complete lines of `path` (rewritten atomically).
void truncateRows(const fs::path& path, const char* header, std::size_t rows) {
  std::ifstream in(path);
  if (!in)
    core::failInput(path.string(), "missing: the checkpoint's run wrote it; restore the output folder as the run left "
                                   "it, or start the run anew without --restart");
  std::string line;
  std::vector<std::string> kept;
  if (!std::getline(in, line) || line != header)
    core::failInput(path.string(), "not a unit-loads file of armour (its header is not '{}'); restore it or start the "
                                   "run anew without --restart", header);
  while (kept.size() < rows && std::getline(in, line)) {
    if (in.eof()) break; // the last line had no newline: cut short by a kill
    kept.push_back(line);
  }
  if (kept.size() < rows)
    core::failInput(path.string(), "holds {} complete rows, but the checkpoint was taken after {}: the file was cut "
                                   "short or edited; start the run anew without --restart", kept.size(), rows);
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << header << '\n';
    for (const auto& k : kept) out << k << '\n';
  });
}

} // namespace

UnitLoadsWriter::UnitLoadsWriter(const fs::path& folder, const std::vector<UnitLoadsUnit>& units,
                                 const std::optional<UnitLoadsRows>& resume)
    : folder_(folder / "unit_loads") {
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec) core::failInput(folder_.string(), "cannot create the folder: {}; check that it is writable", ec.message());
  // units.csv and the surfaces are written anew: the same scene gives the same ones.
  core::writeFileAtomically(folder_ / "units.csv", [&](std::ostream& out) {
    out << kUnitsHeader << '\n';
    for (std::size_t i = 0; i < units.size(); ++i) {
      const UnitLoadsUnit& u = units[i];
      out << fmt::format("{},{},{},{:.17g},{:.17g},{:.17g},{}\n", i, core::csvField(u.name), u.sceneBody, u.mass, u.volume,
                         u.dn, surfaceFileName(u, i));
    }
  });
  for (std::size_t i = 0; i < units.size(); ++i) {
    geometry::writeMesh(units[i].surface, folder_ / surfaceFileName(units[i], i), geometry::MeshFormat::Vtp);
  }
  if (resume) {
    truncateRows(folder_ / "records.csv", kRecordsHeader, resume->records);
    truncateRows(folder_ / "loads.csv", kLoadsHeader, resume->loads);
    rows_ = *resume;
    nextRecord_ = resume->records;
    return;
  }
  core::writeFileAtomically(folder_ / "records.csv", [&](std::ostream& out) { out << kRecordsHeader << '\n'; });
  core::writeFileAtomically(folder_ / "loads.csv", [&](std::ostream& out) { out << kLoadsHeader << '\n'; });
}

void UnitLoadsWriter::append(const std::vector<UnitLoadRecord>& records) {
  if (records.empty()) return;
  std::string rec, loads;
  for (const UnitLoadRecord& r : records) {
    const std::size_t id = nextRecord_++;
    const auto& q = r.orientation;
    rec += fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.9g},{:.9g},{:.9g},"
                       "{:.9g},{:.9g},{:.9g},{:.9g},{}\n",
                       id, r.unit, r.time, r.windowEnd, r.position.x(), r.position.y(), r.position.z(), q.w(), q.x(),
                       q.y(), q.z(), r.velocity.x(), r.velocity.y(), r.velocity.z(), r.angularVelocity.x(),
                       r.angularVelocity.y(), r.angularVelocity.z(), r.contactForce, r.loads.size());
    for (const UnitLoad& l : r.loads) {
      loads += fmt::format("{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", id, r.unit, core::csvField(l.other),
                           l.point.x(), l.point.y(), l.point.z(), l.force.x(), l.force.y(), l.force.z());
      ++rows_.loads;
    }
    ++rows_.records;
  }
  // Loads first: a record row is only on disk when its loads are.
  const auto put = [](const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::app | std::ios::binary);
    out << text;
    out.flush();
    if (!out) core::failInput(path.string(), "cannot append: check that the disk is not full");
  };
  put(folder_ / "loads.csv", loads);
  put(folder_ / "records.csv", rec);
}

// ---------------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------------

namespace {

/// Rows of a CSV file with a known header, each checked to have the header's column count.
struct CsvFile {
  fs::path path;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;

  CsvFile(const fs::path& p, const char* header) : path(p) {
    std::ifstream in(p);
    if (!in)
      core::failInput(p.string(), "missing: run the rigid replay with output.unit_loads naming the units "
                                  "(docs/scene-file.md), then give its output folder");
    std::string line;
    if (!std::getline(in, line) || line != header)
      core::failInput(p.string(), "not a unit-loads file of armour: the header should be '{}'", header);
    columns = core::splitCsvLine(line);
    while (std::getline(in, line)) {
      if (in.eof() && !line.empty()) break; // a last line without newline: a run killed while writing
      if (line.empty()) continue;
      rows.push_back(core::splitCsvLine(line));
      if (rows.back().size() != columns.size())
        core::failInput(fmt::format("{}:{}", p.string(), rows.size() + 1), "{} columns, expected {}; the file is damaged",
                        rows.back().size(), columns.size());
    }
  }
  [[nodiscard]] double number(std::size_t row, std::size_t col) const {
    const std::string& text = rows[row][col];
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
      core::failInput(fmt::format("{}:{}", path.string(), row + 2), "column {} = '{}': not a finite number",
                      columns[col], text);
    return v;
  }
  [[nodiscard]] std::int64_t integer(std::size_t row, std::size_t col) const {
    const double v = number(row, col);
    if (v != std::floor(v))
      core::failInput(fmt::format("{}:{}", path.string(), row + 2), "column {} = '{}': not an integer", columns[col],
                      rows[row][col]);
    return static_cast<std::int64_t>(v);
  }
  [[nodiscard]] geometry::Vec3 vec(std::size_t row, std::size_t col) const {
    return {number(row, col), number(row, col + 1), number(row, col + 2)};
  }
};

} // namespace

UnitLoads readUnitLoads(const fs::path& runFolder) {
  const fs::path folder = runFolder / "unit_loads";
  UnitLoads out;
  const CsvFile units(folder / "units.csv", kUnitsHeader);
  for (std::size_t i = 0; i < units.rows.size(); ++i) {
    UnitLoadsUnit u;
    if (units.integer(i, 0) != static_cast<std::int64_t>(i))
      core::failInput(fmt::format("{}:{}", units.path.string(), i + 2), "unit = {}, expected {}: the rows are numbered "
                                                                       "from 0 in order", units.rows[i][0], i);
    u.name = units.rows[i][1];
    u.sceneBody = static_cast<std::int32_t>(units.integer(i, 2));
    u.mass = units.number(i, 3);
    u.volume = units.number(i, 4);
    u.dn = units.number(i, 5);
    if (!(u.mass > 0.0) || !(u.volume > 0.0))
      core::failInput(fmt::format("{}:{}", units.path.string(), i + 2), "mass and volume must be positive");
    u.surface = geometry::readMesh(folder / units.rows[i][6]);
    out.units.push_back(std::move(u));
  }
  const CsvFile records(folder / "records.csv", kRecordsHeader);
  const CsvFile loads(folder / "loads.csv", kLoadsHeader);
  std::size_t l = 0;
  for (std::size_t i = 0; i < records.rows.size(); ++i) {
    const std::string where = fmt::format("{}:{}", records.path.string(), i + 2);
    UnitLoadRecord r;
    const std::int64_t id = records.integer(i, 0);
    const std::int64_t unit = records.integer(i, 1);
    if (unit < 0 || unit >= static_cast<std::int64_t>(out.units.size()))
      core::failInput(where, "unit = {}: units.csv lists {} units", unit, out.units.size());
    r.unit = static_cast<std::int32_t>(unit);
    r.time = records.number(i, 2);
    r.windowEnd = records.number(i, 3);
    r.position = records.vec(i, 4);
    r.orientation = Eigen::Quaterniond(records.number(i, 7), records.number(i, 8), records.number(i, 9),
                                       records.number(i, 10));
    if (std::abs(r.orientation.norm() - 1.0) > 1e-6) core::failInput(where, "the quaternion (qw, qx, qy, qz) is not a unit one");
    r.orientation.normalize();
    r.velocity = records.vec(i, 11);
    r.angularVelocity = records.vec(i, 14);
    r.contactForce = records.number(i, 17);
    const std::int64_t n = records.integer(i, 18);
    for (std::int64_t k = 0; k < n; ++k, ++l) {
      if (l >= loads.rows.size() || loads.integer(l, 0) != id)
        core::failInput(where, "record {} has {} loads, but loads.csv {}; the files are from different runs or cut short",
                        id, n, l >= loads.rows.size() ? "ends before them" : fmt::format("row {} is of another record", l + 2));
      UnitLoad load;
      load.other = loads.rows[l][2];
      load.point = loads.vec(l, 3);
      load.force = loads.vec(l, 6);
      r.loads.push_back(std::move(load));
    }
    out.records.push_back(std::move(r));
  }
  return out;
}

} // namespace armour::io
