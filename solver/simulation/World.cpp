// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/World.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"
#include "dynamics/Integrator.hpp"
#include "geometry/ConvexHull.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <span>

namespace armour::simulation {
namespace {

constexpr std::uint32_t kPlaneBit = 0x80000000u;  ///< second pair index of a body-plane pair
constexpr std::uint32_t kConvexBit = 0x40000000u; ///< second pair index of a body-convex pair
constexpr std::uint32_t kStaticBits = kPlaneBit | kConvexBit;
constexpr std::uint32_t kReverseBit = 0x80000000u; ///< sample key: B's samples in A

/// One engaged sample point before the law is applied.
struct Engaged {
  std::uint32_t key;  ///< direction bit | sample index
  Vec3 point;         ///< world position (m)
  Vec3 normal;        ///< pushes the probe body (unit)
  double depth;       ///< m
  double area;        ///< m^2
};


const contact::PointHistory* findHistory(const std::vector<std::pair<std::uint32_t, contact::PointHistory>>* h,
                                         std::uint32_t key) {
  if (h == nullptr) {
    return nullptr;
  }
  auto it = std::lower_bound(h->begin(), h->end(), key, [](const auto& e, std::uint32_t k) { return e.first < k; });
  return it != h->end() && it->first == key ? &it->second : nullptr;
}

constexpr int kBuckets = SampleBuckets::kCells;

std::array<int, 3> bucketOf(const SampleBuckets& b, const Vec3& p) {
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k) {
    c[k] = std::clamp(static_cast<int>(std::floor((p[k] - b.origin[k]) / b.cell[k])), 0, kBuckets - 1);
  }
  return c;
}

/// Counting sort of the samples into buckets.
void buildBuckets(ShapeModel& shape) {
  SampleBuckets& b = shape.buckets;
  const geometry::Box3 box = shape.bounds;
  b.origin = box.min;
  b.cell = (box.size() / kBuckets).cwiseMax(Vec3::Constant(1e-12));
  const auto& positions = shape.samples->positions();
  std::vector<std::uint32_t> cellOf(positions.size());
  b.start.assign(kBuckets * kBuckets * kBuckets + 1, 0);
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    const auto c = bucketOf(b, positions[i]);
    cellOf[i] = static_cast<std::uint32_t>(c[0] + kBuckets * (c[1] + kBuckets * c[2]));
    ++b.start[cellOf[i] + 1];
  }
  for (std::size_t k = 1; k < b.start.size(); ++k) {
    b.start[k] += b.start[k - 1];
  }
  b.samples.resize(positions.size());
  std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    b.samples[fill[cellOf[i]]++] = i;
  }
  // A sphere around each bucket's samples: surface samples fill a thin patch of their bucket, so
  // the sphere is the tighter bound for culling a whole bucket against another body's level set.
  const int cells = kBuckets * kBuckets * kBuckets;
  b.sphereCentre.assign(cells, Vec3::Zero());
  b.sphereRadius.assign(cells, 0.0);
  for (int c = 0; c < cells; ++c) {
    if (b.start[c] == b.start[c + 1]) {
      continue;
    }
    geometry::Box3 tight;
    for (std::uint32_t j = b.start[c]; j < b.start[c + 1]; ++j) {
      tight.extend(positions[b.samples[j]]);
    }
    b.sphereCentre[c] = tight.centre();
    for (std::uint32_t j = b.start[c]; j < b.start[c + 1]; ++j) {
      b.sphereRadius[c] = std::max(b.sphereRadius[c], (positions[b.samples[j]] - tight.centre()).norm());
    }
  }
}

/// Call f(cell, lowCorner) for every non-empty bucket of `shape` that overlaps the local box
/// [lo, hi] (body frame of the shape, unscaled).
template <typename F>
void forBucketsNear(const ShapeModel& shape, const Vec3& lo, const Vec3& hi, F&& f) {
  const SampleBuckets& b = shape.buckets;
  if ((hi.array() < shape.bounds.min.array()).any() || (lo.array() > shape.bounds.max.array()).any()) {
    return;
  }
  const auto c0 = bucketOf(b, lo);
  const auto c1 = bucketOf(b, hi);
  for (int z = c0[2]; z <= c1[2]; ++z) {
    for (int y = c0[1]; y <= c1[1]; ++y) {
      for (int x = c0[0]; x <= c1[0]; ++x) {
        const int cell = x + kBuckets * (y + kBuckets * z);
        if (b.start[cell] != b.start[cell + 1]) {
          f(cell, Vec3(b.origin + b.cell.cwiseProduct(Vec3(x, y, z))));
        }
      }
    }
  }
}

} // namespace

/// What one candidate pair produces in the force stage: written by one thread, read serially.
struct World::PairWork {
  contact::BodyPair key;
  Vec3 forceA = Vec3::Zero(), torqueA = Vec3::Zero();
  Vec3 forceB = Vec3::Zero(), torqueB = Vec3::Zero();
  History history;
  double maxPointForce = 0.0;
  double maxOverlap = 0.0;
  double elasticEnergy = 0.0; ///< J
  Vec3 weightedPoint = Vec3::Zero(); ///< sum of normal force x point (N m)
  Vec3 pointSum = Vec3::Zero();      ///< sum of the points (m)
  double normalForce = 0.0;          ///< sum of normal forces (N)
};

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
  materialDamping_.push_back(contact::dampingRatioFromRestitution(m.restitution));
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
  buildBuckets(*model);
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

