// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/PeersBullet.hpp"

#include <btBulletDynamicsCommon.h>
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace armour::bench {

using armour::simulation::Quat;
using armour::simulation::Vec3;

namespace {
btVector3 bt(const Vec3& v) { return {btScalar(v.x()), btScalar(v.y()), btScalar(v.z())}; }
btQuaternion bt(const Quat& q) { return {btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())}; }
Vec3 fromBt(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
} // namespace

struct BulletPile::Impl {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes; // owned; children before their compounds
  std::vector<std::unique_ptr<btDefaultMotionState>> motionStates;
  std::vector<std::unique_ptr<btRigidBody>> bodies;      // the units, in armour's body order
  std::vector<std::unique_ptr<btRigidBody>> statics;

  ~Impl() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
    for (auto& b : statics) world.removeRigidBody(b.get());
  }
};

BulletPile::BulletPile(const armour::simulation::World& world, const std::vector<Deposit::Plane>& walls,
                       const BulletSettings& s)
    : impl_(std::make_unique<Impl>()), settings_(s) {
  namespace dyn = armour::dynamics;
  auto& w = impl_->world;
  const Vec3 g = world.settings().gravity;
  w.setGravity(bt(g));
  w.getSolverInfo().m_numIterations = s.iterations;
  // Bullet combines the two bodies' coefficients by their product (btManifoldResult): give every
  // body the square root, so every pair (unit-unit and unit-wall) gets the armour scene's value.
  const btScalar friction = btScalar(std::sqrt(s.friction));
  const btScalar restitution = btScalar(std::sqrt(s.restitution));

  // One Bullet shape per armour shape and scale, shared by its bodies (as armour shares level sets).
  std::map<std::pair<armour::simulation::ShapeId, double>, btCollisionShape*> made;
  const auto shapeFor = [&](dyn::BodyId b) -> btCollisionShape* {
    const auto key = std::make_pair(world.bodyShape(b), world.bodyScale(b));
    if (auto it = made.find(key); it != made.end()) {
      return it->second;
    }
    const armour::simulation::ShapeModel& model = world.shape(key.first);
    const double scale = key.second;
    btCollisionShape* shape = nullptr;
    const auto hullOf = [&](const std::vector<Vec3>& corners) {
      auto hull = std::make_unique<btConvexHullShape>();
      for (const Vec3& c : corners) {
        hull->addPoint(bt(scale * c), false);
      }
      hull->recalcLocalAabb();
      btConvexHullShape* raw = hull.get();
      impl_->shapes.push_back(std::move(hull));
      return raw;
    };
    if (s.shape == BulletShape::Box) {
      if (model.name != "cube") {
        throw std::invalid_argument(fmt::format("bullet-box: {} is not a cube; use bullet-hull or bullet-compound",
                                                model.name));
      }
      // A cube's principal frame is any frame (its inertia is isotropic), so the box is made in the
      // cube's natural frame, where its faces are normal to the axes, and posed by the natural
      // orientation; the mesh must fill that box.
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      for (const Vec3& v : model.mesh.vertices) {
        const Vec3 n = model.naturalToBody.conjugate() * v;
        lo = lo.cwiseMin(n);
        hi = hi.cwiseMax(n);
      }
      const Vec3 half = 0.5 * (hi - lo);
      const double volume = 8.0 * half.prod();
      if (std::abs(volume / std::abs(model.unitMass.volume) - 1.0) > 1e-6 || (0.5 * (hi + lo)).norm() > 1e-6) {
        throw std::runtime_error(fmt::format("bullet-box: the cube mesh does not fill its natural-frame box "
                                             "(box volume {:.6f}, mesh {:.6f})", volume, model.unitMass.volume));
      }
      auto box = std::make_unique<btBoxShape>(bt(scale * half));
      shape = box.get();
      impl_->shapes.push_back(std::move(box));
      description_ = fmt::format("btBoxShape {:.3f} x {:.3f} x {:.3f} m (margin {:.2f} m inside)", 2 * scale * half.x(),
                                 2 * scale * half.y(), 2 * scale * half.z(), shape->getMargin());
    } else if (s.shape == BulletShape::Hull) {
      const ConvexPieces hull = wholeHull(model);
      shape = hullOf(hull.pieces.front().corners);
      description_ = fmt::format("btConvexHullShape: {}, hull volume / mesh volume - 1 = {:+.2f} % (margin {:.2f} m "
                                 "outside)",
                                 hull.how, 100.0 * hull.volumeError(), shape->getMargin());
    } else {
      pieces_ = model.name == "coreloc" ? coreLocPieces(model, s.corelocPieces) : wholeHull(model);
      auto compound = std::make_unique<btCompoundShape>();
      btTransform identity;
      identity.setIdentity();
      std::string sizes;
      for (const ConvexPiece& p : pieces_.pieces) {
        compound->addChildShape(identity, hullOf(p.corners));
        sizes += fmt::format("{}{}: {} corners, {:.2f} % outside", sizes.empty() ? "" : "; ", p.name, p.corners.size(),
                             100.0 * p.outside);
      }
      shape = compound.get();
      impl_->shapes.push_back(std::move(compound));
      description_ = fmt::format("btCompoundShape of {} btConvexHullShape: {} ({}); pieces' volume / mesh volume - 1 "
                                 "= {:+.2f} %; sampled on {}^3 points, the pieces' union reaches outside the unit by "
                                 "{:.2f} % of its volume and misses {:.2f} % of it (margin {:.2f} m outside each piece)",
                                 pieces_.pieces.size(), pieces_.how, sizes, 100.0 * pieces_.volumeError(),
                                 ConvexPieces::kSamples, 100.0 * pieces_.outside, 100.0 * pieces_.missed,
                                 btConvexHullShape().getMargin());
    }
    made.emplace(key, shape);
    return shape;
  };

  const auto& bodies = world.bodies();
  for (dyn::BodyId b = 0; b < bodies.size(); ++b) {
    if (bodies.motionType(b) == dyn::MotionType::Static) {
      throw std::invalid_argument("bench_peers: fixed bodies are not carried over to Bullet");
    }
    btCollisionShape* shape = shapeFor(b);
    // The body frame is the shape's principal frame with the centroid at its origin (World.hpp,
    // ShapeModel): the same mass and principal moments as armour's body. The box is posed in the
    // cube's natural frame, also principal for a cube.
    const double mass = 1.0 / bodies.inverseMass(b);
    const Vec3 moments = bodies.inverseInertiaBody(b).cwiseInverse();
    const Quat q = s.shape == BulletShape::Box ? world.naturalOrientation(b) : bodies.orientation(b);
    btTransform pose(bt(q), bt(bodies.position(b)));
    auto motion = std::make_unique<btDefaultMotionState>(pose);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motion.get(), shape, bt(moments));
    info.m_friction = friction;
    info.m_restitution = restitution;
    auto body = std::make_unique<btRigidBody>(info);
    body->setLinearVelocity(bt(bodies.velocity(b)));
    body->setAngularVelocity(bt(bodies.worldAngularVelocity(b)));
    if (!s.sleep) {
      body->setActivationState(DISABLE_DEACTIVATION);
    }
    w.addRigidBody(body.get());
    impl_->motionStates.push_back(std::move(motion));
    impl_->bodies.push_back(std::move(body));
  }
  // The walls: armour's static half-spaces as Bullet's static planes n . x = n . point.
  for (const Deposit::Plane& plane : walls) {
    auto shape = std::make_unique<btStaticPlaneShape>(bt(plane.normal), btScalar(plane.normal.dot(plane.point)));
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shape.get());
    info.m_friction = friction;
    info.m_restitution = restitution;
    auto body = std::make_unique<btRigidBody>(info);
    w.addRigidBody(body.get());
    impl_->shapes.push_back(std::move(shape));
    impl_->statics.push_back(std::move(body));
  }
}

BulletPile::~BulletPile() = default;

void BulletPile::step() {
  // One fixed step per call: no interpolation, no substeps beyond the one.
  impl_->world.stepSimulation(btScalar(settings_.timeStep), 1, btScalar(settings_.timeStep));
  time_ += settings_.timeStep;
}

std::size_t BulletPile::bodyCount() const { return impl_->bodies.size(); }

Vec3 BulletPile::position(std::size_t i) const {
  return fromBt(impl_->bodies[i]->getCenterOfMassPosition());
}

Vec3 BulletPile::velocity(std::size_t i) const { return fromBt(impl_->bodies[i]->getLinearVelocity()); }

bool BulletPile::awake(std::size_t i) const { return impl_->bodies[i]->isActive(); }

} // namespace armour::bench
