// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/Deposit.hpp"

#include "contact/LevelSet.hpp"
#include "contact/NarrowPhase.hpp"
#include "contact/SurfaceSamples.hpp"
#include "geometry/ConvexHull.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace armour::placement {
namespace {

/// The narrow phase's view of a placed body (its shape's samples and level set).
contact::ContactShape contactShape(const Placed& u) {
  return {u.shape->levelSet.get(), u.shape->samples.get(), &u.shape->buckets, u.shape->radius};
}

contact::ContactPose contactPose(const Placed& u) {
  contact::ContactPose p;
  p.position = u.x;
  p.rotation = u.R;
  p.scale = u.scale;
  return p;
}

/// True when a sample of `probe` lies within `clearance` of `target`'s surface or inside it: the
/// narrow phase's own touch test.
bool samplesTouch(const Placed& probe, const Placed& target, double clearance) {
  return contact::anySampleWithin(contactShape(probe), contactPose(probe), contactShape(target), contactPose(target),
                                  clearance);
}

bool touches(const Placed& a, const Placed& b, double clearance) {
  const double reach = a.radius + b.radius + clearance;
  if ((a.x - b.x).squaredNorm() > reach * reach) return false;
  return samplesTouch(a, b, clearance) || samplesTouch(b, a, clearance);
}

/// The lowest extent of u along n: min over its mesh vertices of (R v) . n (m, relative to its centroid).
double lowestAlong(const Placed& u, const Vec3& n) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Vec3& v : u.shape->mesh.vertices) lowest = std::min(lowest, (u.R * (u.scale * v)).dot(n));
  return lowest;
}

} // namespace

Quat uniformRotation(std::mt19937_64& rng) {
  // Shoemake's method on three uniform numbers made by hand from the raw bits (portable, unlike
  // std::uniform_real_distribution).
  const auto unit = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  const double u1 = unit(), u2 = unit(), u3 = unit();
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double tau = 2.0 * std::numbers::pi;
  return Quat(a * std::sin(tau * u2), a * std::cos(tau * u2), b * std::sin(tau * u3), b * std::cos(tau * u3))
      .normalized();
}

Deposit::Deposit(double x0, double x1, double y0, double y1, double cellSize) : x0_(x0), y0_(y0), cell_(cellSize) {
  nx_ = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cellSize)));
  ny_ = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cellSize)));
  columns_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
}

int Deposit::col(double x) const { return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1); }
int Deposit::row(double y) const { return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1); }

void Deposit::addPiece(const std::vector<Vec3>& corners) {
  const geometry::ConvexPolyhedron hull = geometry::convexHullPolyhedron(corners, "deposit piece");
  Piece p;
  p.normals = hull.normals;
  p.offsets = hull.offsets;
  p.lo = p.hi = corners.front();
  for (const Vec3& c : corners) {
    p.lo = p.lo.cwiseMin(c);
    p.hi = p.hi.cwiseMax(c);
  }
  pieces_.push_back(std::move(p));
}

void Deposit::addBody(const simulation::ShapeModel& shape, double scale, const Quat& bodyOrientation,
                      const Vec3& position) {
  Placed o;
  o.shape = &shape;
  o.scale = scale;
  o.R = bodyOrientation.toRotationMatrix();
  o.radius = shape.radius * scale;
  o.x = position;
  insert(o);
}

void Deposit::insert(const Placed& p) {
  maxRadius_ = std::max(maxRadius_, p.radius);
  columns_[static_cast<std::size_t>(row(p.x.y()) * nx_ + col(p.x.x()))].push_back(placed_.size());
  placed_.push_back(p);
}

bool Deposit::clearWalls(Placed& u, double clearance) const {
  for (int pass = 0; pass < 2; ++pass) { // a push off one wall may reach the opposite one
    bool moved = false;
    for (const Plane& pl : planes_) {
      if (std::abs(pl.normal.z()) > 1e-9) continue;
      const double gap = (u.x - pl.point).dot(pl.normal) + lowestAlong(u, pl.normal);
      if (gap < clearance) {
        u.x += (clearance - gap) * pl.normal;
        moved = true;
      }
    }
    if (!moved) return true;
  }
  // Still touching a wall after pushing off both sides: it does not fit.
  for (const Plane& pl : planes_) {
    if (std::abs(pl.normal.z()) > 1e-9) continue;
    if ((u.x - pl.point).dot(pl.normal) + lowestAlong(u, pl.normal) < clearance * (1.0 - 1e-9)) return false;
  }
  return true;
}

