// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/StormLoads.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"
#include "hydro/LoadedBodies.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace armour::hydro {
namespace {

/// Leading entry of the saved state: layout version 1 of the "hydro" stage.
constexpr double kStateTag = 4860001.0;
/// Doubles per held load in the saved state.
constexpr std::size_t kHeldDoubles = 13;
/// On an impermeable bed, an element faces down into it when its outward normal's z is at most
/// this: within 25.8 degrees of straight down. A flat bottom face has -1, tilted by the unit's
/// rocking a little less; side faces (0) and a rounded fluke's flanks above about 26 degrees keep
/// their pressure. Ours; the height band (BedSettings::toleranceDn) does most of the selection.
constexpr double kBedNormalZ = -0.9;

void checkSettings(const StormLoadSettings& s) {
  if (!(s.updateInterval > 0.0) || !std::isfinite(s.updateInterval)) {
    core::failInput("hydro.storm.update_interval", "= {} s: must be positive and finite (seed 000: 0.1 s)",
                    s.updateInterval);
  }
  if (!std::isfinite(s.timeOffset)) {
    core::failInput("hydro.storm.time_offset", "= {} s: must be finite", s.timeOffset);
  }
  if (!(s.elementSizePerDn > 0.0) || !(s.elementSizePerDn <= 2.0)) {
    core::failInput("hydro.storm.element_size", "= {} Dn: must be in (0, 2] (0.05 gives about 4000 elements on a "
                    "Core-Loc, as in seed 000)", s.elementSizePerDn);
  }
  if (!(s.wetAlpha >= 0.0 && s.wetAlpha <= 1.0)) {
    core::failInput("hydro.storm.wet_alpha", "= {}: a water fraction must lie in [0, 1] (usually 0.5)", s.wetAlpha);
  }
  if (!(s.drag.coefficient >= 0.0) || !std::isfinite(s.drag.coefficient)) {
    core::failInput("hydro.storm.drag.coefficient", "= {}: C_d must be finite and >= 0 (seed 000: 1)",
                    s.drag.coefficient);
  }
  if (!(s.addedMass.coefficient >= 0.0) || !std::isfinite(s.addedMass.coefficient)) {
    core::failInput("hydro.storm.added_mass.coefficient", "= {}: C_a must be finite and >= 0 (e.g. 1)",
                    s.addedMass.coefficient);
  }
  if (!std::isfinite(s.bed.level)) {
    core::failInput("hydro.storm.bed_level", "= {} m: must be finite (the z of the bed in the scene)", s.bed.level);
  }
  if (!(s.bed.toleranceDn >= 0.0 && s.bed.toleranceDn <= 1.0)) {
    core::failInput("hydro.storm.bed_tolerance", "= {} Dn: must lie in [0, 1] (default 0.01)", s.bed.toleranceDn);
  }
  if (s.variability.patchesPerAxis < 1 || s.variability.patchesPerAxis > 40) {
    core::failInput("hydro.storm.variability.patches_per_axis", "= {}: must be between 1 and 40 (2 = octants)",
                    s.variability.patchesPerAxis);
  }
}

HeldLoad blend(const HeldLoad& a, const HeldLoad& b, double w) {
  HeldLoad r;
  r.pressureForce = (1.0 - w) * a.pressureForce + w * b.pressureForce;
  r.pressureTorque = (1.0 - w) * a.pressureTorque + w * b.pressureTorque;
  r.meanVelocity = (1.0 - w) * a.meanVelocity + w * b.meanVelocity;
  r.fluidAcceleration = (1.0 - w) * a.fluidAcceleration + w * b.fluidAcceleration;
  r.wetFraction = (1.0 - w) * a.wetFraction + w * b.wetFraction;
  return r;
}

} // namespace

struct StormLoads::ShapeData {
  SurfaceElements elements;
  ProjectedAreaTable area;
  double radius = 0.0; ///< largest vertex distance from the centroid, unscaled (m)
  double dn = 0.0;     ///< nominal diameter, the cube root of the volume, unscaled (m)
};

StormLoads::StormLoads(const simulation::World& world, const StormLoadSettings& settings, std::string bodies,
                       const std::string& stormPath)
    : settings_(settings), bodies_(std::move(bodies)) {
  checkSettings(settings_);
  reader_ = std::make_shared<const storm::StormReader>(stormPath);
  initialise(world);
}

