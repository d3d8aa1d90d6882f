// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/UnitLoads.hpp"

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace armour::simulation {
namespace {

constexpr const char* kStateTag = "unit_loads 2";

/// Index of the first record time after t (time = index x interval), as RunOutputs schedules.
long nextIndexAfter(double t, double interval) { return static_cast<long>(std::floor(t / interval + 1e-9)) + 1; }

// Doubles as C99 hexadecimal text: read back bit for bit.
void put(std::ostream& out, double v) { out << ' ' << fmt::format("{:a}", v); }
void put(std::ostream& out, const Vec3& v) {
  put(out, v.x());
  put(out, v.y());
  put(out, v.z());
}

struct StateReader {
  std::istringstream in;
  std::string where; ///< "<folder>/checkpoint.nc (application_state)"
  StateReader(const std::string& text, std::string source) : in(text), where(std::move(source)) {}
  [[noreturn]] void fail(const std::string& what) const {
    core::failInput(where, "the unit-loads state is damaged ({}); start the run anew without --restart", what);
  }
  std::string word() {
    std::string w;
    if (!(in >> w)) fail("it ends early");
    return w;
  }
  double number() {
    const std::string w = word();
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size()) fail(fmt::format("'{}' is not a number", w));
    return v;
  }
  std::size_t count() {
    const double v = number();
    if (!(v >= 0.0) || v != std::floor(v)) fail("a count is not a whole number");
    return static_cast<std::size_t>(v);
  }
  Vec3 vec() {
    const double x = number(), y = number(), z = number();
    return {x, y, z};
  }
  void expect(const char* w) {
    if (word() != w) fail(fmt::format("'{}' expected", w));
  }
};

} // namespace

UnitLoadsRecorder::UnitLoadsRecorder(World& world, UnitLoadsSettings settings, const std::filesystem::path& folder,
                                     const std::string& resumeState)
    : settings_(std::move(settings)) {
  if (!(settings_.interval > 0.0) || !(settings_.cluster > 0.0))
    throw std::invalid_argument("UnitLoadsRecorder: interval and cluster must be positive");
  const std::size_t n = settings_.bodies.size();
  std::vector<io::UnitLoadsUnit> units(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BodyId b = settings_.bodies[i];
    io::UnitLoadsUnit& u = units[i];
    u.name = world.bodies().info(b).name;
    u.sceneBody = settings_.sceneBodies[i];
    u.mass = world.bodies().info(b).mass;
    u.surface = world.shape(world.bodyShape(b)).mesh;
    for (auto& v : u.surface.vertices) v *= world.bodyScale(b);
    u.volume = geometry::signedVolume(u.surface);
    u.dn = std::cbrt(u.volume);
    dn_.push_back(u.dn);
  }
  world.setTracedBodies(settings_.bodies);
  unitOfBody_.assign(world.bodies().size(), -1);
  for (std::size_t i = 0; i < n; ++i) unitOfBody_[settings_.bodies[i]] = static_cast<std::int32_t>(i);
  wasAwake_.resize(world.bodies().size());
  for (BodyId b = 0; b < wasAwake_.size(); ++b) wasAwake_[b] = world.bodies().isAwake(b) ? 1 : 0;
  current_.assign(n, {});
  held_.assign(n, {});
  holding_.assign(n, 0);
  std::optional<io::UnitLoadsRows> resume;
  if (!resumeState.empty()) {
    parseState(resumeState, (folder / "checkpoint.nc").string() + " (application_state)");
    resume = scheduledRows_;
  }
  writer_ = std::make_unique<io::UnitLoadsWriter>(folder, units, resume);
}

void UnitLoadsRecorder::mergeLoads(const World& world) {
  const auto& bodies = world.bodies();
  std::vector<std::vector<TracedContact>> next(current_.size());
  for (const TracedContact& c : world.tracedContacts()) {
    if (c.body < unitOfBody_.size() && unitOfBody_[c.body] >= 0)
      next[static_cast<std::size_t>(unitOfBody_[c.body])].push_back(c);
  }
  // Sleep changes at the end of a step: a body asleep at the last update was asleep through this
  // step's force evaluation. A unit asleep through it had its pairs with static geometry and with
  // bodies asleep through it left out: they hold as they were.
  for (std::size_t i = 0; i < current_.size(); ++i) {
    if (wasAwake_[settings_.bodies[i]] != 0) continue;
    for (const TracedContact& c : current_[i]) {
      if (c.other < 0 || wasAwake_[static_cast<std::size_t>(c.other)] == 0) next[i].push_back(c);
    }
  }
  current_ = std::move(next);
  for (BodyId b = 0; b < wasAwake_.size(); ++b) wasAwake_[b] = bodies.isAwake(b) ? 1 : 0;
}

