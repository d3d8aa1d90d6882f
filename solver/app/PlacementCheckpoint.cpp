// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/PlacementCheckpoint.hpp"

#include "core/Error.hpp"
#include "hydro/HydroSettings.hpp"
#include "simulation/CheckpointFile.hpp"

#include <utility>

namespace armour::app {

namespace {

/// The identity of a placement: the scene as resolved and the placement file's text as run. Hydro
/// settings do not act on a placement, and its storm file may not exist yet (written after the
/// pack, as scripts/fidelity-ladder does): the identity leaves them out (the text keeps them).
std::string placementIdentity(const io::Scene& scene, const std::string& effectiveText) {
  io::Scene identified = scene;
  static const hydro::HydroSettings kNoHydro; // a named default: GCC 12 warns (wrongly) of a temporary's
  identified.hydro = kNoHydro;                // uninitialised string with -O2 -Wmaybe-uninitialized
  return simulation::sceneIdentity(identified) + "# placement file as run\n" + effectiveText;
}

} // namespace

PlacementCheckpoint::PlacementCheckpoint(const io::Scene& scene, const std::string& effectiveText,
                                         std::filesystem::path path)
    : identity_(placementIdentity(scene, effectiveText)), fingerprint_(simulation::fingerprintOf(identity_)),
      path_(std::move(path)), last_(std::chrono::steady_clock::now()) {}

placement::PlacementProgress PlacementCheckpoint::read() const {
  simulation::Checkpoint c = simulation::readCheckpoint(path_, {fingerprint_, identity_, 0});
  if (c.applicationState.empty())
    core::failInput(path_.string(), "is the checkpoint of a run, not of `armour place` (no application_state); "
                                    "start the placement anew without --restart");
  placement::PlacementProgress progress = placement::decodeProgress(c.applicationState, path_.string());
  progress.world = std::move(c.state);
  return progress;
}

placement::SafePointFn PlacementCheckpoint::safePoint(const StopSignals& signals, double minutes) {
  last_ = std::chrono::steady_clock::now();
  return [this, &signals, minutes](const std::function<placement::PlacementProgress()>& capture) {
    const bool stop = signals.received() != 0;
    const auto now = std::chrono::steady_clock::now();
    const bool due = minutes > 0.0 && std::chrono::duration<double>(now - last_).count() >= 60.0 * minutes;
    if (!stop && !due) return false;
    placement::PlacementProgress p = capture();
    simulation::Checkpoint c;
    c.sceneFingerprint = fingerprint_;
    c.sceneIdentity = identity_;
    c.applicationState = placement::encodeProgress(p);
    c.state = std::move(p.world);
    simulation::writeCheckpoint(path_, c);
    last_ = std::chrono::steady_clock::now();
    return stop;
  };
}

} // namespace armour::app
