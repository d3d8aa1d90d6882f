// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/StressCommands.hpp"

#include "analysis/StressEvents.hpp"
#include "core/AtomicFile.hpp"
#include "core/BuildInfo.hpp"
#include "core/CsvText.hpp"
#include "core/Error.hpp"
#include "core/JsonWriter.hpp"
#include "core/Log.hpp"
#include "deformable/UnitStress.hpp"
#include "geometry/VtpFile.hpp"
#include "io/UnitLoadsFile.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

namespace armour::app {
namespace {

namespace fs = std::filesystem;
using deformable::Vec3;

/// A peak is "rocking" when the unit's centre travelled less than this in the look-back (unit:
/// Dn; ours: a unit rocking in place moves its centre by a few per cent of Dn, one that falls or
/// slides into the blow by more).
constexpr double kRockingTravel = 0.1;

struct StressRequest {
  std::string run;
  std::vector<std::string> units;
  std::size_t tets = 4000;
  int order = 2;
  double radius = 0.05;       ///< spread radius (unit: Dn)
  double away = 0.15;         ///< body stress: elements farther than this from every load (unit: Dn)
  double strength = 3.5e6;    ///< concrete's tensile strength (unit: Pa)
  double youngModulus = 26.6e9;
  double poissonRatio = 0.205;
  std::size_t every = 1;
  std::string output;
  int threads = 0;
};

/// One unit's results.
struct UnitResult {
  const io::UnitLoadsUnit* unit = nullptr;
  std::vector<const io::UnitLoadRecord*> records; ///< the ones solved, in time order
  std::vector<deformable::UnitStressResult> stress;
  std::vector<analysis::StressSample> samples;
  analysis::UnitStressSummary summary;
  std::size_t elements = 0;
  double meshSeconds = 0.0;   ///< meshing and factoring (unit: s of wall time)
  double solveSeconds = 0.0;  ///< all load cases (unit: s of wall time)
  std::size_t solved = 0;     ///< load cases solved (the others repeat the one before)
};

void checkRequest(const StressRequest& o) {
  if (o.tets < 50) core::failInput("--tets", "{}: too few tetrahedra to resolve a unit; give at least 50 (e.g. 4000)", o.tets);
  if (o.order != 1 && o.order != 2) core::failInput("--order", "{}: give 1 (4-node tetrahedra) or 2 (10-node, F-bar)", o.order);
  if (!(o.radius > 0.0 && o.radius <= 0.5))
    core::failInput("--radius", "{} Dn: the spread radius must lie in (0, 0.5] Dn, e.g. 0.05", o.radius);
  if (!(o.away >= o.radius && o.away <= 1.0))
    core::failInput("--away", "{} Dn: give at least the spread radius ({} Dn) and at most 1 Dn, e.g. 0.15", o.away,
                    o.radius);
  if (!(o.strength > 0.0)) core::failInput("--strength", "{} Pa: give a positive tensile strength, e.g. 3.5e6", o.strength);
  if (!(o.youngModulus > 0.0)) core::failInput("--young-modulus", "{} Pa: give a positive modulus, e.g. 26.6e9", o.youngModulus);
  if (!(o.poissonRatio > -1.0 && o.poissonRatio < 0.5))
    core::failInput("--poisson-ratio", "{}: must lie in (-1, 0.5), e.g. 0.205", o.poissonRatio);
  if (o.every < 1) core::failInput("--every", "{}: give 1 (every record) or more", o.every);
  if (o.threads < 0) core::failInput("--threads", "{}: give a positive number of threads, or 0 for OpenMP's default", o.threads);
}

/// The units asked for (all recorded ones by default), in units.csv order.
std::vector<std::size_t> chooseUnits(const io::UnitLoads& loads, const StressRequest& o) {
  std::vector<std::size_t> out;
  if (o.units.empty()) {
    for (std::size_t i = 0; i < loads.units.size(); ++i) out.push_back(i);
    return out;
  }
  std::vector<std::string> names;
  for (const auto& u : loads.units) names.push_back(u.name);
  for (const std::string& name : o.units) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      core::failInput("--units", "'{}' was not recorded by the run; it recorded: {} (add it to output.unit_loads and "
                                 "run again)", name, fmt::join(names, ", "));
    out.push_back(static_cast<std::size_t>(it - names.begin()));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// The same loads and spin, bit for bit.
bool sameLoadCase(const io::UnitLoadRecord& a, const io::UnitLoadRecord& b) {
  if (a.angularVelocity != b.angularVelocity || a.loads.size() != b.loads.size()) return false;
  for (std::size_t i = 0; i < a.loads.size(); ++i)
    if (a.loads[i].point != b.loads[i].point || a.loads[i].force != b.loads[i].force) return false;
  return true;
}

analysis::StressSample sampleOf(const io::UnitLoadRecord& r, const deformable::UnitStressResult& s) {
  analysis::StressSample out;
  out.time = r.time;
  out.sigma1 = s.sigma1;
  out.sigma1Away = s.sigma1Away;
  out.differential = s.differential;
  out.contactForce = r.contactForce;
  out.speed = r.velocity.norm();
  out.angularSpeed = r.angularVelocity.norm();
  out.position = r.position;
  for (const io::UnitLoad& l : r.loads) {
    if (l.force.norm() > out.dominantForce) {
      out.dominantForce = l.force.norm();
      out.dominant = l.other;
    }
  }
  return out;
}

/// The case of a record.
deformable::UnitLoadCase caseOf(const io::UnitLoadRecord& r) {
  deformable::UnitLoadCase c;
  c.angularVelocity = r.angularVelocity;
  for (const io::UnitLoad& l : r.loads) c.loads.push_back({l.point, l.force});
  return c;
}

UnitResult analyseUnit(const io::UnitLoads& loads, std::size_t unit, const StressRequest& o, const fs::path& out,
                       const std::shared_ptr<spdlog::logger>& log) {
  using Clock = std::chrono::steady_clock;
  UnitResult res;
  res.unit = &loads.units[unit];
  const io::UnitLoadsUnit& u = *res.unit;
  std::size_t seen = 0;
  for (const io::UnitLoadRecord& r : loads.records) {
    if (r.unit == static_cast<std::int32_t>(unit) && seen++ % o.every == 0) res.records.push_back(&r);
  }
  if (res.records.empty()) core::failInput(u.name, "no records in unit_loads/records.csv; the run ended before its first");
  std::stable_sort(res.records.begin(), res.records.end(),
                   [](const auto* a, const auto* b) { return a->time < b->time; });
  deformable::UnitStressSettings settings;
  settings.material.youngModulus = o.youngModulus;
  settings.material.poissonRatio = o.poissonRatio;
  settings.material.density = u.mass / u.volume;
  settings.order = o.order == 1 ? deformable::ElementOrder::Linear : deformable::ElementOrder::Quadratic;
  settings.tets = o.tets;
  settings.spreadRadius = o.radius * u.dn;
  settings.awayDistance = o.away * u.dn;
  const auto t0 = Clock::now();
  deformable::UnitStressModel model(u.surface, settings, fmt::format("unit '{}'", u.name));
  const auto t1 = Clock::now();
  res.elements = model.elementCount();
  res.stress.resize(res.records.size());
  // A record whose loads and spin are those of the one before (a unit asleep among sleepers) has
  // its stress: only the others are solved.
  std::vector<std::size_t> solve;
  for (std::size_t k = 0; k < res.records.size(); ++k)
    if (k == 0 || !sameLoadCase(*res.records[k], *res.records[k - 1])) solve.push_back(k);
  const auto cases = static_cast<std::int64_t>(solve.size());
  // Load cases in parallel, each written to its own slot: the same results on any thread count.
#pragma omp parallel for schedule(dynamic, 4)
  for (std::int64_t i = 0; i < cases; ++i) {
    const std::size_t k = solve[static_cast<std::size_t>(i)];
    res.stress[k] = model.evaluate(caseOf(*res.records[k]));
  }
  for (std::size_t k = 1; k < res.records.size(); ++k)
    if (sameLoadCase(*res.records[k], *res.records[k - 1])) res.stress[k] = res.stress[k - 1];
  res.solved = solve.size();
  res.solveSeconds = std::chrono::duration<double>(Clock::now() - t1).count();
  res.meshSeconds = std::chrono::duration<double>(t1 - t0).count();
  for (std::size_t k = 0; k < res.records.size(); ++k) res.samples.push_back(sampleOf(*res.records[k], res.stress[k]));
  // The unit at its worst record, for ParaView (body frame).
  const std::size_t worst = static_cast<std::size_t>(
      std::max_element(res.stress.begin(), res.stress.end(),
                       [](const auto& a, const auto& b) { return a.sigma1Away < b.sigma1Away; }) - res.stress.begin());
  model.writeVtu(caseOf(*res.records[worst]), out / (core::fileSafeName(u.name) + "-peak.vtu"));
  analysis::StressEventSettings events;
  events.rockingTravel = kRockingTravel * u.dn;
  res.summary = analysis::summarizeUnitStress(res.samples, events);
  const auto& m = res.samples[res.summary.maxAway];
  log->info("unit '{}': {} elements ({} s to mesh and factor), {} load cases ({} solved, the others repeat the one "
            "before) in {:.2f} s; largest body stress {:.3g} MPa at t = {:.4g} s, largest sigma_1 at a contact {:.3g} MPa",
            u.name, res.elements, fmt::format("{:.2f}", res.meshSeconds), res.records.size(), res.solved, res.solveSeconds,
            1e-6 * m.sigma1Away, m.time, 1e-6 * res.samples[res.summary.maxSigma1].sigma1);
  return res;
}

Vec3 toWorld(const io::UnitLoadRecord& r, const Vec3& body) { return r.position + r.orientation * body; }

void writeUnitsCsv(const fs::path& path, const std::vector<UnitResult>& results, double strength) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "scene_body,name,records,max_body_sigma1_pa,time_s,x,y,z,body_x,body_y,body_z,event,max_sigma1_pa,"
           "time_sigma1_s,max_differential_pa,time_differential_s,over_strength\n";
    for (std::size_t i = 0; i < results.size(); ++i) {
      const UnitResult& r = results[i];
      const std::size_t a = r.summary.maxAway, s = r.summary.maxSigma1, d = r.summary.maxDifferential;
      const Vec3 w = toWorld(*r.records[a], r.stress[a].whereAway);
      const Vec3& b = r.stress[a].whereAway;
      std::string event = "-";
      for (const auto& e : r.summary.events)
        if (e.sample == a) event = e.kind;
      out << fmt::format("{},{},{},{:.6g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{:.6g},{:.9g},{:.6g},{:.9g},{}\n",
                         r.unit->sceneBody, r.unit->name, r.records.size(), r.samples[a].sigma1Away, r.samples[a].time,
                         w.x(), w.y(), w.z(), b.x(), b.y(), b.z(), event, r.samples[s].sigma1, r.samples[s].time,
                         r.samples[d].differential, r.samples[d].time, r.samples[a].sigma1Away > strength ? 1 : 0);
    }
  });
}

