// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Xbloc.cpp
/// An Xbloc-like unit (Delta Marine Consultants 2003): a cubic central body with four square legs
/// in an X on both sides and a square nose front and back; every face flat.
///
/// Natural frame (unit height D = 1): the legs lie in the x-z plane at 45 degrees to the vertical,
/// the noses along -/+y. Leg ends and nose ends reach the faces of the D x D x D box.

#include "geometry/GmshSession.hpp"
#include "geometry/shapes/Generators.hpp"

#include <gmsh.h>

#include <cmath>
#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Leg and nose side relative to D (unit: -). Calibrated (bisection on the exact CAD volume) so that
/// this construction gives V = D^3 / 3, the Xbloc volume-height relation published by DMC;
/// test_shapes_slender checks it.
constexpr double kLegWidth = 0.3671;
/// Central cube side relative to D (unit: -).
constexpr double kBodyWidth = 0.5;

/// Corners of a square `side` wide (m) in the plane through `centre` spanned by the unit vectors
/// e1, e2 (sides along e1 and e2), counter-clockwise about e1 x e2.
std::vector<Vec3> square(const Vec3& centre, const Vec3& e1, const Vec3& e2, double side) {
  const double h = 0.5 * side;
  return {centre + h * (e1 - e2), centre + h * (e1 + e2), centre + h * (-e1 + e2), centre - h * (e1 + e2)};
}

/// OCC solid lofted through polygons whose corners correspond in order: two end caps and one
/// quadrilateral per edge between consecutive sections. Callers pass parallel polygons whose
/// corresponding edges are parallel, so every quadrilateral is planar; building the faces as OCC
/// planes (not ruled B-spline patches, as addThruSections would) keeps the boolean fusion fast and
/// exact.
GmshEntity addLoft(const std::vector<std::vector<Vec3>>& sections) {
  namespace occ = gmsh::model::occ;
  const std::size_t n = sections.front().size();
  std::vector<std::vector<int>> points;
  for (const auto& polygon : sections) {
    std::vector<int> tags;
    for (const Vec3& p : polygon) {
      tags.push_back(occ::addPoint(p.x(), p.y(), p.z()));
    }
    points.push_back(tags);
  }
  std::vector<std::vector<int>> rings;  // edges of each section polygon
  std::vector<std::vector<int>> rails;  // edges from one section to the next
  for (std::size_t s = 0; s < points.size(); ++s) {
    std::vector<int> ring;
    for (std::size_t i = 0; i < n; ++i) {
      ring.push_back(occ::addLine(points[s][i], points[s][(i + 1) % n]));
    }
    rings.push_back(ring);
    if (s + 1 < points.size()) {
      std::vector<int> rail;
      for (std::size_t i = 0; i < n; ++i) {
        rail.push_back(occ::addLine(points[s][i], points[s + 1][i]));
      }
      rails.push_back(rail);
    }
  }
  std::vector<int> faces = {occ::addPlaneSurface({occ::addCurveLoop(rings.front())}),
                            occ::addPlaneSurface({occ::addCurveLoop(rings.back())})};
  for (std::size_t s = 0; s + 1 < points.size(); ++s) {
    for (std::size_t i = 0; i < n; ++i) {
      const int loop = occ::addCurveLoop({rings[s][i], rails[s][(i + 1) % n], rings[s + 1][i], rails[s][i]});
      faces.push_back(occ::addPlaneSurface({loop}));
    }
  }
  return {3, occ::addVolume({occ::addSurfaceLoop(faces)})};
}

/// The unit at D = 1 with leg side t (fraction of D).
TriangleMesh buildXbloc(double t, double* cadVolume = nullptr) {
  GmshSession session("xbloc");
  const Vec3 ex = Vec3::UnitX();
  const Vec3 ey = Vec3::UnitY();
  const Vec3 ez = Vec3::UnitZ();
  const double b = kBodyWidth;
  const GmshEntity body = addLoft({square(-0.5 * b * ez, ex, ey, b), square(0.5 * b * ez, ex, ey, b)});
  std::vector<GmshEntity> limbs;
  // Legs: square prisms from the centre along (-/+1, 0, -/+1)/sqrt(2), end faces square to the leg;
  // the outer corners of an end face reach x = z = -/+ D/2 when the axis is 1/sqrt(2) - t/2 long.
  const double length = std::sqrt(0.5) - 0.5 * t;
  for (double sx : {-1.0, 1.0}) {
    for (double sz : {-1.0, 1.0}) {
      const Vec3 axis = Vec3(sx, 0.0, sz).normalized();
      const Vec3 across = Vec3(-sz, 0.0, sx).normalized(); // in the x-z plane, normal to the leg
      limbs.push_back(addLoft({square(Vec3::Zero(), across, ey, t), square(length * axis, across, ey, t)}));
    }
  }
  // Noses: square prisms along -/+y from the centre to the box faces.
  for (double sy : {-1.0, 1.0}) {
    limbs.push_back(addLoft({square(Vec3::Zero(), ez, ex, t), square(0.5 * sy * ey, ez, ex, t)}));
  }
  const auto solid = session.fuse({body}, limbs);
  if (cadVolume != nullptr) {
    *cadVolume = session.occVolume(solid);
  }
  return session.meshSurface(1.0, 0); // planar faces only
}

} // namespace

ShapeGenerator xblocGenerator() {
  ShapeGenerator g;
  g.name = "xbloc";
  g.summary = "Xbloc-like: cubic body with an X of four square legs and two noses";
  g.proportions = "unit height D; central cube 0.5 D; four legs of square section 0.3671 D at 45 degrees in "
                  "the x-z plane (an X seen from the front), two noses of the same section front and back; "
                  "leg and nose ends on the faces of the D x D x D box; V = D^3/3";
  g.source = "Delta Marine Consultants (2003) Xbloc, V = D^3/3 as published in the Xbloc design guidance; "
             "leg width calibrated to that volume; the shape is an approximation of published photos and "
             "drawings, not the proprietary geometry";
  g.build = [](const ShapeParameterValues&) { return buildXbloc(kLegWidth); };
  return g;
}

} // namespace armour::geometry::shapes
