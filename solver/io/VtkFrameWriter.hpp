// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VtkFrameWriter.hpp
/// Snapshots for ParaView: every output frame, one VTK XML PolyData file with the surfaces of the
/// moving bodies in world coordinates and per-body point data, listed in a ParaView collection
/// (.pvd) that is rewritten after each frame; the fixed bodies (BodySnapshot::fixed: an
/// underlayer's rocks) once, in fixed_bodies.vtp. Optionally the contact points and forces, likewise.
///
/// Layout in the output folder (docs/output-files.md):
///   bodies.pvd                 collection: <DataSet timestep="t" file="bodies/frame_000012.vtp"/>
///   bodies/frame_000012.vtp    surfaces, point data body_id, velocity, speed, angular_velocity,
///                              contact_count, max_contact_force, displacement
///   fixed_bodies.vtp           surfaces of the fixed bodies, point data body_id; written at the
///                              first frame and again only if the set of fixed bodies changes
///   contacts.pvd, contacts/frame_000012.vtp   (with contacts = true)
///
/// Every file is written to a temporary sibling and renamed into place, the frame before the
/// collection that names it: a killed run leaves a valid .pvd whose files all exist.
/// Not thread-safe (VTK's pipeline objects are not): use from one thread.

#include "io/BodySeriesFile.hpp" // BodyFrame, BodySnapshot

#include "geometry/TriangleMesh.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace armour::io {

/// One contact point, for the contacts file.
struct ContactPoint {
  geometry::Vec3 position = geometry::Vec3::Zero(); ///< contact point in the world (unit: m)
  geometry::Vec3 force = geometry::Vec3::Zero();    ///< total force on body A (unit: N)
  double normalForce = 0.0;                         ///< normal part, >= 0 in compression (unit: N)
  std::int32_t bodyA = -1;                          ///< body id (unit: -)
  std::int32_t bodyB = -1;                          ///< body id, -1 for static geometry (unit: -)
};

struct VtkFrameSettings {
  std::filesystem::path folder; ///< output folder; created if missing
  bool contacts = false;        ///< also write contacts.pvd and contacts/frame_*.vtp
  /// Continue a run: keep the collection entries with timestep <= *resumeTime, delete the frame
  /// files of the later ones and number on from the last kept frame. The displacement reference
  /// (each body's first position) is read back from the last kept frame. No collection: start anew.
  std::optional<double> resumeTime; ///< (unit: s)
};

/// One entry of a .pvd collection.
struct CollectionEntry {
  double time = 0.0;  ///< (unit: s)
  std::string file;   ///< relative to the .pvd's folder, e.g. "bodies/frame_000012.vtp"
};

/// Writer of the ParaView time series.
///
/// @code
///   VtkFrameSettings settings;
///   settings.folder = out;
///   settings.contacts = true;
///   VtkFrameWriter vtk(settings);
///   vtk.write(frame, contacts); // every VTK interval
/// @endcode
class VtkFrameWriter {
public:
  /// Create the folders; on a fresh start delete earlier frame files (bodies/frame_*.vtp,
  /// contacts/frame_*.vtp) so that the folder holds one run. Throws core::InputError naming the
  /// folder if it cannot be created, or naming a file that cannot be read back on resume.
  explicit VtkFrameWriter(VtkFrameSettings settings);

  /// Write one frame: vertices p = x + q (s p_body) of every moving body with a surface, its point
  /// data, then the updated collection(s); fixed bodies go to fixed_bodies.vtp (writeFixed). Contacts are written only with settings.contacts.
  /// A body seen for the first time has its position taken as its displacement reference.
  /// @pre frame.time greater than the previous frame's (std::logic_error otherwise); unit
  ///      quaternions.
  /// Throws core::InputError naming the file if VTK cannot write it.
  void write(const BodyFrame& frame, std::span<const ContactPoint> contacts = {});

  /// Use `position` as the displacement reference of body `id` (e.g. the scene's initial position
  /// when a run is resumed without earlier frames). Replaces what the writer remembered.
  void setReferencePosition(std::int32_t id, const geometry::Vec3& position);

  /// Frames listed in bodies.pvd (kept ones included).
  [[nodiscard]] std::size_t frameCount() const { return entries_.size(); }
  [[nodiscard]] const std::vector<CollectionEntry>& entries() const { return entries_; }
  [[nodiscard]] std::filesystem::path collectionPath() const { return settings_.folder / "bodies.pvd"; }
  [[nodiscard]] std::filesystem::path contactCollectionPath() const { return settings_.folder / "contacts.pvd"; }
  [[nodiscard]] std::filesystem::path fixedPath() const { return settings_.folder / "fixed_bodies.vtp"; }

private:
  void resume(double time);
  /// fixed_bodies.vtp, if this writer has not written it yet or the set of fixed bodies changed
  /// (removed if there are none).
  void writeFixed(const std::vector<const BodySnapshot*>& fixed);

  VtkFrameSettings settings_;
  std::vector<CollectionEntry> entries_;
  std::vector<CollectionEntry> contactEntries_;
  std::size_t nextIndex_ = 0;
  std::map<std::int32_t, geometry::Vec3> reference_; ///< first position of each body (unit: m)
  std::vector<geometry::Vec3> vertices_;             ///< staging, reused frame to frame
  std::vector<std::int32_t> fixedIds_;               ///< the fixed bodies in fixed_bodies.vtp
  bool fixedWritten_ = false;
};

/// Write a .pvd collection naming `entries` (times in their shortest exact form), atomically.
void writeCollection(const std::filesystem::path& pvd, const std::vector<CollectionEntry>& entries);

/// Read a .pvd collection written by VtkFrameWriter or writeCollection (DataSet elements, in file order).
/// Throws core::InputError naming the file if it cannot be read or parsed.
std::vector<CollectionEntry> readCollection(const std::filesystem::path& pvd);

} // namespace armour::io
