// SPDX-License-Identifier: GPL-3.0-or-later
// The World itself: construction, materials, shapes, bodies and static geometry, the time step
// limit, and step() running the stages in order. The stages live in files of their own
// (docs/architecture.md, "The time step" and "World's source files"):
//   WorldContacts.cpp  boxes -> broad phase -> narrow phase -> contact law -> accumulate, guard rails
//   WorldLoads.cpp     the external-load stages (LoadStage) and their work
//   WorldSleep.cpp     contact islands: sleeping and waking
//   WorldEnergy.cpp    the energy guard rail
//   WorldState.cpp     captureState / restoreState (checkpoints)
//   WorldConstraint.cpp, WorldManifoldCache.cpp  the constraint solver's step and its manifold reuse
//   WorldInternal.hpp  flag bits shared by these files
#include "simulation/World.hpp"
#include "simulation/WorldInternal.hpp"

#include "core/Error.hpp"
#include "contact/FdemPotential.hpp"
#include "core/Log.hpp"
#include "dynamics/Integrator.hpp"
#include "geometry/ConvexHull.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>

namespace armour::simulation {

namespace {

/// The damping ratios of a restitution, computed once per value and process (a few ms each, and
/// tests build thousands of worlds with the same materials).
contact::DampingByExponent dampingFor(double restitution) {
  static std::mutex mutex;
  static std::map<double, contact::DampingByExponent> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(restitution);
  if (it == cache.end()) it = cache.emplace(restitution, contact::dampingByExponentFromRestitution(restitution)).first;
  return it->second;
}

} // namespace

World::World(const WorldSettings& settings) : settings_(settings) {}
World::~World() = default;

MaterialId World::addMaterial(const Material& m) {
  const std::string where = "material '" + m.name + "'";
  if (!(m.density > 0.0) || !std::isfinite(m.density)) {
    core::failInput(where, "density = {} kg/m^3: must be positive (concrete about 2400)", m.density);
  }
  if (!(m.frictionStatic >= 0.0) || !(m.frictionDynamic >= 0.0) || m.frictionDynamic > m.frictionStatic + 1e-12) {
    core::failInput(where, "friction static = {}, dynamic = {}: both must be >= 0 and dynamic <= static",
                    m.frictionStatic, m.frictionDynamic);
  }
  if (!(m.restitution > 0.0 && m.restitution <= 1.0)) {
    core::failInput(where, "restitution = {}: must be in (0, 1] (concrete on concrete about 0.05)", m.restitution);
  }
  if (!(m.penaltyModulus > 0.0) || !std::isfinite(m.penaltyModulus)) {
    core::failInput(where, "penalty modulus = {} Pa: must be positive (e.g. 1e9)", m.penaltyModulus);
  }
  materials_.push_back(m);
  materialDamping_.push_back(dampingFor(m.restitution));
  cachedStep_ = -1.0;
  return static_cast<MaterialId>(materials_.size() - 1);
}

ShapeId World::addShape(const std::string& name, const geometry::TriangleMesh& mesh) {
  auto model = std::make_unique<ShapeModel>();
  model->name = name;
  const geometry::MassProperties natural = geometry::computeMassProperties(mesh);
  // Body frame = principal frame with the centroid at the origin: the inertia is diagonal there.
  const geometry::Mat3 toBody = natural.principalAxes.transpose();
  model->naturalToBody = Quat(toBody).normalized();
  model->mesh = mesh;
  for (auto& v : model->mesh.vertices) {
    v = toBody * (v - natural.centroid);
    model->radius = std::max(model->radius, v.norm());
  }
  model->unitMass = geometry::computeMassProperties(model->mesh);
  model->bounds = model->mesh.bounds();
  model->levelSet = std::make_unique<contact::LevelSet>(model->mesh, settings_.levelSet, "shape '" + name + "'");
  model->samples = std::make_unique<contact::SurfaceSamples>(model->mesh, settings_.samples, "shape '" + name + "'");
  model->buckets = contact::buildBuckets(*model->samples, model->bounds);
  if (settings_.contactModel == ContactModel::Fdem) {
    model->fdem = std::make_unique<contact::FdemMesh>(model->mesh, settings_.fdem, "shape '" + name + "'");
    // Friction keys hold two element indices in 16 bits each (WorldContacts.cpp).
    if (model->fdem->elements().size() >= 65536u) {
      core::failInput("shape '" + name + "'",
                      "{} contact elements within reach of the surface (of {} tetrahedra): at most 65535; lower "
                      "contact.fdem.elements_per_unit",
                      model->fdem->elements().size(), model->fdem->totalTetCount());
    }
    core::logger("simulation")
        ->debug("shape '{}': fdem {} tetrahedra, {} kept near the surface, {} contactor faces, reach {:.4g} m", name,
                model->fdem->totalTetCount(), model->fdem->elements().size(), model->fdem->faces().size(),
                model->fdem->reach());
  }
  const auto& values = model->levelSet->values();
  model->innerDepth = values.empty() ? 0.0 : -static_cast<double>(*std::min_element(values.begin(), values.end()));
  const double h = model->levelSet->cellSize();
  if (model->innerDepth < 0.25 * h) {
    // No grid node a cell deep inside: the interpolated distance barely (or never) goes negative,
    // so other bodies' points would pass through the shape unseen.
    const double thickness = model->bounds.size().minCoeff();
    const double dn = model->levelSet->nominalDiameter();
    core::failInput("shape '" + name + "'",
                    "is too thin for its level set: {:.3g} m across at the thinnest (bounding box), the deepest "
                    "grid node {:.3g} m inside, but the grid cell is {:.3g} m (Dn / {:.3g}); raise "
                    "contact.level_set_cells_per_dn to at least {:.0f}, or model the part thicker",
                    thickness, std::max(model->innerDepth, 0.0), h, dn / h, std::ceil(4.0 * dn / thickness));
  }
  core::logger("simulation")
      ->debug("shape '{}': {} triangles, {} samples, level set {}x{}x{} (h = {:.4g} m)", name,
              model->mesh.triangleCount(), model->samples->size(), model->levelSet->nodeCounts()[0],
              model->levelSet->nodeCounts()[1], model->levelSet->nodeCounts()[2], model->levelSet->cellSize());
  shapes_.push_back(std::move(model));
  return static_cast<ShapeId>(shapes_.size() - 1);
}

BodyId World::addBody(const BodySpec& spec) {
  const std::string where = spec.name.empty() ? fmt::format("body #{}", bodies_.size()) : "body '" + spec.name + "'";
  if (spec.shape >= shapes_.size()) {
    core::failInput(where, "shape index {} does not exist ({} shapes)", spec.shape, shapes_.size());
  }
  if (spec.material >= materials_.size()) {
    core::failInput(where, "material index {} does not exist ({} materials)", spec.material, materials_.size());
  }
  if (!(spec.scale > 0.0) || !std::isfinite(spec.scale)) {
    core::failInput(where, "scale = {}: must be positive", spec.scale);
  }
  const ShapeModel& shape = *shapes_[spec.shape];
  const double rho = materials_[spec.material].density;
  const double s = spec.scale;
  dynamics::BodyDefinition def;
  def.name = spec.name;
  def.motionType = spec.fixed ? dynamics::MotionType::Static : dynamics::MotionType::Dynamic;
  def.mass = rho * shape.unitMass.volume * s * s * s;
  def.principalMoments = rho * std::pow(s, 5) * shape.unitMass.principalMoments;
  def.position = spec.position;
  def.orientation = (spec.orientation.normalized() * shape.naturalToBody.conjugate()).normalized();
  if (!spec.fixed) {
    def.velocity = spec.velocity;
    def.angularVelocity = spec.angularVelocity;
  }
  def.shapeId = static_cast<std::int32_t>(spec.shape);
  const BodyId id = bodies_.add(def);
  bodyShape_.push_back(spec.shape);
  bodyScale_.push_back(s);
  bodyDn_.push_back(std::cbrt(shape.unitMass.volume) * s);
  bodyMaterial_.push_back(spec.material);
  restTime_.push_back(0.0);
  cachedStep_ = -1.0;
  forcesReady_ = false;
  boxesValid_ = false;
  energyStarted_ = false; // a new body brings its own energy: the guard starts again
  energyPeak_ = 0.0;
  return id;
}

void World::addPlane(const StaticPlane& plane) {
  if (!plane.normal.allFinite() || plane.normal.norm() < 1e-12 || !plane.point.allFinite()) {
    core::failInput("plane '" + plane.name + "'", "normal must be a finite non-zero vector and the point finite");
  }
  if (plane.material >= materials_.size()) {
    core::failInput("plane '" + plane.name + "'", "material index {} does not exist", plane.material);
  }
  StaticPlane p = plane;
  p.normal.normalize();
  planes_.push_back(p);
  forcesReady_ = false;
}

void World::addConvex(const std::string& name, const std::vector<Vec3>& corners, MaterialId material) {
  const std::string where = "static piece '" + name + "'";
  if (material >= materials_.size()) {
    core::failInput(where, "material index {} does not exist", material);
  }
  const geometry::ConvexPolyhedron hull = geometry::convexHullPolyhedron(corners, where);
  StaticConvex piece;
  piece.name = name;
  piece.material = material;
  piece.normals = hull.normals;
  piece.offsets = hull.offsets;
  piece.vertices = hull.vertices;
  for (const auto& v : hull.vertices) {
    piece.box.extend(v);
  }
  // The fdem half-space evaluation clips against every face of a piece at once, in fixed-size
  // polygons (contact::kFdemMaxStaticFaces).
  if (settings_.contactModel == ContactModel::Fdem && piece.normals.size() > contact::kFdemMaxStaticFaces) {
    core::failInput(where, "has {} faces; contact.model fdem handles static pieces of at most {} faces: split the "
                           "piece, coarsen the height field, or use contact.model levelset",
                    piece.normals.size(), contact::kFdemMaxStaticFaces);
  }
  piece.innerDepth = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < piece.normals.size(); ++k) {
    double across = 0.0;
    for (const auto& v : hull.vertices) {
      across = std::max(across, piece.offsets[k] - piece.normals[k].dot(v));
    }
    piece.innerDepth = std::min(piece.innerDepth, 0.5 * across);
  }
  convex_.push_back(std::move(piece));
  forcesReady_ = false;
  boxesValid_ = false;
}

