// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/DeformCommands.hpp"

#include "app/DeformRigidPack.hpp"

#include "app/StopSignals.hpp"
#include "core/AtomicFile.hpp"
#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "core/JsonWriter.hpp"
#include "core/Log.hpp"
#include "contact/LevelSet.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/DeformableCheckpoint.hpp"
#include "deformable/DeformableVtu.hpp"
#include "deformable/StressHistory.hpp"
#include "deformable/StructuredBox.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshFile.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "geometry/Tetrahedralizer.hpp"
#include "io/DeformableScene.hpp"
#include "io/VtkFrameWriter.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

namespace armour::app {
namespace {

namespace fs = std::filesystem;
using deformable::Vec3;

struct DeformRequest {
  std::string scene;
  std::string output;
  int threads = 0;
  bool restart = false;
  double duration = 0.0;
  bool durationGiven = false;
};

/// One part's tets in its own frame: a library shape meshed by gmsh (centred on its centroid), or
/// a box of Kuhn cells (centred on its centre).
geometry::TetMesh meshInOwnFrame(const io::DeformablePart& p, const std::string& source) {
  geometry::TetMesh mesh;
  if (!p.meshFile.empty()) {
    geometry::TriangleMesh surface = geometry::readValidMesh(p.meshFile, "deform");
    const geometry::MassProperties mp = geometry::computeMassProperties(surface);
    const double scale = p.volume > 0.0 ? std::cbrt(p.volume / mp.volume) : 1.0;
    for (auto& v : surface.vertices) v = scale * (v - mp.centroid); // centred on its centroid, as a library shape
    geometry::TetrahedralizeOptions options;
    options.targetTetCount = p.tets;
    options.keepSurface = false;
    options.source = fmt::format("{}: bodies '{}' ({})", source, p.name, p.meshFile.string());
    mesh = geometry::tetrahedralize(surface, options);
  } else if (!p.shape.empty()) {
    geometry::TetrahedralizeOptions options;
    options.targetTetCount = p.tets;
    options.keepSurface = false;
    options.source = fmt::format("{}: bodies '{}'", source, p.name);
    mesh = geometry::tetrahedralize(io::librarySurface(p), options);
  } else {
    mesh = deformable::structuredBox(p.box, static_cast<int>(p.cells[0]), static_cast<int>(p.cells[1]),
                                     static_cast<int>(p.cells[2]));
    for (auto& v : mesh.vertices) v -= 0.5 * p.box; // centred on the box's centre
  }
  return mesh;
}

/// Every part's tets in the world. Parts of the same shape, size, count and seed (a grid's
/// copies) are meshed once and copied.
std::vector<geometry::TetMesh> meshParts(const std::vector<io::DeformablePart>& parts, const std::string& source) {
  std::map<std::string, geometry::TetMesh> meshed;
  std::vector<geometry::TetMesh> out;
  for (const auto& p : parts) {
    std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", p.shape, p.meshFile.string(), p.volume, p.tets, p.shapeSeed, p.box.x(),
                                  p.box.y(), p.box.z(), p.cells[0], p.cells[1], p.cells[2]);
    for (const auto& [name, value] : p.params) key += fmt::format("|{}={}", name, value);
    auto it = meshed.find(key);
    if (it == meshed.end()) it = meshed.emplace(key, meshInOwnFrame(p, source)).first;
    geometry::TetMesh mesh = it->second;
    for (auto& v : mesh.vertices) v = p.orientation * v + p.position;
    out.push_back(std::move(mesh));
  }
  return out;
}

deformable::DeformableSettings bodySettings(const io::DeformableScene& s, double viscosityLength) {
  deformable::DeformableSettings d;
  d.material.density = s.density;
  d.material.youngModulus = s.youngModulus;
  d.material.poissonRatio = s.poissonRatio;
  d.material.viscosity = s.viscosityFraction * deformable::criticalViscosity(d.material, viscosityLength);
  d.gravity = s.gravity;
  d.fBar = s.fBar;
  d.massDamping = s.massDamping;
  d.stepSafety = s.stepSafety;
  d.massScaling = s.massScaling;
  for (const auto& h : s.halfSpaces) d.halfSpaces.push_back({h.point, h.normal});
  d.contactGradient = s.contactGradient;
  d.friction = s.friction;
  d.bodyContact = s.parts.size() > 1;
  d.contactPenalty = s.contactPenalty;
  d.contactDamping = s.contactDamping;
  d.bodyFriction = s.bodyFriction;
  d.rigidContact = !s.rigidBodies.empty();
  return d;
}

/// The fixed rigid bodies: each library shape meshed at its volume (centred on its centroid) and
/// given a level set; `levelSets` keeps them alive for the body.
std::vector<deformable::RigidObstacle> rigidObstacles(const io::DeformableScene& scene,
                                                      std::vector<std::unique_ptr<contact::LevelSet>>& levelSets,
                                                      const std::shared_ptr<spdlog::logger>& log) {
  std::vector<deformable::RigidObstacle> out;
  for (const io::RigidPart& r : scene.rigidBodies) {
    contact::LevelSetSettings settings;
    settings.cellsPerDn = r.cellsPerDn;
    const std::string source = fmt::format("{}: rigid_bodies '{}'", scene.file.string(), r.part.name);
    levelSets.push_back(std::make_unique<contact::LevelSet>(io::librarySurface(r.part), settings, source));
    deformable::RigidObstacle o;
    o.levelSet = levelSets.back().get();
    o.position = r.part.position;
    o.orientation = r.part.orientation;
    out.push_back(o);
    log->info("rigid body '{}': {} of {} m^3, fixed, level set cells of {:.4g} m", r.part.name, r.part.shape,
              r.part.volume, o.levelSet->cellSize());
  }
  return out;
}

void writeSummary(const fs::path& path, const deformable::DeformableBody& body, const deformable::StressHistory& h,
                  const std::vector<std::string>& partOfElementName) {
  const auto& e = h.extremes();
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "{\n";
    out << fmt::format("  \"time_s\": {},\n  \"steps\": {},\n  \"elements\": {},\n  \"nodes\": {},\n",
                       core::jsonNumber(body.time()), body.steps(), body.mesh().elementCount(), body.nodeCount());
    out << fmt::format("  \"added_mass_kg\": {},\n  \"added_mass_elements\": {},\n",
                       core::jsonNumber(body.massScaling().addedMass), body.massScaling().scaled);
    out << fmt::format("  \"time_step_s\": {},\n  \"samples\": {},\n", core::jsonNumber(body.stableStep().dt),
                       h.samples().size());
    const std::pair<const char*, const deformable::StressPeak*> peaks[3] = {
        {"largest_tension", &e.tension}, {"largest_differential_stress", &e.differential}, {"largest_von_mises", &e.vonMises}};
    for (int k = 0; k < 3; ++k) {
      const auto& p = *peaks[k].second;
      out << fmt::format("  \"{}\": {{\"value_Pa\": {}, \"time_s\": {}, \"element\": {}, \"body\": {}, \"x_m\": [{}, {}, {}]}}{}\n",
                         peaks[k].first, core::jsonNumber(p.value), core::jsonNumber(p.time), p.element,
                         core::jsonString(h.samples().empty() ? "" : partOfElementName[p.element]),
                         core::jsonNumber(p.location.x()), core::jsonNumber(p.location.y()),
                         core::jsonNumber(p.location.z()), k < 2 ? "," : "");
    }
    out << "}\n";
  });
}

