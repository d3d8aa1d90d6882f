// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Accropode.cpp
/// An Accropode-like unit (Sogreah 1980): a central square prism with a pair of truncated-pyramid
/// horns across each end, the two pairs at 90 degrees to each other; every face flat.
///
/// Natural frame (overall height H = 1): the body stands along z, centred at the origin; the upper
/// horns point along -/+x, the lower ones along -/+y. Horn tips reach the body's height, so the unit
/// fills an H x H x H box.

#include "geometry/GmshSession.hpp"
#include "geometry/shapes/Generators.hpp"

#include <gmsh.h>

#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Body side (and horn root side) relative to H (unit: -). Calibrated (bisection on the exact CAD
/// volume) so that this construction gives V = 0.34 H^3, the Accropode volume-height relation
/// quoted from the supplier's design guidance (Dn = 0.70 H); test_shapes_slender checks it.
constexpr double kBodyWidth = 0.4919;
/// Horn tip side relative to its root side (unit: -): the truncated pyramids.
constexpr double kHornTipRatio = 0.5;

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

/// The unit at H = 1 with body side a (fraction of H).
TriangleMesh buildAccropode(double a, double* cadVolume = nullptr) {
  GmshSession session("accropode");
  const Vec3 ex = Vec3::UnitX();
  const Vec3 ey = Vec3::UnitY();
  const Vec3 ez = Vec3::UnitZ();
  const GmshEntity body = addLoft({square(-0.5 * ez, ex, ey, a), square(0.5 * ez, ex, ey, a)});
  // Each horn pair tapers from the full body section on the body's axis to its tips, its root
  // flush with the body's end face; starting on the axis (not at the body's side faces) keeps the
  // horn faces off the body faces, which the boolean fusion handles poorly.
  const double zHorn = 0.5 * (1.0 - a);
  const double tip = kHornTipRatio * a;
  const GmshEntity upper = addLoft({square(zHorn * ez - 0.5 * ex, ey, ez, tip), square(zHorn * ez, ey, ez, a),
                                    square(zHorn * ez + 0.5 * ex, ey, ez, tip)});
  const GmshEntity lower = addLoft({square(-zHorn * ez - 0.5 * ey, ez, ex, tip), square(-zHorn * ez, ez, ex, a),
                                    square(-zHorn * ez + 0.5 * ey, ez, ex, tip)});
  const auto solid = session.fuse({body}, {upper, lower});
  if (cadVolume != nullptr) {
    *cadVolume = session.occVolume(solid);
  }
  return session.meshSurface(1.0, 0); // planar faces only
}

} // namespace

ShapeGenerator accropodeGenerator() {
  ShapeGenerator g;
  g.name = "accropode";
  g.summary = "Accropode-like: square prismatic body with two pairs of truncated-pyramid horns at 90 degrees";
  g.proportions = "overall height H (body length = horn span = H); body square 0.4919 H across; each horn pair a "
                  "truncated pyramid from the full body section on the body axis to 0.5 x that side at the "
                  "tips, flush with the body end; V = 0.340 H^3";
  g.source = "Sogreah (1980) Accropode (Accropode I); V = 0.34 H^3 (Dn = 0.70 H) is the relation commonly quoted "
             "from the supplier's (CLI) design guidance, taken as given, not checked against the CLI drawing. Body "
             "width calibrated to that volume; the shape is an approximation of published photos and drawings, "
             "not the proprietary geometry";
  g.build = [](const ShapeParameterValues&) { return buildAccropode(kBodyWidth); };
  return g;
}

} // namespace armour::geometry::shapes
