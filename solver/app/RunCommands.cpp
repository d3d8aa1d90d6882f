// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/RunCommands.hpp"

#include "app/StopSignals.hpp"

#include "core/AtomicFile.hpp"
#include "core/CsvText.hpp"
#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"
#include "hydro/HydroStages.hpp"
#include "io/SceneReader.hpp"
#include "storm/StormFile.hpp"
#include "placement/Placer.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/DomainWatch.hpp"
#include "simulation/Interpenetration.hpp"
#include "simulation/RunOutputs.hpp"
#include "simulation/SceneBuilder.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace armour::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Wall-clock time between progress lines (unit: s): often enough to see a run is alive, rarely
/// enough that a long run's log stays readable.
constexpr double kProgressSeconds = 5.0;
/// Bodies leaving the static domain are logged one by one up to this many, then counted.
constexpr std::size_t kLoggedDomainExits = 10;


// ---------------------------------------------------------------------------------------------
// Checkpoints
// ---------------------------------------------------------------------------------------------

/// Writes the run's checkpoints: the scene's fingerprint and identity and the body names are the
/// same in all of them.
class RunCheckpoints {
public:
  RunCheckpoints(std::string fingerprint, std::string identity, const simulation::World& world)
      : fingerprint_(std::move(fingerprint)), identity_(std::move(identity)) {
    for (simulation::BodyId b = 0; b < world.bodies().size(); ++b) {
      names_.push_back(world.bodies().info(b).name);
    }
  }
  /// Capture the world (read only: the run is not perturbed) and write it atomically.
  void write(const fs::path& path, const simulation::World& world, const simulation::RunOutputs& outputs,
             const std::string& stopReason = {}) const {
    simulation::Checkpoint c;
    c.state = world.captureState();
    c.sceneFingerprint = fingerprint_;
    c.sceneIdentity = identity_;
    c.bodyNames = names_;
    c.outputs = outputs.schedule();
    c.applicationState = outputs.state();
    c.stopReason = stopReason;
    simulation::writeCheckpoint(path, c);
  }

private:
  std::string fingerprint_;
  std::string identity_;
  std::vector<std::string> names_;
};

/// The build line without its thread count, which does not change results.
std::string buildWithoutThreads(std::string build) {
  const auto comma = build.rfind(", ");
  if (comma != std::string::npos && build.find("thread", comma) != std::string::npos) {
    build.erase(comma);
  }
  return build;
}

/// Log a block of text one line at a time, so that every line carries the log prefix.
void logLines(const std::shared_ptr<spdlog::logger>& log, const std::string& text) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    log->info("{}", line);
  }
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
                         core::csvField(scene.bodies[i].name), x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(),
                         v.z());
    }
  });
}

/// The poses final_state.csv holds, as measure::readPoses reads them back (normalised quaternions).
measure::PoseMap finalPoses(const io::Scene& scene, const simulation::BuiltScene& built) {
  measure::PoseMap poses;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const simulation::BodyId b = built.bodyIndexOfSceneBody[i];
    measure::BodyPose& p = poses[scene.bodies[i].name];
    p.position = built.world->bodies().position(b);
    p.orientation = built.world->naturalOrientation(b).normalized();
  }
  return poses;
}

