// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlacementCheckpoint.hpp
/// The checkpoint of a placement (`place-checkpoint.nc`, docs/placement.md "Checkpoints and
/// restart"), shared by `armour place` and `armour ensemble`: the identity that ties it to the scene
/// and to the placement file as run, reading it to continue, and the safe-point callback that
/// writes it every few minutes of wall time and when the process is asked to stop.

#include "app/StopSignals.hpp"
#include "io/Scene.hpp"
#include "placement/PlacementProgress.hpp"
#include "placement/Placer.hpp"

#include <chrono>
#include <filesystem>
#include <string>

namespace armour::app {

class PlacementCheckpoint {
public:
  /// `effectiveText`: the placement file's text with its --set changes applied, as run.
  PlacementCheckpoint(const io::Scene& scene, const std::string& effectiveText, std::filesystem::path path);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

  /// The progress to continue from. Throws core::InputError naming the file when it is missing,
  /// was written for another scene or placement file, or is the checkpoint of a run.
  [[nodiscard]] placement::PlacementProgress read() const;

  /// A safe-point callback for placement::place: writes the checkpoint when `minutes` of wall time
  /// have passed since the last one (0: never on time) or when `signals` received a stop, and then
  /// asks the placement to stop. The callback refers to this object and to `signals`: both must
  /// outlive the placement.
  [[nodiscard]] placement::SafePointFn safePoint(const StopSignals& signals, double minutes);

private:
  std::string identity_;
  std::string fingerprint_;
  std::filesystem::path path_;
  std::chrono::steady_clock::time_point last_;
};

} // namespace armour::app
