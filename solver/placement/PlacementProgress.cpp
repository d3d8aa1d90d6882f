// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/PlacementProgress.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace armour::placement {
namespace {

constexpr const char* kHeader = "armour placement progress 1";

/// A double as a hexadecimal float: exact, and strtod reads it back.
std::string hex(double x) { return fmt::format("{:a}", x); }

/// The fields of one line, the rest of the line (a name, which may hold spaces) kept whole.
class Line {
public:
  Line(std::string text, int number, const std::string& where) : text_(std::move(text)), number_(number), where_(where) {}

  std::string word() {
    while (pos_ < text_.size() && text_[pos_] == ' ') ++pos_;
    const std::size_t end = std::min(text_.find(' ', pos_), text_.size());
    if (end == pos_) fail("too few fields");
    std::string w = text_.substr(pos_, end - pos_);
    pos_ = end;
    return w;
  }
  double number() {
    const std::string w = word();
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size() || errno == ERANGE) fail(fmt::format("'{}' is not a number", w));
    return x;
  }
  std::uint64_t count() {
    const std::string w = word();
    char* end = nullptr;
    const unsigned long long x = std::strtoull(w.c_str(), &end, 10);
    if (end != w.c_str() + w.size() || w.front() == '-') fail(fmt::format("'{}' is not a count", w));
    return x;
  }
  Vec3 vec() {
    const double x = number(), y = number(), z = number();
    return {x, y, z};
  }
  std::string rest() {
    if (pos_ < text_.size() && text_[pos_] == ' ') ++pos_;
    if (pos_ >= text_.size()) fail("a name is missing");
    return text_.substr(pos_);
  }
  [[noreturn]] void fail(const std::string& what) const {
    core::failInput(where_, "application_state line {} ('{}'): {}; the checkpoint is damaged or not from armour "
                            "place: start the placement anew without --restart",
                    number_, text_, what);
  }

private:
  std::string text_;
  std::size_t pos_ = 0;
  int number_;
  const std::string& where_;
};

} // namespace

std::string encodeProgress(const PlacementProgress& p) {
  std::string out = fmt::format("{}\n", kHeader);
  out += fmt::format("units_done {}\nfinal_settle {}\nround {}\n", p.unitsDone, p.finalSettle ? 1 : 0, p.round);
  out += fmt::format("settle_start {}\nround_start {}\nround_start_step {}\nstill_since {}\nwall_seconds {}\n",
                     hex(p.settleStart), hex(p.roundStart), p.roundStartStep, hex(p.stillSince), hex(p.wallSeconds));
  out += fmt::format("capped {} {}\n", p.summary.cappedUnits, p.summary.settleCappedUnits);
  for (const std::string& name : p.summary.drifted) out += fmt::format("drifted {}\n", name);
  for (const Vec3& x : p.roundBefore) out += fmt::format("before {} {} {}\n", hex(x.x()), hex(x.y()), hex(x.z()));
  for (const AddedBody& b : p.bodies)
    out += fmt::format("body {} {} {} {} {} {}\n", b.sceneShape, hex(b.scale), b.material, hex(b.volume),
                       b.fixed ? 1 : 0, b.name);
  for (const UnitRecord& u : p.units) {
    const auto& q = u.releaseOrientation;
    out += fmt::format("unit {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}\n", hex(u.gridPoint.x()),
                       hex(u.gridPoint.y()), hex(u.gridPoint.z()), hex(q.w()), hex(q.x()), hex(q.y()), hex(q.z()),
                       hex(u.touchPoint.x()), hex(u.touchPoint.y()), hex(u.touchPoint.z()), hex(u.settleDrift),
                       hex(u.releaseTime), hex(u.restTime), u.capped ? 1 : 0, u.body, u.name);
  }
  for (std::size_t b : p.frozen) out += fmt::format("frozen {}\n", b);
  for (double d : p.settleDrifts) out += fmt::format("drift {}\n", hex(d));
  out += "end\n";
  return out;
}

PlacementProgress decodeProgress(const std::string& text, const std::string& where) {
  PlacementProgress p;
  std::istringstream in(text);
  std::string raw;
  int number = 0;
  bool ended = false;
  if (!std::getline(in, raw) || raw != kHeader)
    core::failInput(where, "application_state does not start with '{}': not the checkpoint of an armour place run of "
                           "this version; start the placement anew without --restart",
                    kHeader);
  ++number;
  while (std::getline(in, raw)) {
    Line line(raw, ++number, where);
    const std::string key = line.word();
    if (key == "units_done") p.unitsDone = static_cast<int>(line.count());
    else if (key == "final_settle") p.finalSettle = line.count() != 0;
    else if (key == "round") p.round = static_cast<int>(line.count());
    else if (key == "settle_start") p.settleStart = line.number();
    else if (key == "round_start") p.roundStart = line.number();
    else if (key == "round_start_step") p.roundStartStep = line.count();
    else if (key == "still_since") p.stillSince = line.number();
    else if (key == "wall_seconds") p.wallSeconds = line.number();
    else if (key == "capped") {
      p.summary.cappedUnits = static_cast<int>(line.count());
      p.summary.settleCappedUnits = static_cast<int>(line.count());
    } else if (key == "drifted") p.summary.drifted.push_back(line.rest());
    else if (key == "before") p.roundBefore.push_back(line.vec());
    else if (key == "body") {
      AddedBody b;
      b.sceneShape = line.count();
      b.scale = line.number();
      b.material = line.count();
      b.volume = line.number();
      b.fixed = line.count() != 0;
      b.name = line.rest();
      p.bodies.push_back(b);
    } else if (key == "unit") {
      UnitRecord u;
      u.gridPoint = line.vec();
      const double w = line.number(), x = line.number(), y = line.number(), z = line.number();
      u.releaseOrientation = Eigen::Quaterniond(w, x, y, z);
      u.touchPoint = line.vec();
      u.settleDrift = line.number();
      u.releaseTime = line.number();
      u.restTime = line.number();
      u.capped = line.count() != 0;
      u.body = line.count();
      u.name = line.rest();
      p.units.push_back(u);
    } else if (key == "frozen") p.frozen.push_back(line.count());
    else if (key == "drift") p.settleDrifts.push_back(line.number());
    else if (key == "end") {
      ended = true;
      break;
    } else line.fail(fmt::format("unknown record '{}'", key));
  }
  if (!ended)
    core::failInput(where, "application_state ends before its 'end' line: the checkpoint is cut short; start the "
                           "placement anew without --restart");
  if (static_cast<int>(p.units.size()) != p.unitsDone)
    core::failInput(where, "application_state: units_done {} but {} unit records; start the placement anew without "
                           "--restart", p.unitsDone, p.units.size());
  return p;
}

} // namespace armour::placement