void checkScene(const std::string& path, const std::vector<std::string>& sets) {
  const io::Scene scene = io::readScene(path, sets);
  simulation::BuiltScene built = simulation::buildWorld(scene);
  std::cout << io::describeScene(scene);
  if (!built.warnings.empty()) {
    std::cout << fmt::format("build warnings ({}):\n", built.warnings.size());
    for (const std::string& w : built.warnings) {
      std::cout << "  " << w << "\n";
    }
  }
  std::cout << simulation::describeBuild(scene, built);
  // A placement's grid, made as `armour place` makes it: a grid that does not fit fails here.
  if (scene.placement.enabled) {
    const placement::GridPlan plan = placement::planGrid(scene);
    std::cout << fmt::format("placement: {} grid points", plan.points.size());
    if (plan.packingDensity > 0.0) std::cout << fmt::format(", packing density {:.4f} (N Dn^2 / A)", plan.packingDensity);
    std::cout << "\n";
  }
  // Hydrodynamic loads: the storm file is opened and validated, and must cover the run.
  if (const std::string hydro = hydro::attachLoadStages(*built.world, scene.hydro, scene.duration); !hydro.empty()) {
    std::cout << hydro << "\n";
    // The records the run will read, each checked as the run would (not the whole file: a storm
    // of an hour need not be read to check a run of a minute of it).
    std::cout << hydro::validateStormRecords(scene.hydro, scene.duration) << "\n";
  }
  simulation::World& world = *built.world;
  // Bodies inside each other, which the contact cannot separate and the guard rails do not see.
  const simulation::InterpenetrationReport overlaps = simulation::measureInterpenetration(world, built.planes);
  std::cout << simulation::describeInterpenetration(overlaps) << "\n";
  simulation::refuseInterpenetration(overlaps, path);
  // The forces of the initial state: overlaps the guard rails would stop the run for are found
  // now, not after the build of a long run.
  try {
    world.evaluateContacts();
  } catch (const simulation::SimulationError& e) {
    core::failInput(path, "the initial positions cannot be run: {}", e.what());
  }
  std::cout << fmt::format("initial contacts: {} candidate pairs, {} engaged points, deepest overlap {:.4g} m\n",
                           world.lastStep().candidatePairs, world.lastStep().contactPoints, world.lastStep().maxOverlap);
  std::cout << fmt::format("check: {} is valid\n", path);
}

/// `armour storm`: put the storm file on the scene's hydro settings (the scene's own `hydro:`
/// options, or the defaults without one), from the storm's first record if the scene's offset is
/// earlier, and, without --duration, run to the end of the storm.
void applyStorm(io::Scene& scene, const RunRequest& o) {
  hydro::HydroSettings& h = scene.hydro;
  if (h.enabled && h.model != hydro::HydroModel::Storm)
    core::failInput(scene.sourceName, "hydro.model is not `storm`: `armour storm` replays a storm file; set hydro.model: "
                                      "storm (or remove the hydro block for the defaults), or use `armour run`");
  if (!h.enabled) {
    // Without the block every setting keeps its default (the reader leaves them untouched).
    h.enabled = true;
    h.model = hydro::HydroModel::Storm;
    core::logger("run")->info("{} has no hydro: block: the storm's loads with the default settings "
                              "(docs/scene-file.md, Hydrodynamic loads)", scene.sourceName);
  }
  h.storm.file = fs::absolute(o.stormFile).string();
  if (o.variabilitySeed) h.storm.variability.seed = *o.variabilitySeed;
  if (o.timeOffset) {
    if (!(*o.timeOffset >= 0.0) || !std::isfinite(*o.timeOffset))
      core::failInput("--time-offset", "{} s: give the storm time (s, >= 0) at which the run starts", *o.timeOffset);
    h.storm.timeOffset = *o.timeOffset;
  }
  const storm::StormReader reader(h.storm.file);
  if (!o.timeOffset && h.storm.timeOffset < reader.times().front()) {
    // A sampled storm starts at its first sampling time (0.05 s for a run sampled every 0.05 s):
    // replay it from there.
    core::logger("run")->info("the storm file starts at t = {} s: replaying from there (--time-offset to choose)",
                              reader.times().front());
    h.storm.timeOffset = reader.times().front();
  }
  if (!o.durationGiven) {
    const double left = reader.times().back() - h.storm.timeOffset;
    if (!(left > 0.0))
      core::failInput("--time-offset", "{} s is at or after the end of the storm file {} ({} s); give an earlier offset",
                      h.storm.timeOffset, h.storm.file, reader.times().back());
    scene.duration = left;
  }
}


/// The --set changes to read the scene with. `armour storm` names the storm file on the command
/// line, so a placed scene has no hydro block; a `--set hydro.storm.<key>=...` would then make one
/// without its required file: the storm file is set first (applyStorm puts the same file on it).
std::vector<std::string> sceneSets(const RunRequest& o) {
  std::vector<std::string> sets = o.sets;
  const bool hydroSet =
      std::any_of(sets.begin(), sets.end(), [](const std::string& s) { return s.rfind("hydro.storm.", 0) == 0; });
  if (!o.stormFile.empty() && hydroSet)
    sets.insert(sets.begin(), "hydro.storm.file=" + fs::absolute(o.stormFile).string());
  return sets;
}

