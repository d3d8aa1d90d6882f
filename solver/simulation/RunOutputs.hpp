// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RunOutputs.hpp
/// The outputs of a run, written from the World at the scene's intervals: VTK frames of every
/// body's surface (bodies.pvd, for ParaView) every `vtk_interval`, and the per-body netCDF time
/// series (bodies.nc) every `series_interval` (docs/output-files.md). Frames are due when the
/// simulated time passes a multiple of the interval, so output times do not depend on dt.
///
/// Restart: constructed with the OutputSchedule of a checkpoint, the writers keep the frames up
/// to the last scheduled output before the checkpoint, drop the later ones (written by the
/// abandoned run after the checkpoint, or the off-schedule final frame of a finished run that is
/// now extended) and schedule the next output exactly as the uninterrupted run did, so that the
/// outputs of a restarted run equal those of an uninterrupted one.
///
/// Checkpoints and bodies.nc: the series file is flushed to disk every `seriesSyncEvery` records
/// (BodySeriesFile). A checkpoint may only be taken when flushed() is true, so that a run killed
/// with SIGKILL after the checkpoint still has every record up to it on disk.

#include "io/BodySeriesFile.hpp"
#include "io/Scene.hpp"
#include "io/VtkFrameWriter.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/SceneBuilder.hpp"
#include "simulation/UnitLoads.hpp"

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace armour::simulation {

/// Records between flushes of bodies.nc (unit: records): at most 16, and at most the records in
/// one checkpoint interval, so that a checkpoint waits for a flush (flushed()) by less than an
/// interval (checkpoint_interval / series_interval records, at least 1).
std::size_t seriesSyncEvery(const io::OutputSettings& output);

/// "107.5 steps" for an interval of 107.5 time steps, "exactly 100 steps" when the step divides it
/// (to 1e-6 of a step): how an interval relates to the time step, for the run log.
std::string stepsPerInterval(double interval, double timeStep);

/// One line for the run log: the time step and how many steps make a series and a VTK interval.
/// The automatic step rarely divides them: each output is written at the first step at or after
/// its time (at most one step late; the time written is the step's own).
std::string describeOutputTiming(const io::OutputSettings& output, double timeStep);

/// What a run was made from, recorded in bodies.nc so that `armour report` finds the scene as
/// the run read it (docs/output-files.md, global attributes).
struct RunProvenance {
  std::string commandLine;           ///< goes into the netCDF history
  std::filesystem::path sceneFile;   ///< the scene file (recorded absolute as `scene_file`)
  std::vector<std::string> sets;     ///< the --set KEY=VALUE changes it was read with (`scene_sets`)
};

/// Body b of `world` as a frame shows it: pose, velocities, contact counts, the load stages'
/// force, and its surface (the shape's mesh in the body frame, with its scale). Id and `fixed` are
/// the caller's (scene ids differ from World ids).
[[nodiscard]] io::BodySnapshot bodySnapshot(const World& world, BodyId b);

class RunOutputs {
public:
  /// Open the writers in scene.output.folder. bodies.nc records the provenance and, for a storm
  /// replay, the scene's effective storm settings (file, time offset, offset, ramp, loaded
  /// bodies). With `resume` (a restart), continue the files of the run as they stood at that
  /// schedule.
  ///
  /// With `output.unit_loads`, the units' contact loads go to <folder>/unit_loads/ (UnitLoads.hpp);
  /// `resumeState` is the checkpoint's applicationState, where state() put the recorder's.
  RunOutputs(const io::Scene& scene, const BuiltScene& built, const RunProvenance& provenance,
             const std::optional<OutputSchedule>& resume = std::nullopt, const std::string& resumeState = {});
  ~RunOutputs();
  RunOutputs(const RunOutputs&) = delete;
  RunOutputs& operator=(const RunOutputs&) = delete;

  /// Write whatever is due at the world's current time (always at t = 0 on the first call). Called
  /// after every step, and before the first of a new run, not of a restart: the run that wrote
  /// the checkpoint had written everything due at its step.
  void update(const World& world);
  /// Write the final state if it was not just written, and close the files.
  void finish(const World& world);
  /// Close the files without a final frame (a run stopped by a signal: the next output is the
  /// scheduled one, written by the restarted run).
  void close();

  /// The last scheduled output times (finish()'s final frame not included), for a checkpoint.
  [[nodiscard]] OutputSchedule schedule() const { return {lastScheduledVtk_, lastScheduledSeries_}; }
  /// Everything written so far is on disk (bodies.nc flushed; VTK files are complete when renamed).
  [[nodiscard]] bool flushed() const { return !series_ || seriesSinceFlush_ == 0; }
  /// What a checkpoint must hold beyond the World and the schedule to resume the outputs (the
  /// unit-load recorder's state), as its applicationState; "" = nothing.
  [[nodiscard]] std::string state() const { return unitLoads_ ? unitLoads_->state() : std::string(); }
  /// Unit-load records written (0 without output.unit_loads).
  [[nodiscard]] std::size_t unitLoadRecords() const { return unitLoads_ ? unitLoads_->records() : 0; }

  [[nodiscard]] std::size_t vtkFrames() const;
  [[nodiscard]] std::size_t seriesRecords() const;

private:
  io::BodyFrame frame(const World& world) const;
  /// The world's contact patches as contact points of the VTK contacts file (scene body ids).
  std::vector<io::ContactPoint> contactPoints(const World& world) const;

  const io::Scene& scene_;
  const BuiltScene& built_;
  std::unique_ptr<io::VtkFrameWriter> vtk_;
  std::unique_ptr<io::BodySeriesFile> series_;
  std::unique_ptr<UnitLoadsRecorder> unitLoads_;
  long nextVtk_ = 0;    ///< index of the next VTK output time (time = index x interval)
  long nextSeries_ = 0; ///< index of the next series output time
  double lastVtkTime_ = -1.0, lastSeriesTime_ = -1.0;             ///< last written, final frame included (s)
  double lastScheduledVtk_ = -1.0, lastScheduledSeries_ = -1.0;   ///< last written by update() (s)
  std::size_t seriesSyncEvery_ = 16;  ///< as given to BodySeriesFile (unit: records)
  std::size_t seriesSinceFlush_ = 0;  ///< records appended since BodySeriesFile last flushed
};

} // namespace armour::simulation
