// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/RunCommands.hpp"

#include "core/AtomicFile.hpp"
#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"
#include "io/SceneReader.hpp"
#include "simulation/RunOutputs.hpp"
#include "simulation/SceneBuilder.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace armour::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Wall-clock time between progress lines (unit: s): often enough to see a run is alive, rarely
/// enough that a long run's log stays readable.
constexpr double kProgressSeconds = 5.0;

struct RunOptions {
  std::string scene;
  double duration = 0.0; ///< overrides the scene's when durationGiven (unit: s)
  bool durationGiven = false;
  int threads = 0;       ///< OpenMP threads, 0 = OpenMP's default
  std::string output;    ///< overrides the scene's output folder when not empty
};

/// Log a block of text one line at a time, so that every line carries the log prefix.
void logLines(const std::shared_ptr<spdlog::logger>& log, const std::string& text) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    log->info("{}", line);
  }
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) {
    return text;
  }
  std::string quoted = "\"";
  for (char c : text) {
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  }
  return quoted + "\"";
}

/// One row per scene body: index, name, centroid, orientation of the body's natural shape frame
/// (as the scene gives it), velocity. Full double precision so a state can be compared or reused.
void writeStateCsv(const fs::path& path, const io::Scene& scene, const simulation::BuiltScene& built) {
  const simulation::World& world = *built.world;
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz\n";
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const simulation::BodyId b = built.bodyIndexOfSceneBody[i];
      const auto& x = world.bodies().position(b);
      const auto q = world.naturalOrientation(b);
      const auto& v = world.bodies().velocity(b);
      out << fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", i,
                         csvField(scene.bodies[i].name), x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(),
                         v.z());
    }
  });
}

void checkScene(const std::string& path) {
  const io::Scene scene = io::readScene(path);
  const simulation::BuiltScene built = simulation::buildWorld(scene);
  std::cout << io::describeScene(scene);
  if (!built.warnings.empty()) {
    std::cout << fmt::format("build warnings ({}):\n", built.warnings.size());
    for (const std::string& w : built.warnings) {
      std::cout << "  " << w << "\n";
    }
  }
  std::cout << simulation::describeBuild(scene, built);
  std::cout << fmt::format("check: {} is valid\n", path);
}

