// SPDX-License-Identifier: GPL-3.0-or-later
// Peers side by side, in one run (issue 22, part 6): armour's penalty and constraint solvers and
// Bullet 3.24 on the same pile, one after the other in one process, one thread each, so the machine
// load is shared and the rows are comparable.
//
//   bench_peers [--scene cubes|corelocs] [--seconds 10] [--penalty-seconds S] [--penalty-cpu-limit C]
//               [--solvers constraint,bullet-box,bullet-hull,bullet-compound,penalty]
//               [--pieces 3|5|3,5] [--no-sleep] [--bullet-iterations 10] [--count N] [--seed 1]
//               [--trace-unit N --trace-window FROM TO] [--sleep-scope island|neighbours]
//
// The scene is bench_solver's pile with --placement drop (SolverBenchPile.cpp, buildPile): N units
// of Dn = 1 m (concrete 2400 kg/m^3, friction 0.6, restitution 0.1) released at rest from a jittered
// grid of 4 layers, randomly oriented, into a walled box. Each armour solver builds it afresh from
// the same seed; Bullet's bodies are copied from an armour World built the same way (PeersBullet).
// Every solver runs from release for --seconds of simulated time (the penalty solver for
// --penalty-seconds: it is slow), and its row gives the CPU time of the stepping thread
// (CLOCK_THREAD_CPUTIME_ID), body-steps and simulated body-seconds per core-second (all N units
// counted, asleep or not), the largest speed at the end and the largest displacement of any unit
// over the last --drift-window seconds. Figures go to docs/benchmarks.md with the printed command.
//
// This program is built only when CMake finds Bullet (libbullet-dev): an optional benchmark, never
// a dependency of the solver (scripts/bench-peers installs Bullet, builds and runs it).

#include "benchmarks/BenchClock.hpp"
#include "benchmarks/PeersBullet.hpp"
#include "benchmarks/SolverBenchPile.hpp"
#include "benchmarks/SolverBenchReport.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

namespace bench = armour::bench;
namespace sim = armour::simulation;
using armour::simulation::Vec3;

using armour::bench::loadAverages;
using armour::bench::threadCpuNow;

/// A unit slower than this is still (unit: m/s); one that moved less than this x 1 s over the
/// drift window has not drifted: 1 cm/s, a hundredth of Dn per second.
constexpr double kStill = 0.01;

/// --trace-unit: one armour unit's state and loaded contact points at every step of a window, to
/// tell a unit sliding at the Coulomb limit (|f_t| / f_n = mu at its points) from solver jitter.
struct UnitTrace {
  long unit = -1; ///< body index; -1: none
  double from = 0.0, to = 0.0; ///< simulated window (s)
};

void printTrace(const sim::World& world, const UnitTrace& t) {
  if (t.unit < 0 || world.time() < t.from - 1e-12 || world.time() > t.to + 1e-12) return;
  const auto u = static_cast<sim::BodyId>(t.unit);
  const Vec3 x = world.bodies().position(u);
  fmt::print(stderr, "trace: t = {:.3f} s, unit {}: speed {:.4f} m/s, spin {:.4f} rad/s, centroid ({:.4f}, {:.4f}, {:.5f}) m\n",
             world.time(), t.unit, world.bodies().velocity(u).norm(), world.bodies().worldAngularVelocity(u).norm(),
             x.x(), x.y(), x.z());
  Vec3 total = Vec3::Zero();
  for (const sim::TracedContact& c : world.tracedContacts()) {
    total += c.force;
    if (c.normalForce <= 0.0) continue;
    const double tangential = std::sqrt(std::max(0.0, c.force.squaredNorm() - c.normalForce * c.normalForce));
    fmt::print(stderr, "trace:   other {:>4} at ({:.3f}, {:.3f}, {:.3f}) m: normal {:.1f} N, |f_t| / f_n {:.3f}\n",
               c.other, c.point.x(), c.point.y(), c.point.z(), c.normalForce, tangential / c.normalForce);
  }
  fmt::print(stderr, "trace:   contact force on the unit ({:.1f}, {:.1f}, {:.1f}) N\n", total.x(), total.y(), total.z());
}

/// What any of the solvers offers the measuring loop.
struct Stepper {
  std::function<void()> step;
  std::function<double()> time;
  std::function<Vec3(std::size_t)> position;
  std::function<Vec3(std::size_t)> velocity;
  std::function<bool(std::size_t)> awake;
  std::size_t bodies = 0;
};

