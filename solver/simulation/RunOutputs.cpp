// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/RunOutputs.hpp"

#include "core/BuildInfo.hpp"

#include <cmath>

namespace armour::simulation {

RunOutputs::RunOutputs(const io::Scene& scene, const BuiltScene& built, const std::string& commandLine)
    : scene_(scene), built_(built) {
  if (scene.output.vtkInterval > 0.0) {
    io::VtkFrameSettings settings;
    settings.folder = scene.output.folder;
    settings.contacts = false;
    vtk_ = std::make_unique<io::VtkFrameWriter>(settings);
  }
  if (scene.output.seriesInterval > 0.0) {
    io::BodySeriesSettings settings;
    settings.path = scene.output.folder / "bodies.nc";
    settings.title = "armour body time series: " + scene.sourceName;
    settings.history = commandLine;
    std::vector<io::SeriesBody> bodies;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      bodies.push_back({static_cast<std::int32_t>(i), scene.bodies[i].name});
    }
    series_ = std::make_unique<io::BodySeriesFile>(settings, bodies);
  }
}

RunOutputs::~RunOutputs() = default;

io::BodyFrame RunOutputs::frame(const World& world) const {
  io::BodyFrame f;
  f.time = world.time();
  const auto& bodies = world.bodies();
  for (std::size_t i = 0; i < built_.bodyIndexOfSceneBody.size(); ++i) {
    const BodyId b = built_.bodyIndexOfSceneBody[i];
    io::BodySnapshot s;
    s.id = static_cast<std::int32_t>(i);
    s.position = bodies.position(b);
    s.orientation = bodies.orientation(b);
    s.velocity = bodies.velocity(b);
    s.angularVelocity = bodies.worldAngularVelocity(b);
    s.contactCount = world.contactCount(b);
    s.maxContactForce = world.maxContactForce(b);
    s.surface = &world.shape(world.bodyShape(b)).mesh; // body (principal) frame, like the orientation
    s.scale = world.bodyScale(b);
    f.bodies.push_back(s);
  }
  return f;
}

void RunOutputs::update(const World& world) {
  const double t = world.time();
  // Due when t has reached the next multiple of the interval (to a hair, for round-off in t).
  const auto due = [t](long index, double interval) { return t >= index * interval - 1e-9 * interval; };
  if (vtk_ && due(nextVtk_, scene_.output.vtkInterval)) {
    vtk_->write(frame(world));
    lastVtkTime_ = t;
    nextVtk_ = static_cast<long>(std::floor(t / scene_.output.vtkInterval + 1e-9)) + 1;
  }
  if (series_ && due(nextSeries_, scene_.output.seriesInterval)) {
    series_->append(frame(world));
    lastSeriesTime_ = t;
    nextSeries_ = static_cast<long>(std::floor(t / scene_.output.seriesInterval + 1e-9)) + 1;
  }
}

void RunOutputs::finish(const World& world) {
  const double t = world.time();
  if (vtk_ && t > lastVtkTime_) {
    vtk_->write(frame(world));
    lastVtkTime_ = t;
  }
  if (series_) {
    if (t > lastSeriesTime_) {
      series_->append(frame(world));
      lastSeriesTime_ = t;
    }
    series_->close();
  }
}

std::size_t RunOutputs::vtkFrames() const { return vtk_ ? vtk_->frameCount() : 0; }
std::size_t RunOutputs::seriesRecords() const { return series_ ? series_->recordCount() : 0; }

} // namespace armour::simulation
