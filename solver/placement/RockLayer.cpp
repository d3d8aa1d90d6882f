// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/RockLayer.hpp"

#include "placement/Deposit.hpp"
#include "placement/PlacementSupport.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace armour::placement {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
} // namespace

using namespace detail; // PlacementSupport.hpp
using simulation::BodyId;
using simulation::BodySpec;
using simulation::World;

void depositRocks(simulation::BuiltScene& built, io::Scene& scene, const RockSite& site, const RockPass& pass,
                  const std::vector<std::pair<std::size_t, simulation::ShapeId>>& rockShapes,
                  std::vector<BodyId>& rockBodies, std::vector<AddedBody>& added, spdlog::logger& log) {
  const RockSettings& rs = *pass.settings;
  const std::string& key = pass.key;
  const std::string what = key == "rocks" ? "rock underlayer" : "toe berm";
  World& world = *built.world;
  const std::size_t rockMaterial = resolveMaterial(scene, rs.material.empty() ? site.unitMaterial : rs.material,
                                                   "placement." + key + ".material");
  const Quat frame = slopeFrame(site.slope->tanAlpha), toFrame = frame.conjugate();
  double rockRadius = 0.0;
  for (const auto& [s, id] : rockShapes) rockRadius = std::max(rockRadius, world.shape(id).radius);
  const double maxScale = rs.dn50 * std::pow(rs.grading, 0.25);
  Deposit rockDeposit = makeDeposit(built, toFrame, 2.0 * std::max(rockRadius * maxScale, 0.5 * site.unitDn));
  for (BodyId b = 0; b < world.bodies().size(); ++b) addWorldBody(rockDeposit, world, b, toFrame);
  const Vec3 originFrame = toFrame * Vec3(site.slope->origin.x(), 0.0, site.slope->origin.y());
  const double x0 = originFrame.x() + pass.s0, x1 = originFrame.x() + pass.s1;
  const double y0 = site.y0, y1 = site.y1;
  // A jittered grid of drop points (random sequential drops cluster and leave holes).
  const double area = (x1 - x0) * (y1 - y0);
  const double spacing = std::sqrt(area / std::max(1, rs.count));
  const int cols = std::max(1, static_cast<int>(std::round((y1 - y0) / spacing)));
  const int rowsR = std::max(1, (rs.count + cols - 1) / cols);
  const double dxr = (x1 - x0) / rowsR, dyr = (y1 - y0) / cols;
  std::size_t laid = 0;
  for (int i = 0; i < (site.resuming ? 0 : rs.count); ++i) {
    std::mt19937_64 rng = stream(site.seed ^ pass.salt, static_cast<std::uint64_t>(i));
    const int layerPass = i / (rowsR * cols);
    const int k = i % (rowsR * cols);
    const double px = x0 + (k / cols + 0.5 + 0.6 * (uniform(rng) - 0.5) + 0.5 * layerPass) * dxr;
    const double py = y0 + (k % cols + 0.5 + 0.6 * (uniform(rng) - 0.5) + 0.5 * layerPass) * dyr;
    const auto& [sceneShape, shapeId] = rockShapes[rng() % rockShapes.size()];
    const simulation::ShapeModel& model = world.shape(shapeId);
    // Log-uniform nominal diameter between Dn50 / sqrt(g) and Dn50 sqrt(g): Dn85 / Dn15 = g^0.7.
    const double rockDn = rs.dn50 * std::pow(rs.grading, uniform(rng) - 0.5);
    const double scale = rockDn / std::cbrt(model.unitMass.volume);
    Placed best;
    Quat bestNatural = Quat::Identity();
    bool found = false;
    for (int t = 0; t < std::max(1, rs.tries) * 4 && !(found && t >= rs.tries); ++t) {
      const Quat natural = uniformRotation(rng);
      Placed u;
      u.shape = &model;
      u.scale = scale;
      u.R = (toFrame * natural * model.naturalToBody.conjugate()).toRotationMatrix();
      u.radius = model.radius * scale;
      u.x = Vec3(px, py, 0.0);
      if (!rockDeposit.lower(u, 0.05 * rockDn, rs.clearance * rockDn)) continue;
      if (!found || u.x.z() < best.x.z()) {
        best = u;
        bestNatural = natural;
        found = true;
      }
    }
    if (!found) continue; // nothing fits here (a wall corner): the next drop point
    const Mat3 before = best.R;
    rockDeposit.slideDown(best, 6, 0.25 * rockDn, 15.0 * kDeg, 0.05 * rockDn, rs.clearance * rockDn, rng);
    // The orientation change of the slide, applied to the natural frame (in world axes).
    const Quat tiltFrame(Mat3(best.R * before.transpose()));
    const Quat natural = (frame * tiltFrame * toFrame * bestNatural).normalized();
    rockDeposit.add(best);
    BodySpec spec;
    spec.name = fmt::format("rock_{:04d}", rockBodies.size());
    spec.shape = shapeId;
    spec.scale = scale;
    spec.material = static_cast<simulation::MaterialId>(rockMaterial);
    spec.fixed = true;
    spec.position = frame * best.x;
    spec.orientation = natural;
    const BodyId b = world.addBody(spec);
    rockBodies.push_back(b);
    ++laid;
    added.push_back({spec.name, sceneShape, scale, rockMaterial, rockDn * rockDn * rockDn, true});
    if (laid % 500 == 0) log.info("{}: {} of {} rocks", what, laid, rs.count);
    scene.bodies.push_back(sceneBody(world, b, spec.name, sceneShape, rockMaterial, rockDn * rockDn * rockDn, true));
  }
  if (!site.resuming)
    log.info("{}: {} rocks (Dn50 {:.3g} m, grading {:.3g}) on {:.1f} x {:.1f} m", what, laid, rs.dn50, rs.grading,
              x1 - x0, y1 - y0);
}

} // namespace armour::placement