StormLoads::StormLoads(const simulation::World& world, const StormLoadSettings& settings, std::string bodies,
                       std::shared_ptr<const storm::StormReader> reader)
    : settings_(settings), bodies_(std::move(bodies)), reader_(std::move(reader)) {
  checkSettings(settings_);
  if (!reader_) {
    throw std::invalid_argument("StormLoads: null storm reader");
  }
  initialise(world);
}

StormLoads::~StormLoads() = default;

void StormLoads::initialise(const simulation::World& world) {
  const storm::StormHeader& h = reader_->header();
  sampler_ = std::make_unique<storm::StormSampler>(*reader_);
  variability_ = VariabilityModel(h.variability, settings_.variability);
  rho_ = h.waterDensity;
  // The sampler holds the edge value within half a voxel of the outermost centres: that is the grid.
  gridMin_[0] = h.x.front() - 0.5 * h.dx();
  gridMax_[0] = h.x.back() + 0.5 * h.dx();
  gridMin_[1] = h.z.front() - 0.5 * h.dz();
  gridMax_[1] = h.z.back() + 0.5 * h.dz();
  trunkMin_ = h.trunkOrigin;
  trunkMax_ = h.trunkLength > 0.0 ? h.trunkOrigin + h.trunkLength : h.trunkOrigin;
  // A file uniform along y (a 2D tank, analytic waves) holds at every y: its trunk range only says
  // where the values were averaged, and units anywhere along the trunk take loads.
  trunkBounded_ = !h.uniformAlongY && h.trunkLength > 0.0;
  // Bilinear alpha reaches zero one voxel above the last wet centre; a second voxel covers a
  // free surface that is steep or overturning within a column.
  airMargin_ = 2.0 * h.dz();
  offset_ = Vec3(settings_.offsetX, 0.0, settings_.offsetZ);
  syncBodies(world);

  const auto log = core::logger("hydro");
  const double gWorld = world.settings().gravity.norm();
  if (std::abs(gWorld - h.gravity) > 1e-3 * h.gravity) {
    log->warn("storm file '{}' was made with g = {} m/s^2 but the scene uses |g| = {} m/s^2: the hydrostatic "
              "pressure (buoyancy) and the weight do not match",
              reader_->path(), h.gravity, gWorld);
  }
  const auto& bodies = world.bodies();
  std::size_t outsideGrid = 0, outsideTrunk = 0, loadedCount = 0;
  Eigen::Vector2d spanMin(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d spanMax = -spanMin;
  for (BodyId b = 0; b < loaded_.size(); ++b) {
    if (!loaded_[b]) {
      continue;
    }
    ++loadedCount;
    const Vec3 x = bodies.position(b) + offset_;
    spanMin = spanMin.cwiseMin(Eigen::Vector2d(x.x(), x.z()));
    spanMax = spanMax.cwiseMax(Eigen::Vector2d(x.x(), x.z()));
    if (x.x() < gridMin_[0] || x.x() > gridMax_[0] || x.z() < gridMin_[1] || x.z() > gridMax_[1]) {
      ++outsideGrid;
    }
    if (trunkBounded_ && (x.y() < trunkMin_ || x.y() > trunkMax_)) {
      ++outsideTrunk;
    }
  }
  if (loadedCount == 0) {
    log->warn("hydro: no body takes storm loads (bodies filter '{}': fixed bodies never do)", bodies_);
  }
  if (outsideGrid > 0) {
    log->warn("{} of {} loaded bodies have their centroid outside the storm grid of '{}' (x {} .. {} m, z {} .. {} m; "
              "the loaded centroids span x {:.4g} .. {:.4g} m, z {:.4g} .. {:.4g} m in the file's coordinates, "
              "hydro.storm.offset = [{}, {}] m): beyond the grid they take the flow of its edge (held along x, "
              "continued hydrostatically along z), which is right for units just beyond it (fallen off the toe) "
              "and only buoyancy far away; if the scene and the tank have different origins, set "
              "hydro.storm.offset to the file's (x, z) of the scene's origin",
              outsideGrid, loadedCount, reader_->path(), gridMin_[0], gridMax_[0], gridMin_[1], gridMax_[1],
              spanMin.x(), spanMax.x(), spanMin.y(), spanMax.y(), settings_.offsetX, settings_.offsetZ);
  }
  if (h.uniformAlongY) {
    log->info("storm file '{}' holds at every y (uniform_along_y = 1): units at any y take loads (y {} .. {} m is "
              "only the range it was averaged over)",
              reader_->path(), h.trunkOrigin, h.trunkOrigin + h.trunkLength);
  }
  if (outsideTrunk > 0) {
    log->warn("{} of {} loaded bodies have their centroid outside the trunk of '{}' (y {} .. {} m): their "
              "elements take the section's y-averaged flow, and a body wholly outside the trunk gets no "
              "hydrodynamic load (a file from a 2D tank should declare uniform_along_y = 1: "
              "foam-proxy sample --uniform-along-y)",
              outsideTrunk, loadedCount, reader_->path(), trunkMin_, trunkMax_);
  }
  if (settings_.bed.kind == BedKind::Impermeable) {
    log->info("hydro: impermeable bed at z = {} m: surface elements within {} Dn above it (or below it) whose "
              "outward normal points down (n_z <= {}) take no pressure",
              settings_.bed.level, settings_.bed.toleranceDn, kBedNormalZ);
  }
  if (settings_.variability.enabled && !variability_.active()) {
    log->info("storm file '{}' has no usable variability model: loads from the y-averaged pressure only",
              reader_->path());
  }
  for (std::size_t s = 0; s < shapes_.size(); ++s) {
    if (shapes_[s]) {
      const ShapeData& d = *shapes_[s];
      log->info("hydro: shape '{}': {} surface elements (edges <= {:.4g} m), projected area {}",
                world.shape(static_cast<simulation::ShapeId>(s)).name, d.elements.size(), d.elements.elementSize,
                d.area.direct() ? std::string("exact (convex)")
                                : fmt::format("{} table over {} directions", d.area.exact() ? "exact" : "rasterised",
                                              d.area.directions()));
    }
  }
}

void StormLoads::syncBodies(const simulation::World& world) {
  const auto& bodies = world.bodies();
  const std::size_t n = bodies.size();
  if (loaded_.size() == n) {
    return;
  }
  // Bodies are never removed: only new ones need a decision and perhaps their shape's data.
  const std::size_t first = loaded_.size();
  loaded_.resize(n, 0);
  held_[0].resize(n);
  held_[1].resize(n);
  applied_.resize(n);
  elementCount_.resize(n, 0);
  wetCount_.resize(n, 0);
  filledCount_.resize(n, 0);
  skipped_.resize(n, 0);
  for (std::size_t i = first; i < n; ++i) {
    const auto b = static_cast<BodyId>(i);
    const bool take = bodies.motionType(b) != dynamics::MotionType::Static && nameTakesLoads(bodies.info(b).name, bodies_);
    loaded_[b] = take ? 1 : 0;
    if (!take) {
      continue;
    }
    const simulation::ShapeId id = world.bodyShape(b);
    if (shapes_.size() <= id) {
      shapes_.resize(id + 1);
    }
    if (!shapes_[id]) {
      const simulation::ShapeModel& shape = world.shape(id);
      auto data = std::make_unique<ShapeData>();
      const double dn = std::cbrt(shape.unitMass.volume);
      data->elements =
          buildSurfaceElements(shape.mesh, settings_.elementSizePerDn * dn, settings_.variability.patchesPerAxis);
      data->area = ProjectedAreaTable(shape.mesh);
      data->radius = shape.radius;
      data->dn = dn;
      shapes_[id] = std::move(data);
    }
  }
  counters_.loadedBodies = static_cast<std::size_t>(std::count(loaded_.begin(), loaded_.end(), std::uint8_t{1}));
}

const SurfaceElements& StormLoads::elements(simulation::ShapeId shape) const {
  if (shape >= shapes_.size() || !shapes_[shape]) {
    throw std::out_of_range("StormLoads::elements: no loaded body has this shape");
  }
  return shapes_[shape]->elements;
}

const ProjectedAreaTable& StormLoads::areaTable(simulation::ShapeId shape) const {
  if (shape >= shapes_.size() || !shapes_[shape]) {
    throw std::out_of_range("StormLoads::areaTable: no loaded body has this shape");
  }
  return shapes_[shape]->area;
}

double StormLoads::lastUpdateTime() const {
  return heldUpdate_ < 0 ? -1.0 : static_cast<double>(heldUpdate_) * settings_.updateInterval;
}

void StormLoads::update(const simulation::World& world, std::int64_t k, double time) {
  const double dt = settings_.updateInterval;
  const double tk = static_cast<double>(k) * dt;
  checkStormTime(tk + settings_.timeOffset, time);
  counters_.evaluatedBodies = counters_.skippedBodies = counters_.evaluatedElements = counters_.wetElements = 0;
  counters_.filledElements = 0;
  if (settings_.betweenUpdates == BetweenUpdates::Hold) {
    evaluate(world, tk + settings_.timeOffset, held_[0]);
  } else {
    // Interpolate: the loads between t_k and t_(k+1) blend those of storm times t_k and t_(k+1). The
    // t_(k+1) loads are computed now, with the positions of t_k; on a regular step the t_k loads
    // were computed one update ago. The look-ahead stops at the last record (the run may end there).
    const double last = reader_->times().back();
    const double ahead = std::min(tk + dt + settings_.timeOffset, last);
    if (heldUpdate_ >= 0 && k == heldUpdate_ + 1) {
      std::swap(held_[0], held_[1]);
    } else {
      evaluate(world, tk + settings_.timeOffset, held_[0]);
    }
    evaluate(world, ahead, held_[1]);
  }
  heldUpdate_ = k;
  ++counters_.updates;
  core::logger("hydro")->debug("update {} at t = {} s: {} bodies evaluated, {} skipped, {} elements sampled ({} wet)",
                               k, tk, counters_.evaluatedBodies, counters_.skippedBodies, counters_.evaluatedElements,
                               counters_.wetElements);
}

void StormLoads::checkStormTime(double stormTime, double simulationTime) const {
  const auto& times = reader_->times();
  // A microsecond of slack (evaluate() clamps): record times written as float sums of 0.05 s are
  // not exact, and the run's end time should not fail on their last digit.
  const double slack = std::max(1e-6, 1e-9 * std::abs(stormTime));
  if (stormTime < times.front() - slack || stormTime > times.back() + slack) {
    core::failInput(reader_->path(),
                    "storm time {} s (simulation time {} s + hydro.storm.time_offset {} s) is outside the records "
                    "of the file, {} .. {} s: end the run by simulation time {} s or change the time offset",
                    stormTime, simulationTime, settings_.timeOffset, times.front(), times.back(),
                    times.back() - settings_.timeOffset);
  }
}

void StormLoads::evaluate(const simulation::World& world, double stormTime, std::vector<HeldLoad>& out) {
  const auto& times = reader_->times();
  sampler_->setTime(std::clamp(stormTime, times.front(), times.back()));
  // The free surface of every column, once per evaluation, for the dry-body test.
  const storm::StormHeader& h = reader_->header();
  std::vector<double> etaColumns(h.nx());
  for (std::size_t i = 0; i < h.nx(); ++i) {
    etaColumns[i] = sampler_->phase(h.x[i]).elevation;
  }
  const auto n = static_cast<std::int64_t>(loaded_.size());
  // Each body writes only its own slots, so any thread count gives the same loads.
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int64_t i = 0; i < n; ++i) {
    const auto b = static_cast<BodyId>(i);
    evaluateBody(world, b, etaColumns, out[b], elementCount_[b], wetCount_[b], filledCount_[b], skipped_[b]);
  }
  // Bodies: those of this evaluation; elements: summed over the evaluations of the update (two
  // when Interpolate starts).
  counters_.evaluatedBodies = counters_.skippedBodies = 0;
  for (std::size_t b = 0; b < loaded_.size(); ++b) {
    if (!loaded_[b]) {
      continue;
    }
    counters_.evaluatedElements += elementCount_[b];
    counters_.wetElements += wetCount_[b];
    counters_.filledElements += filledCount_[b];
    counters_.wetTotal += wetCount_[b];
    counters_.filledTotal += filledCount_[b];
    counters_.skippedBodies += skipped_[b];
    counters_.evaluatedBodies += elementCount_[b] > 0 ? 1 : 0;
    ++counters_.bodyEvaluationsTotal;
    counters_.skippedTotal += skipped_[b];
  }
}

