// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file World.hpp
/// The rigid FDEM world: shapes (each with its level set and surface samples, and with
/// ContactModel::Fdem its contact-element mesh, shared by all bodies of the shape), materials,
/// bodies, static planes, and the time step as a list of named
/// stages (docs/architecture.md, "The time step"):
///
///   kick(dt/2) -> drift(dt) -> boxes -> broad phase -> narrow phase -> contact law
///     -> accumulate -> kick(dt/2)
///
/// Determinism: the narrow phase and the contact law run in parallel over candidate pairs, each
/// pair writing only its own result slot; forces are then summed into bodies serially in pair
/// order, so 1 and N threads give bit-identical states.

#include "contact/BroadPhase.hpp"
#include "contact/ContactLaw.hpp"
#include "contact/ContactReduction.hpp"
#include "contact/ContactSolver.hpp"
#include "contact/FdemMesh.hpp"
#include "contact/LevelSet.hpp"
#include "contact/NarrowPhase.hpp"
#include "contact/SampleBuckets.hpp"
#include "contact/SurfaceSamples.hpp"
#include "dynamics/RigidBodies.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/TriangleMesh.hpp"
#include "simulation/CacheWalk.hpp"
#include "simulation/LoadStage.hpp"
#include "simulation/StepProfile.hpp"
#include "simulation/RestSettings.hpp"
#include "simulation/StepSettings.hpp"
#include "simulation/WorldState.hpp"

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace armour::simulation {

using dynamics::BodyId;
using dynamics::Quat;
using dynamics::Vec3;

using ShapeId = std::uint32_t;
using MaterialId = std::uint32_t;

/// Contact material. Pairs combine by the smaller friction, the smaller restitution and the
/// smaller penalty modulus (the softer body sets the stiffness).
struct Material {
  std::string name;
  double density = 2400.0;             ///< unit: kg/m^3
  double frictionStatic = 0.75;        ///< Coulomb coefficient while sticking (unit: -)
  double frictionDynamic = 0.75;       ///< Coulomb coefficient while sliding (unit: -)
  double restitution = 0.05;           ///< normal coefficient of restitution (unit: -)
  double penaltyModulus = 1.0e9;       ///< contact pressure per unit relative depth (unit: Pa)
  double tangentialStiffnessRatio = 8.0 / 9.0; ///< k_t / k_n (unit: -): Mindlin 2(1-nu)/(2-nu), nu = 0.2 (concrete)
};

/// The energy guard rail: without work from outside (gravity is in the energy, contacts only
/// dissipate), E = kinetic + gravitational + elastic contact energy cannot grow. A rise of
/// E - W (W: work of external loads) above its lowest value by more than the tolerance means the
/// integration is unstable, and the run stops with the most energetic body named.
struct EnergyGuardSettings {
  bool enabled = true;
  /// Tolerated rise, as a multiple of the largest m |g| Dn of a dynamic body (unit: -): a body
  /// thrown up by its own size is already far beyond integration noise.
  double growthPerBodyWeight = 2.0;
  /// Further tolerated rise, as a fraction of the largest kinetic + elastic energy seen (unit: -):
  /// the bounded energy oscillation of an explicit step through stiff impacts.
  double growthPerPeakEnergy = 0.1;
  std::uint32_t checkInterval = 50; ///< steps between checks (unit: -)
};

/// Which contact model the narrow phase uses: surface samples in level sets (docs/theory.md,
/// sections 6-7) or Munjiza's potential over tetrahedral contact elements ("FDEM potential contact").
/// Both share the broad phase, friction, damping, guard rails and output.
enum class ContactModel { LevelSet, Fdem };

/// Which solver turns contacts into motion (docs/theory.md, "The constraint solver"):
///  - Penalty: forces from the contact law at every sample point, explicit velocity Verlet at a
///    step below the stability limit of the stiffest contact (7e-5 to 4e-4 s for armour units);
///  - Constraint: velocity-level contact constraints on a few reduced points per patch, soft
///    projected Gauss-Seidel with substeps (contact/ContactSolver), at steps of 1/240 s and more.
/// Both read the same narrow phase (contact/NarrowPhase).
enum class ContactSolverKind { Penalty, Constraint };

/// How the penalty law's dashpot is stepped (contact.dashpot; docs/theory.md section 6, "The
/// dashpot over a step"): Explicit, on the half-step velocity, stable for omega dt below
/// 2 (sqrt(1 + zeta^2) - zeta); Implicit, trapezoidal in the dashpot, stable below the root of
/// h^2 (1 + zeta h) = 4, 1.8 to 4.3 times longer steps at e = 0.1 to 0.01 for rebounds further from e.
enum class DashpotIntegration { Explicit, Implicit };

/// Settings of the whole simulation.
struct WorldSettings {
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);   ///< unit: m/s^2
  double timeStep = 0.0;                  ///< unit: s; 0 = automatic (safety x stability limit)
  double timeStepSafety = kTimeStepSafety; ///< fraction of the stability limit used by "auto" (unit: -)
  contact::LevelSetSettings levelSet;     ///< grid resolution per shape
  contact::SurfaceSampleSettings samples; ///< surface sample spacing per shape
  ContactModel contactModel = ContactModel::LevelSet; ///< narrow phase and normal force
  ContactSolverKind solver = ContactSolverKind::Penalty; ///< contact.solver
  DashpotIntegration dashpot = DashpotIntegration::Explicit; ///< contact.dashpot (penalty solver)
  ConstraintSettings constraint;          ///< contact.constraint (solver = Constraint only)
  contact::FdemMeshSettings fdem;         ///< contact elements per shape (fdem only)
  double boxMarginPerDn = 0.05;           ///< world boxes grow by this x Dn (unit: -)
  /// Near-sample lists of body pairs (NarrowPhase.hpp): a full search lists the samples within the
  /// margin plus this x the smaller Dn, and the pair tests only those until it has moved about a
  /// third of it. Exact (the same points bit for bit); a speed setting only. 0: no lists (unit: -).
  double sampleListSlackPerDn = 0.05;
  double maxOverlapPerDn = 0.25;          ///< guard rail: deeper overlaps stop the run (unit: -)
  /// Guard rail against tunnelling: an overlap deeper than this fraction of the thinner part's
  /// inner depth (the depth of its deepest interior point: half the thickness of a slab) stops
  /// the run, before a point can pass the middle of a thin wall and be pushed out the far side (unit: -).
  double maxOverlapPerInnerDepth = 0.5;
  SleepSettings sleep;
  BodyDamping bodyDamping;
  EnergyGuardSettings energyGuard;
  bool recordContacts = false;            ///< keep the contact patches of each force evaluation (contactPatches())
};