/// The command that makes this run, for bodies.nc's history (an ensemble member's run is written
/// as the `armour storm` it amounts to).
std::string commandLineOf(const RunRequest& o) {
  const auto quoted = [](const std::string& s) {
    return s.find_first_of(" '\"[]{}*?$") == std::string::npos ? s : "'" + s + "'";
  };
  std::string line = fmt::format("armour {} {}", o.stormFile.empty() ? "run" : "storm", quoted(o.scene));
  if (!o.stormFile.empty()) line += " --storm " + quoted(o.stormFile);
  if (o.timeOffset) line += fmt::format(" --time-offset {}", *o.timeOffset);
  if (o.variabilitySeed) line += fmt::format(" --variability-seed {}", *o.variabilitySeed);
  if (o.durationGiven) line += fmt::format(" --duration {}", o.duration);
  if (!o.output.empty()) line += " -o " + quoted(o.output);
  for (const std::string& set : o.sets) line += " --set " + quoted(set);
  if (o.restart) line += " --restart";
  return line;
}

/// Start a new run from the scene's initial_state (the state `armour place` left the pack in):
/// the bodies' positions, orientations and velocities and the contacts with their friction
/// springs, at time 0, every body awake (a pack at rest falls asleep again within the sleep time),
/// the load stages fresh. Refused, naming the body, if the state does not belong to the scene:
/// another body order or count, or a position moved by more than a micrometre (an edited scene).
/// Returns whether the contacts were carried over (they are not under other contact settings).
bool startFromInitialState(const io::Scene& scene, simulation::World& world) {
  const std::string file = scene.initialState.string();
  if (std::error_code ec; !fs::is_regular_file(scene.initialState, ec))
    core::failInput(file, "no placed state here (initial_state of {}): `armour place` writes it beside the placed "
                          "scene; place again, or remove initial_state from the scene to start from its positions",
                    scene.sourceName);
  simulation::Checkpoint c = simulation::readCheckpoint(scene.initialState, {"", "", world.bodies().size()});
  constexpr double kSamePosition = 1e-6; // m: the scene's 17 significant digits reproduce the state's
  for (simulation::BodyId b = 0; b < world.bodies().size(); ++b) {
    const std::string& name = world.bodies().info(b).name;
    if (b < c.bodyNames.size() && c.bodyNames[b] != name)
      core::failInput(file, "body {} is '{}' in the state but '{}' in the scene {}: the state is not this scene's; "
                            "place again, or remove initial_state from the scene to start from its positions",
                      b, c.bodyNames[b], name, scene.sourceName);
    const double moved = (c.state.bodies[b].position - world.bodies().position(b)).norm();
    if (!(moved <= kSamePosition))
      core::failInput(file, "body '{}' lies {:.3g} m from where the state has it (more than {} m): the scene {} was "
                            "edited after the placement; place again, or remove initial_state from the scene to "
                            "start from its positions",
                      name, moved, kSamePosition, scene.sourceName);
  }
  simulation::WorldState s = std::move(c.state);
  s.time = 0.0;
  s.steps = 0;
  s.forcesReady = false;
  s.energyStarted = false;
  s.energyMinimum = s.externalWork = s.energyPeak = 0.0;
  s.loadStages = world.captureState().loadStages;
  // The contacts' records (sample keys, friction springs) belong to the contact model they were
  // made with: under other settings (a fidelity study's) the run starts from the bodies' state
  // alone and builds its own contacts.
  const std::string contactModel = io::describeContactModel(scene.contact);
  if (c.applicationState != contactModel) {
    core::logger("run")->warn("{} was saved with '{}', this run uses '{}': its contacts (and their friction springs) "
                              "are not carried over, only the bodies' state",
                              file, c.applicationState.substr(0, c.applicationState.find('\n')), contactModel);
    s.contacts.clear();
    s.manifoldCache.clear();
  }
  try {
    world.restoreState(s);
  } catch (const core::InputError& e) {
    core::failInput(file, "{}", e.what());
  }
  world.wakeAll(); // every body awake, its rest clock at zero
  return c.applicationState == contactModel;
}

/// The run's checkpoint: <output folder>/checkpoint.nc.
fs::path checkpointPathOf(const io::Scene& scene) { return scene.output.folder / "checkpoint.nc"; }

