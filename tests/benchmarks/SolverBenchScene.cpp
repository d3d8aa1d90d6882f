// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchScene.hpp"

#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace armour::bench {

Quat randomOrientation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(rng), u2 = u(rng), u3 = u(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double tau = 2.0 * std::numbers::pi;
  return Quat(a * std::sin(tau * u2), a * std::cos(tau * u2), b * std::sin(tau * u3), b * std::cos(tau * u3))
      .normalized();
}

ShapeSet addShapes(World& world, const std::string& kind, int rockShapes, std::uint64_t seed) {
  ShapeSet set;
  set.kind = kind;
  const int count = kind == "rock" ? rockShapes : 1;
  for (int k = 0; k < count; ++k) {
    armour::geometry::ShapeRequest request;
    request.volume = 1.0;
    request.seed = seed + static_cast<std::uint64_t>(k);
    const std::string name = count > 1 ? fmt::format("{}-{}", kind, k) : kind;
    const ShapeId id = world.addShape(name, armour::geometry::makeShape(kind, request));
    set.ids.push_back(id);
    set.radius = std::max(set.radius, world.shape(id).radius);
  }
  return set;
}

double drawScale(const std::string& kind, double dn, std::mt19937_64& rng) {
  if (kind != "rock") {
    return dn;
  }
  std::uniform_real_distribution<double> volume(0.7, 1.3);
  return dn * std::cbrt(volume(rng));
}

namespace {
armour::simulation::ContactSolverKind benchSolver = armour::simulation::ContactSolverKind::Penalty;
double benchSampleListSlack = WorldSettings{}.sampleListSlackPerDn;
double benchSpeculativeMargin = WorldSettings{}.constraint.speculativeMargin;
} // namespace

void setBenchSolver(armour::simulation::ContactSolverKind solver) { benchSolver = solver; }
void setBenchSampleListSlack(double perDn) { benchSampleListSlack = perDn; }
void setBenchSpeculativeMargin(double perDn) { benchSpeculativeMargin = perDn; }

WorldSettings baseSettings(bool sleep) {
  WorldSettings s;
  s.sleep.enabled = sleep;
  s.solver = benchSolver;
  s.sampleListSlackPerDn = benchSampleListSlack;
  s.constraint.speculativeMargin = benchSpeculativeMargin;
  return s;
}

MaterialId addConcrete(World& world, double friction, double restitution) {
  Material m;
  m.name = "concrete";
  m.density = 2400.0;
  m.frictionStatic = friction;
  m.frictionDynamic = friction;
  m.restitution = restitution;
  return world.addMaterial(m);
}

} // namespace armour::bench