io::UnitLoadRecord UnitLoadsRecorder::recordOf(const World& world, std::size_t unit) const {
  const BodyId b = settings_.bodies[unit];
  const auto& bodies = world.bodies();
  io::UnitLoadRecord r;
  r.unit = static_cast<std::int32_t>(unit);
  r.time = world.time();
  r.position = bodies.position(b);
  r.orientation = bodies.orientation(b);
  r.velocity = bodies.velocity(b);
  const Eigen::Matrix3d toBody = r.orientation.conjugate().toRotationMatrix();
  r.angularVelocity = toBody * bodies.worldAngularVelocity(b);
  // Clusters per other body, in the order met: each point joins the first cluster of its other
  // body whose first point lies within half the cluster width, else starts one (so no cluster is
  // wider than the width).
  const double width = settings_.cluster * dn_[unit];
  struct Cluster {
    std::int64_t other;
    Vec3 first, weighted, sum, force;
    double normal;
    int points;
  };
  std::vector<Cluster> clusters;
  for (const TracedContact& c : current_[unit]) {
    r.contactForce += c.force.norm();
    const Vec3 p = toBody * (c.point - r.position);
    Cluster* into = nullptr;
    for (Cluster& k : clusters) {
      if (k.other == c.other && (k.first - p).norm() <= 0.5 * width) {
        into = &k;
        break;
      }
    }
    if (into == nullptr) {
      clusters.push_back({c.other, p, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 0.0, 0});
      into = &clusters.back();
    }
    const double fn = std::max(c.normalForce, 0.0);
    into->weighted += fn * p;
    into->sum += p;
    into->normal += fn;
    into->force += toBody * c.force;
    ++into->points;
  }
  for (const Cluster& k : clusters) {
    io::UnitLoad l;
    l.other = k.other < 0 ? "static" : settings_.names[static_cast<std::size_t>(k.other)];
    l.point = k.normal > 0.0 ? Vec3(k.weighted / k.normal) : Vec3(k.sum / k.points);
    l.force = k.force;
    r.loads.push_back(std::move(l));
  }
  return r;
}

void UnitLoadsRecorder::update(const World& world) {
  mergeLoads(world);
  const double t = world.time();
  for (std::size_t i = 0; i < current_.size(); ++i) {
    double total = 0.0;
    for (const TracedContact& c : current_[i]) total += c.force.norm();
    // Strictly larger: at rest every step ties and the first of the window is kept.
    if (holding_[i] == 0 || total > held_[i].contactForce) {
      held_[i] = recordOf(world, i);
      holding_[i] = 1;
    }
  }
  const double due = static_cast<double>(nextRecord_) * settings_.interval;
  if (t >= due - 1e-9 * settings_.interval) {
    for (auto& h : held_) h.windowEnd = t;
    writer_->append(held_);
    scheduledRows_ = writer_->rows();
    holding_.assign(holding_.size(), 0);
    nextRecord_ = nextIndexAfter(t, settings_.interval);
  }
}

void UnitLoadsRecorder::finish() {
  if (holding_.empty() || holding_[0] == 0) return;
  std::vector<io::UnitLoadRecord> last = held_;
  for (auto& h : last) h.windowEnd = static_cast<double>(nextRecord_) * settings_.interval;
  writer_->append(last);
}

