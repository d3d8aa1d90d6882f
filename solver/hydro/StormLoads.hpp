// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StormLoads.hpp
/// Hydrodynamic loads on units replayed from a storm file (seed 000 section 2.3), as the World's
/// "hydro" load stage (simulation/LoadStage.hpp). docs/theory.md, "Hydrodynamic loads from a storm
/// file", derives every term; in short, on each loaded body b:
///
///  - form force and moment by pressure integration over the unit's surface elements
///    (SurfaceElements.hpp), buoyancy included:  F_p = -sum_e p_e a_e n_e,
///    M_p = sum_e (r_e - x_b) x (-p_e a_e n_e), with p_e sampled from the storm file (StormSampler)
///    at the element centroid's (x, z) in the file's coordinates (the scene's plus offsetX, offsetZ)
///    and storm time t + timeOffset, plus the Weibull variability (Variability.hpp); p_e = 0
///    (atmospheric) where the water fraction is below wetAlpha or the voxels around the sample
///    have no data; an element beyond the grid's outermost centres (x, z) takes the flow held at
///    the edge, and one beyond a bounded trunk's ends (y) the section's flow, so that the closed
///    surface integral stays consistent for a unit reaching out of the sampling box; on an
///    impermeable bed (StormLoadSettings::bed) the elements lying on it and facing down into it
///    take no pressure (the default, a porous bed, loads every element);
///  - Morison drag (seed 000 eq. 2) at the centre of mass: F_D = 1/2 rho C_d A (u - v)|u - v|, u the
///    area-weighted mean flow velocity over the wet elements, v the body's current velocity, A the
///    silhouette area normal to u - v (ProjectedArea.hpp) times s^2 and the wet area fraction;
///  - optionally the added mass of seed 000 eq. 1, m_a = rho C_a V_wet, as the equivalent force
///    F_x = m_a / (m + m_a) (m a_f - F_c - F_p - F_D - m g), which turns the integrator's
///    (F_c + F_p + F_D + F_x) / m + g into (F_c + F_p + F_D + m g + m_a a_f) / (m + m_a): the added
///    mass only ever adds inertia (no dv/dt feedback, stable for any unit density).
///
/// Ramp: with rampTime T > 0, F_p, M_p, u and a_f are multiplied by r(t) = (1 - cos(pi t / T)) / 2
/// for simulation times t < T (a pack placed dry meets the water gradually, as a flume is filled).
///
/// Updates: F_p, M_p, u, the wet fraction and a_f (the storm's du/dt over the wet elements) are
/// computed at the update times t_k = k updateInterval (simulation time) with the positions of that
/// moment, and held until the next (Hold, seed 000), or computed one interval ahead and blended
/// linearly (Interpolate). Drag and added mass are evaluated at every force evaluation from the held
/// quantities and the bodies' current velocities and contact forces.
///
/// Beyond the grid the flow goes on (StormSampler::sampleExtended): the edge column's is held in
/// x, the edge row's pressure continued hydrostatically in z; voxels without data take the gap fill.
///
/// Cost: fixed bodies and bodies the `bodies` filter excludes are never touched. At an update, a
/// loaded body whose box (centroid +- scale x shape radius) lies outside the trunk's y range
/// (bounded files only) or wholly above the highest free surface of the columns it spans (plus a
/// margin of two voxel heights) is skipped before any element is sampled. The per-body work runs in parallel (OpenMP), each body writing only its own slot: the
/// result does not depend on the thread count.

#include "hydro/HydroSettings.hpp"
#include "hydro/ProjectedArea.hpp"
#include "hydro/SurfaceElements.hpp"
#include "hydro/Variability.hpp"
#include "simulation/LoadStage.hpp"
#include "simulation/World.hpp"
#include "storm/StormFile.hpp"
#include "storm/StormSampler.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace armour::hydro {

using dynamics::BodyId;

/// What one storm evaluation gives a body; held between updates (world frame).
struct HeldLoad {
  Vec3 pressureForce = Vec3::Zero();     ///< -sum p a n, buoyancy included (unit: N)
  Vec3 pressureTorque = Vec3::Zero();    ///< about the centre of mass (unit: N m)
  Vec3 meanVelocity = Vec3::Zero();      ///< flow velocity, area-weighted over the wet elements (unit: m/s)
  Vec3 fluidAcceleration = Vec3::Zero(); ///< du/dt of the storm, area-weighted over the wet elements (unit: m/s^2)
  double wetFraction = 0.0;              ///< wet area / total area (unit: -)
};

/// The loads written for a body by the last apply() (world frame).
struct AppliedLoad {
  Vec3 pressureForce = Vec3::Zero();  ///< unit: N
  Vec3 pressureTorque = Vec3::Zero(); ///< unit: N m
  Vec3 dragForce = Vec3::Zero();      ///< unit: N
  Vec3 addedMassForce = Vec3::Zero(); ///< the equivalent force F_x (unit: N)
  double projectedArea = 0.0;         ///< A of the drag, scaled and wet (unit: m^2)
};

/// Counters of the last update, for logs, benchmarks and tests.
struct StormLoadCounters {
  std::size_t loadedBodies = 0;      ///< bodies that take storm loads (the filter, not fixed) (unit: -)
  std::size_t evaluatedBodies = 0;   ///< loaded bodies whose elements were sampled (unit: -)
  /// Loaded bodies skipped before their elements: beyond a bounded trunk, or dry (unit: -).
  std::size_t skippedBodies = 0;
  std::size_t evaluatedElements = 0; ///< elements sampled (both evaluations when Interpolate starts) (unit: -)
  std::size_t wetElements = 0;       ///< of which wet (same) (unit: -)
  /// Of the wet ones, those in voxels without data that took the gap fill (same) (unit: -).
  std::size_t filledElements = 0;
  std::uint64_t updates = 0;         ///< load updates since construction or restore (unit: -)
  /// Since construction or restore: loaded-body evaluations, and those skipped (unit: -).
  std::uint64_t bodyEvaluationsTotal = 0, skippedTotal = 0;
  /// Since construction or restore: wet element samples, and those of the gap fill (unit: -).
  std::uint64_t wetTotal = 0, filledTotal = 0;
};