Quat World::naturalOrientation(BodyId b) const { return bodies_.orientation(b) * bodyNaturalToBody(b); }

double World::stableTimeStep() const {
  double limit = std::numeric_limits<double>::infinity();
  double maxModulus = 0.0, maxZeta = 0.0;
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    maxModulus = std::max(maxModulus, materials_[i].penaltyModulus);
    maxZeta = std::max(maxZeta, materialDamping_[i].zeta[0]); // zeta falls with the exponent: p = 1 the largest
  }
  // Central difference with the dashpot: explicit, dt < (2 / omega)(sqrt(1 + zeta^2) - zeta);
  // implicit (contact::dampingTime given dt), omega dt < h(zeta): 1.25 at e = 0.1 against 0.70.
  const bool implicit = settings_.dashpot == DashpotIntegration::Implicit;
  const double implicitStep = implicit ? contact::stableStepOfImplicitDashpot(maxZeta) : 0.0;
  const double explicitFactor = std::sqrt(1.0 + maxZeta * maxZeta) - maxZeta;
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    if (bodies_.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    const ShapeModel& shape = *shapes_[bodyShape_[b]];
    const double s = bodyScale_[b];
    const double dn = bodyDn(b);
    // Stiffest plausible contact: a third of the surface engaged (a cube resting in a corner
    // touches with two of its six faces), at the body's own length scale.
    const double k = maxModulus * (shape.samples->totalArea() * s * s / 3.0) / dn;
    const double m = bodies_.info(b).mass;
    const double iMin = bodies_.info(b).principalMoments.minCoeff();
    const double r = shape.radius * s;
    const double omega = std::max(std::sqrt(k / m), std::sqrt(k * r * r / iMin));
    // (The explicit expression keeps its order of operations: the same step to the last bit.)
    limit = std::min(limit, implicit ? implicitStep / omega : 2.0 / omega * explicitFactor);
  }
  return limit;
}