std::string UnitLoadsRecorder::state() const {
  std::ostringstream out;
  out << kStateTag << "\ninterval";
  put(out, settings_.interval);
  out << "\ncluster";
  put(out, settings_.cluster);
  out << "\nunits " << settings_.bodies.size() << "\nnext " << nextRecord_ << "\nrows "
      << scheduledRows_.records << ' ' << scheduledRows_.loads << '\n';
  for (std::size_t i = 0; i < settings_.bodies.size(); ++i) {
    out << "unit " << settings_.bodies[i] << " contacts " << current_[i].size();
    for (const TracedContact& c : current_[i]) {
      out << "\n c " << c.other;
      put(out, c.point);
      put(out, c.force);
      put(out, c.normalForce);
    }
    out << "\n held " << static_cast<int>(holding_[i]);
    if (holding_[i] != 0) {
      const io::UnitLoadRecord& h = held_[i];
      put(out, h.time);
      put(out, h.position);
      put(out, h.orientation.w());
      put(out, h.orientation.vec());
      put(out, h.velocity);
      put(out, h.angularVelocity);
      put(out, h.contactForce);
      out << ' ' << h.loads.size();
      for (const io::UnitLoad& l : h.loads) {
        out << "\n l " << l.other.size() << ' ' << l.other;
        put(out, l.point);
        put(out, l.force);
      }
    }
    out << '\n';
  }
  return out.str();
}

void UnitLoadsRecorder::parseState(const std::string& text, const std::string& where) {
  StateReader in(text, where);
  std::string tag;
  std::getline(in.in, tag);
  if (tag != kStateTag)
    in.fail(fmt::format("it starts with '{}', not '{}'; a checkpoint of another armour version", tag, kStateTag));
  // The schedule and the clusters go on as they were: a restart may not change them.
  in.expect("interval");
  if (const double interval = in.number(); interval != settings_.interval)
    core::failInput(where, "output.unit_loads_interval = {} s, but the checkpoint's run recorded every {} s; give {} "
                           "to continue it, or start the run anew", settings_.interval, interval, interval);
  in.expect("cluster");
  if (const double cluster = in.number(); cluster != settings_.cluster)
    core::failInput(where, "output.unit_loads_cluster = {}, but the checkpoint's run clustered at {} Dn; give {} to "
                           "continue it, or start the run anew", settings_.cluster, cluster, cluster);
  in.expect("units");
  if (in.count() != settings_.bodies.size())
    core::failInput(where, "the checkpoint's run recorded the loads of other units than output.unit_loads names now; "
                           "give the same units, or start the run anew without --restart");
  in.expect("next");
  nextRecord_ = static_cast<long>(in.count());
  in.expect("rows");
  scheduledRows_.records = in.count();
  scheduledRows_.loads = in.count();
  for (std::size_t i = 0; i < settings_.bodies.size(); ++i) {
    in.expect("unit");
    if (in.count() != settings_.bodies[i])
      core::failInput(where, "body '{}' of output.unit_loads was not recorded by the checkpoint's run; give the same "
                             "units, or start the run anew", settings_.names[settings_.bodies[i]]);
    in.expect("contacts");
    const std::size_t n = in.count();
    for (std::size_t k = 0; k < n; ++k) {
      in.expect("c");
      TracedContact c;
      c.body = settings_.bodies[i];
      c.other = static_cast<std::int64_t>(in.number());
      if (c.other < -1 || c.other >= static_cast<std::int64_t>(settings_.names.size()))
        in.fail(fmt::format("a contact with body {}, of {} bodies", c.other, settings_.names.size()));
      c.point = in.vec();
      c.force = in.vec();
      c.normalForce = in.number();
      current_[i].push_back(c);
    }
    in.expect("held");
    holding_[i] = in.count() != 0 ? 1 : 0;
    if (holding_[i] == 0) continue;
    io::UnitLoadRecord& h = held_[i];
    h.unit = static_cast<std::int32_t>(i);
    h.time = in.number();
    h.position = in.vec();
    const double w = in.number();
    const Vec3 q = in.vec();
    h.orientation = Eigen::Quaterniond(w, q.x(), q.y(), q.z());
    h.velocity = in.vec();
    h.angularVelocity = in.vec();
    h.contactForce = in.number();
    const std::size_t loads = in.count();
    for (std::size_t k = 0; k < loads; ++k) {
      in.expect("l");
      const std::size_t length = in.count();
      in.in.get(); // the space before the name
      std::string other(length, '\0');
      in.in.read(other.data(), static_cast<std::streamsize>(length));
      io::UnitLoad l;
      l.other = other;
      l.point = in.vec();
      l.force = in.vec();
      h.loads.push_back(std::move(l));
    }
  }
}

} // namespace armour::simulation
