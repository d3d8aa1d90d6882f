// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/DeformRigidPack.hpp"

#include "core/Error.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/RunOutputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <system_error>

namespace armour::app {
namespace {

namespace fs = std::filesystem;

fs::path nextCheckpointPath(const fs::path& out) { return out / "rigid_checkpoint.next.nc"; }

/// The World's settings: the scene's gravity, the body's step, no sleep (deformable runs last
/// seconds, and a sleeping body would not feel the deformable one until its load woke it), level
/// sets at the finest of the rigid bodies' cells_per_dn.
simulation::WorldSettings worldSettings(const io::DeformableScene& scene, double step) {
  simulation::WorldSettings w;
  w.gravity = scene.gravity;
  w.timeStep = step;
  w.sleep.enabled = false;
  double cells = 0.0;
  for (const auto& r : scene.rigidBodies) cells = std::max(cells, r.cellsPerDn);
  w.levelSet.cellsPerDn = cells;
  return w;
}

/// One line per setting and body of what the World computes (initial state included), for its
/// checkpoint: a restart with other rigid bodies is refused, naming the line that changed.
std::string identityOf(const io::DeformableScene& scene, const simulation::WorldSettings& w) {
  std::string text = fmt::format("step = {:.17g}\ngravity = {:.17g} {:.17g} {:.17g}\ncells_per_dn = {:.17g}\n"
                                 "friction = {:.17g}\nrigid_penalty_modulus = {:.17g}\nrigid_restitution = {:.17g}\n",
                                 w.timeStep, w.gravity.x(), w.gravity.y(), w.gravity.z(), w.levelSet.cellsPerDn,
                                 scene.friction, scene.rigidPenaltyModulus, scene.rigidRestitution);
  for (const auto& h : scene.halfSpaces) {
    text += fmt::format("half_space = {:.17g} {:.17g} {:.17g} / {:.17g} {:.17g} {:.17g}\n", h.point.x(), h.point.y(),
                        h.point.z(), h.normal.x(), h.normal.y(), h.normal.z());
  }
  for (const auto& r : scene.rigidBodies) {
    const auto& p = r.part;
    text += fmt::format("rigid_body {} = {} {:.17g} m^3 seed {} {} at {:.17g} {:.17g} {:.17g} q {:.17g} {:.17g} {:.17g} "
                        "{:.17g} v {:.17g} {:.17g} {:.17g} density {:.17g}",
                        p.name, p.shape, p.volume, p.shapeSeed, r.fixed ? "fixed" : "moving", p.position.x(),
                        p.position.y(), p.position.z(), p.orientation.w(), p.orientation.x(), p.orientation.y(),
                        p.orientation.z(), p.velocity.x(), p.velocity.y(), p.velocity.z(), r.density);
    for (const auto& [name, value] : p.params) text += fmt::format(" {}={:.17g}", name, value);
    text += "\n";
  }
  return text;
}

simulation::Material materialOf(const io::DeformableScene& scene, const std::string& name, double density) {
  simulation::Material m;
  m.name = name;
  m.density = density;
  m.frictionStatic = scene.friction;
  m.frictionDynamic = scene.friction;
  m.restitution = scene.rigidRestitution;
  m.penaltyModulus = scene.rigidPenaltyModulus;
  return m;
}

} // namespace

std::unique_ptr<DeformRigidPack> DeformRigidPack::make(const io::DeformableScene& scene,
                                                       deformable::DeformableBody& body, const fs::path& out,
                                                       const std::shared_ptr<spdlog::logger>& log) {
  if (std::all_of(scene.rigidBodies.begin(), scene.rigidBodies.end(), [](const auto& r) { return r.fixed; })) {
    return nullptr;
  }
  std::unique_ptr<DeformRigidPack> pack(new DeformRigidPack);
  pack->out_ = out;
  pack->body_ = &body;
  const simulation::WorldSettings settings = worldSettings(scene, body.stableStep().dt);
  pack->identity_ = identityOf(scene, settings);
  pack->world_ = std::make_unique<simulation::World>(settings);
  simulation::World& world = *pack->world_;
  const simulation::MaterialId floor = world.addMaterial(materialOf(scene, "half-spaces", scene.density));
  for (std::size_t k = 0; k < scene.halfSpaces.size(); ++k) {
    world.addPlane({fmt::format("half_spaces[{}]", k), scene.halfSpaces[k].point, scene.halfSpaces[k].normal, floor});
  }
  std::vector<simulation::BodyId> ids;
  for (const io::RigidPart& r : scene.rigidBodies) {
    const double density = r.density > 0.0 ? r.density : scene.density;
    simulation::BodySpec spec;
    spec.name = r.part.name;
    spec.shape = world.addShape(r.part.name, io::librarySurface(r.part));
    spec.material = world.addMaterial(materialOf(scene, r.part.name, density));
    spec.fixed = r.fixed;
    spec.position = r.part.position;
    spec.orientation = r.part.orientation;
    spec.velocity = r.part.velocity;
    ids.push_back(world.addBody(spec));
    pack->start_.push_back(world.bodies().position(ids.back()));
    log->info("rigid body '{}': {} of {} m^3, {}, level set cells of {:.4g} m", r.part.name, r.part.shape,
              r.part.volume,
              r.fixed ? std::string("fixed")
                      : fmt::format("moving ({:.6g} kg at {} kg/m^3)", 1.0 / world.bodies().inverseMass(ids.back()),
                                    density),
              world.shape(spec.shape).levelSet->cellSize());
  }
  if (const double limit = world.stableTimeStep(); body.stableStep().dt > limit) {
    core::failInput(scene.file.string() + ": contact.rigid_penalty_modulus",
                    "{:.4g} Pa: the rigid bodies' contact is stable for steps up to {:.4g} s, and the deformable "
                    "step is {:.4g} s; lower the modulus (the default 1e9 Pa) or make the rigid bodies heavier",
                    scene.rigidPenaltyModulus, limit, body.stableStep().dt);
  }
  pack->coupling_ = std::make_shared<simulation::DeformableCoupling>(body, ids);
  world.addLoadStage(pack->coupling_);
  body.setObstacles(pack->coupling_->obstacles(world)); // sizes the friction anchors before a restore
  log->info("rigid solver: penalty contact (modulus {:.4g} Pa, restitution {}, friction {}) among the rigid bodies "
            "and with the half-spaces, at the deformable body's step {:.4g} s (its own limit {:.4g} s)",
            scene.rigidPenaltyModulus, scene.rigidRestitution, scene.friction, world.timeStep(),
            world.stableTimeStep());
  return pack;
}

void DeformRigidPack::restore() {
  const simulation::CheckpointExpectation expect{simulation::fingerprintOf(identity_), identity_, world_->bodies().size()};
  std::string found;
  for (const fs::path& path : {nextCheckpointPath(out_), checkpointPath(out_)}) {
    if (!fs::exists(path)) continue;
    simulation::Checkpoint c = simulation::readCheckpoint(path, expect);
    if (c.state.steps == body_->steps()) {
      world_->restoreState(c.state);
      resumeTime_ = world_->time();
      return;
    }
    found += fmt::format("{}{} holds step {}", found.empty() ? "" : ", ", path.string(), c.state.steps);
  }
  core::failInput(checkpointPath(out_).string(),
                  "the rigid bodies' state of step {} (that of checkpoint.bin) is not there ({}); the folder was "
                  "changed by hand or by another run; start the run anew without --restart",
                  body_->steps(), found.empty() ? "no rigid checkpoint" : found);
}

void DeformRigidPack::stage() const {
  simulation::Checkpoint c;
  c.state = world_->captureState();
  c.sceneFingerprint = simulation::fingerprintOf(identity_);
  c.sceneIdentity = identity_;
  for (simulation::BodyId b = 0; b < world_->bodies().size(); ++b) c.bodyNames.push_back(world_->bodies().info(b).name);
  simulation::writeCheckpoint(nextCheckpointPath(out_), c);
}

void DeformRigidPack::commit() const {
  std::error_code ec;
  fs::rename(nextCheckpointPath(out_), checkpointPath(out_), ec);
  if (ec) {
    core::failInput(checkpointPath(out_).string(), "cannot rename {} over it ({}); check the output folder's space "
                                                   "and permissions",
                    nextCheckpointPath(out_).string(), ec.message());
  }
}

void DeformRigidPack::removeCheckpoints(const fs::path& out) {
  std::error_code ec;
  fs::remove(nextCheckpointPath(out), ec);
  fs::remove(checkpointPath(out), ec);
}

io::BodyFrame DeformRigidPack::frame() const {
  io::BodyFrame f;
  f.time = world_->time();
  for (simulation::BodyId b = 0; b < world_->bodies().size(); ++b) {
    io::BodySnapshot s = simulation::bodySnapshot(*world_, b); // external_force: the deformable body's load
    s.id = static_cast<std::int32_t>(b);
    s.fixed = world_->bodies().motionType(b) == dynamics::MotionType::Static;
    f.bodies.push_back(s);
  }
  return f;
}

void DeformRigidPack::writeFrame() {
  if (!frames_) {
    io::VtkFrameSettings settings;
    settings.folder = out_ / "rigid";
    settings.resumeTime = resumeTime_;
    frames_ = std::make_unique<io::VtkFrameWriter>(settings);
  }
  frames_->write(frame());
}

void DeformRigidPack::logEnd(const std::shared_ptr<spdlog::logger>& log) const {
  const auto& bodies = world_->bodies();
  const auto& loads = body_->obstacleLoads();
  for (simulation::BodyId b = 0; b < bodies.size(); ++b) {
    const simulation::Vec3 f = b < loads.size() ? loads[b].force : simulation::Vec3::Zero();
    const std::string& name = bodies.info(b).name;
    if (bodies.motionType(b) == dynamics::MotionType::Static) {
      log->info("rigid body '{}' (fixed) carries [{:.6g}, {:.6g}, {:.6g}] N from the deformable bodies", name,
                f.x(), f.y(), f.z());
      continue;
    }
    const simulation::Vec3 u = bodies.position(b) - start_[b];
    log->info("rigid body '{}' moved [{:.6g}, {:.6g}, {:.6g}] m, speed {:.4g} m/s; it carries [{:.6g}, {:.6g}, "
              "{:.6g}] N from the deformable bodies",
              name, u.x(), u.y(), u.z(), bodies.velocity(b).norm(), f.x(), f.y(), f.z());
  }
  log->info("rigid frames: {}; rigid state: {}", (out_ / "rigid" / "bodies.pvd").string(), checkpointPath(out_).string());
}

} // namespace armour::app