/// The scene of a run: read with --set, then --duration, --storm and -o applied.
io::Scene readRunScene(const RunRequest& o) {
  if (o.threads < 0) {
    core::failInput("--threads", "{}: give a positive number of threads, or 0 for OpenMP's default", o.threads);
  }
  if (o.threads > 0) {
    omp_set_num_threads(o.threads); // before the build line, which reports the thread count
  }
  io::Scene scene = io::readScene(o.scene, sceneSets(o));
  if (o.durationGiven) {
    if (!(o.duration > 0.0) || !std::isfinite(o.duration)) {
      core::failInput("--duration", "{} s: give a positive simulated time in seconds", o.duration);
    }
    scene.duration = o.duration;
  }
  if (!o.stormFile.empty()) applyStorm(scene, o);
  if (!o.output.empty()) {
    scene.output.folder = fs::absolute(o.output);
  }
  return scene;
}

/// The checkpoint a restart continues from, read before anything in the folder changes (a refused
/// restart leaves the run as it was), and the previous log kept; then the output folder made.
std::optional<simulation::Checkpoint> openRunFolder(const io::Scene& scene, const RunRequest& o,
                                                    const std::string& fingerprint, const std::string& identity) {
  const fs::path checkpointPath = checkpointPathOf(scene);
  std::optional<simulation::Checkpoint> restart;
  if (o.restart) {
    restart = simulation::readCheckpoint(checkpointPath, {fingerprint, identity, 0});
    if (!restart->stopReason.empty()) {
      core::failInput(checkpointPath.string(),
                      "was written when the run stopped on an error ({}): it holds the state of the failed step, "
                      "which cannot be continued; fix the cause and start the run anew",
                      restart->stopReason);
    }
    keepPreviousLog(scene.output.folder / "run.log");
  }
  std::error_code ec;
  fs::create_directories(scene.output.folder, ec);
  if (ec) {
    core::failInput(scene.output.folder.string(), "cannot create the output folder ({}); set output.folder in {} or "
                                                  "--output to a writable place",
                    ec.message(), scene.sourceName);
  }
  return restart;
}

/// The World's first state: a fresh run's (the placed state or the scene's positions, refused when
/// bodies lie inside each other, simulation/Interpenetration.hpp), or the checkpoint's.
void startWorld(const io::Scene& scene, const simulation::BuiltScene& built,
                const std::optional<simulation::Checkpoint>& restart, const std::shared_ptr<spdlog::logger>& log) {
  simulation::World& world = *built.world;
  if (!restart) {
    if (!scene.initialState.empty()) {
      const bool contacts = startFromInitialState(scene, world);
      log->info("started from the placed state {} ({} as the placement left them)", scene.initialState.string(),
                contacts ? "positions, contacts and their friction springs" : "positions and velocities");
    }
    // Bodies inside each other would run silently to the end. A restart continues a state that
    // was checked when its run started.
    const simulation::InterpenetrationReport overlaps = simulation::measureInterpenetration(world, built.planes);
    log->info("{}", simulation::describeInterpenetration(overlaps));
    try {
      simulation::refuseInterpenetration(overlaps, scene.sourceName);
    } catch (const core::InputError& e) {
      log->error("{}", e.what()); // the run log says why the run did not start
      throw;
    }
    return;
  }
  const fs::path checkpointPath = checkpointPathOf(scene);
  try {
    world.restoreState(restart->state);
  } catch (const core::InputError& e) {
    core::failInput(checkpointPath.string(), "{}", e.what());
  }
  if (buildWithoutThreads(restart->build) != buildWithoutThreads(core::buildInfo())) {
    log->warn("{} was written by {}; this is {}: the continued run may differ in the last bits from an "
              "uninterrupted run of either",
              checkpointPath.string(), restart->build, core::buildInfo());
  }
  log->info("restarted from t = {} s (step {}) of {}", world.time(), world.stepCount(), checkpointPath.string());
  if (world.time() >= scene.duration - 0.5 * world.timeStep()) {
    log->warn("the checkpoint is at t = {} s, not before the duration {} s: nothing to run (give a longer "
              "--duration to extend the run)",
              world.time(), scene.duration);
  }
}

/// What the stepping loop counted, for the closing lines of the log.
struct RunTally {
  std::uint64_t firstStep = 0;
  double maxOverlap = 0.0;         ///< deepest overlap seen (unit: m)
  std::size_t movable = 0;         ///< bodies that are not fixed
  double awakeBodySteps = 0.0;     ///< body-steps integrated
  double movableBodySteps = 0.0;   ///< body-steps of movable bodies, asleep or not
  std::size_t domainExits = 0;     ///< bodies that left the static domain
  bool stopped = false;            ///< by SIGINT or SIGTERM
};