contact::ContactParameters World::pairParameters(MaterialId a, MaterialId b, double lengthScale) const {
  const Material& ma = materials_[a];
  const Material& mb = materials_[b];
  contact::ContactParameters p;
  p.penaltyModulus = std::min(ma.penaltyModulus, mb.penaltyModulus);
  p.lengthScale = lengthScale;
  p.frictionStatic = std::min(ma.frictionStatic, mb.frictionStatic);
  p.frictionDynamic = std::min(ma.frictionDynamic, mb.frictionDynamic);
  p.dampingRatio = std::max(materialDamping_[a], materialDamping_[b]); // the smaller restitution
  p.tangentialStiffnessRatio = std::min(ma.tangentialStiffnessRatio, mb.tangentialStiffnessRatio);
  return p;
}

double World::stableTimeStep() const {
  double limit = std::numeric_limits<double>::infinity();
  double maxModulus = 0.0, maxZeta = 0.0;
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    maxModulus = std::max(maxModulus, materials_[i].penaltyModulus);
    maxZeta = std::max(maxZeta, materialDamping_[i]);
  }
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
    // Central difference with viscous damping: dt < (2 / omega)(sqrt(1 + zeta^2) - zeta).
    limit = std::min(limit, 2.0 / omega * (std::sqrt(1.0 + maxZeta * maxZeta) - maxZeta));
  }
  return limit;
}

