// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/Orientation.hpp"

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <map>
#include <numbers>

namespace armour::analysis {

namespace {

/// Below this |u . n| (of a unit axis) an axis counts as lying in the plane, and below this
/// in-plane length as lying along the normal (unit: -): round-off of a rotation is ~1e-16, so an
/// axis placed in the plane is not split between two azimuths pi apart by the sign of its
/// round-off, and a pole placed on the normal does not get a random azimuth.
constexpr double kInPlane = 1e-12;

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

} // namespace

SlopeFrame SlopeFrame::fromTanAlpha(double tanAlpha, const Eigen::Vector3d& point) {
  if (!std::isfinite(tanAlpha)) {
    core::failInput("slope frame", "tan(alpha) = {}: the slope's gradient along x must be finite", tanAlpha);
  }
  if (!finite(point)) {
    core::failInput("slope frame", "the point on the plane ({}, {}, {}) is not finite", point.x(), point.y(),
                    point.z());
  }
  SlopeFrame f;
  f.origin = point;
  f.upSlope = Eigen::Vector3d(1.0, 0.0, tanAlpha).normalized();
  f.trunk = Eigen::Vector3d::UnitY();
  f.normal = f.upSlope.cross(f.trunk);
  return f;
}

Eigen::Vector3d SlopeFrame::toLocal(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d d = world - origin;
  return {d.dot(upSlope), d.dot(trunk), d.dot(normal)};
}

Eigen::Vector3d SlopeFrame::toWorld(const Eigen::Vector3d& local) const {
  return origin + local.x() * upSlope + local.y() * trunk + local.z() * normal;
}

SlopeFrame fitSlopeFrame(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) {
    core::failInput("slope fit", "{} point(s) given: a plane through the trunk axis needs at least 2 points at "
                                 "different x",
                    points.size());
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i])) {
      core::failInput("slope fit", "point {} = ({}, {}, {}) is not finite", i, points[i].x(), points[i].y(),
                      points[i].z());
    }
    mean += points[i];
  }
  mean /= static_cast<double>(points.size());
  // Least squares of z = a + b x in centred coordinates: b = sum dx dz / sum dx^2 (centring keeps
  // the sums free of the cancellation that raw sums of x^2 suffer far from the origin).
  double sxx = 0.0;
  double sxz = 0.0;
  double spread = 0.0;
  for (const auto& p : points) {
    const double dx = p.x() - mean.x();
    sxx += dx * dx;
    sxz += dx * (p.z() - mean.z());
    spread = std::max(spread, std::abs(dx));
  }
  if (!(spread > 1e-12 * (1.0 + std::abs(mean.x())))) {
    core::failInput("slope fit", "all {} points lie at x = {} m: the slope's gradient along x is undefined",
                    points.size(), mean.x());
  }
  return SlopeFrame::fromTanAlpha(sxz / sxx, mean);
}

AxisAttitude attitude(const Eigen::Vector3d& axisWorld, const SlopeFrame& frame) {
  const double length = axisWorld.norm();
  if (!std::isfinite(length) || length == 0.0) {
    core::failInput("axis attitude", "axis ({}, {}, {}) has no direction (zero or not finite)", axisWorld.x(),
                    axisWorld.y(), axisWorld.z());
  }
  Eigen::Vector3d u = axisWorld / length;
  double un = u.dot(frame.normal);
  if (un > kInPlane) {
    u = -u; // the lower-hemisphere pole: the end pointing into the slope
    un = -un;
  }
  const double alongT = u.dot(frame.trunk);
  const double alongDown = -u.dot(frame.upSlope);
  AxisAttitude a;
  // asin loses accuracy near pi/2; atan2 of the normal and in-plane parts does not.
  const double inPlane = std::hypot(alongT, alongDown);
  a.dip = std::atan2(std::max(-un, 0.0), inPlane);
  if (inPlane <= kInPlane) {
    a.dipAzimuth = 0.0; // along -n to round-off: no azimuth
    return a;
  }
  double b = std::atan2(alongDown, alongT);
  if (std::abs(un) <= kInPlane) {
    // In the plane: both ends qualify; keep the one with azimuth in [0, pi).
    if (b < 0.0) {
      b += std::numbers::pi;
    }
    if (b >= std::numbers::pi) {
      b -= std::numbers::pi;
    }
    a.dip = 0.0;
  } else if (b < 0.0) {
    b += 2.0 * std::numbers::pi;
  }
  // atan2 can return exactly pi for -0 inputs; and b + 2 pi can round to 2 pi: fold into range.
  if (b >= 2.0 * std::numbers::pi) {
    b = 0.0;
  }
  a.dipAzimuth = b;
  return a;
}

Eigen::Vector3d axisFromAttitude(const AxisAttitude& a, const SlopeFrame& frame) {
  const Eigen::Vector3d inPlane = std::cos(a.dipAzimuth) * frame.trunk - std::sin(a.dipAzimuth) * frame.upSlope;
  return std::cos(a.dip) * inPlane - std::sin(a.dip) * frame.normal;
}