/// When the run's checkpoints are taken: every interval of simulated time and of wall time.
struct CheckpointPlan {
  double every = 0.0;       ///< simulated time between checkpoints (unit: s); 0 = none
  double wallSeconds = 0.0; ///< wall time between checkpoints (unit: s); 0 = none
  /// Checkpoint k is due at k x interval (simulated), like the outputs; taken at the first step
  /// after that at which bodies.nc is flushed (RunOutputs::flushed), which is within the interval.
  [[nodiscard]] long nextIndex(double t) const {
    return every > 0.0 ? static_cast<long>(std::floor(t / every + 1e-9)) + 1 : LONG_MAX;
  }
};

/// Step the World to the end of the run or to a stop signal: outputs, checkpoints on their plan,
/// the domain watch, progress lines. SimulationError passes through.
RunTally stepToEnd(const io::Scene& scene, const simulation::BuiltScene& built, simulation::RunOutputs& outputs,
                   const RunCheckpoints& checkpoints, const CheckpointPlan& plan, simulation::DomainWatch& domainWatch,
                   const StopSignals& signals, bool restarted, const std::shared_ptr<spdlog::logger>& log) {
  simulation::World& world = *built.world;
  const fs::path checkpointPath = checkpointPathOf(scene);
  const double dt = world.timeStep();
  const double end = scene.duration;
  RunTally tally;
  tally.firstStep = world.stepCount();
  // What the scene did not compute: body-steps of movable bodies spent asleep (fixed bodies, such
  // as a frozen rock underlayer, never cost a step and are not counted).
  for (simulation::BodyId b = 0; b < world.bodies().size(); ++b)
    if (world.bodies().motionType(b) != dynamics::MotionType::Static) ++tally.movable;
  const auto start = Clock::now();
  auto lastReport = start;
  auto lastCheckpoint = start;
  const auto wallSince = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  long nextCheckpoint = plan.nextIndex(world.time());
  // A new run's first record shows the forces of the initial state (contacts, hydrodynamic
  // loads); the first step would compute the same ones, so this changes nothing else. The
  // outputs of the start (a restart's were written before its checkpoint, at this step).
  if (!restarted) {
    world.evaluateContacts();
    outputs.update(world);
  }
  // Same end test as World::advanceTo: the last step lands within half a step of the end.
  while (world.time() < end - 0.5 * dt) {
    world.step();
    outputs.update(world);
    tally.maxOverlap = std::max(tally.maxOverlap, world.lastStep().maxOverlap);
    tally.awakeBodySteps += static_cast<double>(world.bodies().awakeBodies().size());
    tally.movableBodySteps += static_cast<double>(tally.movable);
    for (const simulation::DomainExit& e : domainWatch.update(world))
      if (++tally.domainExits <= kLoggedDomainExits) log->warn("{}", domainWatch.describe(world, e));
    if (signals.received() != 0) {
      tally.stopped = true;
      break;
    }
    const bool due = (plan.every > 0.0 && world.time() >= (static_cast<double>(nextCheckpoint) - 1e-9) * plan.every) ||
                     (plan.wallSeconds > 0.0 && wallSince(lastCheckpoint) >= plan.wallSeconds);
    if (due && outputs.flushed()) {
      checkpoints.write(checkpointPath, world, outputs);
      log->debug("checkpoint at t = {} s (step {})", world.time(), world.stepCount());
      nextCheckpoint = plan.nextIndex(world.time());
      lastCheckpoint = Clock::now();
    }
    if (wallSince(lastReport) >= kProgressSeconds) {
      lastReport = Clock::now();
      const double rate = static_cast<double>(world.stepCount() - tally.firstStep) / wallSince(start);
      const double remaining = (end - world.time()) / dt / rate;
      const simulation::StepStatistics& last = world.lastStep();
      log->info("t = {:.4f} s of {} s ({:.1f} %), {} steps, {:.0f} steps/s, ETA {:.0f} s; contacts {}, candidate "
                "pairs {} ({} manifolds reused), max overlap {:.3g} m",
                world.time(), end, 100.0 * world.time() / end, world.stepCount(), rate, remaining,
                last.contactPoints, last.candidatePairs, last.reusedPairs, tally.maxOverlap);
    }
  }
  return tally;
}

