// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/PackGeometry.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <utility>

namespace armour::analysis {

namespace {

void requireWindow(const SlopeWindow& w, const char* where) {
  if (!std::isfinite(w.s0) || !std::isfinite(w.s1) || !std::isfinite(w.t0) || !std::isfinite(w.t1) ||
      !(w.s1 > w.s0) || !(w.t1 > w.t0)) {
    core::failInput(where, "slope window s [{}, {}) m, t [{}, {}) m is empty, inverted or not finite: give s0 < s1 "
                           "and t0 < t1",
                    w.s0, w.s1, w.t0, w.t1);
  }
}

/// Dn of unit i from a per-unit list or a single value, checked.
double dnOf(const std::vector<double>& dn, std::size_t i, const char* where) {
  const double d = dn.size() == 1 ? dn.front() : dn[i];
  if (!std::isfinite(d) || d <= 0.0) {
    core::failInput(where, "unit {}: Dn = {} m: the nominal diameter must be positive and finite", i, d);
  }
  return d;
}

void requireSizes(std::size_t count, const std::vector<double>& dn, const char* where) {
  if (dn.size() != count && dn.size() != 1) {
    core::failInput(where, "{} positions but {} Dn values: give one Dn for all units or one per unit", count,
                    dn.size());
  }
}

void requireFinite(const Eigen::Vector3d& p, std::size_t i, const char* where) {
  if (!p.allFinite()) {
    core::failInput(where, "unit {}: position ({}, {}, {}) is not finite", i, p.x(), p.y(), p.z());
  }
}

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

} // namespace

bool SlopeWindow::contains(const SlopeFrame& frame, const Eigen::Vector3d& point) const {
  return containsLocal(frame.toLocal(point));
}

double packingDensity(std::size_t count, double dn, double area) {
  if (!std::isfinite(dn) || dn <= 0.0) {
    core::failInput("packing density", "Dn = {} m: the nominal diameter must be positive and finite", dn);
  }
  if (!std::isfinite(area) || area <= 0.0) {
    core::failInput("packing density", "area = {} m^2: the slope area must be positive and finite", area);
  }
  return static_cast<double>(count) * dn * dn / area;
}

PackingDensity packingDensityInWindow(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& dn,
                                      const SlopeFrame& frame, const SlopeWindow& window) {
  constexpr const char* where = "packing density (window)";
  requireWindow(window, where);
  requireSizes(positions.size(), dn, where);
  PackingDensity r;
  r.area = window.area();
  double sumDn2 = 0.0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    requireFinite(positions[i], i, where);
    const double d = dnOf(dn, i, where);
    if (window.contains(frame, positions[i])) {
      r.units.push_back(i);
      sumDn2 += d * d;
    }
  }
  r.count = r.units.size();
  r.phi = sumDn2 / r.area;
  return r;
}

double convexHullArea(std::vector<Eigen::Vector2d> points) {
  if (points.size() < 3) {
    return 0.0;
  }
  // Andrew's monotone chain, then the shoelace formula.
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) { // lower hull
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], p) <= 0.0) {
      --k;
    }
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) { // upper hull
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0.0) {
      --k;
    }
    hull[k++] = points[i];
  }
  hull.resize(k - 1); // the last point repeats the first
  double twice = 0.0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const auto& a = hull[i];
    const auto& b = hull[(i + 1) % hull.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * std::abs(twice);
}

PackingDensity packingDensityHull(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& dn,
                                  const SlopeFrame& frame) {
  constexpr const char* where = "packing density (hull)";
  requireSizes(positions.size(), dn, where);
  std::vector<Eigen::Vector2d> projected;
  PackingDensity r;
  double sumDn2 = 0.0;
  // Centred on the mean so that the hull's shoelace sum does not cancel far from the origin.
  for (std::size_t i = 0; i < positions.size(); ++i) {
    requireFinite(positions[i], i, where);
    const double d = dnOf(dn, i, where);
    const Eigen::Vector3d local = frame.toLocal(positions[i]);
    projected.emplace_back(local.x(), local.y());
    r.units.push_back(i);
    sumDn2 += d * d;
  }
  if (!projected.empty()) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : projected) mean += p;
    mean /= static_cast<double>(projected.size());
    for (auto& p : projected) p -= mean;
  }
  r.area = convexHullArea(projected);
  if (!(r.area > 0.0)) {
    core::failInput(where, "the {} centroids projected on the slope plane span no area (fewer than 3, or all in a "
                           "line): use a window instead",
                    positions.size());
  }
  r.count = positions.size();
  r.phi = sumDn2 / r.area;
  return r;
}