struct Row {
  std::string solver;
  std::string shape;       ///< short: what the units are made of
  std::string description; ///< long, below the table
  double dt = 0.0;
  double seconds = 0.0;   ///< simulated (s)
  std::uint64_t steps = 0;
  double cpu = 0.0;       ///< thread CPU time of the stepping (s)
  double wall = 0.0;      ///< s
  std::size_t bodies = 0;
  double awakeSum = 0.0;  ///< sum over steps of awake units
  std::size_t awakeEnd = 0;
  double maxSpeed = 0.0;  ///< at the end (m/s)
  double maxDrift = 0.0;  ///< largest displacement over the drift window (m)
  std::size_t moving = 0;  ///< units faster than kStill at the end
  std::size_t drifted = 0; ///< units displaced more than kStill x 1 s over the drift window
  double driftFrom = 0.0; ///< start of the drift window (s)
  std::size_t escaped = 0;
  std::string loadStart, loadEnd;
  bool cutShort = false;   ///< stopped before --seconds by the CPU limit
  std::string error;
};

/// Run `s` to `seconds` of simulated time. With cpuLimit > 0 the run may stop early, at a whole
/// simulated second, when the next second (costing what the last one did) would pass the limit;
/// its drift is then taken over that last whole second.
Row measure(const std::string& solver, Stepper& s, double seconds, double driftWindow, double halfWidth,
            double cpuLimit) {
  Row r;
  r.solver = solver;
  r.bodies = s.bodies;
  r.loadStart = loadAverages();
  fmt::print(stderr, "{}: running {:.2f} s of simulated time ...\n", solver, seconds);
  const double driftFrom = std::max(0.0, seconds - driftWindow);
  std::vector<Vec3> before(s.bodies);
  bool haveBefore = false;
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = threadCpuNow();
  double nextReport = 1.0;
  std::vector<Vec3> mark(s.bodies); // positions at the last whole second, for a run cut short
  for (std::size_t i = 0; i < s.bodies; ++i) mark[i] = s.position(i);
  double markTime = s.time(), cpuAtMark = cpu0;
  try {
    // A step is taken while time < seconds (to round-off): the window ends at the first step at or past it.
    while (s.time() < seconds - 1e-9) {
      if (!haveBefore && s.time() >= driftFrom - 1e-9) {
        for (std::size_t i = 0; i < s.bodies; ++i) before[i] = s.position(i);
        haveBefore = true;
        r.driftFrom = s.time();
      }
      s.step();
      ++r.steps;
      std::size_t awake = 0;
      for (std::size_t i = 0; i < s.bodies; ++i) awake += s.awake(i) ? 1 : 0;
      r.awakeSum += static_cast<double>(awake);
      if (s.time() >= nextReport) {
        double fastest = 0.0;
        std::size_t moving = 0, which = 0;
        for (std::size_t i = 0; i < s.bodies; ++i) {
          const double v = s.velocity(i).norm();
          which = v > fastest ? i : which;
          fastest = std::max(fastest, v);
          moving += v > kStill ? 1 : 0;
        }
        const double cpuNow = threadCpuNow();
        const Vec3 at = s.position(which);
        fmt::print(stderr, "  {}: t = {:.2f} s, {} awake, {} faster than {} m/s, largest speed {:.3g} m/s (unit {} at "
                   "({:.2f}, {:.2f}, {:.2f}) m), {:.0f} s CPU\n",
                   solver, s.time(), awake, moving, kStill, fastest, which, at.x(), at.y(), at.z(), cpuNow - cpu0);
        nextReport += 1.0;
        if (cpuLimit > 0.0 && s.time() < seconds - 1e-9 && (cpuNow - cpu0) + (cpuNow - cpuAtMark) > cpuLimit) {
          before = mark; // the drift over the last whole second
          haveBefore = true;
          r.driftFrom = markTime;
          r.cutShort = true;
          fmt::print(stderr, "  {}: stopped at t = {:.2f} s: the next second would pass the CPU limit of {} s\n", solver,
                     s.time(), cpuLimit);
          break;
        }
        for (std::size_t i = 0; i < s.bodies; ++i) mark[i] = s.position(i);
        markTime = s.time();
        cpuAtMark = cpuNow;
      }
    }
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  r.cpu = threadCpuNow() - cpu0;
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  r.seconds = s.time();
  r.dt = r.steps > 0 ? r.seconds / static_cast<double>(r.steps) : 0.0;
  for (std::size_t i = 0; i < s.bodies; ++i) {
    const Vec3 x = s.position(i);
    const double v = s.velocity(i).norm();
    r.maxSpeed = std::max(r.maxSpeed, v);
    r.moving += v > kStill ? 1 : 0;
    if (haveBefore) {
      const double d = (x - before[i]).norm();
      r.maxDrift = std::max(r.maxDrift, d);
      r.drifted += d > kStill * (r.seconds - r.driftFrom) ? 1 : 0;
    }
    r.awakeEnd += s.awake(i) ? 1 : 0;
    // Out of the box by more than the armour guard rail's overlap (0.25 Dn, Dn = 1 m): gone through a wall.
    if (!x.allFinite() || std::abs(x.x()) > halfWidth + 0.25 || std::abs(x.y()) > halfWidth + 0.25 || x.z() < -0.25) {
      ++r.escaped;
    }
  }
  if (!haveBefore) r.driftFrom = r.seconds;
  r.loadEnd = loadAverages();
  return r;
}

void printRowHeader(double driftWindow) {
  fmt::print("| solver | units as | dt (s) | simulated window (s) | steps | thread CPU (s) | wall (s) | body-steps / "
             "core-s | simulated body-s / core-s | mean awake | awake at end | largest speed at end (m/s) | units "
             "faster than {} m/s | largest drift over the last {} s (m) | units drifted more than {} m | escaped | "
             "load avg 1/5/15 min, start; end |\n",
             kStill, driftWindow, kStill * driftWindow);
  fmt::print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  std::fflush(stdout);
}

void printRow(const Row& r) {
  const double bodySteps = static_cast<double>(r.bodies) * static_cast<double>(r.steps);
  fmt::print("| {} | {} | {} | 0 - {:.2f} | {} | {} | {} | {} | {} | {:.0f} | {} | {} | {} | {} (from t = {:.2f} s) | {} "
             "| {} | {}; {} |{}\n",
             r.solver, r.shape, bench::si(r.dt), r.seconds, bench::group(static_cast<double>(r.steps)),
             bench::si(r.cpu), bench::si(r.wall), bench::group(bodySteps / r.cpu),
             bench::si(static_cast<double>(r.bodies) * r.seconds / r.cpu),
             r.steps > 0 ? r.awakeSum / static_cast<double>(r.steps) : 0.0, r.awakeEnd, bench::si(r.maxSpeed), r.moving,
             bench::si(r.maxDrift), r.driftFrom, r.drifted, r.escaped, r.loadStart, r.loadEnd,
             r.error.empty() ? (r.cutShort ? " (cut short by --penalty-cpu-limit)" : "")
                             : " STOPPED: " + r.error);
  std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
  bench::recordInvocation(argc, argv);
  CLI::App app{"armour penalty, armour constraint and Bullet 3.24 on the same pile, in one run (issue 22 part 6)"};
  std::string scene = "cubes";
  double seconds = 10.0;
  double penaltySeconds = -1.0;
  double penaltyCpuLimit = 0.0;
  double driftWindow = 1.0;
  std::vector<std::string> solvers;
  std::vector<int> pieces{3};
  bool noSleep = false;
  int iterations = 10;
  int count = 0;
  std::uint64_t seed = 1;
  app.add_option("--scene", scene, "cubes (256 unit cubes) or corelocs (242 Core-Locs of Dn 1 m)")
      ->check(CLI::IsMember({"cubes", "corelocs"}));
  app.add_option("--seconds", seconds, "simulated time from release, every solver but penalty (s)")
      ->check(CLI::PositiveNumber);
  app.add_option("--penalty-seconds", penaltySeconds, "simulated time of the penalty solver (s); default --seconds");
  app.add_option("--penalty-cpu-limit", penaltyCpuLimit,
                 "stop the penalty solver at the whole simulated second after which the next would pass this "
                 "much thread CPU time (s); 0: no limit");
  app.add_option("--drift-window", driftWindow, "the drift is the largest displacement over this last window (s)");
  std::string sleepScope = "island";
  app.add_option("--sleep-scope", sleepScope, "armour solvers: island (a whole contact island rests) or neighbours "
                                              "(a body and those it touches rest; scene key sleep.scope)")
      ->check(CLI::IsMember({"island", "neighbours"}));
  UnitTrace trace;
  std::vector<double> traceWindow;
  app.add_option("--trace-unit", trace.unit, "armour solvers: print this unit's speed and its loaded contact points "
                                             "(normal force, |f_t| / f_n) at every step of --trace-window to stderr");
  app.add_option("--trace-window", traceWindow, "FROM TO: the simulated window of --trace-unit (s)")->expected(2);
  app.add_option("--solvers", solvers,
                 "comma-separated, run in this order: constraint, bullet-box (cubes), bullet-hull, bullet-compound, "
                 "penalty; default: constraint, bullet-box, bullet-hull, penalty (cubes) or constraint, "
                 "bullet-compound, bullet-hull, penalty (corelocs)")
      ->delimiter(',')
      ->check(CLI::IsMember({"penalty", "constraint", "bullet-box", "bullet-hull", "bullet-compound"}));
  app.add_option("--pieces", pieces,
                 "convex pieces of a Core-Loc in bullet-compound: 3 (the members), 5 (the joins apart) or 3,5 (a "
                 "row each)")
      ->delimiter(',')
      ->check(CLI::IsMember({3, 5}));
  app.add_flag("--no-sleep", noSleep, "armour: sleep off; Bullet: deactivation off (default: both on)");
  app.add_option("--bullet-iterations", iterations, "Bullet's sequential-impulse iterations (its default 10)")
      ->check(CLI::PositiveNumber);
  app.add_option("--count", count, "units (default 256 cubes, 242 Core-Locs)")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "orientation and jitter seed");
  CLI11_PARSE(app, argc, argv);
  if (penaltySeconds <= 0.0) penaltySeconds = seconds;
  if (solvers.empty()) {
    solvers = scene == "cubes" ? std::vector<std::string>{"constraint", "bullet-box", "bullet-hull", "penalty"}
                               : std::vector<std::string>{"constraint", "bullet-compound", "bullet-hull", "penalty"};
  }
  // bullet-compound once per piece count (Core-Locs; a cube is one piece whatever is asked).
  std::vector<std::pair<std::string, int>> runs;
  for (const std::string& solver : solvers) {
    if (solver == "bullet-compound" && scene == "corelocs") {
      for (const int n : pieces) runs.emplace_back(solver, n);
    } else {
      runs.emplace_back(solver, pieces.front());
    }
  }
  if (trace.unit >= 0) {
    if (traceWindow.size() != 2 || !(traceWindow[0] <= traceWindow[1])) {
      fmt::print(stderr, "error: --trace-unit needs --trace-window FROM TO with FROM <= TO (s), e.g. --trace-window 9 10\n");
      return 1;
    }
    trace.from = traceWindow[0];
    trace.to = traceWindow[1];
  }
  omp_set_num_threads(1); // one thread each: armour's OpenMP loops run on the measuring thread

  bench::PileOptions o;
  o.shape = scene == "cubes" ? "cube" : "coreloc";
  o.count = count > 0 ? count : scene == "cubes" ? 256 : 242;
  o.placement = "drop";
  o.sleep = !noSleep;
  o.seed = seed;

  try {
    bench::printHeader(fmt::format("Peers side by side: {} {} (issue 22 part 6)", o.count, scene));
    bench::BulletSettings bs;
    bs.iterations = iterations;
    bs.sleep = !noSleep;
    bs.friction = o.friction;
    bs.restitution = o.restitution;
    {
      sim::World probe(bench::baseSettings(o.sleep));
      const bench::PileScene p = bench::buildPile(probe, o);
      fmt::print("Scene: {} units of Dn {} m ({}, concrete 2400 kg/m^3, friction {}, restitution {}), dropped from a "
                 "jittered grid of {} x {} per layer, pitch {:.3f} m (bounding diameter + 2 x 0.05 Dn), {} layers, "
                 "random orientations (seed {}), top centroid at z = {:.2f} m, into a box {:.2f} m x {:.2f} m (floor "
                 "and four walls); released at rest. Sleep {} (armour: sleep; Bullet: deactivation, default "
                 "thresholds). One thread each.  \n",
                 o.count, o.dn, o.shape, o.friction, o.restitution, p.side, p.side, p.cell,
                 (o.count + p.side * p.side - 1) / (p.side * p.side), seed, p.top, 2 * p.halfWidth, 2 * p.halfWidth,
                 o.sleep ? "on" : "off");
      fmt::print("Bullet 3.24 (libbullet-dev, single precision): btDiscreteDynamicsWorld, btDbvtBroadphase, "
                 "btSequentialImpulseConstraintSolver with {} iterations (split impulse, warm starting: its defaults), "
                 "fixed step {:.6f} s (1/240 s), each body's friction sqrt({}) and restitution sqrt({}) (Bullet "
                 "multiplies the pair's), mass and principal moments copied from armour's bodies.\n\n",
                 bs.iterations, bs.timeStep, o.friction, o.restitution);
    }
    printRowHeader(driftWindow);
    std::vector<Row> rows;
    for (const auto& [solver, pieceCount] : runs) {
      Row row;
      bs.corelocPieces = pieceCount;
      if (solver == "penalty" || solver == "constraint") {
        bench::setBenchSolver(solver == "penalty" ? sim::ContactSolverKind::Penalty
                                                  : sim::ContactSolverKind::Constraint);
        sim::WorldSettings ws = bench::baseSettings(o.sleep);
        ws.sleep.scope = sleepScope == "neighbours" ? sim::SleepScope::Neighbours : sim::SleepScope::Island;
        sim::World world(ws);
        const bench::PileScene p = bench::buildPile(world, o);
        Stepper s;
        s.bodies = world.bodies().size();
        if (trace.unit >= 0) world.setTracedBodies({static_cast<sim::BodyId>(trace.unit)});
        s.step = [&] {
          world.step();
          printTrace(world, trace);
        };
        s.time = [&] { return world.time(); };
        s.position = [&](std::size_t i) { return world.bodies().position(static_cast<sim::BodyId>(i)); };
        s.velocity = [&](std::size_t i) { return world.bodies().velocity(static_cast<sim::BodyId>(i)); };
        s.awake = [&](std::size_t i) { return world.bodies().isAwake(static_cast<sim::BodyId>(i)); };
        row = measure(solver, s, solver == "penalty" ? penaltySeconds : seconds, driftWindow, p.halfWidth,
                      solver == "penalty" ? penaltyCpuLimit : 0.0);
        row.shape = "level set";
        row.description = fmt::format("{}: level set 24 cells per Dn, surface samples 0.1 Dn, {} step {} s{}", solver,
                                      solver, bench::si(world.timeStep()),
                                      solver == "constraint" ? fmt::format(", {} substeps", world.settings().constraint.substeps)
                                                             : " (auto: 0.2 x the stability limit)");
        if (o.sleep) row.description += fmt::format("; sleep scope {}", sleepScope);
      } else {
        bench::setBenchSolver(sim::ContactSolverKind::Penalty);
        sim::World world(bench::baseSettings(o.sleep)); // the scene's bodies, never stepped
        const bench::PileScene p = bench::buildPile(world, o);
        bs.shape = solver == "bullet-box" ? bench::BulletShape::Box
                   : solver == "bullet-hull" ? bench::BulletShape::Hull
                                             : bench::BulletShape::Compound;
        bench::BulletPile pile(world, p.box, bs);
        Stepper s;
        s.bodies = pile.bodyCount();
        s.step = [&] { pile.step(); };
        s.time = [&] { return pile.time(); };
        s.position = [&](std::size_t i) { return pile.position(i); };
        s.velocity = [&](std::size_t i) { return pile.velocity(i); };
        s.awake = [&](std::size_t i) { return pile.awake(i); };
        fmt::print(stderr, "{}: {}\n", solver, pile.description());
        row = measure(solver, s, seconds, driftWindow, p.halfWidth, 0.0);
        row.shape = solver == "bullet-box"    ? "btBoxShape"
                    : solver == "bullet-hull" ? "btConvexHullShape"
                                              : fmt::format("btCompoundShape, {} hulls", pile.pieces().pieces.size());
        row.description = fmt::format("{}: {}", solver, pile.description());
      }
      printRow(row);
      rows.push_back(row);
    }
    fmt::print("\n");
    for (const Row& r : rows) fmt::print("- {}\n", r.description);
    fmt::print("\nColumns: body-steps / core-s = units x steps / thread CPU time; simulated body-s / core-s = units x "
               "simulated time / thread CPU time (all units counted, asleep or not); mean awake = units awake per "
               "step, averaged over the window; drift = largest displacement of a centroid between the start of the "
               "last {} s of the window and its end (units drifted: more than 1 cm per second of it); escaped = centroids outside the walls or under the floor by "
               "more than 0.25 Dn.\n",
               driftWindow);
    bool ok = true;
    for (const Row& r : rows) ok = ok && r.error.empty() && r.escaped == 0;
    return ok ? 0 : 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}