/// A run stopped by a guard rail: the state at the stop (CSV and a checkpoint for inspection),
/// logged and printed; exits 3.
[[noreturn]] void stopOnError(const simulation::SimulationError& e, const io::Scene& scene,
                              const simulation::BuiltScene& built, simulation::RunOutputs& outputs,
                              const RunCheckpoints& checkpoints, const std::shared_ptr<spdlog::logger>& log) {
  const fs::path state = scene.output.folder / "state_at_error.csv";
  const fs::path errorCheckpoint = scene.output.folder / "checkpoint_at_error.nc";
  const fs::path runLog = scene.output.folder / "run.log";
  log->error("the simulation stopped after {} steps: {}", built.world->stepCount(), e.what());
  writeStateCsv(state, scene, built);
  std::string saved = state.string();
  try {
    checkpoints.write(errorCheckpoint, *built.world, outputs, e.what());
    saved += ", " + errorCheckpoint.string();
  } catch (const core::InputError& writeError) {
    log->error("{}", writeError.what()); // the stop itself is the news: report it regardless
  }
  log->error("state at the stop written to {}; run log {}", saved, runLog.string());
  log->flush();
  std::cerr << fmt::format("error: {}: the simulation stopped: {}\n(state at the stop: {}; run log: {})\n",
                           scene.sourceName, e.what(), saved, runLog.string());
  throw CLI::RuntimeError(3);
}

/// A run stopped by SIGINT or SIGTERM: the outputs closed without a final frame (the restarted run
/// writes the next scheduled one), a checkpoint, and the command that continues; exits 130.
[[noreturn]] void stopOnSignal(const RunRequest& o, const io::Scene& scene, const simulation::World& world,
                               simulation::RunOutputs& outputs, const RunCheckpoints& checkpoints, int signal,
                               const std::shared_ptr<spdlog::logger>& log) {
  const fs::path checkpointPath = checkpointPathOf(scene);
  outputs.close();
  checkpoints.write(checkpointPath, world, outputs);
  std::string again = fmt::format("armour {} {} --restart{}", o.stormFile.empty() ? "run" : "storm", shellWord(o.scene),
                                  o.output.empty() ? std::string() : " -o " + shellWord(o.output));
  if (!o.stormFile.empty()) again += " --storm " + shellWord(o.stormFile);
  if (o.variabilitySeed) again += fmt::format(" --variability-seed {}", *o.variabilitySeed);
  for (const std::string& set : o.sets) again += " --set " + shellWord(set);
  log->warn("stopped by {} at t = {} s (step {}); checkpoint written to {}; continue with: {}", signalName(signal),
            world.time(), world.stepCount(), checkpointPath.string(), again);
  log->flush();
  std::cerr << fmt::format("{}: stopped by {} at t = {} s; checkpoint written to {}\ncontinue with: {}\n",
                           scene.sourceName, signalName(signal), world.time(), checkpointPath.string(), again);
  throw CLI::RuntimeError(kExitStopped);
}

/// The run log's closing lines: steps and wall time, energy and overlap, what slept, domain exits,
/// the load stages' summaries, the step's profile (printed with --profile), the files written.
void logRunEnd(const RunRequest& o, const io::Scene& scene, const simulation::World& world,
               const simulation::RunOutputs& outputs, const simulation::DomainWatch& domainWatch,
               const RunTally& tally, double wall, bool restarted, const std::shared_ptr<spdlog::logger>& log) {
  const double dt = world.timeStep();
  const std::uint64_t steps = world.stepCount() - tally.firstStep;
  log->info("finished: t = {:.6g} s in {} steps of {:.4g} s{}, wall time {:.2f} s ({:.0f} steps/s)", world.time(),
            world.stepCount(), dt, restarted ? fmt::format(" ({} since the restart)", steps) : std::string(), wall,
            static_cast<double>(steps) / std::max(wall, 1e-9));
  log->info("final kinetic energy {:.6g} J; deepest overlap seen {:.4g} m", world.bodies().totalKineticEnergy(),
            tally.maxOverlap);
  if (tally.movableBodySteps > 0.0)
    log->info("computed: {} of {} bodies movable ({} fixed, never stepped); asleep {:.1f} % of the movable "
              "body-steps (on average {:.1f} awake)",
              tally.movable, world.bodies().size(), world.bodies().size() - tally.movable,
              100.0 * (1.0 - tally.awakeBodySteps / tally.movableBodySteps),
              tally.awakeBodySteps / static_cast<double>(steps));
  if (tally.domainExits > 0)
    log->warn("{} bodies left the static domain in this run{} ({} outside it at the end): they fell off the edge of "
              "the scene's unbounded items",
              tally.domainExits,
              tally.domainExits > kLoggedDomainExits ? fmt::format(" (the first {} logged)", kLoggedDomainExits) : "",
              domainWatch.outsideCount());
  for (const auto& stage : world.loadStages())
    if (const std::string s = stage->summary(); !s.empty()) log->info("{}", s);
  // The step's stages (World::profile): where the wall time of the stepping went.
  const std::string profile = world.profile().table(steps);
  log->info("time step by stage ({} solver, {} steps):\n{}",
            world.settings().solver == simulation::ContactSolverKind::Constraint ? "constraint" : "penalty", steps,
            profile);
  if (o.profile) std::cout << profile << std::flush;
  log->info("wrote {} VTK frames, {} series records, {} and {}", outputs.vtkFrames(), outputs.seriesRecords(),
            (scene.output.folder / "final_state.csv").string(), checkpointPathOf(scene).string());
}

} // namespace