/// Surface samples bucketed on a coarse grid over the shape's bounds (contact/SampleBuckets.hpp).
using SampleBuckets = contact::SampleBuckets;

/// A shape prepared for simulation: moved to its principal frame, with its contact geometry.
struct ShapeModel {
  std::string name;
  geometry::TriangleMesh mesh;          ///< body (principal) frame, centroid at the origin (m)
  geometry::MassProperties unitMass;    ///< per unit density, body frame
  Quat naturalToBody = Quat::Identity(); ///< rotation from the shape's natural frame to its principal frame
  std::unique_ptr<contact::LevelSet> levelSet;
  std::unique_ptr<contact::SurfaceSamples> samples;
  SampleBuckets buckets;
  std::unique_ptr<contact::FdemMesh> fdem; ///< contact elements (ContactModel::Fdem only)
  geometry::Box3 bounds;                ///< bounds of `mesh` (unit: m, body frame)
  double innerDepth = 0.0;              ///< depth of the deepest interior point, -min phi (unit: m, unscaled)
  double radius = 0.0;                  ///< largest vertex distance from the centroid (m)
};

/// How to create a body.
struct BodySpec {
  std::string name;
  ShapeId shape = 0;
  double scale = 1.0;                   ///< uniform scale of the shape (unit: -)
  MaterialId material = 0;
  bool fixed = false;                   ///< static: never moves
  Vec3 position = Vec3::Zero();         ///< centroid, world (unit: m)
  Quat orientation = Quat::Identity();  ///< natural shape frame -> world (unit: -)
  Vec3 velocity = Vec3::Zero();         ///< unit: m/s
  Vec3 angularVelocity = Vec3::Zero();  ///< world (unit: rad/s)
};