std::string StormLoads::summary() const {
  const auto& c = counters_;
  if (c.bodyEvaluationsTotal == 0) return {};
  std::string text = fmt::format("hydro: {} load updates; {} of {} unit evaluations skipped ({:.1f} %: dry, above the "
                                 "water, or beyond a bounded trunk section, no surface element sampled)",
                                 c.updates, c.skippedTotal, c.bodyEvaluationsTotal,
                                 100.0 * static_cast<double>(c.skippedTotal) /
                                     static_cast<double>(c.bodyEvaluationsTotal));
  if (c.filledTotal > 0) {
    text += fmt::format("; {} of {} wet element samples ({:.2f} %) fell in voxels without data and took the gap fill "
                        "(still water under the free surface: docs/theory.md)",
                        c.filledTotal, c.wetTotal,
                        100.0 * static_cast<double>(c.filledTotal) / static_cast<double>(c.wetTotal));
  }
  return text;
}

void StormLoads::evaluateBody(const simulation::World& world, BodyId b, const std::vector<double>& etaColumns,
                              HeldLoad& out, std::uint32_t& elements, std::uint32_t& wet, std::uint32_t& filled,
                              std::uint8_t& skipped) const {
  out = HeldLoad{};
  elements = 0;
  wet = 0;
  filled = 0;
  skipped = 0;
  const auto& bodies = world.bodies();
  if (!loaded_[b] || bodies.motionType(b) == dynamics::MotionType::Static) {
    return;
  }
  const ShapeData& shape = *shapes_[world.bodyShape(b)];
  const double s = world.bodyScale(b);
  const Vec3 x = bodies.position(b) + offset_; // in the storm file's coordinates
  const double r = s * shape.radius;
  const storm::StormHeader& h = reader_->header();
  // Cheap rejections before any element is touched: for a file bounded along y, the trunk (a unit
  // wholly beyond its ends counts as skipped: no flow was simulated there)...
  if (trunkBounded_ && (x.y() + r < trunkMin_ || x.y() - r > trunkMax_)) {
    skipped = 1;
    return;
  }
  // ... and the highest free surface of the columns it spans (one column more on each side: the
  // sampler interpolates between neighbouring columns; beyond the grid, the edge column's).
  {
    const double dx = h.dx();
    const auto last = static_cast<double>(h.nx() - 1);
    double lo = 0.0, hi = last;
    if (dx > 0.0) {
      lo = std::clamp(std::floor((x.x() - r - h.x.front()) / dx) - 1.0, 0.0, last);
      hi = std::clamp(std::ceil((x.x() + r - h.x.front()) / dx) + 1.0, 0.0, last);
    }
    double top = -std::numeric_limits<double>::infinity();
    for (auto i = static_cast<std::size_t>(lo); i <= static_cast<std::size_t>(hi); ++i) {
      top = std::max(top, etaColumns[i]);
    }
    if (x.z() - r > h.stillWaterLevel + top + airMargin_) {
      skipped = 1;
      return;
    }
  }

  const SurfaceElements& el = shape.elements;
  const Eigen::Matrix3d rotation = bodies.orientation(b).toRotationMatrix();
  const Eigen::Matrix3d scaledRotation = s * rotation;
  // Variability: one deviation per patch for this body and the half wave at its centroid.
  std::vector<double> deviation(static_cast<std::size_t>(el.patchCount()), 0.0);
  if (variability_.active()) {
    const storm::WavePhase phase = sampler_->phase(x.x());
    for (int k = 0; k < el.patchCount(); ++k) {
      deviation[static_cast<std::size_t>(k)] = variability_.pressureDeviation(b, k, phase);
    }
  }
  const bool addedMass = settings_.addedMass.enabled;
  const double wetAlpha = settings_.wetAlpha;
  // An impermeable bed (BedSettings): no water, so no pressure, under the elements lying on it and
  // facing down into it; the top of the band in the file's z, like the element centroids below.
  const bool bed = settings_.bed.kind == BedKind::Impermeable;
  const double bedTop = settings_.bed.level + offset_.z() + settings_.bed.toleranceDn * s * shape.dn;
  Vec3 forceBody = Vec3::Zero(), torqueBody = Vec3::Zero(), velocitySum = Vec3::Zero(), rateSum = Vec3::Zero();
  double wetArea = 0.0, rateArea = 0.0;
  std::uint32_t sampled = 0, wetElements = 0, filledElements = 0;
  // The water does not end where the sampling box does, nor where a 3D tank's file has data.
  // Elements beyond the grid's outermost columns take the edge column's flow, beyond its outermost
  // rows the edge row's pressure continued hydrostatically, beyond a bounded trunk's ends in y the
  // section's (the fields are y-averaged: they do not depend on y), and in voxels without data the
  // gap fill (still water under the column's free surface): leaving any of them atmospheric, the
  // pressure of the rest would push the unit out with p A, several times its weight a few metres
  // down (docs/theory.md, "Elements beyond the sampling box").
  for (std::size_t e = 0; e < el.size(); ++e) {
    const Vec3 c = x + scaledRotation * el.centroid[e];
    const storm::StormSampler::Located at = sampler_->locateExtended(c.x(), c.z());
    const storm::FlowSample f = sampler_->sampleExtended(at);
    ++sampled;
    if (!f.valid || f.alpha < wetAlpha) {
      continue; // atmospheric: gauge pressure 0
    }
    ++wetElements;
    filledElements += f.filled ? 1 : 0;
    const double a = el.area[e];
    const double p = f.p + deviation[el.patch[e]];
    if (!(bed && c.z() <= bedTop && rotation.row(2).dot(el.normal[e]) <= kBedNormalZ)) {
      forceBody.noalias() -= (p * a) * el.normal[e];
      torqueBody.noalias() -= p * el.momentArm[e];
    }
    wetArea += a;
    velocitySum += a * Vec3(f.u, f.v, f.w);
    if (addedMass) {
      const storm::FlowSample dudt = sampler_->rateExtended(at);
      if (dudt.valid) {
        rateSum += a * Vec3(dudt.u, dudt.v, dudt.w);
        rateArea += a;
      }
    }
  }
  elements = sampled;
  wet = wetElements;
  filled = filledElements;
  if (settings_.pressure) {
    out.pressureForce = (s * s) * (rotation * forceBody);
    out.pressureTorque = (s * s * s) * (rotation * torqueBody);
  }
  if (wetArea > 0.0) {
    out.meanVelocity = velocitySum / wetArea;
    out.wetFraction = wetArea / el.totalArea;
  }
  if (rateArea > 0.0) {
    out.fluidAcceleration = rateSum / rateArea;
  }
}