void writeSeriesCsv(const fs::path& path, const std::vector<UnitResult>& results) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "name,time_s,body_sigma1_pa,sigma1_pa,differential_pa,contact_force_n,speed_m_s,angular_speed_rad_s,"
           "imbalance\n";
    for (const UnitResult& r : results) {
      for (std::size_t k = 0; k < r.samples.size(); ++k) {
        const auto& s = r.samples[k];
        out << fmt::format("{},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g},{:.4g},{:.2g}\n", r.unit->name, s.time,
                           s.sigma1Away, s.sigma1, s.differential, s.contactForce, s.speed, s.angularSpeed,
                           r.stress[k].imbalance);
      }
    }
  });
}

void writeEventsCsv(const fs::path& path, const std::vector<UnitResult>& results) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "name,time_s,body_sigma1_pa,kind,other,other_force_n,contact_force_n,speed_m_s,angular_speed_rad_s,x,y,z\n";
    for (const UnitResult& r : results) {
      for (const auto& e : r.summary.events) {
        const auto& s = r.samples[e.sample];
        const Vec3 w = toWorld(*r.records[e.sample], r.stress[e.sample].whereAway);
        out << fmt::format("{},{:.9g},{:.6g},{},{},{:.6g},{:.6g},{:.4g},{:.4g},{:.6g},{:.6g},{:.6g}\n", r.unit->name,
                           s.time, s.sigma1Away, e.kind, s.dominant.empty() ? "-" : s.dominant, s.dominantForce,
                           s.contactForce, s.speed, s.angularSpeed, w.x(), w.y(), w.z());
      }
    }
  });
}