/// A static half-space {x : (x - point) . normal <= 0} (the solid side is below the plane).
struct StaticPlane {
  std::string name;
  Vec3 point = Vec3::Zero();   ///< a point on the plane (unit: m)
  Vec3 normal = Vec3::UnitZ(); ///< unit normal out of the solid (unit: -)
  MaterialId material = 0;
};

/// A static convex polyhedron {x : n_k . x <= d_k for every face k} (toe blocks, slope pieces,
/// height-field cells). Unions of pieces model non-convex static geometry.
struct StaticConvex {
  std::string name;
  std::vector<Vec3> normals;   ///< unit outward face normals (unit: -)
  std::vector<double> offsets; ///< n_k . x = d_k on face k (unit: m)
  std::vector<Vec3> vertices;  ///< corners (unit: m)
  geometry::Box3 box;          ///< bounds of the corners (unit: m)
  /// Depth of the deepest interior point, estimated as half the smallest extent across a face
  /// (exact for boxes and slabs) (unit: m).
  double innerDepth = 0.0;
  MaterialId material = 0;
};

/// The resultant of one contact pair in the last force evaluation: what a force-chain plot shows.
struct ContactPatch {
  BodyId bodyA = 0;                ///< the body pushed by `force`
  std::int64_t bodyB = -1;         ///< the other body, or -1 for static geometry (a plane or piece)
  Vec3 point = Vec3::Zero();       ///< normal-force-weighted centre of the engaged points (unit: m)
  Vec3 force = Vec3::Zero();       ///< total contact force on A; B gets minus it (unit: N)
  double normalForce = 0.0;        ///< sum of the points' normal forces (unit: N)
  std::int32_t points = 0;         ///< engaged sample points (unit: -)
};

/// One contact point force on a traced body (World::setTracedBodies): what `armour stress`
/// replays on a deformable model of the unit (simulation/UnitLoads.hpp).
struct TracedContact {
  BodyId body = 0;                 ///< the traced body the force acts on
  std::int64_t other = -1;         ///< the other body, or -1 for static geometry (a plane or piece)
  Vec3 point = Vec3::Zero();       ///< where it acts, world (unit: m)
  Vec3 force = Vec3::Zero();       ///< on `body` (unit: N)
  double normalForce = 0.0;        ///< its part along the contact normal (unit: N)
};

/// Why a run had to stop.
class SimulationError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Counters of the last step, for logs and benchmarks.
struct StepStatistics {
  std::size_t candidatePairs = 0;   ///< broad-phase pairs (bodies and planes)
  std::size_t warmStarted = 0;      ///< constraint solver: reduced points that found their impulses of the last step
  std::size_t reusedPairs = 0;      ///< constraint solver: pairs that kept their patches (manifold reuse)
  std::size_t contactPoints = 0;    ///< engaged sample points (fdem: element-pair and face records)
  std::size_t awakeBodies = 0;      ///< dynamic bodies integrated this step
  std::size_t sampleSearches = 0;   ///< body-pair directions searched in full (near-sample lists made)
  std::size_t sampleListReuses = 0; ///< body-pair directions served from their near-sample list
  std::size_t sampleListListed = 0;  ///< listed samples in those directions
  std::size_t sampleListLookups = 0; ///< of them, those looked up (the others skipped by their value)
  double maxOverlap = 0.0;          ///< deepest penetration (unit: m)
};

