// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Xbloc.cpp
/// An Xbloc-like unit (Delta Marine Consultants 2003): a cubic central body with four square legs
/// in an X on both sides and a square nose front and back; every face flat.
///
/// Natural frame (unit height D = 1): the legs lie in the x-z plane at 45 degrees to the vertical,
/// the noses along -/+y. Leg ends and nose ends reach the faces of the D x D x D box.

#include "geometry/GmshSession.hpp"
#include "geometry/shapes/Generators.hpp"
#include "geometry/shapes/PlanarLoft.hpp"

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

/// The unit at D = 1 with leg side t (fraction of D).
TriangleMesh buildXbloc(double t, double* cadVolume = nullptr) {
  GmshSession session("xbloc");
  const Vec3 ex = Vec3::UnitX();
  const Vec3 ey = Vec3::UnitY();
  const Vec3 ez = Vec3::UnitZ();
  const double b = kBodyWidth;
  const GmshEntity body = addPlanarLoft({squareSection(-0.5 * b * ez, ex, ey, b), squareSection(0.5 * b * ez, ex, ey, b)});
  std::vector<GmshEntity> limbs;
  // Legs: square prisms from the centre along (-/+1, 0, -/+1)/sqrt(2), end faces square to the leg;
  // the outer corners of an end face reach x = z = -/+ D/2 when the axis is 1/sqrt(2) - t/2 long.
  const double length = std::sqrt(0.5) - 0.5 * t;
  for (double sx : {-1.0, 1.0}) {
    for (double sz : {-1.0, 1.0}) {
      const Vec3 axis = Vec3(sx, 0.0, sz).normalized();
      const Vec3 across = Vec3(-sz, 0.0, sx).normalized(); // in the x-z plane, normal to the leg
      limbs.push_back(addPlanarLoft({squareSection(Vec3::Zero(), across, ey, t), squareSection(length * axis, across, ey, t)}));
    }
  }
  // Noses: square prisms along -/+y from the centre to the box faces.
  for (double sy : {-1.0, 1.0}) {
    limbs.push_back(addPlanarLoft({squareSection(Vec3::Zero(), ez, ex, t), squareSection(0.5 * sy * ey, ez, ex, t)}));
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
