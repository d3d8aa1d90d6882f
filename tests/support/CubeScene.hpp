// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CubeScene.hpp
/// A World with one material and one unit cube shape (scaled per body), a floor, and concrete of a
/// given restitution and friction: the fixture of the contact physics tests of both solvers.

#include "geometry/ShapeLibrary.hpp"
#include "simulation/World.hpp"

namespace armour::test {

using simulation::BodyId;
using simulation::Material;
using simulation::MaterialId;
using simulation::Quat;
using simulation::ShapeId;
using simulation::Vec3;
using simulation::World;
using simulation::WorldSettings;

/// Settings with sleeping off: contact physics tests watch the bodies, not the sleep logic.
inline WorldSettings noSleep() {
  WorldSettings s;
  s.sleep.enabled = false;
  return s;
}

/// Concrete with restitution e and friction mu (static = dynamic).
inline Material concrete(double restitution, double mu) {
  Material m;
  m.name = "concrete";
  m.restitution = restitution;
  m.frictionStatic = m.frictionDynamic = mu;
  return m;
}

struct CubeScene {
  World world;
  MaterialId material = 0;
  ShapeId cube = 0;

  explicit CubeScene(const Material& m = {}, const WorldSettings& settings = noSleep()) : world(settings) {
    material = world.addMaterial(m);
    geometry::ShapeRequest r;
    r.volume = 1.0;
    cube = world.addShape("cube", geometry::makeShape("cube", r));
  }
  /// A cube of side `scale` (m) at `position` (its centroid).
  BodyId addCube(const Vec3& position, const Quat& orientation = Quat::Identity(), const Vec3& velocity = Vec3::Zero(),
                 double scale = 1.0) {
    simulation::BodySpec b;
    b.shape = cube;
    b.material = material;
    b.scale = scale;
    b.position = position;
    b.orientation = orientation;
    b.velocity = velocity;
    return world.addBody(b);
  }
  void addFloor(const Vec3& normal = Vec3::UnitZ()) { world.addPlane({"floor", Vec3::Zero(), normal, material}); }
};

} // namespace armour::test
