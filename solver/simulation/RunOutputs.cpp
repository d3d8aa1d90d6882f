// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/RunOutputs.hpp"

#include "core/BuildInfo.hpp"
#include "core/Error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace armour::simulation {
namespace {

/// Index of the first output time after t (time = index x interval), with the same allowance for
/// round-off in t as the due test in update().
long nextIndexAfter(double t, double interval) { return static_cast<long>(std::floor(t / interval + 1e-9)) + 1; }

/// The largest flush block of bodies.nc (BodySeriesFile's default): few flushes, little at risk.
constexpr std::size_t kMaxSyncEvery = 16;

} // namespace

std::size_t seriesSyncEvery(const io::OutputSettings& output) {
  if (!(output.checkpointInterval > 0.0) || !(output.seriesInterval > 0.0)) {
    return kMaxSyncEvery;
  }
  const double perInterval = std::floor(output.checkpointInterval / output.seriesInterval * (1.0 + 1e-9));
  return static_cast<std::size_t>(std::clamp(perInterval, 1.0, static_cast<double>(kMaxSyncEvery)));
}

std::string stepsPerInterval(double interval, double timeStep) {
  const double steps = interval / timeStep;
  if (std::abs(steps - std::round(steps)) <= 1e-6) return fmt::format("exactly {:.0f} steps", steps);
  return fmt::format("{:.6g} steps", steps);
}

std::string describeOutputTiming(const io::OutputSettings& output, double timeStep) {
  std::string intervals;
  if (output.seriesInterval > 0.0)
    intervals += fmt::format("series every {} s ({})", output.seriesInterval, stepsPerInterval(output.seriesInterval, timeStep));
  if (output.vtkInterval > 0.0)
    intervals += fmt::format("{}VTK every {} s ({})", intervals.empty() ? "" : ", ", output.vtkInterval,
                             stepsPerInterval(output.vtkInterval, timeStep));
  if (intervals.empty()) intervals = "no series or VTK output";
  return fmt::format("time step {:.6g} s; {}: each output is written at the first step at or after its time (at most "
                     "one step late, stamped with the step's own time)",
                     timeStep, intervals);
}

RunOutputs::RunOutputs(const io::Scene& scene, const BuiltScene& built, const RunProvenance& provenance,
                       const std::optional<OutputSchedule>& resume, const std::string& resumeState)
    : scene_(scene), built_(built) {
  if (resume) {
    // Kept for the next checkpoint even when an output is now off, so that turning it on again
    // in a later restart keeps its earlier frames.
    lastScheduledVtk_ = resume->lastVtkTime;
    lastScheduledSeries_ = resume->lastSeriesTime;
  }
  if (scene.output.vtkInterval > 0.0) {
    io::VtkFrameSettings settings;
    settings.folder = scene.output.folder;
    settings.contacts = scene.output.contacts;
    if (resume) {
      settings.resumeTime = resume->lastVtkTime;
    }
    vtk_ = std::make_unique<io::VtkFrameWriter>(settings);
    if (resume && resume->lastVtkTime >= 0.0) {
      lastVtkTime_ = resume->lastVtkTime;
      nextVtk_ = nextIndexAfter(lastVtkTime_, scene.output.vtkInterval);
    }
    if (resume && vtk_->frameCount() == 0) {
      // No earlier frame to measure displacements from: use the initial positions, as the first
      // frame of the uninterrupted run would have.
      for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
        vtk_->setReferencePosition(static_cast<std::int32_t>(i), scene.bodies[i].position);
      }
    }
  }
  if (scene.output.seriesInterval > 0.0) {
    io::BodySeriesSettings settings;
    settings.path = scene.output.folder / "bodies.nc";
    settings.title = "armour body time series: " + scene.sourceName;
    settings.history = provenance.commandLine;
    if (!provenance.sceneFile.empty())
      settings.textAttributes.emplace_back("scene_file", std::filesystem::absolute(provenance.sceneFile).string());
    if (!provenance.sets.empty()) {
      std::string sets;
      for (const std::string& s : provenance.sets) sets += (sets.empty() ? "" : "\n") + s;
      settings.textAttributes.emplace_back("scene_sets", sets);
    }
    const hydro::HydroSettings& h = scene.hydro;
    if (h.enabled && h.model == hydro::HydroModel::Storm) {
      settings.textAttributes.emplace_back("storm_file", std::filesystem::absolute(h.storm.file).string());
      settings.textAttributes.emplace_back("hydro_bodies", h.bodies);
      settings.numberAttributes.emplace_back("storm_time_offset", h.storm.timeOffset);
      settings.numberAttributes.emplace_back("storm_offset_x", h.storm.offsetX);
      settings.numberAttributes.emplace_back("storm_offset_z", h.storm.offsetZ);
      settings.numberAttributes.emplace_back("storm_ramp_time", h.storm.rampTime);
    }
    settings.syncEvery = seriesSyncEvery_ = seriesSyncEvery(scene.output);
    if (resume) {
      settings.resumeTime = resume->lastSeriesTime;
    }
    std::vector<io::SeriesBody> bodies;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      bodies.push_back({static_cast<std::int32_t>(i), scene.bodies[i].name});
    }
    series_ = std::make_unique<io::BodySeriesFile>(settings, bodies);
    // The schedule goes on from the checkpoint's last record, which the file holds: a checkpoint
    // is only taken when the file is flushed (flushed()).
    if (resume && resume->lastSeriesTime >= 0.0) {
      lastSeriesTime_ = resume->lastSeriesTime;
      nextSeries_ = nextIndexAfter(lastSeriesTime_, scene.output.seriesInterval);
    }
  }
  if (!scene.output.unitLoads.empty()) {
    if (resume && resumeState.empty())
      core::failInput((scene.output.folder / "checkpoint.nc").string(),
                      "the run that wrote this checkpoint did not record unit loads, so the loads of its sleeping "
                      "units are not in it and cannot be recorded from here; remove output.unit_loads to continue it, "
                      "or start the run anew with it");
    UnitLoadsSettings u;
    for (std::size_t i : io::unitLoadBodies(scene)) {
      u.bodies.push_back(built.bodyIndexOfSceneBody[i]);
      u.sceneBodies.push_back(static_cast<std::int32_t>(i));
    }
    World& world = *built.world;
    for (BodyId b = 0; b < world.bodies().size(); ++b) u.names.push_back(world.bodies().info(b).name);
    u.interval = scene.output.unitLoadsInterval;
    u.cluster = scene.output.unitLoadsCluster;
    unitLoads_ = std::make_unique<UnitLoadsRecorder>(world, std::move(u), scene.output.folder, resumeState);
  }
}