/// The run log's lines on the body: elements, the step and what sets it, mass scaling.
void logBody(const std::shared_ptr<spdlog::logger>& log, const deformable::DeformableBody& body,
             const io::DeformableScene& scene) {
  const double dt = body.stableStep().dt;
  log->info("{} elements ({}), {} nodes; step {:.4g} s (safety {} x the limit: {}{}); "
            "viscosity {:.4g} Pa s",
            body.mesh().elementCount(), scene.quadratic ? "tet10" : "tet4", body.nodeCount(), dt, scene.stepSafety,
            body.stableStep().meshBound
                ? fmt::format("the mesh's frequency bound {:.4g} rad/s (Gershgorin; the smallest element alone would "
                              "give {:.4g} rad/s)",
                              body.stableStep().meshFrequency,
                              2.0 * body.stableStep().waveSpeed / body.massScaling().length)
                : fmt::format("smallest element {:.4g} m", body.stableStep().lengthMin),
            body.stableStep().contactFrequency > 0.0
                ? fmt::format(", contact {:.4g} rad/s", body.stableStep().contactFrequency)
                : std::string(),
            body.settings().material.viscosity);
  if (const auto& ms = body.massScaling(); scene.massScaling > 0.0) {
    log->info("mass scaling (run.mass_scaling = {}): {} of {} elements heavier, {:.4g} kg added ({:.3g} % of {:.4g} kg; "
              "at most {:.3g} % of a body's own mass); the smallest element {:.4g} m acts as {:.4g} m ({:.3g} times; the "
              "contact may hold the step shorter)",
              scene.massScaling, ms.scaled, body.mesh().elementCount(), ms.addedMass, 100.0 * ms.addedMass / ms.mass,
              ms.mass, 100.0 * ms.largestPartFraction, ms.lengthMin, ms.length, ms.length / ms.lengthMin);
  }
}