void writeSummaryJson(const fs::path& path, const std::vector<UnitResult>& results, const StressRequest& o,
                      double wall) {
  std::size_t over = 0, cases = 0;
  double solve = 0.0;
  for (const auto& r : results) {
    over += r.samples[r.summary.maxAway].sigma1Away > o.strength ? 1 : 0;
    cases += r.samples.size();
    solve += r.solveSeconds;
  }
  const auto n = core::jsonNumber;
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "{\n  \"armour\": " << core::jsonString(core::buildInfo()) << ",\n";
    out << fmt::format("  \"run\": {},\n  \"strength_pa\": {},\n  \"units\": {},\n  \"units_over_strength\": {},\n",
                       core::jsonString(fs::absolute(o.run).string()), n(o.strength), results.size(), over);
    out << fmt::format("  \"model\": {{\"order\": {}, \"tets_asked\": {}, \"spread_radius_dn\": {}, \"away_dn\": {}, "
                       "\"young_modulus_pa\": {}, \"poisson_ratio\": {}, \"every\": {}}},\n",
                       o.order, o.tets, n(o.radius), n(o.away), n(o.youngModulus), n(o.poissonRatio), o.every);
    out << fmt::format("  \"load_cases\": {},\n  \"solve_seconds\": {},\n  \"wall_seconds\": {},\n", cases, n(solve), n(wall));
    out << "  \"per_unit\": [\n";
    for (std::size_t i = 0; i < results.size(); ++i) {
      const UnitResult& r = results[i];
      const auto& a = r.samples[r.summary.maxAway];
      out << fmt::format("    {{\"name\": {}, \"elements\": {}, \"load_cases\": {}, \"solved\": {}, "
                         "\"solve_seconds\": {}, \"max_body_sigma1_pa\": {}, \"time_s\": {}, \"max_sigma1_pa\": {}, \"max_differential_pa\": {}, \"events\": {}}}{}\n",
                         core::jsonString(r.unit->name), r.elements, r.samples.size(), r.solved, n(r.solveSeconds),
                         n(a.sigma1Away), n(a.time),
                         n(r.samples[r.summary.maxSigma1].sigma1), n(r.samples[r.summary.maxDifferential].differential),
                         r.summary.events.size(), i + 1 < results.size() ? "," : "");
    }
    out << "  ]\n}\n";
  });
}