RunOutputs::~RunOutputs() = default;

io::BodySnapshot bodySnapshot(const World& world, BodyId b) {
  const auto& bodies = world.bodies();
  io::BodySnapshot s;
  s.position = bodies.position(b);
  s.orientation = bodies.orientation(b);
  s.velocity = bodies.velocity(b);
  s.angularVelocity = bodies.worldAngularVelocity(b);
  s.contactCount = world.contactCount(b);
  s.maxContactForce = world.maxContactForce(b);
  s.externalForce = world.externalForce(b);
  s.surface = &world.shape(world.bodyShape(b)).mesh; // body (principal) frame, like the orientation
  s.scale = world.bodyScale(b);
  return s;
}

io::BodyFrame RunOutputs::frame(const World& world) const {
  io::BodyFrame f;
  f.time = world.time();
  for (std::size_t i = 0; i < built_.bodyIndexOfSceneBody.size(); ++i) {
    const BodyId b = built_.bodyIndexOfSceneBody[i];
    io::BodySnapshot s = bodySnapshot(world, b);
    s.id = static_cast<std::int32_t>(i);
    s.fixed = scene_.bodies[i].fixed;
    f.bodies.push_back(s);
  }
  return f;
}

std::vector<io::ContactPoint> RunOutputs::contactPoints(const World& world) const {
  std::vector<io::ContactPoint> out;
  if (!scene_.output.contacts) {
    return out;
  }
  // World bodies -> scene body ids (static meshes are world bodies too, but not scene bodies: -1).
  std::vector<std::int32_t> sceneId(world.bodies().size(), -1);
  for (std::size_t i = 0; i < built_.bodyIndexOfSceneBody.size(); ++i) {
    sceneId[built_.bodyIndexOfSceneBody[i]] = static_cast<std::int32_t>(i);
  }
  out.reserve(world.contactPatches().size());
  for (const ContactPatch& p : world.contactPatches()) {
    io::ContactPoint c;
    c.position = p.point;
    c.force = p.force;
    c.normalForce = p.normalForce;
    c.bodyA = sceneId[p.bodyA];
    c.bodyB = p.bodyB >= 0 ? sceneId[static_cast<std::size_t>(p.bodyB)] : -1;
    out.push_back(c);
  }
  return out;
}

void RunOutputs::update(const World& world) {
  if (unitLoads_) unitLoads_->update(world);
  const double t = world.time();
  // Due when t has reached the next multiple of the interval (to a hair, for round-off in t).
  const auto due = [t](long index, double interval) { return t >= index * interval - 1e-9 * interval; };
  if (vtk_ && due(nextVtk_, scene_.output.vtkInterval)) {
    vtk_->write(frame(world), contactPoints(world));
    lastVtkTime_ = lastScheduledVtk_ = t;
    nextVtk_ = nextIndexAfter(t, scene_.output.vtkInterval);
  }
  if (series_ && due(nextSeries_, scene_.output.seriesInterval)) {
    series_->append(frame(world));
    // BodySeriesFile flushes after every seriesSyncEvery_-th append since it was opened.
    seriesSinceFlush_ = (seriesSinceFlush_ + 1) % seriesSyncEvery_;
    lastSeriesTime_ = lastScheduledSeries_ = t;
    nextSeries_ = nextIndexAfter(t, scene_.output.seriesInterval);
  }
}

void RunOutputs::finish(const World& world) {
  const double t = world.time();
  if (unitLoads_) unitLoads_->finish();
  if (vtk_ && t > lastVtkTime_) {
    vtk_->write(frame(world), contactPoints(world));
    lastVtkTime_ = t;
  }
  if (series_) {
    if (t > lastSeriesTime_) {
      series_->append(frame(world));
      lastSeriesTime_ = t;
    }
    series_->close();
    seriesSinceFlush_ = 0;
  }
}

void RunOutputs::close() {
  if (series_) {
    series_->close();
    seriesSinceFlush_ = 0;
  }
}

std::size_t RunOutputs::vtkFrames() const { return vtk_ ? vtk_->frameCount() : 0; }
std::size_t RunOutputs::seriesRecords() const { return series_ ? series_->recordCount() : 0; }

} // namespace armour::simulation
