// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RunOutputs.hpp
/// The outputs of a run, written from the World at the scene's intervals: VTK frames of every
/// body's surface (bodies.pvd, for ParaView) every `vtk_interval`, and the per-body netCDF time
/// series (bodies.nc) every `series_interval` (docs/output-files.md). Frames are due when the
/// simulated time passes a multiple of the interval, so output times do not depend on dt.

#include "io/BodySeriesFile.hpp"
#include "io/Scene.hpp"
#include "io/VtkFrameWriter.hpp"
#include "simulation/SceneBuilder.hpp"

#include <memory>
#include <string>

namespace armour::simulation {

class RunOutputs {
public:
  /// Open the writers in scene.output.folder. `commandLine` goes into the netCDF history.
  RunOutputs(const io::Scene& scene, const BuiltScene& built, const std::string& commandLine);
  ~RunOutputs();
  RunOutputs(const RunOutputs&) = delete;
  RunOutputs& operator=(const RunOutputs&) = delete;

  /// Write whatever is due at the world's current time (always at t = 0 on the first call).
  void update(const World& world);
  /// Write the final state if it was not just written, and close the files.
  void finish(const World& world);

  [[nodiscard]] std::size_t vtkFrames() const;
  [[nodiscard]] std::size_t seriesRecords() const;

private:
  io::BodyFrame frame(const World& world) const;

  const io::Scene& scene_;
  const BuiltScene& built_;
  std::unique_ptr<io::VtkFrameWriter> vtk_;
  std::unique_ptr<io::BodySeriesFile> series_;
  long nextVtk_ = 0;    ///< index of the next VTK output time (time = index x interval)
  long nextSeries_ = 0; ///< index of the next series output time
  double lastVtkTime_ = -1.0, lastSeriesTime_ = -1.0;
};

} // namespace armour::simulation