double World::timeStep() const {
  if (cachedStep_ > 0.0) {
    return cachedStep_;
  }
  if (settings_.solver == ContactSolverKind::Constraint) {
    // No stability limit from the contact stiffness (the soft constraints are capped at a quarter
    // of the substep rate); the largest step is the one measured stable (docs/benchmarks.md).
    const double dt = settings_.timeStep > 0.0 ? settings_.timeStep : settings_.constraint.timeStep;
    if (!(dt <= kMaxConstraintStep) || !(dt >= kMinConstraintStep)) {
      core::failInput("time_step", "{:.4g} s with contact.solver: constraint: the solver is measured stable for steps "
                                   "of {:.4g} to {:.4g} s; use time_step: auto ({:.4g} s) or a step in that range",
                      dt, kMinConstraintStep, kMaxConstraintStep, settings_.constraint.timeStep);
    }
    cachedStep_ = dt;
    return cachedStep_;
  }
  const double limit = stableTimeStep();
  if (settings_.timeStep > 0.0) {
    if (settings_.timeStep > limit) {
      core::failInput("time_step", "{:.4g} s exceeds the stability limit {:.4g} s of the stiffest contact (penalty "
                                   "modulus, smallest body, restitution); use time_step <= {:.4g} s or auto",
                      settings_.timeStep, limit, limit);
    }
    cachedStep_ = settings_.timeStep;
  } else {
    if (!std::isfinite(limit)) {
      cachedStep_ = 1e-3; // no dynamic body: any step is stable
    } else {
      cachedStep_ = settings_.timeStepSafety * limit;
    }
  }
  return cachedStep_;
}

