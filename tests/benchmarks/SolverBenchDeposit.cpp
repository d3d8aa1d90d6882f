// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchDeposit.hpp"

#include <stdexcept>
#include <utility>

namespace armour::bench {
namespace {

/// True when a sample of `probe` lies within `clearance` of `target`'s surface or inside it
/// (the narrow phase's own test: surface samples against the level set).
bool samplesTouch(const Placed& probe, const Placed& target, double clearance) {
  const auto& ls = *target.shape->levelSet;
  const double reach = target.radius + clearance;
  const Vec3 grow = Vec3::Constant(clearance / target.scale + std::sqrt(3.0) * ls.cellSize());
  const Vec3 lo = ls.meshBounds().min - grow, hi = ls.meshBounds().max + grow;
  const armour::geometry::Mat3 toTarget = target.R.transpose() * probe.R * (probe.scale / target.scale);
  const Vec3 offset = target.R.transpose() * (probe.x - target.x) / target.scale;
  const Vec3 probeInTarget = probe.x - target.x;
  for (const Vec3& p : probe.shape->samples->positions()) {
    const Vec3 X = probeInTarget + probe.R * (probe.scale * p);
    if (X.squaredNorm() > reach * reach) {
      continue;
    }
    const Vec3 L = toTarget * p + offset;
    if ((L.array() < lo.array()).any() || (L.array() > hi.array()).any()) {
      continue;
    }
    if (ls.value(L) * target.scale < clearance) {
      return true;
    }
  }
  return false;
}

bool touches(const Placed& a, const Placed& b, double clearance) {
  const double reach = a.radius + b.radius + clearance;
  if ((a.x - b.x).squaredNorm() > reach * reach) {
    return false;
  }
  return samplesTouch(a, b, clearance) || samplesTouch(b, a, clearance);
}

} // namespace

Deposit::Deposit(double x0, double x1, double y0, double y1, double cellSize, std::vector<Plane> planes)
    : x0_(x0), x1_(x1), y0_(y0), y1_(y1), cell_(cellSize), planes_(std::move(planes)) {
  nx_ = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cellSize)));
  ny_ = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cellSize)));
  columns_.resize(static_cast<std::size_t>(nx_ * ny_));
}

void Deposit::addObstacle(const armour::simulation::ShapeModel& shape, double scale, const Quat& bodyOrientation,
                          const Vec3& position) {
  Placed o;
  o.shape = &shape;
  o.scale = scale;
  o.R = bodyOrientation.toRotationMatrix();
  o.radius = shape.radius * scale;
  o.x = position;
  insert(o);
}

Deposit::Result Deposit::place(const armour::simulation::ShapeModel& shape, double scale, double dn, double clearance,
                               int tries, int moves, std::mt19937_64& rng, const Vec3* plan) {
  Placed best;
  Quat bestNatural = Quat::Identity();
  double bestZ = std::numeric_limits<double>::infinity();
  std::uniform_real_distribution<double> ux(x0_, x1_), uy(y0_, y1_);
  for (int t = 0, attempts = 0; t < std::max(1, tries) && attempts < 100 * std::max(1, tries); ++attempts) {
    const Quat natural = randomOrientation(rng);
    Placed u;
    u.shape = &shape;
    u.scale = scale;
    u.R = (natural * shape.naturalToBody.conjugate()).toRotationMatrix();
    u.radius = shape.radius * scale;
    u.x = plan != nullptr ? Vec3(plan->x(), plan->y(), kAbove) : Vec3(ux(rng), uy(rng), kAbove);
    if (!lower(u, dn, clearance)) {
      continue; // through a wall: draw again
    }
    ++t;
    if (u.x.z() < bestZ) {
      best = u;
      bestZ = u.x.z();
      bestNatural = natural;
    }
  }
  if (!std::isfinite(bestZ)) {
    throw std::invalid_argument("deposit: no pose of a unit fits between the walls; use fewer --layers or a "
                                "larger box");
  }
  // Slide and tilt downhill.
  std::uniform_real_distribution<double> shift(-0.25 * dn, 0.25 * dn);
  std::uniform_real_distribution<double> angle(0.0, 15.0 * std::numbers::pi / 180.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int failed = 0; failed < moves;) {
    Placed u = best;
    const Vec3 axis = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const Quat tilt(Eigen::AngleAxisd(angle(rng), axis));
    u.R = tilt.toRotationMatrix() * best.R;
    u.x += Vec3(shift(rng), shift(rng), 0.0);
    if (lower(u, dn, clearance) && u.x.z() < best.x.z() - 1e-3 * dn) {
      best = u;
      bestNatural = (tilt * bestNatural).normalized();
      failed = 0;
    } else {
      ++failed;
    }
  }
  insert(best);
  return {best.x, bestNatural};
}

