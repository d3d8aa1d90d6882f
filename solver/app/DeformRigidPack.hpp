// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformRigidPack.hpp
/// The moving rigid bodies of a deformable scene (`rigid_bodies[i].fixed: false`,
/// docs/deformable-file.md): armour's rigid solver (a simulation::World with the penalty contact)
/// holds every rigid body of the scene, moving or fixed, with the scene's half-spaces as static
/// planes; the deformable body advances inside the World's step (simulation/DeformableCoupling),
/// at its own stable step.
///
/// Outputs beside the deformable run's: rigid/bodies.pvd with rigid/bodies/frame_*.vtp (the moving
/// bodies at every frame; rigid/fixed_bodies.vtp the fixed ones), and rigid_checkpoint.nc, the
/// World's state (simulation/CheckpointFile) at the step of checkpoint.bin.
///
/// The two checkpoints are written in three moves, so that a kill at any point leaves a pair of
/// the same step: the World's state to rigid_checkpoint.next.nc (stage), then checkpoint.bin (the
/// commit point, atomic), then rigid_checkpoint.next.nc renamed over rigid_checkpoint.nc (commit).
/// A restart takes whichever of the two files holds checkpoint.bin's step.

#include "deformable/DeformableBody.hpp"
#include "io/DeformableScene.hpp"
#include "io/VtkFrameWriter.hpp"
#include "simulation/DeformableCoupling.hpp"
#include "simulation/World.hpp"

#include <spdlog/logger.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace armour::app {

class DeformRigidPack {
public:
  /// The World of the scene's rigid bodies, coupled to `body` (whose rigid contact is on), or null
  /// when every rigid body is fixed (the body then meets them as fixed obstacles). Gives the body
  /// the rigid bodies at their initial poses. `out` is the run's output folder. Throws
  /// core::InputError naming the scene's key on a shape that cannot be made.
  static std::unique_ptr<DeformRigidPack> make(const io::DeformableScene& scene, deformable::DeformableBody& body,
                                               const std::filesystem::path& out,
                                               const std::shared_ptr<spdlog::logger>& log);

  /// Advance the World and the deformable body by one step of the body's.
  void step() { world_->step(); }
  [[nodiscard]] const simulation::World& world() const { return *world_; }

  /// After the body's checkpoint is read: the World's state of the same step; the frames after
  /// its time are dropped. Throws core::InputError naming the file when there is none of that
  /// step or it is another scene's.
  void restore();
  /// Write the World's state to rigid_checkpoint.next.nc: before checkpoint.bin.
  void stage() const;
  /// Rename rigid_checkpoint.next.nc over rigid_checkpoint.nc: after checkpoint.bin.
  void commit() const;
  /// One frame of the moving rigid bodies at the World's time.
  void writeFrame();
  /// The run log's closing lines: each moving body's displacement and the load of the deformable body on it.
  void logEnd(const std::shared_ptr<spdlog::logger>& log) const;

  /// Remove a previous run's rigid checkpoints from `out` (a fresh start), so that a later
  /// restart cannot pair them with this run's checkpoint.bin.
  static void removeCheckpoints(const std::filesystem::path& out);
  /// The path of the committed World checkpoint in `out`.
  static std::filesystem::path checkpointPath(const std::filesystem::path& out) { return out / "rigid_checkpoint.nc"; }

private:
  DeformRigidPack() = default;
  [[nodiscard]] io::BodyFrame frame() const;

  std::unique_ptr<simulation::World> world_;
  std::shared_ptr<simulation::DeformableCoupling> coupling_;
  std::unique_ptr<io::VtkFrameWriter> frames_; ///< made at the first frame
  std::optional<double> resumeTime_;           ///< set by restore()
  std::vector<simulation::Vec3> start_; ///< initial positions (unit: m)
  std::string identity_;                ///< what the World computes, for the checkpoint
  std::filesystem::path out_;
  const deformable::DeformableBody* body_ = nullptr;
};

} // namespace armour::app