class StormLoads final : public simulation::LoadStage {
public:
  /// Opens the storm file at `stormPath` (already resolved against the scene's folder).
  /// `bodies`: "all" or a name prefix. Throws core::InputError for bad settings (naming the key)
  /// or a bad storm file.
  StormLoads(const simulation::World& world, const StormLoadSettings& settings, std::string bodies,
             const std::string& stormPath);
  /// Shares an open reader (the reader is not modified; the stage keeps it alive).
  StormLoads(const simulation::World& world, const StormLoadSettings& settings, std::string bodies,
             std::shared_ptr<const storm::StormReader> reader);
  ~StormLoads() override;

  [[nodiscard]] std::string name() const override { return "hydro"; }
  [[nodiscard]] std::string summary() const override;
  void apply(const simulation::World& world, double time, std::span<dynamics::Vec3> force,
             std::span<dynamics::Vec3> torque) override;
  [[nodiscard]] std::vector<double> saveState() const override;
  void restoreState(const std::vector<double>& state) override;

  // --- Introspection (tests, logs, output) ---------------------------------------------------------
  [[nodiscard]] const StormLoadSettings& settings() const { return settings_; }
  [[nodiscard]] const storm::StormReader& reader() const { return *reader_; }
  [[nodiscard]] const StormLoadCounters& counters() const { return counters_; }
  /// Does body b take storm loads (filter and motion type at the last apply or construction)?
  [[nodiscard]] bool loaded(BodyId b) const { return b < loaded_.size() && loaded_[b] != 0; }
  /// The loads written for body b by the last apply().
  [[nodiscard]] const AppliedLoad& applied(BodyId b) const { return applied_.at(b); }
  /// The held storm quantities of body b at the last update (Interpolate: those of t_k).
  [[nodiscard]] const HeldLoad& held(BodyId b) const { return held_[0].at(b); }
  /// Elements of body b sampled at the last update (0 if skipped or not loaded) (unit: -).
  [[nodiscard]] std::uint32_t evaluatedElements(BodyId b) const {
    return b < elementCount_.size() ? elementCount_[b] : 0;
  }
  /// Surface elements and projected-area table of a shape (built for shapes of loaded bodies only).
  [[nodiscard]] const SurfaceElements& elements(simulation::ShapeId shape) const;
  [[nodiscard]] const ProjectedAreaTable& areaTable(simulation::ShapeId shape) const;
  /// The factor of the load ramp at simulation time `time` (StormLoadSettings::rampTime): 0 at 0,
  /// (1 - cos(pi t / T)) / 2 up to T, 1 from then on (and without a ramp) (unit: -).
  [[nodiscard]] double rampFactor(double time) const;
  /// Simulation time of the last update, or -1 before the first (unit: s).
  [[nodiscard]] double lastUpdateTime() const;

private:
  struct ShapeData;
  void initialise(const simulation::World& world);
  void syncBodies(const simulation::World& world);
  void update(const simulation::World& world, std::int64_t k, double time);
  /// Throws core::InputError if the storm time is outside the file's records.
  void checkStormTime(double stormTime, double simulationTime) const;
  void evaluate(const simulation::World& world, double stormTime, std::vector<HeldLoad>& out);
  void evaluateBody(const simulation::World& world, BodyId b, const std::vector<double>& etaColumns,
                    HeldLoad& out, std::uint32_t& elements, std::uint32_t& wet, std::uint32_t& filled,
                    std::uint8_t& skipped) const;
  [[nodiscard]] HeldLoad current(BodyId b, double time) const;

  StormLoadSettings settings_;
  std::string bodies_;
  std::shared_ptr<const storm::StormReader> reader_;
  std::unique_ptr<storm::StormSampler> sampler_;
  VariabilityModel variability_;
  std::vector<std::unique_ptr<ShapeData>> shapes_; ///< by ShapeId; null for shapes no loaded body uses

  // Storm file constants.
  double rho_ = 1025.0;                  ///< unit: kg/m^3
  double gridMin_[2] = {0.0, 0.0};       ///< x, z lower edges of the grid: outermost centres - half a voxel (m)
  double gridMax_[2] = {0.0, 0.0};       ///< upper edges (m)
  double trunkMin_ = 0.0, trunkMax_ = 0.0; ///< y range of the trunk; unbounded if trunkLength <= 0 (m)
  /// Loads only within [trunkMin_, trunkMax_]; false for a file uniform along y (unit: -).
  bool trunkBounded_ = true;
  Vec3 offset_ = Vec3::Zero();           ///< scene -> storm coordinates: (offsetX, 0, offsetZ) (m)
  double airMargin_ = 0.0;               ///< a body this far above the highest free surface is dry (m)

  // Per body.
  std::vector<std::uint8_t> loaded_;
  std::vector<HeldLoad> held_[2];        ///< [0] at t_k, [1] at t_(k+1) (Interpolate only)
  std::vector<AppliedLoad> applied_;
  std::vector<std::uint32_t> elementCount_;
  std::vector<std::uint32_t> wetCount_;
  std::vector<std::uint32_t> filledCount_;
  std::vector<std::uint8_t> skipped_;
  std::int64_t heldUpdate_ = -1;         ///< k of the held loads; -1: none yet
  StormLoadCounters counters_;
};

} // namespace armour::hydro