void World::step() {
  if (settings_.solver == ContactSolverKind::Constraint) {
    stepConstraint();
    return;
  }
  const double dt = timeStep();
  if (!forcesReady_) {
    computeForces(dt, time_);
    forcesReady_ = true;
  }
  // Work of the external loads over the step, trapezoidal in F . v (exact for constant loads and
  // velocity; second order otherwise), so the energy guard sees waves as work, not instability.
  const double powerBefore = externalPower();
  auto clock = StepProfile::Clock::now();
  dynamics::kick(bodies_, 0.5 * dt, settings_.gravity);
  dynamics::drift(bodies_, dt);
  profile_.add(Stage::Integrate, clock);
  computeForces(dt, time_ + dt);
  clock = StepProfile::Clock::now();
  dynamics::kick(bodies_, 0.5 * dt, settings_.gravity);
  clock = profile_.add(Stage::Integrate, clock);
  externalWork_ += 0.5 * dt * (powerBefore + externalPower());
  time_ += dt;
  ++steps_;
  finishStep(dt, clock);
}

void World::finishStep(double dt, StepProfile::Clock::time_point clock) {
  stats_.awakeBodies = bodies_.awakeBodies().size();
  profile_.count({static_cast<double>(stats_.awakeBodies), static_cast<double>(stats_.candidatePairs),
                  static_cast<double>(stats_.contactPoints), static_cast<double>(stats_.sampleSearches),
                  static_cast<double>(stats_.sampleListListed), static_cast<double>(stats_.sampleListLookups)});
  applyBodyDamping(dt);
  for (BodyId b : bodies_.awakeBodies()) {
    if (!bodies_.position(b).allFinite() || !bodies_.velocity(b).allFinite() ||
        !bodies_.worldAngularVelocity(b).allFinite()) {
      throw SimulationError(fmt::format("t = {:.6g} s: {} has a non-finite state (position, velocity or "
                                        "angular velocity); the step is unstable: lower the time step",
                                        time_, bodies_.describe(b)));
    }
  }
  clock = profile_.add(Stage::Guards, clock);
  updateSleep(dt);
  clock = profile_.add(Stage::Sleep, clock);
  if (settings_.energyGuard.enabled && steps_ % std::max<std::uint32_t>(1, settings_.energyGuard.checkInterval) == 0) {
    checkEnergy();
  }
  profile_.add(Stage::Guards, clock);
}

void World::applyBodyDamping(double dt) {
  const BodyDamping& d = settings_.bodyDamping;
  if (d.linear == 0.0 && d.angular == 0.0) return;
  // The exact decay over the step, applied after it (operator splitting): unconditionally stable,
  // it only removes energy, and n steps give exp(-c n dt) to round-off whatever the step.
  const double linear = std::exp(-d.linear * dt), angular = std::exp(-d.angular * dt);
  for (BodyId b : bodies_.awakeBodies()) {
    if (bodies_.motionType(b) != dynamics::MotionType::Dynamic) continue;
    bodies_.setVelocity(b, linear * bodies_.velocity(b));
    bodies_.setWorldAngularVelocity(b, angular * bodies_.worldAngularVelocity(b));
  }
}

void World::evaluateContacts() {
  computeForces(timeStep(), time_);
  forcesReady_ = true;
}

void World::advanceTo(double t) {
  while (time_ < t - 0.5 * timeStep()) {
    step();
  }
}

} // namespace armour::simulation