double World::timeStep() const {
  if (cachedStep_ > 0.0) {
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

void World::updateBoxes() {
  const std::size_t n = bodies_.size();
  const auto boxOf = [&](BodyId b) {
    const ShapeModel& shape = *shapes_[bodyShape_[b]];
    const double s = bodyScale_[b];
    const geometry::Box3 local = shape.levelSet->meshBounds();
    const geometry::Mat3 R = bodies_.orientation(b).toRotationMatrix();
    const Vec3 centre = bodies_.position(b) + R * (s * local.centre());
    const Vec3 half = R.cwiseAbs() * (0.5 * s * local.size()) + Vec3::Constant(settings_.boxMarginPerDn * bodyDn(b));
    boxes_[b].min = centre - half;
    boxes_[b].max = centre + half;
  };
  if (!boxesValid_ || boxes_.size() != n + convex_.size()) {
    // Everything: bodies first, then the static convex pieces (never active: they pair only
    // with awake bodies).
    boxes_.resize(n + convex_.size());
    active_.resize(n + convex_.size());
    for (std::size_t k = 0; k < convex_.size(); ++k) {
      boxes_[n + k] = convex_[k].box;
      active_[n + k] = 0;
    }
    for (BodyId b = 0; b < n; ++b) {
      boxOf(b);
      active_[b] = bodies_.isAwake(b) ? 1 : 0;
    }
    boxesValid_ = true;
    broadPhase_.invalidate();
    return;
  }
  // Only awake bodies move: a body's box stays valid while it is static or asleep (it fell
  // asleep at the position its box was last computed for).
  for (BodyId b = 0; b < n; ++b) {
    active_[b] = bodies_.isAwake(b) ? 1 : 0;
  }
  for (BodyId b : bodies_.awakeBodies()) {
    boxOf(b);
  }
}

void World::computeForces(double dt, double stateTime) {
  bodies_.clearForces();
  updateBoxes();
  broadPhase_.findPairs(boxes_, active_, pairs_);
  const auto nBodies = static_cast<std::uint32_t>(bodies_.size());
  // Work list: body pairs from the broad phase, then body-plane pairs (awake bodies whose box
  // reaches below the plane).
  std::vector<PairWork> work;
  work.reserve(pairs_.size() + nBodies);
  for (const auto& p : pairs_) {
    PairWork pw;
    pw.key = p.second < nBodies ? p : contact::BodyPair{p.first, kConvexBit | (p.second - nBodies)};
    work.push_back(std::move(pw));
  }
  for (BodyId b = 0; b < nBodies; ++b) {
    if (!active_[b]) {
      continue;
    }
    for (std::uint32_t k = 0; k < planes_.size(); ++k) {
      const auto& pl = planes_[k];
      // Lowest corner of the box along the normal.
      const Vec3 lowest(pl.normal.x() >= 0 ? boxes_[b].min.x() : boxes_[b].max.x(),
                        pl.normal.y() >= 0 ? boxes_[b].min.y() : boxes_[b].max.y(),
                        pl.normal.z() >= 0 ? boxes_[b].min.z() : boxes_[b].max.z());
      if ((lowest - pl.point).dot(pl.normal) < 0.0) {
        PairWork pw;
        pw.key = {b, kPlaneBit | k};
        work.push_back(std::move(pw));
      }
    }
  }

  // One pair can cost as much as a hundred (a concave unit on another versus a body on one
  // height-field cell): pairs are handed out one at a time.
#pragma omp parallel for schedule(dynamic, 1) if (work.size() >= 16)
  for (std::size_t w = 0; w < work.size(); ++w) {
    PairWork& pw = work[w];
    const BodyId a = pw.key.first;
    const bool plane = (pw.key.second & kStaticBits) != 0; // any static geometry: plane or convex piece
    const History* previous = findPairHistory(pw.key);
    std::vector<Engaged> engaged;
    const ShapeModel& shapeA = *shapes_[bodyShape_[a]];
    const double sA = bodyScale_[a];
    const Quat& qA = bodies_.orientation(a);
    const Vec3& xA = bodies_.position(a);
    const auto& samplesA = *shapeA.samples;
    double lengthScale = bodyDn(a);
    contact::ContactParameters params;
    double inverseMassSum = bodies_.inverseMass(a);

    if (plane) {
      // Static geometry as a set of half-spaces: a plane is one, a convex piece several; a
      // sample is inside when it is below all of them, at the depth of the nearest face.
      const bool isPlane = (pw.key.second & kPlaneBit) != 0;
      const std::uint32_t index = pw.key.second & ~kStaticBits;
      // Views of the faces, no copies: this runs for every body-static pair every step.
      std::span<const Vec3> normals;
      std::span<const double> offsets;
      double planeOffset = 0.0;
      MaterialId staticMaterial = 0;
      geometry::Box3 region; // where samples can be inside (world)
      if (isPlane) {
        const StaticPlane& pl = planes_[index];
        planeOffset = pl.normal.dot(pl.point);
        normals = std::span<const Vec3>(&pl.normal, 1);
        offsets = std::span<const double>(&planeOffset, 1);
        staticMaterial = pl.material;
        region = boxes_[a];
      } else {
        const StaticConvex& piece = convex_[index];
        normals = piece.normals;
        offsets = piece.offsets;
        staticMaterial = piece.material;
        region = piece.box;
      }
      // Visit only the buckets that reach into the region and below every face.
      const SampleBuckets& bk = shapeA.buckets;
      const geometry::Mat3 RA = qA.toRotationMatrix();
      const geometry::Mat3 toLocal = RA.transpose();
      const Vec3 regionCentre = toLocal * (region.centre() - xA) / sA;
      const Vec3 regionHalf = toLocal.cwiseAbs() * (0.5 * region.size()) / sA;
      const Vec3 cellHalf = 0.5 * bk.cell;
      forBucketsNear(shapeA, regionCentre - regionHalf, regionCentre + regionHalf, [&](int cell, const Vec3& low) {

        const Vec3 worldCentre = xA + qA * (sA * (low + cellHalf));
        for (std::size_t k = 0; k < normals.size(); ++k) {
          const double reach = sA * cellHalf.dot((toLocal * normals[k]).cwiseAbs());
          if (normals[k].dot(worldCentre) - offsets[k] > reach) {
            return; // the whole bucket is outside this face
          }
        }
        for (std::uint32_t j = bk.start[cell]; j < bk.start[cell + 1]; ++j) {
          const std::uint32_t i = bk.samples[j];

          const Vec3 X = xA + RA * (sA * samplesA.positions()[i]);
          double phi = -std::numeric_limits<double>::infinity();
          std::size_t nearest = 0;
          for (std::size_t k = 0; k < normals.size(); ++k) {
            const double d = normals[k].dot(X) - offsets[k];
            if (d > phi) {
              phi = d;
              nearest = k;
            }
          }
          if (phi < 0.0) {
            pw.maxOverlap = std::max(pw.maxOverlap, -phi); // engaged or not: the guard rails see every point inside
            // Projected tributary area: the pressure acts on the part of the sample's area that
            // faces the static surface, so a face pressed flat engages exactly its own area.
            const Vec3& n = normals[nearest];
            const double area = -sA * sA * (RA * samplesA.areaVectors()[i]).dot(n);
            if (area > 0.0) {
              engaged.push_back({i, X, n, -phi, area});
            }
          }
        }
      });
      params = pairParameters(bodyMaterial_[a], staticMaterial, lengthScale);
    } else {
      const BodyId b = pw.key.second;
      const ShapeModel& shapeB = *shapes_[bodyShape_[b]];
      const double sB = bodyScale_[b];
      lengthScale = std::min(lengthScale, bodyDn(b));
      inverseMassSum += bodies_.inverseMass(b);
      // Both directions, so that both bodies' edges and corners are detected, each weighted by
      // its probe's sample density: w_A = h_B^2 / (h_A^2 + h_B^2), h = sample spacing (a fixed
      // fraction of Dn), so w_A + w_B = 1. Equal bodies get half each (symmetric in A and B); a
      // unit on one 4.6 times its size (mass ratio 100) is measured mostly by its own fine
      // samples, not by the few coarse samples of the big one that fall on its small face.
      const double hA2 = bodyDn(a) * bodyDn(a), hB2 = bodyDn(b) * bodyDn(b);
      const std::array<double, 2> weight{hB2 / (hA2 + hB2), hA2 / (hA2 + hB2)};
      // Near misses first: in a rough pile most candidate pairs never touch (the boxes overlap,
      // the bodies do not: a rock under a Core-Loc's box but between its legs). A ball of radius
      // R around a body's centroid holds the body; if the other body's true distance at that
      // centre exceeds R, they are apart (LevelSet::distanceLowerBound: phi - sqrt(3) h inside the
      // grid, the distance to the mesh box outside it), for either body.
      bool apart = false;
      for (int dir = 0; dir < 2 && !apart; ++dir) {
        const BodyId probe = dir == 0 ? a : b;
        const BodyId target = dir == 0 ? b : a;
        const ShapeModel& ps = dir == 0 ? shapeA : shapeB;
        const ShapeModel& ts = dir == 0 ? shapeB : shapeA;
        const double st = bodyScale_[target];
        const Vec3 centre = bodies_.orientation(target).conjugate() * (bodies_.position(probe) - bodies_.position(target)) / st;
        apart = ts.levelSet->distanceLowerBound(centre) > (ps.radius * bodyScale_[probe]) / st;
      }
      for (int dir = 0; dir < 2 && !apart; ++dir) {
        const BodyId probe = dir == 0 ? a : b;
        const BodyId target = dir == 0 ? b : a;
        const ShapeModel& ps = dir == 0 ? shapeA : shapeB;
        const ShapeModel& ts = dir == 0 ? shapeB : shapeA;
        const double sp = dir == 0 ? sA : sB;
        const double st = dir == 0 ? sB : sA;
        const geometry::Mat3 Rp = bodies_.orientation(probe).toRotationMatrix();
        const Vec3& xp = bodies_.position(probe);
        const geometry::Mat3 Rt = bodies_.orientation(target).toRotationMatrix();
        const Vec3& xt = bodies_.position(target);
        const auto& samples = *ps.samples;
        const contact::LevelSet& ls = *ts.levelSet;
        // Probe frame (unscaled) -> target frame (unscaled): L = Rrel p + trel.
        const geometry::Mat3 Rrel = Rt.transpose() * Rp * (sp / st);
        const Vec3 trel = Rt.transpose() * (xp - xt) / st;
        // phi < 0 needs L within the target's mesh bounds grown by sqrt(3) h (LevelSet::mayPenetrate).
        const Vec3 grow = Vec3::Constant(std::sqrt(3.0) * ls.cellSize());
        const Vec3 targetLo = ls.meshBounds().min - grow;
        const Vec3 targetHi = ls.meshBounds().max + grow;
        // The target's grown mesh box (an oriented box) seen from the probe's unscaled body
        // frame, as an axis-aligned box there: tighter than the target's world box.
        const geometry::Mat3 toProbe = Rp.transpose() * Rt * (st / sp);
        const Vec3 centre = toProbe * (0.5 * (targetLo + targetHi)) + Rp.transpose() * (xt - xp) / sp;
        const Vec3 half = toProbe.cwiseAbs() * (0.5 * (targetHi - targetLo));
        const double h = ls.cellSize();
        forBucketsNear(ps, centre - half, centre + half, [&](int cell, const Vec3& /*low*/) {

          // Whole bucket first, by the sphere around its samples (radius r, centre c, in the
          // target frame): an interpolated phi < 0 at x needs a true distance below sqrt(3) h
          // there, and the true distance at x is at least that at c minus r; so a lower bound
          // of the distance at c above r + sqrt(3) h rules out the whole bucket.
          const Vec3 bc = Rrel * ps.buckets.sphereCentre[cell] + trel;
          const double r = ps.buckets.sphereRadius[cell] * (sp / st);
          if (ls.distanceLowerBound(bc) - r > std::sqrt(3.0) * h) {
            return;
          }

          for (std::uint32_t j = ps.buckets.start[cell]; j < ps.buckets.start[cell + 1]; ++j) {
            const std::uint32_t i = ps.buckets.samples[j];

            const Vec3 L = Rrel * samples.positions()[i] + trel;
            if ((L.array() < targetLo.array()).any() || (L.array() > targetHi.array()).any() || !(ls.value(L) < 0.0)) {
              continue;
            }

            const contact::LevelSetQuery q = ls.query(L);
            if (q.phi < 0.0) {
              // Engaged or not, the guard rails see every point inside: past the other body's
              // middle a point faces the wrong way and is not engaged, but the overlap is real.
              pw.maxOverlap = std::max(pw.maxOverlap, -q.phi * st);
            }
            if (q.phi < 0.0 && q.normal.squaredNorm() > 0.0) {
              const Vec3 X = xp + Rp * (sp * samples.positions()[i]);
              const Vec3 n = Rt * q.normal; // out of the target: pushes the probe
              // The direction's weight scales the tributary area (k = E_p a / L is linear in a).
              const double area = -weight[dir] * sp * sp * (Rp * samples.areaVectors()[i]).dot(n);
              if (area > 0.0) {
                engaged.push_back({(dir == 0 ? 0u : kReverseBit) | i, X, dir == 0 ? n : Vec3(-n), -q.phi * st, area});
              }
            }
          }
        });
      }
      params = pairParameters(bodyMaterial_[a], bodyMaterial_[b], lengthScale);
    }
    if (engaged.empty()) {
      continue;
    }
    double pairStiffness = 0.0;
    for (const auto& e : engaged) {
      pairStiffness += contact::pointStiffness(params, e.area);
    }
    const double effectiveMass = inverseMassSum > 0.0 ? 1.0 / inverseMassSum : 0.0;
    const double beta = contact::dampingTime(params, effectiveMass, pairStiffness);
    const BodyId b = plane ? a : pw.key.second;
    const Vec3& xB = bodies_.position(b);
    pw.history.reserve(engaged.size());
    for (const auto& e : engaged) {
      // For B's samples (reverse bit) the normal was flipped to push A: the law always sees A
      // as the pushed body, so history and forces stay in one convention.
      Vec3 vRel = bodies_.velocityAtPoint(a, e.point);
      if (!plane) {
        vRel -= bodies_.velocityAtPoint(b, e.point);
      }
      const contact::PointHistory* prev = findHistory(previous, e.key);
      const contact::PointForce f = contact::evaluatePointContact(params, {e.normal, e.depth, e.area, vRel},
                                                                  prev ? *prev : contact::PointHistory{}, beta, dt);
      pw.maxPointForce = std::max(pw.maxPointForce, f.force.norm());
      pw.weightedPoint += f.normalForce * e.point;
      pw.pointSum += e.point;
      pw.normalForce += f.normalForce;
      // Elastic energy: the normal spring, and the friction spring up to the stretch its elastic
      // normal force can hold (after an impact the stored stretch carries the dashpot's share of
      // the cap too, which the spring can never give back).
      const double k = contact::pointStiffness(params, e.area);
      const double kt = params.tangentialStiffnessRatio * k;
      const double holdable = kt > 0.0 ? params.frictionStatic * k * e.depth / kt : 0.0;
      const double stretch = std::min(f.history.stretch.norm(), holdable);
      pw.elasticEnergy += 0.5 * (k * e.depth * e.depth + kt * stretch * stretch);
      pw.forceA += f.force;
      pw.torqueA += (e.point - xA).cross(f.force);
      if (!plane) {
        pw.forceB -= f.force;
        pw.torqueB -= (e.point - xB).cross(f.force);
      }
      pw.history.emplace_back(e.key, f.history);
    }
    std::sort(pw.history.begin(), pw.history.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  }

  // Serial, ordered accumulation: bit-identical for any thread count.
  stats_ = {};
  stats_.candidatePairs = work.size();
  contactEnergy_ = 0.0;
  patches_.clear();
  contactCount_.assign(nBodies, 0);
  maxContactForce_.assign(nBodies, 0.0);
  PairHistories nextHistory;
  nextHistory.reserve(history_.size() + 16);
  for (auto& pw : work) {
    if (pw.history.empty() && pw.maxOverlap == 0.0) {
      continue;
    }
    const BodyId a = pw.key.first;
    auto forces = bodies_.forces();
    auto torques = bodies_.torques();
    forces[a] += pw.forceA;
    torques[a] += pw.torqueA;
    const auto points = static_cast<std::int32_t>(pw.history.size());
    contactCount_[a] += points;
    maxContactForce_[a] = std::max(maxContactForce_[a], pw.maxPointForce);
    if ((pw.key.second & kStaticBits) == 0) {
      forces[pw.key.second] += pw.forceB;
      torques[pw.key.second] += pw.torqueB;
      contactCount_[pw.key.second] += points;
      maxContactForce_[pw.key.second] = std::max(maxContactForce_[pw.key.second], pw.maxPointForce);
    }
    stats_.contactPoints += pw.history.size();
    contactEnergy_ += pw.elasticEnergy;
    if (settings_.recordContacts && points > 0) {
      ContactPatch patch;
      patch.bodyA = a;
      patch.bodyB = (pw.key.second & kStaticBits) == 0 ? static_cast<std::int64_t>(pw.key.second) : -1;
      patch.force = pw.forceA;
      patch.normalForce = pw.normalForce;
      patch.points = points;
      // A patch held only by friction and damping can have no normal force: plain mean then.
      patch.point = pw.normalForce > 0.0 ? Vec3(pw.weightedPoint / pw.normalForce) : Vec3(pw.pointSum / points);
      patches_.push_back(patch);
    }
    stats_.maxOverlap = std::max(stats_.maxOverlap, pw.maxOverlap);
    // Guard rails: an overlap this deep means the contact cannot hold (time step, stiffness or
    // speed), and the forces that follow are meaningless; past the middle of a thin part the
    // push would even turn and carry the body through (tunnelling).
    const BodyId other = pw.key.second & ~kStaticBits;
    double dn = bodyDn(a);
    double inner = shapes_[bodyShape_[a]]->innerDepth * bodyScale_[a];
    std::string otherName;
    if ((pw.key.second & kStaticBits) == 0) {
      dn = std::min(dn, bodyDn(other));
      inner = std::min(inner, shapes_[bodyShape_[other]]->innerDepth * bodyScale_[other]);
      otherName = bodies_.describe(other);
    } else if ((pw.key.second & kPlaneBit) != 0) {
      otherName = "plane '" + planes_[other].name + "'";
    } else {
      inner = std::min(inner, convex_[other].innerDepth);
      otherName = "static piece '" + convex_[other].name + "'";
    }
    const double overlapLimit = settings_.maxOverlapPerDn * dn;
    const double tunnelLimit = settings_.maxOverlapPerInnerDepth * inner;
    if (pw.maxOverlap > std::min(overlapLimit, tunnelLimit)) {
      if (tunnelLimit < overlapLimit) {
        throw SimulationError(fmt::format(
            "t = {:.6g} s: {} and {} overlap by {:.4g} m, more than {} x the inner depth {:.4g} m of the thinner "
            "part: it would pass through it (tunnel); make thin parts thicker, lower the speed, or raise the "
            "penalty modulus",
            time_, bodies_.describe(a), otherName, pw.maxOverlap, settings_.maxOverlapPerInnerDepth, inner));
      }
      throw SimulationError(fmt::format(
          "t = {:.6g} s: {} and {} overlap by {:.4g} m, more than {} x Dn = {:.4g} m; the contact cannot hold: "
          "lower the time step, raise the penalty modulus, or check the initial positions",
          time_, bodies_.describe(a), otherName, pw.maxOverlap, settings_.maxOverlapPerDn, overlapLimit));
    }
    if (!pw.history.empty()) {
      nextHistory.emplace_back(pw.key, std::move(pw.history));
    }
  }
  // Pairs that were not examined because none of their bodies is awake keep their friction
  // springs: a sleeping pack wakes with the same contact state it fell asleep with.
  for (auto& [key, h] : history_) {
    const bool bodyPair = (key.second & kStaticBits) == 0;
    if (!bodies_.isAwake(key.first) && (!bodyPair || !bodies_.isAwake(key.second))) {
      nextHistory.emplace_back(key, std::move(h));
    }
  }
  // Sorted by pair, for the binary search of the next step (keys are unique: a pair is either
  // examined or kept).
  std::sort(nextHistory.begin(), nextHistory.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  history_ = std::move(nextHistory);
  applyLoadStages(stateTime);
}

void World::addLoadStage(std::shared_ptr<LoadStage> stage) {
  if (!stage) {
    throw std::invalid_argument("World::addLoadStage: null stage");
  }
  loadStages_.push_back(std::move(stage));
  forcesReady_ = false;
}

void World::applyLoadStages(double stateTime) {
  const std::size_t n = bodies_.size();
  if (loadStages_.empty()) {
    externalForce_.clear();
    externalTorque_.clear();
    return;
  }
  externalForce_.assign(n, Vec3::Zero());
  externalTorque_.assign(n, Vec3::Zero());
  for (const auto& stage : loadStages_) {
    stageForce_.assign(n, Vec3::Zero());
    stageTorque_.assign(n, Vec3::Zero());
    stage->apply(*this, stateTime, stageForce_, stageTorque_);
    for (std::size_t b = 0; b < n; ++b) {
      if (!stageForce_[b].allFinite() || !stageTorque_[b].allFinite()) {
        throw SimulationError(fmt::format("t = {:.6g} s: the '{}' loads on {} are not finite (force {}, {}, {}); "
                                          "check the load input (storm file, force model) at this time",
                                          stateTime, stage->name(), bodies_.describe(static_cast<BodyId>(b)),
                                          stageForce_[b].x(), stageForce_[b].y(), stageForce_[b].z()));
      }
      externalForce_[b] += stageForce_[b];
      externalTorque_[b] += stageTorque_[b];
    }
  }
  auto forces = bodies_.forces();
  auto torques = bodies_.torques();
  for (const BodyId b : bodies_.awakeBodies()) {
    forces[b] += externalForce_[b];
    torques[b] += externalTorque_[b];
  }
}

double World::externalPower() const {
  double power = 0.0;
  if (externalForce_.empty()) {
    return power;
  }
  for (const BodyId b : bodies_.awakeBodies()) {
    power += externalForce_[b].dot(bodies_.velocity(b)) + externalTorque_[b].dot(bodies_.worldAngularVelocity(b));
  }
  return power;
}

const World::History* World::findPairHistory(const contact::BodyPair& key) const {
  const auto it = std::lower_bound(history_.begin(), history_.end(), key,
                                   [](const auto& e, const contact::BodyPair& k) { return e.first < k; });
  return it != history_.end() && it->first == key ? &it->second : nullptr;
}

void World::updateSleep(double dt) {
  const SleepSettings& st = settings_.sleep;
  if (!st.enabled) {
    return;
  }
  const auto n = static_cast<BodyId>(bodies_.size());
  for (BodyId b : bodies_.awakeBodies()) {
    const bool resting = bodies_.velocity(b).norm() < st.linearSpeed &&
                         bodies_.worldAngularVelocity(b).norm() < st.angularSpeed;
    restTime_[b] = resting ? restTime_[b] + dt : 0.0;
  }
  // A sleeper whose external load has changed (a wave arrives) wakes: it was asleep under the old load.
  if (!externalForce_.empty()) {
    sleepLoad_.resize(n, Vec3::Zero());
    for (BodyId b = 0; b < n; ++b) {
      if (bodies_.motionType(b) == dynamics::MotionType::Sleeping &&
          (externalForce_[b] - sleepLoad_[b]).norm() >
              st.wakeLoadFraction * bodies_.info(b).mass * settings_.gravity.norm()) {
        bodies_.wake(b);
        restTime_[b] = 0.0;
      }
    }
  }
  // Contact islands over non-static bodies (union-find on the pairs in contact).
  std::vector<BodyId> parent(n);
  for (BodyId b = 0; b < n; ++b) {
    parent[b] = b;
  }
  const auto find = [&](BodyId b) {
    while (parent[b] != b) {
      parent[b] = parent[parent[b]];
      b = parent[b];
    }
    return b;
  };
  std::vector<BodyId> toWake;
  for (const auto& [key, h] : history_) {
    if ((key.second & kStaticBits) != 0 || h.empty()) {
      continue;
    }
    const BodyId a = key.first, b = key.second;
    const auto ta = bodies_.motionType(a), tb = bodies_.motionType(b);
    if (ta == dynamics::MotionType::Static || tb == dynamics::MotionType::Static) {
      continue;
    }
    parent[find(a)] = find(b);
    // Something moving touches a sleeper: wake it (its neighbours follow as contact spreads).
    if (ta == dynamics::MotionType::Sleeping && bodies_.isAwake(b) && restTime_[b] < st.time) {
      toWake.push_back(a);
    }
    if (tb == dynamics::MotionType::Sleeping && bodies_.isAwake(a) && restTime_[a] < st.time) {
      toWake.push_back(b);
    }
  }
  for (BodyId b : toWake) {
    bodies_.wake(b);
    restTime_[b] = 0.0;
  }
  // An island sleeps when every awake member has rested long enough.
  std::vector<char> islandRestless(n, 0);
  for (BodyId b : bodies_.awakeBodies()) {
    if (restTime_[b] < st.time) {
      islandRestless[find(b)] = 1;
    }
  }
  std::vector<BodyId> toSleep;
  for (BodyId b : bodies_.awakeBodies()) {
    if (!islandRestless[find(b)]) {
      toSleep.push_back(b);
    }
  }
  for (BodyId b : toSleep) {
    bodies_.sleep(b);
    if (!externalForce_.empty()) {
      sleepLoad_.resize(n, Vec3::Zero());
      sleepLoad_[b] = externalForce_[b];
    }
  }
}

void World::step() {
  const double dt = timeStep();
  if (!forcesReady_) {
    computeForces(dt, time_);
    forcesReady_ = true;
  }
  // Work of the external loads over the step, trapezoidal in F . v (exact for constant loads and
  // velocity; second order otherwise), so the energy guard sees waves as work, not instability.
  const double powerBefore = externalPower();
  dynamics::kick(bodies_, 0.5 * dt, settings_.gravity);
  dynamics::drift(bodies_, dt);
  computeForces(dt, time_ + dt);
  dynamics::kick(bodies_, 0.5 * dt, settings_.gravity);
  externalWork_ += 0.5 * dt * (powerBefore + externalPower());
  time_ += dt;
  ++steps_;
  stats_.awakeBodies = bodies_.awakeBodies().size();
  for (BodyId b : bodies_.awakeBodies()) {
    if (!bodies_.position(b).allFinite() || !bodies_.velocity(b).allFinite() ||
        !bodies_.worldAngularVelocity(b).allFinite()) {
      throw SimulationError(fmt::format("t = {:.6g} s: {} has a non-finite state (position, velocity or "
                                        "angular velocity); the step is unstable: lower the time step",
                                        time_, bodies_.describe(b)));
    }
  }
  updateSleep(dt);
  if (settings_.energyGuard.enabled && steps_ % std::max<std::uint32_t>(1, settings_.energyGuard.checkInterval) == 0) {
    checkEnergy();
  }
}

void World::checkEnergy() {
  const EnergyGuardSettings& g = settings_.energyGuard;
  double kinetic = 0.0, potential = 0.0, weightScale = 0.0;
  BodyId hottest = 0;
  double hottestEnergy = -1.0;
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    if (bodies_.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    const double m = bodies_.info(b).mass;
    const double ke = bodies_.kineticEnergy(b);
    kinetic += ke;
    potential -= m * settings_.gravity.dot(bodies_.position(b));
    const double dn = bodyDn(b);
    weightScale = std::max(weightScale, m * settings_.gravity.norm() * dn);
    if (ke > hottestEnergy) {
      hottestEnergy = ke;
      hottest = b;
    }
  }
  const double net = kinetic + potential + contactEnergy_ - externalWork_;
  energyPeak_ = std::max(energyPeak_, kinetic + contactEnergy_);
  if (!energyStarted_) {
    energyStarted_ = true;
    energyMinimum_ = net;
    return;
  }
  const double tolerance = g.growthPerBodyWeight * weightScale + g.growthPerPeakEnergy * energyPeak_;
  if (net > energyMinimum_ + tolerance) {
    throw SimulationError(fmt::format(
        "t = {:.6g} s: the energy grew by {:.4g} J without work from outside (kinetic {:.4g} J, contact {:.4g} J; "
        "tolerance {:.4g} J); the integration is unstable, fastest body: {} ({:.4g} J): lower the time step or "
        "the penalty modulus, or raise the restitution damping",
        time_, net - energyMinimum_, kinetic, contactEnergy_, tolerance, bodies_.describe(hottest), hottestEnergy));
  }
  energyMinimum_ = std::min(energyMinimum_, net);
}

WorldState World::captureState() const {
  WorldState s;
  s.time = time_;
  s.steps = steps_;
  s.forcesReady = forcesReady_;
  s.energyMinimum = energyMinimum_;
  s.externalWork = externalWork_;
  s.energyPeak = energyPeak_;
  s.energyStarted = energyStarted_;
  s.bodies.resize(bodies_.size());
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    BodyState& o = s.bodies[b];
    o.motion = bodies_.motionType(b);
    o.position = bodies_.position(b);
    o.orientation = bodies_.orientation(b);
    o.velocity = bodies_.velocity(b);
    o.angularMomentum = bodies_.angularMomentumWorld(b);
    o.force = bodies_.force(b);
    o.torque = bodies_.torque(b);
    o.restTime = restTime_[b];
    o.contactCount = contactCount(b);
    o.maxContactForce = maxContactForce(b);
    o.externalForce = externalForce(b);
    o.externalTorque = externalTorque(b);
    o.sleepLoad = b < sleepLoad_.size() ? sleepLoad_[b] : Vec3::Zero();
  }
  for (const auto& stage : loadStages_) {
    s.loadStages.emplace_back(stage->name(), stage->saveState());
  }
  for (const auto& [pair, points] : history_) {
    for (const auto& [key, h] : points) {
      s.contacts.push_back({pair.first, pair.second, key, h.stretch, h.sliding});
    }
  }
  return s;
}

void World::restoreState(const WorldState& s) {
  if (s.bodies.size() != bodies_.size()) {
    core::failInput("checkpoint", "holds {} bodies but the scene builds {}: restart with the scene the run was "
                                  "started with", s.bodies.size(), bodies_.size());
  }
  const auto nBodies = static_cast<std::uint32_t>(bodies_.size());
  for (const ContactPointState& c : s.contacts) {
    const std::uint32_t index = c.second & ~kStaticBits;
    const bool ok = c.first < nBodies &&
                    ((c.second & kPlaneBit) != 0   ? index < planes_.size()
                     : (c.second & kConvexBit) != 0 ? index < convex_.size()
                                                    : c.second < nBodies && c.first < c.second);
    if (!ok) {
      core::failInput("checkpoint", "contact ({}, {:#x}) does not exist in this scene: restart with the scene the "
                                    "run was started with", c.first, c.second);
    }
  }
  time_ = s.time;
  steps_ = s.steps;
  energyMinimum_ = s.energyMinimum;
  externalWork_ = s.externalWork;
  energyPeak_ = s.energyPeak;
  energyStarted_ = s.energyStarted;
  contactCount_.assign(nBodies, 0);
  maxContactForce_.assign(nBodies, 0.0);
  bodies_.clearForces();
  auto forces = bodies_.forces();
  auto torques = bodies_.torques();
  for (BodyId b = 0; b < nBodies; ++b) {
    const BodyState& o = s.bodies[b];
    if ((o.motion == dynamics::MotionType::Static) != (bodies_.motionType(b) == dynamics::MotionType::Static)) {
      core::failInput("checkpoint", "{} is {} in the checkpoint but {} in the scene: restart with the scene the run "
                                    "was started with", bodies_.describe(b),
                      o.motion == dynamics::MotionType::Static ? "fixed" : "free",
                      o.motion == dynamics::MotionType::Static ? "free" : "fixed");
    }
    bodies_.restoreState(b, o.motion, o.position, o.orientation, o.velocity, o.angularMomentum);
    forces[b] = o.force;
    torques[b] = o.torque;
    restTime_[b] = o.restTime;
    contactCount_[b] = o.contactCount;
    maxContactForce_[b] = o.maxContactForce;
  }
  // Load stages: the same stages, in the same order, each given back its own state.
  if (s.loadStages.size() != loadStages_.size()) {
    core::failInput("checkpoint", "holds {} load stages but the scene has {}: restart with the scene the run was "
                                  "started with", s.loadStages.size(), loadStages_.size());
  }
  externalForce_.clear();
  externalTorque_.clear();
  sleepLoad_.clear();
  if (!loadStages_.empty()) {
    externalForce_.resize(nBodies);
    externalTorque_.resize(nBodies);
    sleepLoad_.resize(nBodies);
    for (BodyId b = 0; b < nBodies; ++b) {
      externalForce_[b] = s.bodies[b].externalForce;
      externalTorque_[b] = s.bodies[b].externalTorque;
      sleepLoad_[b] = s.bodies[b].sleepLoad;
    }
  }
  for (std::size_t k = 0; k < loadStages_.size(); ++k) {
    if (s.loadStages[k].first != loadStages_[k]->name()) {
      core::failInput("checkpoint", "load stage {} is '{}' in the checkpoint but '{}' in the scene: restart with the "
                                    "scene the run was started with", k, s.loadStages[k].first, loadStages_[k]->name());
    }
    loadStages_[k]->restoreState(s.loadStages[k].second);
  }
  std::map<contact::BodyPair, History> byPair;
  for (const ContactPointState& c : s.contacts) {
    byPair[{c.first, c.second}].emplace_back(c.key, contact::PointHistory{c.stretch, c.sliding});
  }
  history_.clear();
  for (auto& [pair, points] : byPair) {
    std::sort(points.begin(), points.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    history_.emplace_back(pair, std::move(points));
  }
  forcesReady_ = s.forcesReady;
  boxesValid_ = false;
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

double World::mechanicalEnergy() const {
  double e = 0.0;
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    if (bodies_.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    e += bodies_.kineticEnergy(b) - bodies_.info(b).mass * settings_.gravity.dot(bodies_.position(b));
  }
  return e;
}

} // namespace armour::simulation