double Deposit::staticFloor(const Placed& u, double clearance) const {
  double floorZ = -std::numeric_limits<double>::infinity();
  // Upward planes: z n_z >= clearance + p.n - n_xy . x_xy - min over vertices of (R v) . n.
  for (const Plane& pl : planes_) {
    if (pl.normal.z() <= 1e-9) continue;
    const double lowest = lowestAlong(u, pl.normal);
    const double planar = pl.normal.x() * (u.x.x() - pl.point.x()) + pl.normal.y() * (u.x.y() - pl.point.y());
    floorZ = std::max(floorZ, pl.point.z() + (clearance - planar - lowest) / pl.normal.z());
  }
  if (pieces_.empty()) return floorZ;
  // Convex pieces: each sample, descending, first meets a piece (grown by the clearance) at the
  // lowest of its upward faces' heights over the sample's plan position, if its vertical line
  // passes through the piece at all.
  const double r = u.radius + clearance;
  std::vector<const Piece*> near;
  for (const Piece& p : pieces_) {
    if (u.x.x() + r < p.lo.x() || u.x.x() - r > p.hi.x() || u.x.y() + r < p.lo.y() || u.x.y() - r > p.hi.y()) continue;
    near.push_back(&p);
  }
  if (near.empty()) return floorZ;
  for (const Vec3& s : u.shape->samples->positions()) {
    const Vec3 off = u.R * (u.scale * s);
    const double px = u.x.x() + off.x(), py = u.x.y() + off.y();
    for (const Piece* p : near) {
      if (px < p->lo.x() - clearance || px > p->hi.x() + clearance || py < p->lo.y() - clearance ||
          py > p->hi.y() + clearance)
        continue;
      double top = std::numeric_limits<double>::infinity(), bottom = -top;
      bool misses = false;
      for (std::size_t k = 0; k < p->normals.size() && !misses; ++k) {
        const Vec3& n = p->normals[k];
        const double rest = p->offsets[k] + clearance - n.x() * px - n.y() * py;
        if (n.z() > 1e-9) {
          top = std::min(top, rest / n.z());
        } else if (n.z() < -1e-9) {
          bottom = std::max(bottom, rest / n.z());
        } else if (rest < 0.0) {
          misses = true; // outside a vertical face: the line passes beside the piece
        }
      }
      if (misses || !(top > bottom) || !std::isfinite(top)) continue;
      floorZ = std::max(floorZ, top - off.z());
    }
  }
  return floorZ;
}

template <class F> bool Deposit::anyNear(const Placed& u, double gap, F&& f) const {
  const int cx = col(u.x.x()), cy = row(u.x.y());
  const int reach = static_cast<int>(std::ceil((u.radius + maxRadius_ + gap) / cell_));
  for (int j = std::max(0, cy - reach); j <= std::min(ny_ - 1, cy + reach); ++j) {
    for (int i = std::max(0, cx - reach); i <= std::min(nx_ - 1, cx + reach); ++i) {
      for (const std::size_t k : columns_[static_cast<std::size_t>(j * nx_ + i)]) {
        if (f(k)) return true;
      }
    }
  }
  return false;
}

bool Deposit::touchesBodies(const Placed& u, double clearance) const {
  return anyNear(u, clearance, [&](std::size_t k) { return touches(u, placed_[k], clearance); });
}

std::vector<std::size_t> Deposit::touching(const Placed& u, double clearance) const {
  std::vector<std::size_t> out;
  anyNear(u, clearance, [&](std::size_t k) {
    if (touches(u, placed_[k], clearance)) out.push_back(k);
    return false;
  });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::size_t> Deposit::near(const Placed& u, double gap) const {
  std::vector<std::size_t> out;
  anyNear(u, gap, [&](std::size_t k) {
    const double r = u.radius + placed_[k].radius + gap;
    if ((u.x - placed_[k].x).squaredNorm() < r * r) out.push_back(k);
    return false;
  });
  std::sort(out.begin(), out.end());
  return out;
}

bool Deposit::lower(Placed& u, double step, double clearance, double startZ) const {
  if (!clearWalls(u, clearance)) return false;
  const double floorZ = staticFloor(u, clearance);
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
  // Without a static floor below, the lowest point any neighbour can stop it at.
  double bottom = floorZ;
  if (!std::isfinite(bottom)) {
    if (near.empty()) return false; // nothing below: it would fall for ever
    bottom = std::numeric_limits<double>::infinity();
    for (const Placed* o : near) bottom = std::min(bottom, o->x.z() - (u.radius + o->radius + clearance));
  }
  double free = top; // nothing can touch above the sphere-free height
  if (startZ < top) {
    if (startZ < floorZ || blocked(startZ)) return false;
    free = startZ;
  }
  if (!std::isfinite(free)) free = bottom; // no neighbour and a floor: start on it
  double z = free;
  bool landed = std::isfinite(floorZ);
  while (z > bottom) {
    const double next = std::max(bottom, z - step);
    if (blocked(next)) {
      landed = true;
      double bad = next;
      for (int k = 0; k < 5; ++k) { // to step / 32
        const double mid = 0.5 * (free + bad);
        (blocked(mid) ? bad : free) = mid;
      }
      break;
    }
    free = z = next;
  }
  u.x.z() = free;
  return landed;
}

void Deposit::add(const Placed& p) { insert(p); }

bool Deposit::slideDown(Placed& u, int moves, double shift, double tilt, double step, double clearance,
                        std::mt19937_64& rng, double maxDrift, double lift,
                        const std::function<double(const Placed&)>& cost, double costStep) const {
  const Eigen::Vector2d start = u.x.head<2>();
  double current = cost ? cost(u) : 0.0;
  const auto unit = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  bool movedAny = false;
  for (int failed = 0; failed < moves;) {
    Placed v = u;
    // A random tilt about a uniformly random axis and a random sideways shift.
    const double zc = 2.0 * unit() - 1.0, phi = 2.0 * std::numbers::pi * unit();
    const double rc = std::sqrt(std::max(0.0, 1.0 - zc * zc));
    const Vec3 axis(rc * std::cos(phi), rc * std::sin(phi), zc);
    v.R = Eigen::AngleAxisd(tilt * unit(), axis).toRotationMatrix() * u.R;
    v.x += Vec3(shift * (2.0 * unit() - 1.0), shift * (2.0 * unit() - 1.0), 0.0);
    if ((v.x.head<2>() - start).norm() > maxDrift || !lower(v, step, clearance, u.x.z() + lift)) {
      ++failed;
      continue;
    }
    const double next = cost ? cost(v) : 0.0;
    if (cost ? next < current - 1e-3 * costStep : v.x.z() < u.x.z() - 1e-3 * step) {
      u = v;
      current = next;
      movedAny = true;
      failed = 0;
    } else {
      ++failed;
    }
  }
  return movedAny;
}

} // namespace armour::placement