/// The units at their last recorded pose, each triangle carrying its unit's largest stresses.
void writeStressMap(const fs::path& path, const std::vector<UnitResult>& results, double strength) {
  geometry::TriangleMesh all;
  geometry::CellArray body{"max_body_sigma1_Pa", {}}, contact{"max_sigma1_Pa", {}}, over{"over_strength", {}},
      id{"scene_body", {}};
  for (const UnitResult& r : results) {
    const io::UnitLoadRecord& last = *r.records.back();
    const auto base = static_cast<std::int32_t>(all.vertices.size());
    for (const auto& v : r.unit->surface.vertices) all.vertices.push_back(toWorld(last, v));
    const double s = r.samples[r.summary.maxAway].sigma1Away;
    for (const auto& t : r.unit->surface.triangles) {
      all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      body.values.push_back(s);
      contact.values.push_back(r.samples[r.summary.maxSigma1].sigma1);
      over.values.push_back(s > strength ? 1.0 : 0.0);
      id.values.push_back(r.unit->sceneBody);
    }
  }
  geometry::writeVtp(all, path, {body, contact, over, id});
}

void runStress(const StressRequest& o) {
  checkRequest(o);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  const auto start = std::chrono::steady_clock::now();
  const io::UnitLoads loads = io::readUnitLoads(o.run);
  if (loads.units.empty())
    core::failInput((fs::path(o.run) / "unit_loads" / "units.csv").string(), "lists no units; name some in output.unit_loads");
  const fs::path out = o.output.empty() ? fs::path(o.run) / "stress" : fs::path(o.output);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) core::failInput(out.string(), "cannot create the output folder ({}); give another with -o", ec.message());
  const core::ScopedLogFile logFile((out / "stress.log").string());
  auto log = core::logger("stress");
  log->info("{}", core::buildInfo());
  log->info("unit loads of {}: {} units, {} records; tet{} meshes of about {} tetrahedra, contact forces spread over "
            "{} Dn, body stress {} Dn or more from every contact, E = {} Pa, nu = {}, strength {} Pa",
            o.run, loads.units.size(), loads.records.size(), o.order == 1 ? 4 : 10, o.tets, o.radius, o.away,
            o.youngModulus, o.poissonRatio, o.strength);
  std::vector<UnitResult> results;
  for (std::size_t u : chooseUnits(loads, o)) results.push_back(analyseUnit(loads, u, o, out, log));
  writeUnitsCsv(out / "units.csv", results, o.strength);
  writeSeriesCsv(out / "series.csv", results);
  writeEventsCsv(out / "events.csv", results);
  writeStressMap(out / "stress_map.vtp", results, o.strength);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeSummaryJson(out / "summary.json", results, o, wall);
  std::size_t over = 0;
  fmt::print("{:<20} {:>8} {:>16} {:>10} {:>10} {:>16}\n", "unit", "records", "body sigma1 MPa", "at t s", "event",
             "contact s1 MPa");
  for (const UnitResult& r : results) {
    const std::size_t a = r.summary.maxAway;
    std::string event = "-";
    for (const auto& e : r.summary.events)
      if (e.sample == a) event = e.kind;
    const bool above = r.samples[a].sigma1Away > o.strength;
    over += above ? 1 : 0;
    fmt::print("{:<20} {:>8} {:>16.4g} {:>10.4g} {:>10} {:>16.4g}{}\n", r.unit->name, r.records.size(),
               1e-6 * r.samples[a].sigma1Away, r.samples[a].time, event, 1e-6 * r.samples[r.summary.maxSigma1].sigma1,
               above ? "  ABOVE STRENGTH" : "");
  }
  fmt::print("{} of {} units above the tensile strength {:.3g} MPa; outputs in {}\n", over, results.size(),
             1e-6 * o.strength, out.string());
  log->info("{} of {} units above {} Pa; wall time {:.2f} s; outputs: units.csv, series.csv, events.csv, summary.json, "
            "stress_map.vtp, <unit>-peak.vtu in {}", over, results.size(), o.strength, wall, out.string());
}

} // namespace

void addStressCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto o = std::make_shared<StressRequest>();
  auto* c = app.add_subcommand("stress", "the stress in the units of a rigid run that recorded their contact loads "
                                         "(output.unit_loads): largest tension per unit, times, events, units above "
                                         "the tensile strength (docs/user-guide.md)");
  c->add_option("run", o->run, "the run's output folder (it holds unit_loads/)")->required();
  c->add_option("--units", o->units, "names of the recorded units to analyse (default: all)")->delimiter(',');
  c->add_option("--tets", o->tets, "tetrahedra per unit mesh (gmsh)")->capture_default_str();
  c->add_option("--order", o->order, "element order: 2 = 10-node tetrahedra with F-bar, 1 = 4-node")->capture_default_str();
  c->add_option("--radius", o->radius, "each contact force spread over the surface within this radius (unit: Dn)")
      ->capture_default_str();
  c->add_option("--away", o->away, "body stress: elements farther than this from every contact (unit: Dn)")
      ->capture_default_str();
  c->add_option("--strength", o->strength, "tensile strength of the concrete (unit: Pa; 3.5e6 = 3.5 MPa)")
      ->capture_default_str();
  c->add_option("--young-modulus", o->youngModulus, "E (unit: Pa; seed 002 Table 2)")->capture_default_str();
  c->add_option("--poisson-ratio", o->poissonRatio, "nu (seed 002 Table 2)")->capture_default_str();
  c->add_option("--every", o->every, "solve every n-th record of each unit")->capture_default_str();
  c->add_option("-o,--output", o->output, "output folder (default RUN/stress)");
  c->add_option("--threads", o->threads, "OpenMP threads over the load cases (0 = OpenMP's default)")->capture_default_str();
  c->callback([o] { runStress(*o); });
}

} // namespace armour::app