double StormLoads::rampFactor(double time) const {
  const double T = settings_.rampTime;
  if (!(T > 0.0) || time >= T) return 1.0;
  if (time <= 0.0) return 0.0;
  return 0.5 * (1.0 - std::cos(std::numbers::pi * time / T));
}

HeldLoad StormLoads::current(BodyId b, double time) const {
  if (settings_.betweenUpdates == BetweenUpdates::Hold) {
    return held_[0][b];
  }
  const double dt = settings_.updateInterval;
  const double w = std::clamp((time - static_cast<double>(heldUpdate_) * dt) / dt, 0.0, 1.0);
  return blend(held_[0][b], held_[1][b], w);
}

void StormLoads::apply(const simulation::World& world, double time, std::span<dynamics::Vec3> force,
                       std::span<dynamics::Vec3> torque) {
  syncBodies(world);
  // Update k covers [k dt, (k+1) dt); the 1e-9 absorbs the round-off of a time summed step by step.
  const auto k = static_cast<std::int64_t>(std::floor(time / settings_.updateInterval + 1e-9));
  if (k != heldUpdate_) {
    update(world, k, time);
  }
  const auto& bodies = world.bodies();
  const Vec3 gravity = world.settings().gravity;
  const double halfRhoCd = 0.5 * rho_ * settings_.drag.coefficient;
  const double ramp = rampFactor(time);
  const auto n = static_cast<std::int64_t>(loaded_.size());
#pragma omp parallel for schedule(static) if (n >= 1024)
  for (std::int64_t i = 0; i < n; ++i) {
    const auto b = static_cast<BodyId>(i);
    AppliedLoad& out = applied_[b];
    out = AppliedLoad{};
    if (!loaded_[b] || bodies.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    HeldLoad load = current(b, time);
    if (ramp < 1.0) {
      load.pressureForce *= ramp;
      load.pressureTorque *= ramp;
      load.meanVelocity *= ramp;
      load.fluidAcceleration *= ramp;
    }
    out.pressureForce = load.pressureForce;
    out.pressureTorque = load.pressureTorque;
    if (load.wetFraction > 0.0) {
      const ShapeData& shape = *shapes_[world.bodyShape(b)];
      const double s = world.bodyScale(b);
      // Morison drag (seed 000 eq. 2) with the body's velocity of this evaluation.
      if (settings_.drag.enabled) {
        const Vec3 relative = load.meanVelocity - bodies.velocity(b);
        const double speed = relative.norm();
        if (speed > 0.0) {
          const Vec3 directionBody = bodies.orientation(b).conjugate() * (relative / speed);
          out.projectedArea = shape.area(directionBody) * s * s * load.wetFraction;
          out.dragForce = (halfRhoCd * out.projectedArea * speed) * relative;
        }
      }
      // Added mass (seed 000 eq. 1) as the equivalent force F_x (docs/theory.md): the body's
      // acceleration becomes (F_c + F_h + m g + m_a a_f) / (m + m_a).
      if (settings_.addedMass.enabled) {
        const double volumeWet = shape.elements.volume * s * s * s * load.wetFraction;
        const double ma = rho_ * settings_.addedMass.coefficient * volumeWet;
        const double m = bodies.info(b).mass;
        if (ma > 0.0 && m > 0.0) {
          if (bodies.isAwake(b)) {
            const Vec3 hydro = out.pressureForce + out.dragForce;
            out.addedMassForce = (ma / (m + ma)) * (m * load.fluidAcceleration - bodies.force(b) - hydro - m * gravity);
          } else {
            // A sleeping body is held by its contacts in equilibrium (F_c + F_h + m g = 0): only the
            // flow's acceleration remains, which is what should decide its waking.
            out.addedMassForce = (ma * m / (m + ma)) * load.fluidAcceleration;
          }
        }
      }
    }
    force[b] = out.pressureForce + out.dragForce + out.addedMassForce;
    torque[b] = out.pressureTorque;
  }
}

std::vector<double> StormLoads::saveState() const {
  const int sets = settings_.betweenUpdates == BetweenUpdates::Hold ? 1 : 2;
  std::vector<double> state;
  state.reserve(5 + sets * loaded_.size() * kHeldDoubles);
  state.push_back(kStateTag);
  state.push_back(static_cast<double>(loaded_.size()));
  state.push_back(static_cast<double>(sets));
  state.push_back(static_cast<double>(heldUpdate_));
  state.push_back(settings_.updateInterval);
  for (int set = 0; set < sets; ++set) {
    for (const HeldLoad& l : held_[set]) {
      for (const Vec3* v : {&l.pressureForce, &l.pressureTorque, &l.meanVelocity, &l.fluidAcceleration}) {
        state.insert(state.end(), {v->x(), v->y(), v->z()});
      }
      state.push_back(l.wetFraction);
    }
  }
  return state;
}

void StormLoads::restoreState(const std::vector<double>& state) {
  const int sets = settings_.betweenUpdates == BetweenUpdates::Hold ? 1 : 2;
  const std::size_t n = loaded_.size();
  if (state.size() < 5 || state[0] != kStateTag) {
    core::failInput("checkpoint", "the saved 'hydro' stage state is not one this version writes: restart from a "
                    "checkpoint of the same armour version, or run from the start");
  }
  if (state[1] != static_cast<double>(n) || state[2] != static_cast<double>(sets) ||
      state[4] != settings_.updateInterval || state.size() != 5 + sets * n * kHeldDoubles) {
    core::failInput("checkpoint",
                    "the saved 'hydro' stage state ({} bodies, {} held set(s), update interval {} s) does not fit this "
                    "scene ({} bodies, {} held set(s), update interval {} s): restart with the scene that wrote the "
                    "checkpoint",
                    state[1], state[2], state[4], n, sets, settings_.updateInterval);
  }
  heldUpdate_ = static_cast<std::int64_t>(state[3]);
  std::size_t i = 5;
  for (int set = 0; set < sets; ++set) {
    for (HeldLoad& l : held_[set]) {
      for (Vec3* v : {&l.pressureForce, &l.pressureTorque, &l.meanVelocity, &l.fluidAcceleration}) {
        *v = Vec3(state[i], state[i + 1], state[i + 2]);
        i += 3;
      }
      l.wetFraction = state[i++];
    }
  }
  counters_ = StormLoadCounters{};
  counters_.loadedBodies = static_cast<std::size_t>(std::count(loaded_.begin(), loaded_.end(), std::uint8_t{1}));
}

} // namespace armour::hydro