double layerCoefficient(double thickness, int layers, double dn) {
  if (layers < 1 || !(dn > 0.0) || !std::isfinite(thickness)) {
    core::failInput("layer coefficient", "thickness {} m, {} layer(s), Dn {} m: need layers >= 1, Dn > 0 and a "
                                         "finite thickness",
                    thickness, layers, dn);
  }
  return thickness / (layers * dn);
}

double porosityFromPackingDensity(double phi, int layers, double k) {
  if (layers < 1 || !(k > 0.0) || !std::isfinite(phi)) {
    core::failInput("layer porosity", "phi {}, {} layer(s), k_D {}: need layers >= 1, k_D > 0 and a finite phi",
                    phi, layers, k);
  }
  return 1.0 - phi / (layers * k);
}

Eigen::Vector2d normalExtent(const geometry::TriangleMesh& bodyMesh, const Eigen::Vector3d& position,
                             const Eigen::Quaterniond& orientation, const SlopeFrame& frame) {
  if (bodyMesh.vertices.empty()) {
    core::failInput("normal extent", "the unit's mesh has no vertices");
  }
  // n . (c + R v) - n . o = n . (c - o) + (R^T n) . v: one rotation instead of one per vertex.
  const Eigen::Vector3d nBody = orientation.normalized().conjugate() * frame.normal;
  const double offset = frame.normal.dot(position - frame.origin);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (const auto& v : bodyMesh.vertices) {
    const double h = nBody.dot(v);
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  return {offset + lo, offset + hi};
}

LayerThickness layerThickness(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& tops,
                              const std::vector<double>& dn, const SlopeFrame& frame, const SlopeWindow& window,
                              int layers) {
  constexpr const char* where = "layer thickness";
  requireWindow(window, where);
  requireSizes(positions.size(), dn, where);
  if (tops.size() != positions.size()) {
    core::failInput(where, "{} positions but {} unit tops: give one top height per unit", positions.size(),
                    tops.size());
  }
  if (layers < 1) {
    core::failInput(where, "layers = {}: the armour has at least one layer", layers);
  }
  LayerThickness r;
  double sumTop = 0.0;
  double sumDn = 0.0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    requireFinite(positions[i], i, where);
    const double d = dnOf(dn, i, where);
    if (!std::isfinite(tops[i])) {
      core::failInput(where, "unit {}: top height {} m is not finite", i, tops[i]);
    }
    if (window.contains(frame, positions[i])) {
      ++r.count;
      sumTop += tops[i];
      sumDn += d;
    }
  }
  if (r.count == 0) {
    core::failInput(where, "no unit centroid falls in the window s [{}, {}) m, t [{}, {}) m", window.s0, window.s1,
                    window.t0, window.t1);
  }
  const double c = static_cast<double>(r.count);
  r.thickness = sumTop / c;
  r.layerCoefficient = r.thickness / (layers * (sumDn / c));
  return r;
}

double halton(std::uint64_t index, unsigned base) {
  double f = 1.0;
  double r = 0.0;
  const double inv = 1.0 / static_cast<double>(base);
  while (index > 0) {
    f *= inv;
    r += f * static_cast<double>(index % base);
    index /= base;
  }
  return r;
}