/// The deformable body of a scene: every part meshed, placed and merged into one mesh (parts touch
/// through the body contact), with its initial velocities; and the body name of each element.
struct DeformSetup {
  std::unique_ptr<deformable::DeformableBody> body;
  std::vector<std::string> partOfElementName;
};

DeformSetup buildBody(const io::DeformableScene& scene, const std::string& source,
                      const std::shared_ptr<spdlog::logger>& log) {
  const std::vector<geometry::TetMesh> parts = meshParts(scene.parts, source);
  DeformSetup setup;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    setup.partOfElementName.insert(setup.partOfElementName.end(), parts[k].tets.size(), scene.parts[k].name);
    if (k < 10 || k + 1 == parts.size()) {
      log->info("body '{}': {} tetrahedra, {:.6g} m^3", scene.parts[k].name, parts[k].tets.size(),
                parts[k].totalVolume());
    } else if (k == 10) {
      log->info("... ({} bodies in all)", parts.size());
    }
  }
  const geometry::TetMesh merged = deformable::mergeTetMeshes(parts, std::vector<Vec3>(parts.size(), Vec3::Zero()));
  const double h = std::cbrt(merged.totalVolume() / static_cast<double>(merged.tets.size()));
  setup.body = std::make_unique<deformable::DeformableBody>(
      deformable::makeDeformableMesh(merged, scene.quadratic ? deformable::ElementOrder::Quadratic
                                                             : deformable::ElementOrder::Linear,
                                     "deform scene"),
      bodySettings(scene, h), source);
  deformable::DeformableBody& body = *setup.body;
  std::vector<Vec3> velocity(body.nodeCount(), Vec3::Zero());
  std::size_t element = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    for (std::size_t e = 0; e < parts[k].tets.size(); ++e, ++element) {
      const std::int32_t* nodes = body.mesh().element(element);
      for (int a = 0; a < body.mesh().nodesPerElement(); ++a) {
        velocity[static_cast<std::size_t>(nodes[a])] = scene.parts[k].velocity;
      }
    }
  }
  body.setVelocities(velocity);
  return setup;
}

