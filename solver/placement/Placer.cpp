// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/Placer.hpp"

#include "analysis/UnderlayerSurface.hpp"
#include "contact/SurfaceSamples.hpp"
#include "core/Error.hpp"
#include "core/Log.hpp"
#include "placement/Deposit.hpp"
#include "placement/Interlock.hpp"
#include "placement/PlacementGrid.hpp"
#include "placement/PlacementSupport.hpp"
#include "placement/RockLayer.hpp"
#include "simulation/Interpenetration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <memory>
#include <tuple>
#include <optional>

namespace armour::placement {
namespace {

using simulation::BodyId;
using simulation::BodySpec;
using simulation::ShapeId;
using simulation::World;
using namespace detail; // PlacementSupport.hpp
constexpr double kDeg = std::numbers::pi / 180.0;


/// The orientation of unit i (natural shape frame -> the frame of the settings: the world, or the
/// slope face's), from its own stream.
Quat unitOrientation(const OrientationSettings& o, std::mt19937_64& rng) {
  if (o.mode == OrientationMode::Random) return uniformRotation(rng);
  const Quat base = io::quaternionFromTaitBryan(o.phiDeg * kDeg, o.thetaDeg * kDeg, o.psiDeg * kDeg);
  const double max = o.maxAngleDeg * kDeg;
  const Quat aboutZ(Eigen::AngleAxisd(max * (2.0 * uniform(rng) - 1.0), Vec3::UnitZ()));
  if (o.mode == OrientationMode::Perturbed) return (aboutZ * base).normalized();
  const double azimuth = 2.0 * std::numbers::pi * uniform(rng);
  const Quat tilt(Eigen::AngleAxisd(max * uniform(rng), Vec3(std::cos(azimuth), std::sin(azimuth), 0.0)));
  return (tilt * aboutZ * base).normalized();
}

/// Index of the scene shape a placement names: a named shape, or a generator used directly
/// (added to the scene's shapes as the reader would).
std::size_t resolveShape(io::Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    if (scene.shapes[i].name == name) return i;
  io::ShapeSpec spec;
  spec.name = name;
  spec.generator = name;
  spec.seed = scene.seed;
  scene.shapes.push_back(spec);
  return scene.shapes.size() - 1;
}


/// The slope the grid lies on.
const io::StaticSlope* findSlope(const io::Scene& scene) {
  const std::string& wanted = scene.placement.slope;
  for (const io::StaticSlope& s : scene.statics.slopes)
    if (wanted.empty() || s.name == wanted) return &s;
  if (!wanted.empty())
    core::failInput(scene.sourceName, "placement.slope = {}: the scene has no slope of that name", wanted);
  return nullptr;
}

/// The y extent between the trunk walls, if both exist.
std::pair<double, double> trunkWalls(const io::Scene& scene) {
  double lo = std::nan(""), hi = std::nan("");
  for (const io::StaticWall& w : scene.statics.walls) {
    if (w.axis != 1) continue;
    (w.atMinimum ? lo : hi) = w.position;
  }
  return {lo, hi};
}

/// Total kinetic energy and mass of the awake bodies (sleeping ones are at rest by definition).
std::pair<double, double> motion(const World& world, std::size_t firstBody) {
  const auto& bodies = world.bodies();
  double ke = 0.0, mass = 0.0;
  for (BodyId b = firstBody; b < bodies.size(); ++b) {
    if (bodies.motionType(b) == dynamics::MotionType::Static) continue;
    mass += bodies.info(b).mass;
    if (bodies.isAwake(b)) ke += bodies.kineticEnergy(b);
  }
  return {ke, mass};
}

/// True when every movable body from firstBody on sleeps.
bool allAsleep(const World& world, std::size_t firstBody) {
  const auto& bodies = world.bodies();
  for (BodyId b = firstBody; b < bodies.size(); ++b)
    if (bodies.isAwake(b)) return false;
  return true;
}

/// The largest speed of a point of any awake movable body from firstBody on: |v| + |omega| r, r the
/// body's radius (unit: m/s).
double largestSpeed(const World& world, std::size_t firstBody) {
  const auto& bodies = world.bodies();
  double top = 0.0;
  for (BodyId b = firstBody; b < bodies.size(); ++b) {
    if (!bodies.isAwake(b)) continue;
    const double radius = world.shape(world.bodyShape(b)).radius * world.bodyScale(b);
    top = std::max(top, bodies.velocity(b).norm() + bodies.worldAngularVelocity(b).norm() * radius);
  }
  return top;
}

/// How a settle ended.
enum class SettleEnd {
  Rest,     ///< rms speed below restSpeed (crane, or sleeping disabled)
  Asleep,   ///< every body sleeps
  Still,    ///< untilAsleep: no point of any body faster than restSpeed for the sleep time, though an island stays awake
  TimeCap,  ///< maxTime reached
};

/// Where a settle stands: enough to continue it exactly after a checkpoint.
struct SettleClock {
  double start = 0.0;          ///< World time the settle began (unit: s)
  std::uint64_t startStep = 0; ///< World step count then (unit: -)
  double stillSince = -1.0;    ///< settle time since which no point moved faster than restSpeed; < 0: moving (unit: s)
};

/// Called at each check of a settle (every 10 ms of simulated time); true stops the placement.
using SettleSafePoint = std::function<bool(const SettleClock&)>;

/// Step until the bodies from firstBody on have an rms speed below restSpeed (after minTime),
/// or, with `untilAsleep` and sleeping enabled, until they all sleep (at rest for the sleep time)
/// or no point of any of them has moved faster than restSpeed for the sleep time (a large contact
/// island can stay awake for ever when one contact in it chatters just above the sleep speed);
/// at most maxTime. `clock` is where it stands (a new settle: {now, step count, -1}). Returns the
/// time taken and how it ended.
std::pair<double, SettleEnd> settle(World& world, std::size_t firstBody, double restSpeed, double minTime,
                                    double maxTime, bool untilAsleep, SettleClock clock,
                                    const SettleSafePoint& safePoint = {}) {
  untilAsleep = untilAsleep && world.settings().sleep.enabled;
  auto log = core::logger("place");
  auto lastReport = std::chrono::steady_clock::now();
  const double dt = world.timeStep();
  const std::uint64_t checkEvery = std::max(1L, std::lround(0.01 / dt)); // every 10 ms
  for (;;) {
    world.step();
    const double t = world.time() - clock.start;
    if ((world.stepCount() - clock.startStep) % checkEvery != 0 && t < maxTime) continue;
    const auto [ke, mass] = motion(world, firstBody);
    if (const auto now = std::chrono::steady_clock::now(); now - lastReport > std::chrono::seconds(10)) {
      lastReport = now;
      log->info("  settling: t = {:.2f} s, rms speed {:.3g} m/s, fastest point {:.3g} m/s, {} awake", t,
                std::sqrt(2.0 * ke / std::max(mass, 1e-300)), largestSpeed(world, firstBody),
                world.bodies().awakeBodies().size());
    }
    if (untilAsleep) {
      if (t >= minTime && allAsleep(world, firstBody)) return {t, SettleEnd::Asleep};
      if (largestSpeed(world, firstBody) >= restSpeed) clock.stillSince = -1.0;
      else if (clock.stillSince < 0.0) clock.stillSince = t;
      if (t >= minTime && clock.stillSince >= 0.0 && t - clock.stillSince >= world.settings().sleep.time)
        return {t, SettleEnd::Still};
    } else if (t >= minTime && ke <= 0.5 * mass * restSpeed * restSpeed) {
      return {t, SettleEnd::Rest};
    }
    if (t >= maxTime) return {t, SettleEnd::TimeCap};
    if (safePoint && safePoint(clock)) throw PlacementStopped("stopped in the final settle");
  }
}

/// The median of a non-empty list (the mean of the middle two for an even count).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// How a unit's own settle ended (settleAlone).
struct LoneSettle {
  double time = 0.0;   ///< simulated (unit: s)
  double drift = 0.0;  ///< centroid distance from where it started (unit: m)
  bool rested = false; ///< at rest (or asleep) before the cap
  bool held = false;   ///< stopped at the drift limit
};

/// The per-unit settle (SettleEachSettings): step the World with body b the only body awake (the
/// caller froze the others), its velocity and spin decaying as exp(-damping t) on top of gravity
/// and contacts, until both its centroid speed and |omega| r (r its radius) have stayed below
/// restSpeed for restTime, or it sleeps, or (with holdAtMaxDrift) its centroid is farther than
/// maxDrift from where it started, or maxTime. The cost is that of one awake body.
LoneSettle settleAlone(World& world, BodyId b, const SettleEachSettings& s, double dn) {
  auto& bodies = world.bodies();
  const double dt = world.timeStep();
  // The drag as an exact decay over the step, applied between steps: unconditionally stable and
  // it only removes energy, so the World's energy guard sees nothing unusual.
  const double decay = std::exp(-s.damping * dt);
  const double radius = world.shape(world.bodyShape(b)).radius * world.bodyScale(b);
  const Vec3 from = bodies.position(b);
  const double start = world.time();
  double still = 0.0;
  LoneSettle out;
  for (;;) {
    world.step();
    out.time = world.time() - start;
    out.drift = (bodies.position(b) - from).norm();
    if (!bodies.isAwake(b)) { // asleep: at rest by the scene's own (stricter) sleep criterion
      out.rested = true;
      break;
    }
    bodies.setVelocity(b, decay * bodies.velocity(b));
    bodies.setWorldAngularVelocity(b, decay * bodies.worldAngularVelocity(b));
    const bool slow = bodies.velocity(b).norm() < s.restSpeed &&
                      bodies.worldAngularVelocity(b).norm() * radius < s.restSpeed;
    still = slow ? still + dt : 0.0;
    if (still >= s.restTime) {
      out.rested = true;
      break;
    }
    if (s.holdAtMaxDrift && out.drift > s.maxDrift * dn) {
      out.held = true;
      break;
    }
    if (out.time >= s.maxTime) break;
  }
  return out;
}


/// A lowered unit and its cost by the orientation's `select` (lowest: its centroid's height).
struct Candidate {
  Placed u;
  Quat natural = Quat::Identity(); ///< natural shape frame -> world
  double cost = 0.0;
};

/// Where `select: keyed` measures a candidate's top: along the slope normal, from the underlayer's
/// top (the mean top of its surface stones, or the face without stones).
struct LayerBase {
  Vec3 normal = Vec3::UnitZ(); ///< the slope's outward normal in the deposit frame (unit: -)
  double offset = 0.0;         ///< normal . x of the underlayer's top, deposit frame (unit: m)
};

/// The cost of a lowered candidate under `select: keyed` (Dn): how far its highest point lies from
/// the layer's design top (`layer_thickness` above the underlayer; without one, the height of the
/// top itself: the lower the better), plus offUnderlayerCost when it touches no support (a body
/// added before the units, or a static: the slope, the toe) and unkeyedCost when it touches no
/// unit placed before it. Deposit indices are body ids: the deposit holds the World's bodies in
/// order, supports first.
double keyedCost(const Deposit& deposit, const Placed& u, std::size_t firstUnitBody, double clearance, double dn,
                 const OrientationSettings& os, const LayerBase& base) {
  const LayerContact c = layerContact(deposit, u, firstUnitBody, clearance, base.normal, base.offset);
  const double height = os.layerThickness > 0.0 ? std::abs(c.top / dn - os.layerThickness) : c.top / dn;
  return height + (c.onSupport ? 0.0 : os.offUnderlayerCost) + (c.unitsTouched > 0 ? 0.0 : os.unkeyedCost);
}


} // namespace

namespace {

/// The grid settings as `place` uses them: a generated grid starts at the first wall.
GridSettings effectiveGridSettings(const io::Scene& scene) {
  GridSettings g = scene.placement.grid;
  const auto [wallLo, wallHi] = trunkWalls(scene);
  if (g.file.empty()) {
    if (g.width <= 0.0 && std::isfinite(wallLo)) g.yStart = std::max(g.yStart, wallLo);
    if (g.yStart == 0.0 && std::isfinite(wallLo)) g.yStart = wallLo;
  }
  return g;
}

} // namespace

GridPlan planGrid(const io::Scene& scene) {
  const PlacementSettings& ps = scene.placement;
  const double dn = std::cbrt(ps.volume);
  const io::StaticSlope* slope = findSlope(scene);
  const auto [wallLo, wallHi] = trunkWalls(scene);
  GridPlan plan;
  plan.wallWidth = std::isfinite(wallLo) && std::isfinite(wallHi) ? wallHi - wallLo : 0.0;
  const GridSettings g = effectiveGridSettings(scene);
  if (!g.file.empty()) {
    plan.points = readGridFile(g.file);
    return plan;
  }
  if (slope == nullptr)
    core::failInput(scene.sourceName, "placement.grid: a generated grid lies on a slope, and the scene has none; add "
                                      "a static slope or give placement.grid.file");
  const GridSlope gridSlope{slope->origin.x(), slope->origin.y(), slope->tanAlpha};
  plan.points = generateGrid(g, gridSlope, dn, plan.wallWidth, ps.seed, scene.sourceName);
  plan.packingDensity = gridSpacing(g, dn, plan.wallWidth, scene.sourceName).packingDensity;
  // Every unit is lowered onto the face: a grid running past the crest edge puts units where the
  // placement does not hold them (seed 003's case once had 15 rows on a 30 m face; 104 units ended
  // inside the bed).
  const double crestX = slope->origin.x() + slope->crestHeight / slope->tanAlpha;
  std::size_t beyond = 0, topRow = 0;
  for (const GridPoint& p : plan.points) {
    if (p.plan.x() > crestX) {
      ++beyond;
      topRow = std::max<std::size_t>(topRow, static_cast<std::size_t>(p.row) + 1);
    }
  }
  if (beyond > 0) {
    const double face = slope->crestHeight * std::sqrt(1.0 + 1.0 / (slope->tanAlpha * slope->tanAlpha));
    core::failInput(scene.sourceName,
                    "placement.grid: {} of the {} grid points (up to row {}) lie beyond the crest edge of slope '{}' "
                    "at x = {:.3g} m, past the end of its {:.3g} m face: use fewer rows, a smaller dy or first_row, "
                    "or a higher crest_height",
                    beyond, plan.points.size(), topRow, slope->name, crestX, face);
  }
  return plan;
}

namespace {

/// One placement in progress (place() below): the scene being placed, its World, and what the
/// phases share. The phases, in order: the rock underlayer (layRocks), the units (prepareUnits,
/// then placeUnit for each grid point), the final settle (settleAll), the placed scene and its
/// summary (finish). Not copyable: the slope and the aliases point into `result`.
class PlacementRun {
public:
  PlacementRun(const io::Scene& input, const ProgressFn& progress, const PlaceOptions& options);
  PlacementRun(const PlacementRun&) = delete;
  PlacementRun& operator=(const PlacementRun&) = delete;