void Deposit::insert(const Placed& p) {
  maxRadius_ = std::max(maxRadius_, p.radius);
  columns_[static_cast<std::size_t>(row(p.x.y()) * nx_ + col(p.x.x()))].push_back(placed_.size());
  placed_.push_back(p);
}

bool Deposit::lower(Placed& u, double dn, double clearance) const {
  // Static planes: walls (horizontal normals) must be cleared here; the others give the lowest
  // height, z n_z >= clearance + p.n - n_xy . x_xy - min over vertices of (R v) . n.
  double floorZ = -std::numeric_limits<double>::infinity();
  for (const Plane& pl : planes_) {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& v : u.shape->mesh.vertices) {
      lowest = std::min(lowest, (u.R * (u.scale * v)).dot(pl.normal));
    }
    const double planar = pl.normal.x() * (u.x.x() - pl.point.x()) + pl.normal.y() * (u.x.y() - pl.point.y());
    if (pl.normal.z() > 1e-9) {
      floorZ = std::max(floorZ, pl.point.z() + (clearance - planar - lowest) / pl.normal.z());
    } else if (planar + lowest < clearance) {
      return false;
    }
  }
  // Neighbours whose bounding spheres can meet this one's at some height.
  std::vector<const Placed*> near;
  double top = floorZ;
  const int cx = col(u.x.x()), cy = row(u.x.y());
  const int reach = static_cast<int>(std::ceil((u.radius + maxRadius_ + clearance) / cell_));
  for (int j = std::max(0, cy - reach); j <= std::min(ny_ - 1, cy + reach); ++j) {
    for (int i = std::max(0, cx - reach); i <= std::min(nx_ - 1, cx + reach); ++i) {
      for (const std::size_t k : columns_[static_cast<std::size_t>(j * nx_ + i)]) {
        const Placed& o = placed_[k];
        const double r = u.radius + o.radius + clearance;
        const double d2 = (o.x.head<2>() - u.x.head<2>()).squaredNorm();
        if (d2 < r * r) {
          near.push_back(&o);
          top = std::max(top, o.x.z() + std::sqrt(r * r - d2));
        }
      }
    }
  }
  const auto blocked = [&](double z) {
    u.x.z() = z;
    return std::any_of(near.begin(), near.end(), [&](const Placed* o) { return touches(u, *o, clearance); });
  };
  double free = top; // the sphere-free height: nothing can touch above it
  if (u.x.z() < top) {
    if (u.x.z() < floorZ || blocked(u.x.z())) {
      return false;
    }
    free = u.x.z();
  }
  const double step = 0.05 * dn;
  double z = free;
  while (z > floorZ) {
    const double next = std::max(floorZ, z - step);
    if (blocked(next)) {
      double bad = next;
      for (int k = 0; k < 5; ++k) { // to Dn / 640
        const double mid = 0.5 * (free + bad);
        (blocked(mid) ? bad : free) = mid;
      }
      break;
    }
    free = z = next;
  }
  u.x.z() = free;
  return true;
}

} // namespace armour::bench
