// SPDX-License-Identifier: GPL-3.0-or-later
#include "simulation/DeformableCoupling.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <utility>

namespace armour::simulation {

DeformableCoupling::DeformableCoupling(deformable::DeformableBody& body, std::vector<BodyId> rigid)
    : body_(body), rigid_(std::move(rigid)) {
  if (!body_.settings().rigidContact) {
    throw std::invalid_argument("DeformableCoupling: the deformable body has rigid contact off");
  }
}

std::vector<deformable::RigidObstacle> DeformableCoupling::obstacles(const World& world) const {
  std::vector<deformable::RigidObstacle> out;
  out.reserve(rigid_.size());
  for (const BodyId b : rigid_) {
    deformable::RigidObstacle o;
    o.levelSet = world.shape(world.bodyShape(b)).levelSet.get(); // principal frame, centroid at the origin
    o.scale = world.bodyScale(b);
    o.position = world.bodies().position(b); // the centre of mass: the loads' moments are about it
    o.orientation = world.bodies().orientation(b);
    o.moving = true; // the World's checkpoint holds the pose
    out.push_back(o);
  }
  return out;
}

void DeformableCoupling::apply(const World& world, double time, std::span<dynamics::Vec3> force,
                               std::span<dynamics::Vec3> torque) {
  body_.setObstacles(obstacles(world));
  const double h = world.timeStep();
  if (time > body_.time() + 0.5 * h) {
    body_.step(h);
    ++steps_;
  } else {
    body_.prepare();
  }
  if (std::abs(body_.time() - time) > 1e-9 * std::max(1.0, std::abs(time))) {
    throw std::logic_error(fmt::format("DeformableCoupling: the deformable body is at t = {} s and the World "
                                       "evaluates t = {} s; the two must start at the same time with the same step",
                                       body_.time(), time));
  }
  const auto& loads = body_.obstacleLoads();
  for (std::size_t k = 0; k < rigid_.size(); ++k) {
    force[rigid_[k]] += loads[k].force;
    torque[rigid_[k]] += loads[k].torque;
  }
}

std::string DeformableCoupling::summary() const {
  return fmt::format("deformable body advanced {} steps with the rigid bodies", steps_);
}

} // namespace armour::simulation