  void layRocks();
  void prepareUnits();
  void lowerUnits();
  void settleAll();
  PlacementResult finish();

private:
  /// The World shape of a scene shape, added on first use.
  ShapeId worldShape(std::size_t sceneShape);
  Deposit rebuildDeposit() const;
  std::pair<Vec3, double> descentStart(const GridPoint& g) const;
  PlacementProgress progressNow() const;
  void placeUnit(int i);
  std::vector<Candidate> chooseCandidates(const GridPoint& g, std::mt19937_64& rng);
  std::size_t trySettledCandidates(BodyId b, const std::vector<Candidate>& candidates, const GridPoint& g);
  /// One rock pass (RockLayer.hpp) on this placement's face, between its walls.
  void depositRocks(const RockSettings& rs, double s0, double s1,
                    const std::vector<std::pair<std::size_t, ShapeId>>& rockShapes, const std::string& key,
                    std::uint64_t salt);

  const io::Scene& input;
  const ProgressFn& progress;
  const PlaceOptions& options;
  std::shared_ptr<spdlog::logger> log;
  std::chrono::steady_clock::time_point wallStart;
  PlacementResult result;
  const PlacementProgress* resume = nullptr;
  std::vector<AddedBody> added; ///< every body placed, for checkpoints
  std::size_t unitShape = 0;
  std::size_t unitMaterial = 0;
  double dn = 0.0;              ///< the units' nominal diameter (unit: m)
  const io::StaticSlope* slope = nullptr; ///< in result.scene
  double wallLo = 0.0, wallHi = 0.0;      ///< the trunk's walls along y (unit: m)
  GridSettings gridSettings;
  GridPlan plan;
  std::size_t givenBodies = 0;
  ShapeId unitShapeId = 0;
  double unitScale = 1.0;
  double clearance = 0.0;       ///< unit: m
  std::vector<BodyId> rockBodies;
  std::size_t firstUnitBody = 0;
  bool alongNormal = false;
  Quat unitFrame = Quat::Identity();   ///< deposit -> world
  Quat toUnitFrame = Quat::Identity();
  std::optional<Deposit> staticDeposit; ///< the statics alone
  std::optional<Deposit> deposit_;      ///< the pack so far
  int total = 0;                ///< units to place
  bool settleEach = false;
  std::vector<BodyId> frozen;
  std::vector<double> settleDrifts;
  LayerBase layerBase;
  std::optional<InterlockJudge> judge; ///< select: interlocked (the unit's hull made once)
  double step = 0.0;            ///< lowering step (unit: m)
};

PlacementRun::PlacementRun(const io::Scene& input_, const ProgressFn& progress_, const PlaceOptions& options_)
    : input(input_), progress(progress_), options(options_), log(core::logger("place")),
      wallStart(std::chrono::steady_clock::now()) {
  const PlacementSettings& ps = input.placement;
  if (!ps.enabled) core::failInput(input.sourceName, "no placement block: `armour place` needs one (docs/placement.md)");
  io::Scene& scene = result.scene;
  scene = input;
  resume = options.resume;
  if (resume != nullptr && !options.dynamics)
    core::failInput(input.sourceName, "a placement without dynamics has no checkpoints to continue from");

  unitShape = resolveShape(scene, ps.shape);
  unitMaterial = resolveMaterial(scene, ps.material, "placement.material");
  dn = std::cbrt(ps.volume);
  slope = findSlope(scene);
  std::tie(wallLo, wallHi) = trunkWalls(scene);

  // Grid points first: bad grids fail before anything is built.
  gridSettings = effectiveGridSettings(scene);
  plan = planGrid(scene);
  result.summary.gridPackingDensity = plan.packingDensity;

  // The World of the scene as given (statics and any bodies already there).
  result.built = simulation::buildWorld(scene);
  scene.placement = PlacementSettings{}; // the placed scene has no placement block
  World& world = *result.built.world;
  if (resume == nullptr) {
    // The bodies the scene gives (fixed or not) must not start inside each other or the statics:
    // the units would be lowered onto them and the settle could not separate them.
    const auto overlaps = simulation::measureInterpenetration(world, result.built.planes);
    log->info("{}", simulation::describeInterpenetration(overlaps));
    simulation::refuseInterpenetration(overlaps, scene.sourceName);
  }
  givenBodies = scene.bodies.size();
  result.firstAddedBody = givenBodies;

  // Shapes: the unit's, and the rock library.
  unitShapeId = worldShape(unitShape);
  const simulation::ShapeModel& unitModel = world.shape(unitShapeId);
  unitScale = std::cbrt(ps.volume / unitModel.unitMass.volume);
  clearance = ps.clearance * dn;
}

ShapeId PlacementRun::worldShape(std::size_t sceneShape) {
  io::Scene& scene = result.scene;
  World& world = *result.built.world;
  if (result.built.shapeOfSceneShape.size() <= sceneShape) result.built.shapeOfSceneShape.resize(sceneShape + 1);
  auto& id = result.built.shapeOfSceneShape[sceneShape];
  if (!id) id = world.addShape(scene.shapes[sceneShape].name, simulation::shapeMesh(scene.shapes[sceneShape]));
  return *id;
}

// 1. The rock underlayer.
void PlacementRun::layRocks() {
  const PlacementSettings& ps = input.placement;
  io::Scene& scene = result.scene;
  World& world = *result.built.world;
  const RockSettings& rs = ps.rocks;
  if (!rs.enabled) return;
  if (slope == nullptr) core::failInput(scene.sourceName, "placement.rocks: the rocks are dropped on a slope; add one");
  std::vector<std::pair<std::size_t, ShapeId>> rockShapes;
  for (int k = 0; k < rs.shapes; ++k) {
    io::ShapeSpec spec;
    spec.name = fmt::format("rock_{:02d}", k);
    spec.generator = "rock";
    spec.seed = ps.seed * 1000 + static_cast<std::uint64_t>(k);
    scene.shapes.push_back(spec);
    result.addedShapes.push_back(spec);
    rockShapes.emplace_back(scene.shapes.size() - 1, worldShape(scene.shapes.size() - 1));
  }
  // Rocks cover the face from the toe (toeLength offshore of the origin) to sEnd, between the walls.
  const std::vector<GridPoint>& grid = plan.points;
  const double rows = grid.empty() ? 0.0 : std::max_element(grid.begin(), grid.end(), [](auto& a, auto& b) {
                                               return a.s < b.s;
                                             })->s;
  depositRocks(rs, -rs.toeLength, rs.sEnd > 0.0 ? rs.sEnd : rows + dn, rockShapes, "rocks", 0x726f636bULL);
  // Then the toe berm, on the underlayer in front of the first row (its rocks are supports too).
  if (ps.toeBerm.enabled)
    depositRocks(ps.toeBerm, -ps.toeBerm.toeLength, ps.toeBerm.sEnd, rockShapes, "toe_berm", 0x6265726dULL);
  if (resume != nullptr) {
    // The rocks of the checkpoint, as they were laid (their poses come with the World's state).
    for (const AddedBody& r : resume->bodies) {
      if (!r.fixed) continue;
      BodySpec spec;
      spec.name = r.name;
      spec.shape = worldShape(r.sceneShape);
      spec.scale = r.scale;
      spec.material = static_cast<simulation::MaterialId>(r.material);
      spec.fixed = true;
      spec.position = resume->world.bodies.at(world.bodies().size()).position;
      rockBodies.push_back(world.addBody(spec));
      added.push_back(r);
    }
  }
  result.summary.rocks = static_cast<int>(rockBodies.size());
}

void PlacementRun::depositRocks(const RockSettings& rs, double s0, double s1,
                                const std::vector<std::pair<std::size_t, ShapeId>>& rockShapes, const std::string& key,
                                std::uint64_t salt) {
  RockSite site;
  site.slope = slope;
  site.y0 = std::isfinite(wallLo) ? wallLo : gridSettings.yStart;
  site.y1 = std::isfinite(wallHi) ? wallHi : site.y0 + (gridSettings.width > 0 ? gridSettings.width : plan.wallWidth);
  site.unitDn = dn;
  site.seed = input.placement.seed;
  site.unitMaterial = input.placement.material;
  site.resuming = resume != nullptr;
  placement::depositRocks(result.built, result.scene, site, {&rs, s0, s1, key, salt}, rockShapes, rockBodies, added,
                          *log);
}

Deposit PlacementRun::rebuildDeposit() const {
  const World& world = *result.built.world;
  Deposit d = *staticDeposit;
  for (BodyId b = 0; b < world.bodies().size(); ++b) addWorldBody(d, world, b, toUnitFrame);
  return d;
}

// Where unit i starts its descent, in the deposit frame: its grid point (on the face, or at the
// grid file's height) and the height to lower from.
std::pair<Vec3, double> PlacementRun::descentStart(const GridPoint& g) const {
    if (!alongNormal) return {Vec3(g.plan.x(), g.plan.y(), 0.0), g.startZ ? *g.startZ : Deposit::kAbove};
    const double faceZ = slope->origin.y() + std::max(0.0, g.plan.x() - slope->origin.x()) * slope->tanAlpha;
    const Vec3 p = toUnitFrame * Vec3(g.plan.x(), g.plan.y(), g.startZ ? *g.startZ : faceZ);
    return {Vec3(p.x(), p.y(), 0.0), g.startZ ? p.z() : Deposit::kAbove};
}

// The progress at a safe point (PlacementProgress): the bodies, records and counts so far and
// the World's state; the caller fills in the stage.
PlacementProgress PlacementRun::progressNow() const {
  const World& world = *result.built.world;
    PlacementProgress p;
    p.unitsDone = static_cast<int>(result.units.size());
    p.bodies = added;
    p.units = result.units;
    p.frozen.assign(frozen.begin(), frozen.end());
    p.settleDrifts = settleDrifts;
    p.summary.cappedUnits = result.summary.cappedUnits;
    p.summary.settleCappedUnits = result.summary.settleCappedUnits;
    p.summary.drifted = result.summary.drifted;
    p.wallSeconds = (resume != nullptr ? resume->wallSeconds : 0.0) +
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    p.world = world.captureState();
    return p;
}

void PlacementRun::prepareUnits() {
  const PlacementSettings& ps = input.placement;
  io::Scene& scene = result.scene;
  World& world = *result.built.world;
  const std::vector<GridPoint>& grid = plan.points;
  const simulation::ShapeModel& unitModel = world.shape(unitShapeId);
  // 2. The units, lowered vertically (world frame) or along the slope normal (the deposit works
  // in the slope frame, so a unit lands on the face at its grid point's up-slope distance s
  // instead of h tan(alpha) further up, h its centroid's height above the face).
  firstUnitBody = world.bodies().size();
  alongNormal = ps.lowering == Lowering::SlopeNormal;
  if (alongNormal && slope == nullptr)
    core::failInput(scene.sourceName, "placement.lowering = slope_normal needs a slope; add one or use vertical");
  unitFrame = alongNormal ? slopeFrame(slope->tanAlpha) : Quat::Identity(); // deposit -> world
  toUnitFrame = unitFrame.conjugate();
  // The statics once (their convex hulls take a while for a rough face), then a copy per rebuild.
  staticDeposit.emplace(
      makeDeposit(result.built, toUnitFrame, 2.0 * std::max(unitModel.radius * unitScale, 0.5 * dn)));
  if (resume != nullptr) {
    // The units of the checkpoint, then the World's state over all: poses, velocities, contacts'
    // friction springs, rest timers, time and step count as they were.
    for (const AddedBody& u : resume->bodies) {
      if (u.fixed) continue;
      BodySpec spec;
      spec.name = u.name;
      spec.shape = unitShapeId;
      spec.scale = u.scale;
      spec.material = static_cast<simulation::MaterialId>(u.material);
      spec.position = resume->world.bodies.at(world.bodies().size()).position;
      world.addBody(spec);
      added.push_back(u);
    }
    if (world.bodies().size() != resume->world.bodies.size())
      core::failInput(scene.sourceName, "the checkpoint holds {} bodies but its placement record names {}: start the "
                                        "placement anew without --restart", resume->world.bodies.size(),
                      world.bodies().size());
    for (BodyId b = 0; b < world.bodies().size(); ++b)
      if (resume->world.bodies[b].motion == dynamics::MotionType::Static)
        world.bodies().setMotionType(b, dynamics::MotionType::Static);
    world.restoreState(resume->world);
    for (BodyId b : rockBodies) {
      const AddedBody& r = added[b - givenBodies];
      scene.bodies.push_back(sceneBody(world, b, r.name, r.sceneShape, r.material, r.volume, true));
    }
    log->info("continuing from the checkpoint: {} rocks and {} units placed, t = {:.3f} s{}", rockBodies.size(),
              resume->unitsDone, world.time(), resume->finalSettle ? ", in the final settle" : "");
  }
  deposit_.emplace(rebuildDeposit());
  total = static_cast<int>(grid.size());
  // settle_each: every movable body but the one settling is held fixed (Static) until the final
  // release; the scene's own movable bodies too, so one body is awake at a time.
  settleEach = ps.settleEach.enabled && options.dynamics;
  if (resume != nullptr) {
    frozen.assign(resume->frozen.begin(), resume->frozen.end());
  } else if (settleEach) {
    for (BodyId b = 0; b < firstUnitBody; ++b) {
      if (world.bodies().motionType(b) == dynamics::MotionType::Static) continue;
      world.bodies().setMotionType(b, dynamics::MotionType::Static);
      frozen.push_back(b);
    }
  }
  if (resume != nullptr) {
    settleDrifts = resume->settleDrifts;
    result.units = resume->units;
    result.summary.cappedUnits = resume->summary.cappedUnits;
    result.summary.settleCappedUnits = resume->summary.settleCappedUnits;
    result.summary.drifted = resume->summary.drifted;
  }
  // select: keyed and interlocked measure tops from the underlayer's: the mean top of the rocks' surface stones
  // (here, after a restart has restored the rocks' poses).
  if (ps.orientation.select != OrientationSelect::Lowest) {
    const Vec3 origin = slope != nullptr ? Vec3(slope->origin.x(), 0.0, slope->origin.y()) : Vec3::Zero();
    const analysis::SlopeFrame frame = analysis::SlopeFrame::fromTanAlpha(slope != nullptr ? slope->tanAlpha : 0.0, origin);
    std::vector<analysis::PosedMesh> rocks;
    for (BodyId b : rockBodies)
      rocks.push_back({&world.shape(world.bodyShape(b)).mesh, world.bodyScale(b), world.bodies().position(b),
                       world.bodies().orientation(b)});
    const double inf = std::numeric_limits<double>::infinity();
    const double top = analysis::meanTopIn(analysis::surfaceStones(rocks, frame), {-inf, inf, -inf, inf});
    layerBase.normal = toUnitFrame * frame.normal;
    layerBase.offset = frame.normal.dot(origin) + top;
  }
  if (ps.orientation.select == OrientationSelect::Interlocked)
    judge.emplace(*deposit_, world.shape(unitShapeId), firstUnitBody, clearance, dn, ps.orientation, layerBase.normal,
                  layerBase.offset);
  step = 0.05 * dn;
}

void PlacementRun::lowerUnits() {
  for (int i = resume != nullptr ? resume->unitsDone : 0; i < total; ++i) placeUnit(i);
}

/// The best lowered candidate of a unit at grid point g by the orientation's `select`, nested
/// when `nest:` is on; with `interlocked`, the best `settle_candidates` of them, best first, each
/// nested. Empty if none fits. Draws from the unit's own stream.
std::vector<Candidate> PlacementRun::chooseCandidates(const GridPoint& g, std::mt19937_64& rng) {
  const PlacementSettings& ps = input.placement;
  const OrientationSettings& os = ps.orientation;
  const simulation::ShapeModel& unitModel = result.built.world->shape(unitShapeId);
  Deposit& deposit = *deposit_;
  const bool keyed = os.select == OrientationSelect::Keyed;
  const bool interlocked = os.select == OrientationSelect::Interlocked;
  const auto [start, startZ] = descentStart(g);
  // Work a lowered unit into the hole below its grid point; the tilt of the slide turns its
  // natural frame too (world axes: the deposit is not rotated for the units).
  // Keyed and interlocked: the slide keeps the moves that lower the rule's cost, not the centroid.
  std::function<double(const Placed&)> cost;
  if (keyed)
    cost = [&](const Placed& u) { return keyedCost(deposit, u, firstUnitBody, clearance, dn, os, layerBase); };
  if (interlocked) cost = [&](const Placed& u) { return judge->score(u, start).cost; };
  const auto nestUnit = [&](Placed& u, Quat& natural) {
    const Mat3 before = u.R;
    deposit.slideDown(u, ps.nest.moves, ps.nest.shift * dn, ps.nest.tiltDeg * kDeg, step, clearance, rng,
                      ps.nest.maxDrift * dn, ps.nest.shift * dn, cost, step / dn);
    natural = (unitFrame * Quat(Mat3(u.R * before.transpose())) * toUnitFrame * natural).normalized();
  };
  const auto unitAt = [&](const Quat& natural, const Vec3& x) {
    Placed u;
    u.shape = &unitModel;
    u.scale = unitScale;
    u.R = (toUnitFrame * natural * unitModel.naturalToBody.conjugate()).toRotationMatrix();
    u.radius = unitModel.radius * unitScale;
    u.x = x;
    return u;
  };
  const std::size_t keep = interlocked ? static_cast<std::size_t>(std::max(1, os.settleCandidates)) : 1;
  std::vector<Candidate> kept; // the best `keep` so far, best first (ties: the earlier)
  const auto consider = [&](const Placed& u, const Quat& natural, double c) {
    if (kept.size() == keep && c >= kept.back().cost) return;
    auto at = std::upper_bound(kept.begin(), kept.end(), c, [](double v, const Candidate& k) { return v < k.cost; });
    kept.insert(at, Candidate{u, natural, c});
    if (kept.size() > keep) kept.pop_back();
  };
  // In the slope frame, z is the face's outward normal: a rotation about y by -alpha takes it there.
  const Quat frame = os.slopeFrame && slope != nullptr ? slopeFrame(slope->tanAlpha) : Quat::Identity();
  for (int t = 0; t < std::max(1, os.tries) * 4 && !(!kept.empty() && t >= os.tries); ++t) {
    Quat natural = (frame * unitOrientation(os, rng)).normalized();
    if (interlocked) {
      // The grid point, then `offsets` shifts uniform in a disc along the face (the deposit's
      // x-y plane: normal to the lowering), each lowered from above to its first touch.
      for (int k = 0; k <= os.offsets; ++k) {
        const double r = k == 0 ? 0.0 : os.offsetRadius * dn * std::sqrt(uniform(rng));
        const double a = 2.0 * std::numbers::pi * uniform(rng);
        Placed u = unitAt(natural, start + Vec3(r * std::cos(a), r * std::sin(a), 0.0));
        if (deposit.lower(u, step, clearance, startZ)) consider(u, natural, cost(u));
      }
      continue;
    }
    Placed u = unitAt(natural, start);
    if (!deposit.lower(u, step, clearance, startZ)) continue;
    // Keyed: each candidate is nested before it is judged, as the operator judges a unit where
    // it settles into the hole, not where it first touched.
    if (keyed && ps.nest.enabled) nestUnit(u, natural);
    consider(u, natural, keyed ? cost(u) : u.x.z());
  }
  // Lowest and interlocked: the chosen ones are worked into their holes (interlocked by its cost).
  if (ps.nest.enabled && !keyed) {
    for (Candidate& c : kept) {
      nestUnit(c.u, c.natural);
      if (interlocked) c.cost = cost(c.u);
    }
    std::stable_sort(kept.begin(), kept.end(), [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  }
  if (!kept.empty() && interlocked) {
    const InterlockScore sc = judge->score(kept.front().u, start);
    log->debug("  interlocked: cost {:.3f}, top {:.3f} Dn, centroid {:.3f} Dn, {} units touched, {}, envelope {:.3f}",
               sc.cost, sc.top, sc.centroid, sc.unitsTouched, sc.onSupport ? "on the underlayer" : "off it",
               sc.envelopeShare);
  }
  return kept;
}

/// `settle_candidates`: each candidate (best first) is added as body b's pose to the state
/// captured with the first, settled alone, and judged where it rests; the best at rest is then
/// settled again from the same state (the same steps: the same rest) and kept. Returns its index.
std::size_t PlacementRun::trySettledCandidates(BodyId b, const std::vector<Candidate>& candidates, const GridPoint& g) {
  World& world = *result.built.world;
  const PlacementSettings& ps = input.placement;
  const simulation::WorldState first = world.captureState();
  const Quat firstBody = world.bodies().orientation(b);
  const auto start = [&](std::size_t k) {
    simulation::WorldState s = first;
    // Body orientation of candidate k: its natural one turned as the first's natural one is.
    s.bodies[b].orientation = (candidates[k].natural * candidates[0].natural.conjugate() * firstBody).normalized();
    s.bodies[b].position = unitFrame * candidates[k].u.x;
    world.restoreState(s);
    world.invalidateBoxes();
  };
  const Vec3 gridPoint = descentStart(g).first;
  std::size_t best = 0;
  double bestCost = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    start(k);
    const LoneSettle lone = settleAlone(world, b, ps.settleEach, dn);
    Placed u = candidates[k].u;
    u.x = toUnitFrame * world.bodies().position(b);
    u.R = (toUnitFrame * world.bodies().orientation(b)).toRotationMatrix();
    const double c = judge->score(u, gridPoint).cost + (lone.rested ? 0.0 : ps.orientation.stackedCost);
    log->debug("  candidate {}: cost {:.3f} at first touch, {:.3f} at rest", k, candidates[k].cost, c);
    if (c < bestCost) {
      bestCost = c;
      best = k;
    }
  }
  start(best);
  return best;
}

/// Unit i: lowered at its grid point in the best of its trial orientations, nested, then settled
/// as the method says; a safe point after it.
void PlacementRun::placeUnit(int i) {
  const PlacementSettings& ps = input.placement;
  const io::Scene& scene = result.scene;
  World& world = *result.built.world;
  const std::vector<GridPoint>& grid = plan.points;
  Deposit& deposit = *deposit_;
  const GridPoint& g = grid[static_cast<std::size_t>(i)];
  std::mt19937_64 rng = stream(ps.seed, static_cast<std::uint64_t>(i));
  const std::string name = fmt::format("{}_{:04d}", ps.namePrefix, i);
  const std::vector<Candidate> candidates = chooseCandidates(g, rng);
  if (candidates.empty())
    core::failInput(scene.sourceName, "{}: grid point {} ({:.3f}, {:.3f}) m: the unit fits nowhere on this vertical "
                                      "(between the walls, or blocked where it starts); move the point or the walls",
                    name, i, g.plan.x(), g.plan.y());
  const Placed& best = candidates.front().u;
  const Quat& bestNatural = candidates.front().natural;
  BodySpec spec;
  spec.name = name;
  spec.shape = unitShapeId;
  spec.scale = unitScale;
  spec.material = static_cast<simulation::MaterialId>(unitMaterial);
  spec.position = unitFrame * best.x;
  spec.orientation = bestNatural;
  UnitRecord rec;
  rec.name = name;
  rec.gridPoint = spec.position;
  rec.releaseOrientation = bestNatural;
  rec.releaseTime = world.time();
  rec.touchPoint = spec.position;
  if (settleEach) {
    // Its own settle, everything else fixed, then frozen where it rests: the next unit is
    // lowered onto it as it lies.
    if (ps.method == Method::Crane) spec.velocity = unitFrame * Vec3(0.0, 0.0, -ps.crane.speed);
    rec.body = world.addBody(spec);
    if (candidates.size() > 1) rec.touchPoint = unitFrame * candidates[trySettledCandidates(rec.body, candidates, g)].u.x;
    const LoneSettle lone = settleAlone(world, rec.body, ps.settleEach, dn);
    world.bodies().setMotionType(rec.body, dynamics::MotionType::Static);
    frozen.push_back(rec.body);
    rec.gridPoint = world.bodies().position(rec.body);
    rec.releaseOrientation = world.naturalOrientation(rec.body).normalized();
    rec.restTime = lone.time;
    rec.capped = !lone.rested;
    rec.settleDrift = lone.drift / dn;
    settleDrifts.push_back(rec.settleDrift);
    if (!lone.rested) ++result.summary.settleCappedUnits;
    if (rec.settleDrift > ps.settleEach.maxDrift) result.summary.drifted.push_back(name);
    log->debug("{}: own settle {:.3f} s, {}, drift {:.3f} Dn", name, lone.time,
               lone.rested ? "at rest" : (lone.held ? "held at max drift" : "time cap"), rec.settleDrift);
    addWorldBody(deposit, world, rec.body, toUnitFrame);
  } else if (ps.method == Method::Crane && options.dynamics) {
    spec.velocity = unitFrame * Vec3(0.0, 0.0, -ps.crane.speed); // along the lowering direction
    rec.body = world.addBody(spec);
    const auto [t, end] = settle(world, firstUnitBody, ps.crane.restSpeed, ps.crane.minTime, ps.crane.maxTime,
                                 false, {world.time(), world.stepCount(), -1.0});
    rec.restTime = t;
    rec.capped = end == SettleEnd::TimeCap;
    if (rec.capped) ++result.summary.cappedUnits;
    deposit = rebuildDeposit(); // the pack as it now lies
  } else {
    rec.body = world.addBody(spec);
    deposit.add(best);
  }
  result.units.push_back(rec);
  added.push_back({name, unitShape, unitScale, unitMaterial, ps.volume, false});
  if (progress) progress(i + 1, total, world.time());
  // Safe points where the World alone says where the placement stands (method grid without
  // settle_each keeps its geometric deposit, which is not in a checkpoint: it has none until
  // the final settle, and its units cost no simulation).
  if (options.dynamics && (settleEach || ps.method == Method::Crane) && options.safePoint &&
      options.safePoint([this] { return progressNow(); }))
    throw PlacementStopped(fmt::format("stopped after {} of {} units", i + 1, total));
}

void PlacementRun::settleAll() {
  const PlacementSettings& ps = input.placement;
  World& world = *result.built.world;
  // 3. Settle: until every unit sleeps (or no point of any unit moves faster than the rest speed
  // for the sleep time), then wake them all and again, until a round moves no unit by more than
  // kCreep: a unit that fell asleep while creeping down the face moves on when woken, as it would
  // when the placed scene is run.
  constexpr double kCreep = 1.0e-4; // m: a tenth of the 1 mm a pack at rest may drift in 60 s
  const bool resumeSettle = resume != nullptr && resume->finalSettle;
  if (settleEach && !resumeSettle) {
    // The final release: every unit (and movable scene body) from where its own settle left it.
    for (BodyId b : frozen) world.bodies().setMotionType(b, dynamics::MotionType::Dynamic);
    world.motionTypesChanged();
    frozen.clear();
    for (UnitRecord& u : result.units) u.releaseTime = world.time();
  }
  if (settleEach) {
    if (!settleDrifts.empty()) {
      result.summary.medianSettleDriftDn = median(settleDrifts);
    }
    log->info("units settled one by one: {} frozen before they rested, {} drifted more than {} Dn, median drift "
              "{:.3f} Dn", result.summary.settleCappedUnits, result.summary.drifted.size(), ps.settleEach.maxDrift,
              result.summary.medianSettleDriftDn);
  }
  const double settleStart = resumeSettle ? resume->settleStart : world.time();
  bool rest = false;
  for (int round = resumeSettle ? resume->round : 0;
       options.dynamics && world.time() - settleStart < ps.settle.maxTime; ++round) {
    std::vector<Vec3> before;
    SettleClock clock{world.time(), world.stepCount(), -1.0};
    if (resumeSettle && round == resume->round) {
      before = resume->roundBefore;
      clock = {resume->roundStart, resume->roundStartStep, resume->stillSince};
    } else {
      for (const UnitRecord& u : result.units) before.push_back(world.bodies().position(u.body));
      if (round > 0) world.wakeAll();
    }
    const double left = ps.settle.maxTime - (clock.start - settleStart);
    const SettleSafePoint safePoint = [&](const SettleClock& c) {
      if (!options.safePoint) return false;
      return options.safePoint([&]() {
        PlacementProgress p = progressNow();
        p.finalSettle = true;
        p.round = round;
        p.settleStart = settleStart;
        p.roundStart = c.start;
        p.roundStartStep = c.startStep;
        p.stillSince = c.stillSince;
        p.roundBefore = before;
        return p;
      });
    };
    const auto [t, end] = settle(world, firstUnitBody, ps.settle.restSpeed, round == 0 ? ps.settle.minTime : 0.0,
                                 left, true, clock, safePoint);
    double creep = 0.0;
    for (std::size_t k = 0; k < result.units.size(); ++k)
      creep = std::max(creep, (world.bodies().position(result.units[k].body) - before[k]).norm());
    log->info("settling round {}: {:.2f} s, largest move {:.3g} m, {}", round + 1, t, creep,
              end == SettleEnd::Asleep ? "all asleep"
              : end == SettleEnd::Still ? fmt::format("no point faster than {} m/s for {} s", ps.settle.restSpeed,
                                                      world.settings().sleep.time)
              : end == SettleEnd::Rest  ? "rms speed below the rest speed"
                                        : "time cap");
    if (end == SettleEnd::TimeCap) break;
    if (round > 0 && creep < kCreep) {
      rest = true;
      break;
    }
  }
  if (options.dynamics)
    log->info("settled {} after {:.2f} s", rest ? "to rest" : "(time cap reached)", world.time() - settleStart);
}

PlacementResult PlacementRun::finish() {
  const PlacementSettings& ps = input.placement;
  io::Scene& scene = result.scene;
  World& world = *result.built.world;
  const std::vector<GridPoint>& grid = plan.points;
  const double wallWidth = plan.wallWidth;
  // The placed scene: the units where they lie.
  for (const UnitRecord& u : result.units)
    scene.bodies.push_back(sceneBody(world, u.body, u.name, unitShape, unitMaterial, ps.volume, false));
  const auto& bodies = world.bodies();
  std::vector<double> moves;
  for (const UnitRecord& u : result.units) {
    const double moved = (bodies.position(u.body) - u.gridPoint).norm() / dn;
    moves.push_back(moved);
    result.summary.maxDisplacementDn = std::max(result.summary.maxDisplacementDn, moved);
    if (moved > 1.0) result.summary.moved.push_back(u.name);
    const double speed = bodies.velocity(u.body).norm();
    if (bodies.isAwake(u.body) && speed > ps.settle.restSpeed) result.summary.moving.push_back(u.name);
  }
  if (!moves.empty()) {
    result.summary.medianDisplacementDn = median(moves);
  }

  // Summary measures over the window of the rows.
  PlacementSummary& sm = result.summary;
  sm.units = total;
  sm.dn = dn;
  sm.simulatedTime = world.time();
  if (slope != nullptr && gridSettings.file.empty()) {
    const Vec3 origin(slope->origin.x(), 0.0, slope->origin.y());
    double s0 = std::numeric_limits<double>::infinity(), s1 = -s0;
    for (const GridPoint& g : grid) {
      s0 = std::min(s0, g.s);
      s1 = std::max(s1, g.s);
    }
    const GridSpacing spacing = gridSpacing(gridSettings, dn, wallWidth, scene.sourceName);
    // Each row owns a band dy wide about its centre line: the window of n rows is n dy wide, and
    // a grid whose units stay put has exactly its own packing density there.
    s0 -= 0.5 * spacing.dy;
    s1 += 0.5 * spacing.dy;
    sm.windowArea = (s1 - s0) * spacing.width;
    // The layer's top: the units' mean top; its base: the mean top of the rocks' surface stones
    // (analysis/UnderlayerSurface, as armour analyse measures it), both in the window.
    const analysis::SlopeFrame frame = analysis::SlopeFrame::fromTanAlpha(slope->tanAlpha, origin);
    const analysis::SlopeWindow window{s0, s1, -std::numeric_limits<double>::infinity(),
                                       std::numeric_limits<double>::infinity()};
    const auto posed = [&](BodyId b) {
      return analysis::PosedMesh{&world.shape(world.bodyShape(b)).mesh, world.bodyScale(b), bodies.position(b),
                                 bodies.orientation(b)};
    };
    std::vector<analysis::PosedMesh> units, rocks;
    for (const UnitRecord& u : result.units) units.push_back(posed(u.body));
    for (BodyId b : rockBodies) rocks.push_back(posed(b));
    const analysis::SurfaceStones unitTops = analysis::surfaceStones(units, frame);
    double unitTop = 0.0;
    for (std::size_t k = 0; k < units.size(); ++k) {
      if (!window.containsLocal(unitTops.local[k])) continue;
      ++sm.windowUnits;
      unitTop += unitTops.top[k];
    }
    const double rockTop = analysis::meanTopIn(analysis::surfaceStones(rocks, frame), window);
    if (sm.windowUnits > 0 && sm.windowArea > 0.0) {
      sm.packingDensity = sm.windowUnits * dn * dn / sm.windowArea;
      sm.layerThickness = unitTop / sm.windowUnits - rockTop;
      if (sm.layerThickness > 0.0)
        sm.porosity = 1.0 - sm.windowUnits * ps.volume / (sm.windowArea * sm.layerThickness);
    }
  }
  sm.wallSeconds = (resume != nullptr ? resume->wallSeconds : 0.0) +
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  return std::move(result);
}

} // namespace

PlacementResult place(const io::Scene& input, const ProgressFn& progress, const PlaceOptions& options) {
  PlacementRun run(input, progress, options);
  run.layRocks();
  run.prepareUnits();
  run.lowerUnits();
  run.settleAll();
  return run.finish();
}

} // namespace armour::placement