measure::PoseMap runScene(const RunRequest& o) {
  io::Scene scene = readRunScene(o);
  const fs::path checkpointPath = checkpointPathOf(scene);
  // What the run computes, to recognise its checkpoints: duration and output settings excluded.
  const std::string identity = simulation::sceneIdentity(scene);
  const std::string fingerprint = simulation::fingerprintOf(identity);
  const std::optional<simulation::Checkpoint> restart = openRunFolder(scene, o, fingerprint, identity);
  // The file sink first, then the build line again: the run log must start with it.
  const core::ScopedLogFile logFile((scene.output.folder / "run.log").string());
  auto log = core::logger("run");
  log->info("{}", core::buildInfo());
  log->info("run {} -> {}{}", o.scene, scene.output.folder.string(), o.restart ? " (restart)" : "");
  for (const std::string& set : o.sets) log->info("--set {} (changes the scene file's setting for this run)", set);
  logLines(log, io::describeScene(scene));
  log->info("scene fingerprint {} (checkpoints are refused by a scene with another one)", fingerprint);

  const auto buildStart = Clock::now();
  simulation::BuiltScene built = simulation::buildWorld(scene);
  logLines(log, simulation::describeBuild(scene, built));
  simulation::World& world = *built.world;
  // Load stages before a restart: their state is in the checkpoint.
  if (const std::string hydro = hydro::attachLoadStages(world, scene.hydro, scene.duration); !hydro.empty()) {
    log->info("{}", hydro);
  }
  log->info("built in {:.2f} s", std::chrono::duration<double>(Clock::now() - buildStart).count());
  startWorld(scene, built, restart, log);
  const std::optional<simulation::OutputSchedule> resume =
      restart ? std::optional<simulation::OutputSchedule>(restart->outputs) : std::nullopt;
  simulation::RunOutputs outputs(scene, built, {commandLineOf(o), o.scene, sceneSets(o)}, resume,
                                 restart ? restart->applicationState : std::string());
  log->info("outputs in {}: bodies.pvd (VTK every {} s), bodies.nc (series every {} s), final_state.csv",
            scene.output.folder.string(), scene.output.vtkInterval, scene.output.seriesInterval);
  const RunCheckpoints checkpoints(fingerprint, identity, world);
  const CheckpointPlan plan{scene.output.checkpointInterval, 60.0 * scene.output.checkpointWallMinutes};
  std::string when;
  if (plan.every > 0.0) when += fmt::format("every {} s of simulated time, ", plan.every);
  if (plan.wallSeconds > 0.0) when += fmt::format("every {} min of wall time, ", scene.output.checkpointWallMinutes);
  log->info("checkpoints to {}: {}at the end and when stopped by SIGINT or SIGTERM", checkpointPath.string(), when);
  log->info("{}", simulation::describeOutputTiming(scene.output, world.timeStep()));
  simulation::DomainWatch domainWatch(built.domain, world);
  if (domainWatch.outsideCount() > 0)
    log->warn("{} bodies are outside the static domain at the start (t = {} s): they left it before, or the scene "
              "puts them beyond its unbounded items' edges",
              domainWatch.outsideCount(), world.time());
  StopSignals signals;
  const auto start = Clock::now();
  RunTally tally;
  try {
    tally = stepToEnd(scene, built, outputs, checkpoints, plan, domainWatch, signals, restart.has_value(), log);
  } catch (const simulation::SimulationError& e) {
    stopOnError(e, scene, built, outputs, checkpoints, log);
  }
  if (tally.stopped) stopOnSignal(o, scene, world, outputs, checkpoints, signals.received(), log);
  outputs.finish(world);
  checkpoints.write(checkpointPath, world, outputs);
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  writeStateCsv(scene.output.folder / "final_state.csv", scene, built);
  logRunEnd(o, scene, world, outputs, domainWatch, tally, wall, restart.has_value(), log);
  log->flush();
  return finalPoses(scene, built);
}