std::vector<SlabPorosity> porosityProfile(const InsideTest& inside, const SlopeFrame& frame, const SlopeWindow& window,
                                          double n0, double n1, std::size_t slabs, std::size_t samplesPerSlab) {
  constexpr const char* where = "porosity";
  requireWindow(window, where);
  if (!std::isfinite(n0) || !std::isfinite(n1) || !(n1 > n0)) {
    core::failInput(where, "slope-normal range [{}, {}) m: give n0 < n1, both finite", n0, n1);
  }
  if (slabs == 0 || samplesPerSlab == 0) {
    core::failInput(where, "{} slab(s) of {} sample(s): need at least one of each", slabs, samplesPerSlab);
  }
  if (!inside) {
    core::failInput(where, "no inside(point) test given");
  }
  std::vector<SlabPorosity> out(slabs);
  const double h = (n1 - n0) / static_cast<double>(slabs);
  for (std::size_t k = 0; k < slabs; ++k) {
    SlabPorosity& slab = out[k];
    slab.n0 = n0 + h * static_cast<double>(k);
    slab.n1 = k + 1 == slabs ? n1 : n0 + h * static_cast<double>(k + 1);
    slab.volume = window.area() * (slab.n1 - slab.n0);
    slab.samples = samplesPerSlab;
    for (std::size_t i = 0; i < samplesPerSlab; ++i) {
      // Index from 1: index 0 is the corner (0, 0, 0) of every base, a point on the slab's faces.
      const std::uint64_t j = i + 1;
      const Eigen::Vector3d local(window.s0 + halton(j, 2) * (window.s1 - window.s0),
                                  window.t0 + halton(j, 3) * (window.t1 - window.t0),
                                  slab.n0 + halton(j, 5) * (slab.n1 - slab.n0));
      if (inside(frame.toWorld(local))) {
        ++slab.solid;
      }
    }
    const double fraction = static_cast<double>(slab.solid) / static_cast<double>(slab.samples);
    slab.porosity = 1.0 - fraction;
    slab.standardError = std::sqrt(fraction * (1.0 - fraction) / static_cast<double>(slab.samples));
  }
  return out;
}

double porosityFromCount(double count, double unitVolume, double slabVolume) {
  if (!(count >= 0.0) || !(unitVolume > 0.0) || !(slabVolume > 0.0) || !std::isfinite(count) ||
      !std::isfinite(unitVolume) || !std::isfinite(slabVolume)) {
    core::failInput("porosity", "{} units of {} m^3 in {} m^3: need count >= 0 and positive finite volumes", count,
                    unitVolume, slabVolume);
  }
  return 1.0 - count * unitVolume / slabVolume;
}

double windingNumber(const geometry::TriangleMesh& mesh, const Eigen::Vector3d& point) {
  double total = 0.0;
  for (const auto& f : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[f[0]] - point;
    const Eigen::Vector3d b = mesh.vertices[f[1]] - point;
    const Eigen::Vector3d c = mesh.vertices[f[2]] - point;
    const double la = a.norm();
    const double lb = b.norm();
    const double lc = c.norm();
    // Van Oosterom and Strackee (1983): tan(Omega / 2) = a . (b x c) / (|a||b||c| + (a.b)|c| +
    // (a.c)|b| + (b.c)|a|); atan2 keeps the quadrant, so Omega is right for large solid angles.
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    total += 2.0 * std::atan2(num, den);
  }
  return total / (4.0 * std::numbers::pi);
}

bool insideMesh(const geometry::TriangleMesh& mesh, const Eigen::Vector3d& point) {
  return windingNumber(mesh, point) > 0.5;
}