void runScene(const RunOptions& o) {
  if (o.threads < 0) {
    core::failInput("--threads", "{}: give a positive number of threads, or 0 for OpenMP's default", o.threads);
  }
  if (o.threads > 0) {
    omp_set_num_threads(o.threads); // before the build line, which reports the thread count
  }
  io::Scene scene = io::readScene(o.scene);
  if (o.durationGiven) {
    if (!(o.duration > 0.0) || !std::isfinite(o.duration)) {
      core::failInput("--duration", "{} s: give a positive simulated time in seconds", o.duration);
    }
    scene.duration = o.duration;
  }
  if (!o.output.empty()) {
    scene.output.folder = fs::absolute(o.output);
  }
  std::error_code ec;
  fs::create_directories(scene.output.folder, ec);
  if (ec) {
    core::failInput(scene.output.folder.string(), "cannot create the output folder ({}); set output.folder in {} or "
                                                  "--output to a writable place",
                    ec.message(), scene.sourceName);
  }
  const fs::path runLog = scene.output.folder / "run.log";
  // The file sink first, then the build line again: the run log must start with it.
  core::addLogFile(runLog.string());
  auto log = core::logger("run");
  log->info("{}", core::buildInfo());
  log->info("run {} -> {}", o.scene, scene.output.folder.string());
  logLines(log, io::describeScene(scene));

  const auto buildStart = Clock::now();
  simulation::BuiltScene built = simulation::buildWorld(scene);
  logLines(log, simulation::describeBuild(scene, built));
  log->info("built in {:.2f} s", std::chrono::duration<double>(Clock::now() - buildStart).count());
  simulation::RunOutputs outputs(scene, built, "armour run " + o.scene);
  log->info("outputs in {}: bodies.pvd (VTK every {} s), bodies.nc (series every {} s), final_state.csv",
            scene.output.folder.string(), scene.output.vtkInterval, scene.output.seriesInterval);

  simulation::World& world = *built.world;
  const double dt = world.timeStep();
  const double end = scene.duration;
  double maxOverlap = 0.0;
  const auto start = Clock::now();
  auto lastReport = start;
  const auto wallSince = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  try {
    // Same end test as World::advanceTo: the last step lands within half a step of the end.
    outputs.update(world);
    while (world.time() < end - 0.5 * dt) {
      world.step();
      outputs.update(world);
      maxOverlap = std::max(maxOverlap, world.lastStep().maxOverlap);
      if (wallSince(lastReport) >= kProgressSeconds) {
        lastReport = Clock::now();
        const double wall = wallSince(start);
        const double rate = static_cast<double>(world.stepCount()) / wall;
        const double remaining = (end - world.time()) / dt / rate;
        log->info("t = {:.4f} s of {} s ({:.1f} %), {} steps, {:.0f} steps/s, ETA {:.0f} s; contacts {}, max overlap "
                  "{:.3g} m",
                  world.time(), end, 100.0 * world.time() / end, world.stepCount(), rate, remaining,
                  world.lastStep().contactPoints, maxOverlap);
      }
    }
  } catch (const simulation::SimulationError& e) {
    const fs::path state = scene.output.folder / "state_at_error.csv";
    log->error("the simulation stopped after {} steps: {}", world.stepCount(), e.what());
    writeStateCsv(state, scene, built);
    log->error("state at the stop written to {}; run log {}", state.string(), runLog.string());
    log->flush();
    std::cerr << fmt::format("error: {}: the simulation stopped: {}\n(state at the stop: {}; run log: {})\n",
                             scene.sourceName, e.what(), state.string(), runLog.string());
    throw CLI::RuntimeError(3);
  }
  outputs.finish(world);
  const double wall = wallSince(start);
  const fs::path finalState = scene.output.folder / "final_state.csv";
  writeStateCsv(finalState, scene, built);
  log->info("finished: t = {:.6g} s in {} steps of {:.4g} s, wall time {:.2f} s ({:.0f} steps/s)", world.time(),
            world.stepCount(), dt, wall, static_cast<double>(world.stepCount()) / std::max(wall, 1e-9));
  log->info("final kinetic energy {:.6g} J; deepest overlap seen {:.4g} m", world.bodies().totalKineticEnergy(),
            maxOverlap);
  log->info("wrote {} VTK frames, {} series records and {}", outputs.vtkFrames(), outputs.seriesRecords(),
            finalState.string());
  log->flush();
}

} // namespace

void addRunCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto checkPath = std::make_shared<std::string>();
  auto* check = app.add_subcommand("check", "validate a scene file and build its world (shapes, level sets, static "
                                            "pieces) without running it; prints the resolved settings and time step");
  check->add_option("scene", *checkPath, "scene file (.yaml), docs/scene-file.md")->required();
  check->callback([checkPath] { checkScene(*checkPath); });

  auto o = std::make_shared<RunOptions>();
  auto* run = app.add_subcommand("run", "run a scene file: build the world and step it to the scene's duration");
  run->add_option("scene", o->scene, "scene file (.yaml), docs/scene-file.md")->required();
  auto* duration = run->add_option("--duration", o->duration, "simulated time (s), instead of the scene's duration");
  run->add_option("--threads", o->threads, "OpenMP threads (0 = OpenMP's default: OMP_NUM_THREADS or all cores)")
      ->capture_default_str();
  run->add_option("-o,--output", o->output, "output folder, instead of the scene's output.folder");
  run->callback([o, duration] {
    o->durationGiven = duration->count() > 0;
    runScene(*o);
  });
}

} // namespace armour::app