class World {
public:
  explicit World(const WorldSettings& settings = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  MaterialId addMaterial(const Material& material);
  /// Add a shape from a closed mesh in its natural frame (validated by the caller). Builds the
  /// level set and the samples once; every body of the shape shares them.
  ShapeId addShape(const std::string& name, const geometry::TriangleMesh& mesh);
  BodyId addBody(const BodySpec& spec);
  void addPlane(const StaticPlane& plane);
  /// Add a static convex polyhedron: the convex hull of `corners` (world, m). Throws
  /// core::InputError naming `name` for fewer than 4 corners, flat sets or a bad material.
  void addConvex(const std::string& name, const std::vector<Vec3>& corners, MaterialId material);
  [[nodiscard]] std::size_t staticConvexCount() const { return convex_.size(); }
  [[nodiscard]] const StaticConvex& staticConvex(std::size_t k) const { return convex_[k]; }

  /// Stability limit of the explicit step from the stiffest plausible contact of each dynamic body
  /// (translation and rotation, including damping): docs/theory.md (unit: s).
  [[nodiscard]] double stableTimeStep() const;
  /// The step in use: the user's (checked against the limit) or safety x limit.
  /// Throws core::InputError if the user's step exceeds the limit, giving the limit.
  [[nodiscard]] double timeStep() const;

  /// Advance one step. Throws SimulationError (bodies named) on a non-finite state or an overlap
  /// deeper than maxOverlapPerDn x Dn.
  void step();
  /// Advance until time() >= t.
  void advanceTo(double t);

  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::uint64_t stepCount() const { return steps_; }
  [[nodiscard]] const dynamics::RigidBodies& bodies() const { return bodies_; }
  [[nodiscard]] dynamics::RigidBodies& bodies() { return bodies_; }
  [[nodiscard]] const ShapeModel& shape(ShapeId id) const { return *shapes_[id]; }
  [[nodiscard]] ShapeId bodyShape(BodyId b) const { return bodyShape_[b]; }
  [[nodiscard]] double bodyScale(BodyId b) const { return bodyScale_[b]; }
  [[nodiscard]] const Quat& bodyNaturalToBody(BodyId b) const { return shapes_[bodyShape_[b]]->naturalToBody; }
  /// The narrow phase's view of body b: its shape's contact geometry and its pose (WorldContacts.cpp).
  [[nodiscard]] contact::ContactShape contactShape(BodyId b) const;
  [[nodiscard]] contact::ContactPose contactPose(BodyId b) const;
  [[nodiscard]] const StepStatistics& lastStep() const { return stats_; }
  /// Wall time per named stage of the step, summed since the World was made or the profile reset.
  [[nodiscard]] const StepProfile& profile() const { return profile_; }
  void resetProfile() { profile_.reset(); }
  /// Engaged sample points (fdem: element-pair and face records) on body b in the last force
  /// evaluation (unit: -).
  [[nodiscard]] std::int32_t contactCount(BodyId b) const { return b < contactCount_.size() ? contactCount_[b] : 0; }
  /// Largest single-point contact force on body b in the last force evaluation (unit: N).
  [[nodiscard]] double maxContactForce(BodyId b) const { return b < maxContactForce_.size() ? maxContactForce_[b] : 0.0; }
  [[nodiscard]] const WorldSettings& settings() const { return settings_; }
  /// Orientation of the body's natural shape frame in the world (what the user gave).
  [[nodiscard]] Quat naturalOrientation(BodyId b) const;
  /// Total mechanical energy: kinetic + gravitational potential (J), contact energy excluded.
  [[nodiscard]] double mechanicalEnergy() const;
  /// Contact pairs of the last force evaluation, in pair order; empty unless
  /// settings.recordContacts (or setRecordContacts(true)).
  [[nodiscard]] const std::vector<ContactPatch>& contactPatches() const { return patches_; }
  void setRecordContacts(bool on) { settings_.recordContacts = on; }
  /// Keep the point forces of every contact on these bodies in each force evaluation
  /// (tracedContacts()); empty: none. Changes no result.
  void setTracedBodies(const std::vector<BodyId>& bodies);
  /// The point forces on the traced bodies in the last force evaluation, in pair order (penalty:
  /// each engaged sample point; constraint: each reduced point, its mean force over the last
  /// substep; fdem: each element-pair record). Pairs not examined (none of their bodies awake)
  /// are absent: their forces are those of the evaluation in which they fell asleep.
  [[nodiscard]] const std::vector<TracedContact>& tracedContacts() const { return traced_; }
  /// Evaluate the contact forces of the current state without stepping (the guard rails apply:
  /// a deep initial overlap throws SimulationError naming the bodies). For `armour check`.
  void evaluateContacts();
  /// Elastic energy of the engaged contact points in the last force evaluation (J):
  /// sum of k_point d^2 / 2 (normal springs) and k_t |s|^2 / 2 (friction springs).
  [[nodiscard]] double contactEnergy() const { return contactEnergy_; }
  /// Record work done on the bodies by loads outside the world (hydrodynamics), so the energy
  /// guard does not take it for an instability (unit: J).
  void addExternalWork(double joules) { externalWork_ += joules; }
  /// Work done on the bodies so far by load stages and addExternalWork (unit: J).
  [[nodiscard]] double externalWork() const { return externalWork_; }

  /// Add a stage of external loads (LoadStage.hpp), run after the contacts in every force
  /// evaluation, in the order added. The World shares ownership.
  void addLoadStage(std::shared_ptr<LoadStage> stage);
  [[nodiscard]] const std::vector<std::shared_ptr<LoadStage>>& loadStages() const { return loadStages_; }
  /// Sum of the load stages' force on body b in the last force evaluation (unit: N, world).
  [[nodiscard]] Vec3 externalForce(BodyId b) const { return b < externalForce_.size() ? externalForce_[b] : Vec3::Zero(); }
  /// Sum of the load stages' torque about b's centre of mass, last force evaluation (unit: N m).
  [[nodiscard]] Vec3 externalTorque(BodyId b) const { return b < externalTorque_.size() ? externalTorque_[b] : Vec3::Zero(); }

  /// Wake every sleeping body and restart its rest clock (as a run started from these positions
  /// would): a pack that only slept while creeping shows it by moving again.
  void wakeAll();

  /// Static or sleeping bodies were moved by hand (bodies().setPosition ...): recompute their
  /// boxes on the next step (awake bodies' boxes are recomputed every step anyway).
  void invalidateBoxes() { boxesValid_ = false; }

  /// Bodies were switched between static and dynamic by hand (bodies().setMotionType), e.g. the
  /// units a placement freezes while the next one settles and releases at the end: the cached
  /// forces and boxes are stale and the energy guard must take its reference again, as when a
  /// body is added (the released bodies bring their potential energy into the count).
  void motionTypesChanged();

  /// The complete dynamic state, for checkpoints (WorldState.hpp).
  [[nodiscard]] WorldState captureState() const;
  /// Continue from a captured state of a world built from the same scene. Throws
  /// core::InputError when the body count or a contact index does not fit this world.
  void restoreState(const WorldState& state);

private:
  using History = std::vector<std::pair<std::uint32_t, contact::PointHistory>>;
  using PairHistories = std::vector<std::pair<contact::BodyPair, History>>;
  [[nodiscard]] double bodyDn(BodyId b) const { return bodyDn_[b]; }
  // The stages of the step, grouped by the source file that holds them (docs/architecture.md,
  // "World's source files"); World.cpp holds the rest and step() itself.
  // WorldContacts.cpp: boxes -> broad phase -> narrow phase -> contact law -> accumulate.
  struct PairWork;
  void computeForces(double dt, double stateTime);
  /// The pair's resultant as a ContactPatch (settings.recordContacts).
  void recordPatch(const PairWork& pw, std::int32_t points);
  void updateBoxes();
  /// The fdem narrow phase and law of one pair (WorldContacts.cpp): fills pw like the level-set path.
  void fdemPairForces(PairWork& pw, double dt) const;
  /// The pair's effective mass along its contact normal at its contact centre, rotation included:
  /// 1 / (1/m_a + (r_a x n) . I_a^-1 (r_a x n) + the same for b), b absent (-1) for static geometry
  /// (rigid-body impact theory), with the centre and normal the stiffness-weighted means of the
  /// engaged points; if the normals nearly cancel (|sum k n| < 0.5 sum k, points pushing opposite
  /// ways) the masses alone (unit: kg).
  [[nodiscard]] double pairEffectiveMass(BodyId a, std::int64_t b, const contact::PatchSums& patch) const;
  /// The step the penalty law's dashpot is integrated over: dt (implicit) or 0 (explicit).
  [[nodiscard]] double dashpotStep(double dt) const {
    return settings_.dashpot == DashpotIntegration::Implicit ? dt : 0.0;
  }
  contact::ContactParameters pairParameters(MaterialId a, MaterialId b, double lengthScale) const;
  /// Candidate pairs of this step: broad-phase body pairs (convex pieces flagged), then body-plane
  /// pairs of awake bodies reaching below a plane (WorldContacts.cpp).
  void candidatePairs(std::vector<contact::BodyPair>& out);
  /// Guard rails on one pair's deepest overlap: throws SimulationError naming the bodies.
  void guardOverlap(const contact::BodyPair& key, double maxOverlap, double fdemReach) const;
  /// Pairs not examined because none of their bodies is awake keep their history (sleeping packs
  /// wake with their contacts); then history_ = next, sorted by pair.
  void keepSleepingHistory(PairHistories& next);
  /// After either solver's step: non-finite guard, sleep, energy guard (World.cpp).
  void finishStep(double dt, StepProfile::Clock::time_point clock);
  /// Body damping (WorldSettings::bodyDamping): v and omega of the awake dynamic bodies times exp(-c dt).
  void applyBodyDamping(double dt);
  // WorldConstraint.cpp: the constraint solver's step (contact.solver: constraint).
  void stepConstraint();
  struct PairManifold;
  /// Manifold reuse (WorldManifoldCache.cpp; docs/theory.md, "Manifold reuse"): a pair's reduced
  /// patches at its last full narrow phase, points in A's and B's frames, normals in B's, with A's
  /// pose in B's frame then (B static: the world).
  struct CachedManifold {
    Vec3 relP = Vec3::Zero();
    Quat relQ = Quat::Identity();
    double maxOverlap = 0.0;
    double margin = 0.0;                              ///< PairManifold::margin of its narrow phase (unit: m)
    std::vector<contact::ContactPatchPoints> patches; ///< points in A's frame, normals in B's
    std::vector<std::array<Vec3, 4>> pointsB;         ///< the same points in B's frame
    std::uint64_t stamp = 0;                          ///< the step that last used it (not saved)
  };
  /// By pairKey(key): a hash map, as the lookups of every candidate pair at every step are its
  /// cost; saved sorted by key, so checkpoints do not depend on its order.
  std::unordered_map<std::uint64_t, CachedManifold> manifoldCache_;
  [[nodiscard]] static std::uint64_t pairKey(const contact::BodyPair& key) {
    return (std::uint64_t{key.first} << 32) | key.second;
  }
  std::uint64_t manifoldCacheStamp_ = 0; ///< counts cacheManifolds calls (CachedManifold::stamp)
  /// The entries of the last cacheManifolds call in its order (findCachedManifolds walks them).
  /// Cleared with the cache. Plane pairs come last: their bit is detail::kPlaneBit of the second index.
  CacheWalk<CachedManifold> manifoldWalk_{{}, {}, std::uint64_t{0x80000000u}};
  /// Empty the cache (and its walk).
  void clearManifoldCache();
  /// entries[w]: keys[w]'s cache entry, or null.
  void findCachedManifolds(const std::vector<contact::BodyPair>& keys, std::vector<CachedManifold*>& entries);
  /// A's pose in B's frame (B static: the world).
  void relativePose(const contact::BodyPair& key, Vec3& p, Quat& q) const;
  /// m.key's cached patches moved to the current poses, if the pair has moved less than the reuse
  /// distance r since they were found and no sample left out then can touch in this step: `travel`
  /// (m, what the pair may close in it) plus r stays below the margin they were found with.
  /// turnedCos = cos(r): the turn test (computed once per narrow phase by the caller). `entry`:
  /// the pair's cache entry (findCachedManifolds), not null.
  bool reuseManifold(PairManifold& m, double travel, double turnedCos, const CachedManifold& entry) const;
  /// The cache after a narrow phase: reused pairs keep their entries, the others' are made anew.
  /// entries[w]: pair w's entry as findCachedManifolds found it (null: none).
  void cacheManifolds(const std::vector<PairManifold>& manifolds, const std::vector<char>& reused,
                      const std::vector<CachedManifold*>& entries);
  /// The constraint step's manifolds, a member so that their patch storage is reused from step to
  /// step (World.cpp, where PairManifold is complete, destroys it).
  std::vector<PairManifold> stepManifolds_;
  [[nodiscard]] std::vector<double> saveManifoldCache() const;
  void restoreManifoldCache(const std::vector<double>& flat);
  void collideConstraint(std::vector<PairManifold>& manifolds);
  void buildConstraints(std::vector<PairManifold>& manifolds, double h);
  /// One pair's constraints into constraints_.patches from patchAt and .points from pointAt (the
  /// slots buildConstraints gave it); returns how many of its points were warm-started.
  std::uint32_t buildPairConstraints(const PairManifold& m, std::uint32_t pairIndex, std::size_t patchAt,
                                     std::size_t pointAt, double h);
  void storeConstraintResults(const std::vector<PairManifold>& manifolds, double dt);
  void syncSolverBodies(bool inertia);
  void writeSolverVelocities();
  // WorldLoads.cpp: the external-load stages.
  void applyLoadStages(double time);
  [[nodiscard]] double externalPower() const;
  // WorldSleep.cpp: contact islands, sleeping and waking.
  void updateSleep(double dt);
  /// The awake bodies to put to sleep, from the pairs of movable bodies in contact:
  /// SleepScope::Island, whole islands rested long enough (union-find over the pairs);
  [[nodiscard]] std::vector<BodyId> restedIslands(const std::vector<std::pair<BodyId, BodyId>>& touching) const;
  /// SleepScope::Neighbours, bodies rested long enough that touch no restless body.
  [[nodiscard]] std::vector<BodyId> restedWithNeighbours(const std::vector<std::pair<BodyId, BodyId>>& touching) const;
  /// A sleeping body woke: restart the energy guard's reference (WorldSleep.cpp says why).
  void energyWakeReset();
  // WorldEnergy.cpp: the energy guard rail.
  void checkEnergy();

  WorldSettings settings_;
  dynamics::RigidBodies bodies_;
  std::vector<std::unique_ptr<ShapeModel>> shapes_;
  std::vector<Material> materials_;
  std::vector<contact::DampingByExponent> materialDamping_; ///< damping ratios of each material's restitution
  std::vector<StaticPlane> planes_;
  std::vector<StaticConvex> convex_;
  // Per-body cold-ish data used by the contact stages.
  std::vector<ShapeId> bodyShape_;
  std::vector<double> bodyScale_;
  std::vector<double> bodyDn_;   ///< nominal diameter: cube root of the volume (unit: m)
  std::vector<MaterialId> bodyMaterial_;
  std::vector<double> restTime_; ///< how long each body has been at rest (unit: s)
  std::vector<std::int32_t> contactCount_; ///< engaged points per body, last force evaluation
  std::vector<double> maxContactForce_;    ///< largest point force per body (unit: N)
  std::vector<geometry::Box3> boxes_;
  std::vector<std::uint8_t> active_;
  contact::BroadPhase broadPhase_;
  std::vector<contact::BodyPair> pairs_;
  // Constraint solver state (WorldConstraint.cpp): solver body 0 is the ground.
  std::vector<contact::SolverBody> solverBodies_;
  std::vector<std::int32_t> solverIndex_;          ///< body -> solver body (0: ground)
  contact::ConstraintSet constraints_;
  std::vector<std::uint32_t> constraintPair_;      ///< constraint -> manifold index
  std::size_t warmStarted_ = 0;                    ///< points of this step's constraints that found their impulses
  std::size_t reusedPairs_ = 0;                    ///< pairs of this step that kept their patches
  std::vector<Vec3> stepStartPosition_;            ///< awake bodies' x at the step start (m)
  std::vector<Quat> stepStartOrientation_;
  StepProfile profile_;
  /// Friction history per body pair (or body-plane / body-convex pair: second = flag bit | index), per
  /// sample key (direction bit | sample index), sorted by key.
  PairHistories history_; ///< sorted by pair
  /// Near-sample lists per body-body pair (key: first << 32 | second), kept while the pair stays a
  /// candidate; derived state (exact), so a restart simply makes them anew.
  struct CachedSamples {
    contact::PairSampleCache cache;
    std::uint64_t step = 0; ///< last step the pair was a candidate
  };
  std::unordered_map<std::uint64_t, CachedSamples> sampleLists_;
  /// The last step's body pairs' entries in their order (sampleListsFor walks them). Cleared with
  /// the lists (clearSampleLists).
  CacheWalk<CachedSamples> sampleWalk_;
  void clearSampleLists();
  std::vector<contact::PairSampleCache*> stepLists_; ///< this step's, per candidate pair (constraint solver)
  /// The near-sample list of each candidate pair (nullptr for static geometry, or lists off); drops
  /// the lists of pairs no longer candidates. Serial (WorldContacts.cpp).
  std::vector<contact::PairSampleCache*> sampleListsFor(const std::vector<contact::BodyPair>& keys);
  [[nodiscard]] double sampleListSlack(BodyId a, BodyId b) const {
    return settings_.sampleListSlackPerDn * std::min(bodyDn(a), bodyDn(b));
  }
  /// Adds the lists' searches and reuses of this step to stats_.
  void countSampleLists(const std::vector<contact::PairSampleCache*>& lists);
  [[nodiscard]] const History* findPairHistory(const contact::BodyPair& key) const; // WorldContacts.cpp
  mutable double cachedStep_ = -1.0;
  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  bool forcesReady_ = false;
  /// Boxes of static and sleeping bodies are computed once and kept; false forces a full update
  /// (bodies added, a restart). Moving a static body by hand needs invalidateBoxes().
  bool boxesValid_ = false;
  StepStatistics stats_;
  std::vector<ContactPatch> patches_;
  std::vector<std::uint8_t> isTraced_;  ///< per body: 1 = its contact point forces go to traced_
  std::vector<TracedContact> traced_;
  /// Whether a pair's point forces are traced (either body traced).
  [[nodiscard]] bool tracesPair(const contact::BodyPair& key) const;
  /// Append one point force of pair `key` (on A; B gets minus it) to traced_ for its traced bodies.
  void traceContact(const contact::BodyPair& key, const Vec3& point, const Vec3& forceOnA, double normalForce);
  double contactEnergy_ = 0.0;  ///< J, last force evaluation
  double externalWork_ = 0.0;   ///< J, since the start
  std::vector<std::shared_ptr<LoadStage>> loadStages_;
  std::vector<Vec3> externalForce_;  ///< N, sum of the load stages, last force evaluation
  std::vector<Vec3> externalTorque_; ///< N m
  std::vector<Vec3> stageForce_, stageTorque_; ///< scratch for one stage
  std::vector<Vec3> sleepLoad_;      ///< external force when each body fell asleep (N)
  double energyMinimum_ = 0.0;  ///< lowest E - W seen at a check (J)
  double energyPeak_ = 0.0;     ///< largest kinetic + elastic energy seen at a check (J)
  bool energyStarted_ = false;
};

} // namespace armour::simulation
