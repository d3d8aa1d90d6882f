// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/PlacementSupport.hpp"

#include "core/Error.hpp"

#include <cmath>
#include <limits>

namespace armour::placement::detail {

using simulation::BodyId;
using simulation::World;

std::mt19937_64 stream(std::uint64_t seed, std::uint64_t k) {
  std::uint64_t z = seed * 0x9e3779b97f4a7c15ULL + (k + 1) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return std::mt19937_64(z ^ (z >> 31));
}

double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

std::size_t resolveMaterial(const io::Scene& scene, const std::string& name, const std::string& key) {
  const std::ptrdiff_t m = scene.findMaterial(name);
  if (m < 0) {
    std::string names;
    for (const auto& mat : scene.materials) names += (names.empty() ? "" : ", ") + mat.name;
    core::failInput(scene.sourceName, "{} = {}: no such material; the scene has {}", key, name, names);
  }
  return static_cast<std::size_t>(m);
}

Quat slopeFrame(double tanAlpha) { return Quat(Eigen::AngleAxisd(-std::atan(tanAlpha), Vec3::UnitY())); }

Deposit makeDeposit(const simulation::BuiltScene& built, const Quat& toFrame, double cell) {
  const auto& d = built.domain;
  // The plan bounds of the domain in the deposit frame (its corners, rotated).
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c((i & 1) ? d.xMax : d.xMin, (i & 2) ? d.yMax : d.yMin, (i & 4) ? d.depth : -d.depth);
    lo = lo.cwiseMin(toFrame * c);
    hi = hi.cwiseMax(toFrame * c);
  }
  Deposit deposit(lo.x(), hi.x(), lo.y(), hi.y(), cell);
  for (const auto& p : built.planes) deposit.addPlane({toFrame * p.point, toFrame * p.normal});
  for (const auto& piece : built.convexPieces) {
    std::vector<Vec3> corners;
    for (const Vec3& c : piece.corners) corners.push_back(toFrame * c);
    deposit.addPiece(corners);
  }
  return deposit;
}

void addWorldBody(Deposit& deposit, const World& world, BodyId b, const Quat& toFrame) {
  deposit.addBody(world.shape(world.bodyShape(b)), world.bodyScale(b), toFrame * world.bodies().orientation(b),
                  toFrame * world.bodies().position(b));
}

io::Body sceneBody(const World& world, BodyId b, const std::string& name, std::size_t shape, std::size_t material,
                   double volume, bool fixed) {
  io::Body out;
  out.name = name;
  out.shape = shape;
  out.material = material;
  out.volume = volume;
  out.position = world.bodies().position(b);
  out.orientation = world.naturalOrientation(b).normalized();
  out.fixed = fixed;
  return out;
}

} // namespace armour::placement::detail