std::vector<Eigen::Vector3d> noseAxesWorld(const std::vector<Eigen::Quaterniond>& orientations,
                                           const Eigen::Vector3d& noseAxisBody) {
  const double length = noseAxisBody.norm();
  if (!std::isfinite(length) || length == 0.0) {
    core::failInput("nose axes", "body axis ({}, {}, {}) has no direction (zero or not finite)", noseAxisBody.x(),
                    noseAxisBody.y(), noseAxisBody.z());
  }
  const Eigen::Vector3d a = noseAxisBody / length;
  std::vector<Eigen::Vector3d> axes;
  axes.reserve(orientations.size());
  for (std::size_t i = 0; i < orientations.size(); ++i) {
    const double qn = orientations[i].norm();
    if (!std::isfinite(qn) || qn == 0.0) {
      core::failInput("nose axes", "unit {}: orientation quaternion (w {}, x {}, y {}, z {}) is zero or not finite",
                      i, orientations[i].w(), orientations[i].x(), orientations[i].y(), orientations[i].z());
    }
    axes.push_back(orientations[i].normalized() * a);
  }
  return axes;
}

Eigen::Vector2d stereonetPoint(const AxisAttitude& a) {
  // Equal area: the cap of half-angle theta = pi/2 - dip about the pole -n has solid angle
  // 2 pi (1 - cos theta) = 4 pi sin^2(theta/2), half the hemisphere's 2 pi times r^2 with
  // r = sqrt(2) sin(theta/2).
  const double theta = 0.5 * std::numbers::pi - a.dip;
  const double r = std::numbers::sqrt2 * std::sin(0.5 * theta);
  return {-r * std::cos(a.dipAzimuth), -r * std::sin(a.dipAzimuth)};
}

namespace {

const std::map<std::string, std::vector<UnitAxis>>& axisTable() {
  using V = Eigen::Vector3d;
  static const std::map<std::string, std::vector<UnitAxis>> table = {
      {"coreloc",
       {{"nose", V::UnitX(), "axis of the central member (assumed nose: seed 000 does not define it)"},
        {"outer", V::UnitZ(), "axis of the two parallel outer members"},
        {"normal", V::UnitY(), "normal to the plane of the unit"}}},
      {"xbloc",
       {{"nose", V::UnitY(), "axis of the two noses"},
        {"up", V::UnitZ(), "the vertical of the legs' X (bisecting it, in its plane)"}}},
      {"dolos",
       {{"nose", V::UnitZ(), "the shank (the dolos has no nose; its main axis)"},
        {"shank", V::UnitZ(), "axis of the shank"},
        {"upper-fluke", V::UnitX(), "axis of the upper fluke (normal to the shank)"},
        {"lower-fluke", V::UnitY(), "axis of the lower fluke (normal to the shank)"}}},
      {"antifer", {{"nose", V::UnitZ(), "taper axis, from the base to the narrower top"}}},
      {"cube",
       {{"nose", V::UnitZ(), "the aspect_z edge"},
        {"x", V::UnitX(), "the x edge"},
        {"y", V::UnitY(), "the aspect_y edge"}}},
      {"accropode",
       {{"nose", V::UnitZ(), "the body (central prism) axis"},
        {"upper-horns", V::UnitX(), "axis of the upper pair of horns"},
        {"lower-horns", V::UnitY(), "axis of the lower pair of horns"}}},
      {"tetrapod", {{"nose", V::UnitZ(), "the upper leg, from the centre to its tip"}}},
      {"cubipod", {{"nose", V::UnitZ(), "the cube's z edge"}}},
      {"vcross", {{"nose", V::UnitZ(), "the z arm"}}},
      {"vrcross", {{"nose", V::UnitZ(), "the z arm"}}},
  };
  return table;
}

std::vector<std::string> shapesWithAxes() {
  std::vector<std::string> names;
  for (const auto& [name, axes] : axisTable()) {
    names.push_back(name);
  }
  return names;
}

} // namespace

const std::vector<UnitAxis>& unitAxesOf(const std::string& shapeName) {
  (void)geometry::findShapeGenerator(shapeName); // unknown names: the library's message lists the valid ones
  static const std::vector<UnitAxis> none;
  const auto& table = axisTable();
  const auto it = table.find(shapeName);
  return it == table.end() ? none : it->second;
}

Eigen::Vector3d unitAxisOf(const std::string& shapeName, const std::string& axisName) {
  const auto& axes = unitAxesOf(shapeName);
  if (axes.empty()) {
    core::failInput("unit axis", "shape '{}' has no named axes (a rock has no natural axis); shapes with axes: {}",
                    shapeName, fmt::join(shapesWithAxes(), ", "));
  }
  std::vector<std::string> names;
  for (const auto& a : axes) {
    if (a.name == axisName) {
      return a.body;
    }
    names.push_back(a.name);
  }
  core::failInput("unit axis", "shape '{}' has no axis '{}'; its axes are: {}", shapeName, axisName,
                  fmt::join(names, ", "));
}

Eigen::Vector3d noseAxisOf(const std::string& shapeName) {
  const auto& axes = unitAxesOf(shapeName);
  if (axes.empty()) {
    core::failInput("nose axis", "shape '{}' has no nose or main axis to plot (a rock has no natural axis); "
                                 "shapes with one: {}",
                    shapeName, fmt::join(shapesWithAxes(), ", "));
  }
  return axes.front().body;
}

} // namespace armour::analysis