/// The run log's closing lines: time, cost, the extremes, the rigid bodies' loads, the outputs.
void logFinish(const std::shared_ptr<spdlog::logger>& log, const deformable::DeformableBody& body,
               const deformable::StressHistory& history, const DeformSetup& setup, const io::DeformableScene& scene,
               const DeformRigidPack* pack, double wall, const fs::path& out) {
  const auto& e = history.extremes();
  const auto& times = body.stepTimes();
  log->info("finished: t = {} s in {} steps, {:.1f} s of wall time (element forces {:.1f} s, nodal sums with "
            "contact {:.1f} s, update {:.1f} s)",
            body.time(), body.steps(), wall, times.elementForces, times.gather, times.update);
  log->info("largest tension sigma_1 {:.4g} MPa at t = {:.4g} s (body '{}', element {}); largest sigma_1 - sigma_3 "
            "{:.4g} MPa at t = {:.4g} s; largest von Mises {:.4g} MPa",
            1e-6 * e.tension.value, e.tension.time, setup.partOfElementName[e.tension.element], e.tension.element,
            1e-6 * e.differential.value, e.differential.time, 1e-6 * e.vonMises.value);
  if (pack) pack->logEnd(log);
  for (std::size_t k = 0; !pack && k < body.obstacleLoads().size(); ++k) {
    const Vec3& f = body.obstacleLoads()[k].force;
    log->info("rigid body '{}' carries [{:.6g}, {:.6g}, {:.6g}] N from the deformable bodies", scene.rigidBodies[k].part.name,
              f.x(), f.y(), f.z());
  }
  log->info("outputs: {} (ParaView), {}, {}, {}", (out / "frames.pvd").string(), (out / "stress_history.csv").string(),
            (out / "summary.json").string(), (out / "checkpoint.bin").string());
}

/// The output folder made (frames/ in it), the previous log kept on a restart; refuses a restart
/// without a checkpoint.
void prepareOutput(const fs::path& out, const DeformRequest& o) {
  if (o.restart && !fs::exists(out / "checkpoint.bin")) {
    core::failInput((out / "checkpoint.bin").string(), "no checkpoint to continue from; run without --restart first");
  }
  if (o.restart) keepPreviousLog(out / "run.log");
  std::error_code ec;
  fs::create_directories(out / "frames", ec);
  if (ec) {
    core::failInput(out.string(), "cannot create the output folder ({}); set output.folder in {} or --output to a "
                                  "writable place", ec.message(), o.scene);
  }
}