InsideTest insideAnyUnit(const std::vector<geometry::TriangleMesh>& shapes, const std::vector<std::size_t>& shapeOfUnit,
                         const std::vector<Eigen::Vector3d>& positions,
                         const std::vector<Eigen::Quaterniond>& orientations) {
  constexpr const char* where = "inside test";
  if (shapeOfUnit.size() != positions.size() || orientations.size() != positions.size()) {
    core::failInput(where, "{} shape indices, {} positions, {} orientations: give one of each per unit",
                    shapeOfUnit.size(), positions.size(), orientations.size());
  }
  struct Placed {
    std::vector<geometry::TriangleMesh> shapes;
    std::vector<double> radius; // bounding sphere about the body origin, per shape (m)
    std::vector<std::size_t> shapeOf;
    std::vector<Eigen::Vector3d> centre;
    std::vector<Eigen::Quaterniond> toBody;
  };
  auto data = std::make_shared<Placed>();
  data->shapes = shapes;
  for (const auto& s : shapes) {
    double r = 0.0;
    for (const auto& v : s.vertices) r = std::max(r, v.norm());
    data->radius.push_back(r);
  }
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (shapeOfUnit[i] >= shapes.size()) {
      core::failInput(where, "unit {}: shape index {} but {} shape(s) given", i, shapeOfUnit[i], shapes.size());
    }
    requireFinite(positions[i], i, where);
    const double qn = orientations[i].norm();
    if (!std::isfinite(qn) || qn == 0.0) {
      core::failInput(where, "unit {}: orientation quaternion is zero or not finite", i);
    }
  }
  data->shapeOf = shapeOfUnit;
  data->centre = positions;
  for (const auto& q : orientations) data->toBody.push_back(q.normalized().conjugate());
  return [data](const Eigen::Vector3d& p) {
    for (std::size_t i = 0; i < data->centre.size(); ++i) {
      const Eigen::Vector3d d = p - data->centre[i];
      const std::size_t s = data->shapeOf[i];
      if (d.squaredNorm() > data->radius[s] * data->radius[s]) {
        continue;
      }
      if (insideMesh(data->shapes[s], data->toBody[i] * d)) {
        return true;
      }
    }
    return false;
  };
}

PackContacts contactNumbers(const std::vector<Contact>& contacts, const std::vector<BodyRole>& roles, double minForce) {
  constexpr const char* where = "contact numbers";
  if (!std::isfinite(minForce) || minForce < 0.0) {
    core::failInput(where, "minimum force {} N: must be finite and non-negative", minForce);
  }
  // Merge the entries of each pair (unordered) into the pair force.
  std::map<std::pair<std::size_t, std::size_t>, double> pairs;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    if (c.bodyA >= roles.size() || c.bodyB >= roles.size()) {
      core::failInput(where, "contact {}: bodies {} and {} but only {} bodies have a role", k, c.bodyA, c.bodyB,
                      roles.size());
    }
    if (c.bodyA == c.bodyB) {
      core::failInput(where, "contact {}: body {} touches itself", k, c.bodyA);
    }
    if (!std::isfinite(c.force) || c.force < 0.0) {
      core::failInput(where, "contact {} (bodies {}, {}): force {} N must be a finite magnitude (>= 0)", k, c.bodyA,
                      c.bodyB, c.force);
    }
    pairs[std::minmax(c.bodyA, c.bodyB)] += c.force;
  }
  PackContacts r;
  r.bodies.resize(roles.size());
  for (const auto& [pair, force] : pairs) {
    if (force < minForce) {
      continue;
    }
    const auto [a, b] = pair;
    const bool unitA = roles[a] == BodyRole::unit;
    const bool unitB = roles[b] == BodyRole::unit;
    if (!unitA && !unitB) {
      continue;
    }
    if (unitA && unitB) {
      ++r.unitUnitPairs;
      ++r.bodies[a].unitNeighbours;
      ++r.bodies[b].unitNeighbours;
    } else {
      ++r.unitSupportPairs;
      ++r.bodies[unitA ? a : b].supportNeighbours;
    }
    for (const std::size_t u : {a, b}) {
      if (roles[u] == BodyRole::unit) {
        r.bodies[u].maxForce = std::max(r.bodies[u].maxForce, force);
        r.maxForce = std::max(r.maxForce, force);
      }
    }
  }
  std::size_t sum = 0;
  bool first = true;
  for (std::size_t i = 0; i < roles.size(); ++i) {
    if (roles[i] != BodyRole::unit) {
      continue;
    }
    UnitContacts& u = r.bodies[i];
    u.contactNumber = u.unitNeighbours + u.supportNeighbours;
    ++r.unitCount;
    sum += u.contactNumber;
    r.minContactNumber = first ? u.contactNumber : std::min(r.minContactNumber, u.contactNumber);
    r.maxContactNumber = std::max(r.maxContactNumber, u.contactNumber);
    first = false;
  }
  if (r.unitCount > 0) {
    r.coordinationNumber = 2.0 * static_cast<double>(r.unitUnitPairs) / static_cast<double>(r.unitCount);
    r.meanContactNumber = static_cast<double>(sum) / static_cast<double>(r.unitCount);
  }
  return r;
}

} // namespace armour::analysis
