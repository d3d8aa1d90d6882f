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
#include "geometry/shapes/PlanarLoft.hpp"

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

/// The unit at H = 1 with body side a (fraction of H).
TriangleMesh buildAccropode(double a, double* cadVolume = nullptr) {
  GmshSession session("accropode");
  const Vec3 ex = Vec3::UnitX();
  const Vec3 ey = Vec3::UnitY();
  const Vec3 ez = Vec3::UnitZ();
  const GmshEntity body = addPlanarLoft({squareSection(-0.5 * ez, ex, ey, a), squareSection(0.5 * ez, ex, ey, a)});
  // Each horn pair tapers from the full body section on the body's axis to its tips, its root
  // flush with the body's end face; starting on the axis (not at the body's side faces) keeps the
  // horn faces off the body faces, which the boolean fusion handles poorly.
  const double zHorn = 0.5 * (1.0 - a);
  const double tip = kHornTipRatio * a;
  const GmshEntity upper = addPlanarLoft({squareSection(zHorn * ez - 0.5 * ex, ey, ez, tip), squareSection(zHorn * ez, ey, ez, a),
                                    squareSection(zHorn * ez + 0.5 * ex, ey, ez, tip)});
  const GmshEntity lower = addPlanarLoft({squareSection(-zHorn * ez - 0.5 * ey, ez, ex, tip), squareSection(-zHorn * ez, ez, ex, a),
                                    squareSection(-zHorn * ez + 0.5 * ey, ez, ex, tip)});
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