void runDeform(const DeformRequest& o) {
  io::DeformableScene scene = io::readDeformableScene(o.scene);
  if (o.durationGiven) scene.duration = o.duration;
  if (!o.output.empty()) scene.output = fs::absolute(o.output);
  const fs::path out = scene.output;
  const fs::path checkpoint = out / "checkpoint.bin";
  const fs::path historyFile = out / "stress_history.csv";
  const fs::path pvd = out / "frames.pvd";
  prepareOutput(out, o);
  const core::ScopedLogFile logFile((out / "run.log").string());
  auto log = core::logger("deform");
  log->info("{}", core::buildInfo());
  log->info("deform {} -> {}{}", o.scene, out.string(), o.restart ? " (restart)" : "");
  if (o.threads > 0) omp_set_num_threads(o.threads);

  std::vector<std::unique_ptr<contact::LevelSet>> levelSets; // the fixed rigid bodies' (before the body: they outlive it)
  const DeformSetup setup = buildBody(scene, o.scene, log);
  deformable::DeformableBody& body = *setup.body;
  // Moving rigid bodies: a World of them all, the body advancing inside its step; else fixed obstacles.
  const std::unique_ptr<DeformRigidPack> pack = DeformRigidPack::make(scene, body, out, log);
  if (!pack && !scene.rigidBodies.empty()) body.setObstacles(rigidObstacles(scene, levelSets, log));
  const double dt = body.stableStep().dt;
  logBody(log, body, scene);
  deformable::StressHistory history;
  std::vector<io::CollectionEntry> frames;
  if (o.restart) {
    // The history and the frames are written before the checkpoint (save below): what a stop
    // left beyond the checkpoint's time is dropped and made again.
    deformable::readDeformableCheckpoint(checkpoint, body);
    if (pack) {
      pack->restore();
    } else if (fs::exists(DeformRigidPack::checkpointPath(out))) {
      core::failInput(DeformRigidPack::checkpointPath(out).string(),
                      "the run that wrote the checkpoint had moving rigid bodies, and {} has none; restore their "
                      "'fixed: false' or start anew without --restart", o.scene);
    }
    if (fs::exists(historyFile)) history = deformable::StressHistory::readCsv(historyFile);
    history.keepUpTo(body.time());
    if (fs::exists(pvd)) frames = io::readCollection(pvd);
    std::erase_if(frames, [&](const io::CollectionEntry& e) { return e.time > body.time(); });
    log->info("continued from t = {} s, step {} ({} stress samples, {} frames)", body.time(), body.steps(),
              history.samples().size(), frames.size());
  }
  const auto writeFrame = [&] {
    const std::string name = fmt::format("frames/frame_{:06d}.vtu", frames.size());
    deformable::writeDeformableVtu(body, out / name);
    frames.push_back({body.time(), name});
    io::writeCollection(pvd, frames);
    if (pack) pack->writeFrame();
  };
  const auto save = [&] { // the checkpoint last: a stop in between leaves outputs ahead of it, not behind
    history.writeCsv(historyFile);
    writeSummary(out / "summary.json", body, history, setup.partOfElementName);
    if (pack) pack->stage();
    deformable::writeDeformableCheckpoint(body, checkpoint); // the commit point (DeformRigidPack.hpp)
    if (pack) pack->commit();
  };
  if (!o.restart) DeformRigidPack::removeCheckpoints(out);
  if (frames.empty()) writeFrame();
  if (history.samples().empty()) history.record(body);
  const double every = scene.framesEvery;
  double nextFrame = every > 0.0 ? every * (std::floor(body.time() / every + 1e-9) + 1.0) : scene.duration;
  const StopSignals signals;
  auto lastSave = std::chrono::steady_clock::now();
  const auto start = lastSave;
  while (body.time() < scene.duration * (1.0 - 1e-12)) {
    if (pack) {
      pack->step(); // the World's step advances the body by dt inside it
    } else {
      body.step(dt); // fixed steps: a restart to a longer duration continues the same sequence
    }
    if (body.steps() % scene.stressEvery == 0) history.record(body);
    if (body.time() >= nextFrame * (1.0 - 1e-12) && body.time() < scene.duration * (1.0 - 1e-12)) {
      writeFrame();
      while (nextFrame <= body.time() * (1.0 + 1e-12)) nextFrame += every; // a step longer than the interval skips frames
    }
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - lastSave).count() > scene.checkpointEvery) {
      save();
      lastSave = now;
      log->info("t = {:.6g} s, step {}: checkpoint; largest tension so far {:.4g} MPa", body.time(), body.steps(),
                1e-6 * history.extremes().tension.value);
    }
    if (const int signal = signals.received(); signal != 0) {
      save();
      log->warn("stopped by {} at t = {} s, step {}; continue with --restart", signalName(signal), body.time(),
                body.steps());
      throw CLI::RuntimeError(kExitStopped);
    }
  }
  // No sample at the end unless its step is a sampling step: a run continued from here samples
  // the same steps as one that went through (--restart is bit-identical, the history included).
  writeFrame();
  save();
  logFinish(log, body, history, setup, scene, pack.get(),
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), out);
}

} // namespace

void addDeformCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto o = std::make_shared<DeformRequest>();
  auto* deform = app.add_subcommand("deform", "run a deformable-body scene (seed 002's Solidity_D): stresses in the "
                                              "units, VTU frames, checkpoints (docs/deformable-file.md)");
  deform->add_option("scene", o->scene, "deformable scene file (.yaml), docs/deformable-file.md")->required();
  auto* duration = deform->add_option("--duration", o->duration, "simulated time (s), instead of the scene's run.duration");
  deform->add_option("--threads", o->threads, "OpenMP threads (0 = OpenMP's default)")->capture_default_str();
  deform->add_option("-o,--output", o->output, "output folder, instead of the scene's output.folder");
  deform->add_flag("--restart", o->restart,
                   "continue the run in the output folder from its checkpoint.bin (to the duration, which may be "
                   "longer); the scene must be the one that wrote it");
  deform->callback([o, duration] {
    o->durationGiven = duration->count() > 0;
    runDeform(*o);
  });
}

} // namespace armour::app