void addSetOption(CLI::App& command, std::vector<std::string>& sets) {
  command.add_option("--set", sets,
                     "KEY=VALUE: change a scene setting for this run, e.g. --set hydro.storm.update_interval=0.5 "
                     "--set contact.model=fdem --set static[0].friction=0.7 (repeatable; docs/user-guide.md)")
      ->take_all()
      ->allow_extra_args(false);
}

void addRunCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto c = std::make_shared<RunRequest>();
  auto* check = app.add_subcommand("check", "validate a scene file and build its world (shapes, level sets, static "
                                            "pieces) without running it; prints the resolved settings and time step");
  check->add_option("scene", c->scene, "scene file (.yaml), docs/scene-file.md")->required();
  addSetOption(*check, c->sets);
  check->callback([c] { checkScene(c->scene, c->sets); });

  auto o = std::make_shared<RunRequest>();
  auto* run = app.add_subcommand("run", "run a scene file: build the world and step it to the scene's duration");
  run->add_option("scene", o->scene, "scene file (.yaml), docs/scene-file.md")->required();
  auto* duration = run->add_option("--duration", o->duration, "simulated time (s), instead of the scene's duration");
  run->add_option("--threads", o->threads, "OpenMP threads (0 = OpenMP's default: OMP_NUM_THREADS or all cores)")
      ->capture_default_str();
  run->add_option("-o,--output", o->output, "output folder, instead of the scene's output.folder");
  addSetOption(*run, o->sets);
  run->add_flag("--profile", o->profile, "print the wall time of each stage of the time step at the end (also in run.log)");
  run->add_flag("--restart", o->restart,
                "continue the run in the output folder from its checkpoint.nc (to the duration, which may be longer); "
                "the scene may differ in duration and output settings only (docs/user-guide.md)");
  run->callback([o, duration] {
    o->durationGiven = duration->count() > 0;
    runScene(*o);
  });

  auto s = std::make_shared<RunRequest>();
  auto* storm = app.add_subcommand("storm", "replay a storm file on a placed scene (its hydro: options, or the "
                                            "defaults), to the end of the storm; checkpoints and --restart as run");
  storm->add_option("scene", s->scene, "placed scene file (.yaml), e.g. from armour place")->required();
  storm->add_option("--storm", s->stormFile, "storm file (netCDF-4, docs/storm-file.md): from foam-proxy, the "
                                             "armourSampler function object or armour storm-file synth")
      ->required()
      ->check(CLI::ExistingFile);
  auto* offset = storm->add_option("--time-offset", "storm time at simulation time 0 (s), instead of the scene's");
  auto* stormDuration = storm->add_option("--duration", s->duration, "simulated time (s); default: to the storm's end");
  storm->add_option("--threads", s->threads, "OpenMP threads (0 = OpenMP's default)")->capture_default_str();
  storm->add_option("-o,--output", s->output, "output folder, instead of the scene's output.folder");
  addSetOption(*storm, s->sets);
  storm->add_option("--variability-seed", s->variabilitySeed,
                    "seed of the storm's variability draws (a storm realisation), instead of the scene's");
  storm->add_flag("--profile", s->profile, "print the wall time of each stage of the time step at the end (also in run.log)");
  storm->add_flag("--restart", s->restart, "continue from the output folder's checkpoint.nc (same scene and storm)");
  storm->callback([s, offset, stormDuration] {
    s->durationGiven = stormDuration->count() > 0;
    if (offset->count() > 0) s->timeOffset = offset->as<double>();
    runScene(*s);
  });
}

} // namespace armour::app
