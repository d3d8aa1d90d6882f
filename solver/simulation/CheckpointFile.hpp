// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CheckpointFile.hpp
/// checkpoint.nc: the complete dynamic state of a run (WorldState) in a netCDF-4 file, so that
/// `armour run --restart` continues a stopped run bit for bit, and so that ncdump or Python can
/// look at it. Layout (docs/output-files.md, "Checkpoint"): dimensions body, contact (netCDF's
/// unlimited dimension when there are no contacts, its only way to say 0), vec = 3, quat = 4; per body position,
/// orientation, velocity, angular_momentum, force, torque, motion_type, rest_time,
/// contact_count, max_contact_force (and body_name); per friction spring contact_first,
/// contact_second, contact_key, contact_stretch, contact_sliding; global attributes time, steps,
/// forces_ready, the energy monitor, the format version, the armour build line and the scene
/// fingerprint (and stop_reason for a checkpoint at a guard-rail stop). Doubles are stored as
/// NC_DOUBLE and the step count as NC_UINT64: every value reads back bit for bit.
///
/// Shapes, materials, static geometry and settings are not stored: they come from the scene,
/// which the checkpoint identifies by its fingerprint (sceneFingerprint). A restart rebuilds the
/// World from the scene and refuses a checkpoint whose fingerprint differs, naming the first
/// setting that changed.
///
/// Written atomically: to a temporary sibling, renamed over the destination when complete, so a
/// kill during the write leaves the previous checkpoint intact.
/// Not thread-safe (nor is the netCDF-C library): use from one thread.

#include "io/Scene.hpp"
#include "simulation/WorldState.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace armour::simulation {

/// Version of the file layout; a reader refuses other versions.
constexpr int kCheckpointFormatVersion = 1;

/// Where the run's outputs stood when the checkpoint was taken, so that a restart resumes them
/// (keeps the frames up to these times, drops the later ones) and schedules the next output
/// exactly as the uninterrupted run did. A final frame written at the end of a run (off the
/// schedule) is deliberately not counted: a restart that extends the run drops it.
struct OutputSchedule {
  double lastVtkTime = -1.0;    ///< time of the last scheduled VTK frame (unit: s); < 0: none
  double lastSeriesTime = -1.0; ///< time of the last scheduled bodies.nc record (unit: s); < 0: none
};

/// Everything in a checkpoint file.
struct Checkpoint {
  WorldState state;
  std::string sceneFingerprint;       ///< sceneFingerprint() of the run's scene
  std::string sceneIdentity;          ///< sceneIdentity() text; optional, names the change on a mismatch
  std::vector<std::string> bodyNames; ///< World body order; optional, for people reading the file
  OutputSchedule outputs;
  /// Why the run stopped, for a checkpoint taken at a guard-rail stop (checkpoint_at_error.nc):
  /// its state is that of a failed step, for inspection, not for a restart. "" = a good state.
  std::string stopReason;
  /// The state of the command around the World, for commands that are more than a run (`armour
  /// place`: which units are placed, their records, where the final settle stands), stored as the
  /// text variable application_state; "" = none. Its owner writes and parses it.
  std::string applicationState;
  std::string build;                  ///< the armour build line: set by the writer, read back by the reader
  int formatVersion = kCheckpointFormatVersion; ///< read back by the reader
};

/// What a reader checks beyond the file's own consistency.
struct CheckpointExpectation {
  std::string sceneFingerprint; ///< "" = not checked
  std::string sceneIdentity;    ///< the current scene's sceneIdentity(), to name what changed
  std::size_t bodies = 0;       ///< body count of the World to restore into; 0 = not checked
};

/// Write `checkpoint` (build line: core::buildInfo()) to `path`, atomically. Non-finite values
/// are written as they are (a checkpoint at a guard-rail stop may hold them; reading refuses
/// them). Throws core::InputError naming the path and netCDF's message if the file cannot be
/// written (folder missing or not writable, disk full).
void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

/// Read and validate a checkpoint. Throws core::InputError naming the file, the variable or
/// attribute and the fix when the file is missing, is not a netCDF file or not an armour
/// checkpoint, has another format version, has wrong dimension sizes, holds a non-finite or
/// invalid value, or does not match `expect` (fingerprint: the first differing scene line is named).
[[nodiscard]] Checkpoint readCheckpoint(const std::filesystem::path& path, const CheckpointExpectation& expect = {});

/// The text that identifies what a run computes: io::describeScene of the scene without what may
/// change between a run and its restart, i.e. without the scene's name, source file, base folder
/// and description, the duration (a restart may extend the run), the output settings (folder,
/// intervals, checkpoints) and the reader's warnings. Mesh files are identified by their size
/// and content hash instead of their path, so a case folder may be moved. Everything else -
/// gravity, time step, seed, contact and sleep settings, materials, shapes, bodies (initial
/// state), static geometry - is in it. Throws core::InputError if a mesh file cannot be read.
[[nodiscard]] std::string sceneIdentity(const io::Scene& scene);

/// "fnv1a64:<16 hex digits>": the 64-bit FNV-1a hash of sceneIdentity(scene). Not a security
/// measure: it tells a checkpoint's scene from an edited one.
[[nodiscard]] std::string sceneFingerprint(const io::Scene& scene);

/// The same hash of an identity text (sceneFingerprint(s) == fingerprintOf(sceneIdentity(s))).
[[nodiscard]] std::string fingerprintOf(const std::string& identity);

} // namespace armour::simulation
