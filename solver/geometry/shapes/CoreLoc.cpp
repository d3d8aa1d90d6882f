// SPDX-License-Identifier: GPL-3.0-or-later
/// @file CoreLoc.cpp
/// A Core-Loc-like unit (Melby and Turk 1994, USACE; Core-Loc International): a central member
/// joining two parallel outer members, all octagonal in section, with chamfered joins.
///
/// Natural frame (overall height C = 1): the outer members stand along z at x = -/+ (C - w)/2, the
/// central member lies along x between them, so the unit fills a C x w x C box (w: member width
/// across flats). As in the patent (US 5,441,362, claims 1-6) the members are equally long (C over
/// their outer faces) and the outer members are two octagonal frustums joined by an intermediate
/// prism; the joins carry 45-degree chamfers in the plane of the unit (above and below the
/// central member). Every face is planar.

#include "geometry/GmshSession.hpp"
#include "geometry/shapes/Generators.hpp"
#include "geometry/shapes/PlanarLoft.hpp"

#include <gmsh.h>

#include <cmath>
#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Member width across flats relative to C (unit: -). Calibrated (bisection on the exact CAD volume)
/// so that this construction gives V = 0.22 C^3, the Core-Loc volume relation of the USACE/CLI
/// guidance (C = unit height); test_shapes_slender checks it.
constexpr double kMemberWidth = 0.3561;
/// Outer-member end width relative to its middle width (unit: -): the tapering "frustum" ends.
constexpr double kEndRatio = 0.65;
/// Chamfer leg at each join relative to the member width (unit: -).
constexpr double kChamferRatio = 0.25;
/// Central-member width at the outer members' axes relative to its middle width (unit: -).
constexpr double kCentralEndRatio = 0.85;

/// The unit at C = 1 with member width w (fraction of C).
TriangleMesh buildCoreLoc(double w, double* cadVolume = nullptr) {
  GmshSession session("coreloc");
  const Vec3 ex = Vec3::UnitX();
  const Vec3 ey = Vec3::UnitY();
  const Vec3 ez = Vec3::UnitZ();
  const double c = kChamferRatio * w;
  const double xOuter = 0.5 * (1.0 - w); // outer-member axes: their outer faces are the unit's sides
  const double xInner = xOuter - 0.5 * w; // inner faces of the outer members
  // The intermediate (full-width) part of each outer member spans the chamfers, so the chamfer
  // material meets a flat face rather than a tapering one.
  const double zFull = 0.5 * w + c;
  // The central member is two frustums too (patent claim 3): full width at its middle, tapering
  // towards the outer members' axes. Being narrower than the outer members where it meets them
  // also keeps its faces off theirs (coplanar faces make the OCC fusion slow and fragile).
  const auto centralWidth = [&](double x) { return w * (1.0 - (1.0 - kCentralEndRatio) * std::abs(x) / xOuter); };

  std::vector<GmshEntity> outer;
  for (double side : {-1.0, 1.0}) {
    const Vec3 axis = side * xOuter * ex;
    outer.push_back(addPlanarLoft({octagonSection(axis - 0.5 * ez, ex, ey, kEndRatio * w), octagonSection(axis - zFull * ez, ex, ey, w),
                             octagonSection(axis + zFull * ez, ex, ey, w), octagonSection(axis + 0.5 * ez, ex, ey, kEndRatio * w)}));
  }
  // Central member with its chamfers in one loft: over the last c before each join its top and
  // bottom flats rise (fall) by c, at exactly 45 degrees (the stretch makes up for the taper), then
  // run on into the outer member's axis plane, inside the outer member's full-width part.
  const double stretch = c + 0.5 * (centralWidth(xInner - c) - centralWidth(xInner));
  std::vector<std::vector<Vec3>> sections;
  for (double x : {-xOuter, -xInner, -(xInner - c), 0.0, xInner - c, xInner, xOuter}) {
    sections.push_back(octagonSection(x * ex, ey, ez, centralWidth(x), std::abs(x) >= xInner ? stretch : 0.0));
  }
  const GmshEntity central = addPlanarLoft(sections);
  const auto solid = session.fuse({central}, outer);
  if (cadVolume != nullptr) {
    *cadVolume = session.occVolume(solid);
  }
  return session.meshSurface(1.0, 0); // planar faces only
}

} // namespace

ShapeGenerator coreLocGenerator() {
  ShapeGenerator g;
  g.name = "coreloc";
  g.summary = "Core-Loc-like: central octagonal member joining two parallel outer members, chamfered joins";
  g.proportions =
      "overall height C = length of every member over its outer faces; members regular octagons w = 0.3561 C "
      "across flats; outer members full width over their middle 1.5 w = 0.534 C, tapering linearly to 0.65 w "
      "at their flat ends; central member tapering from w at its middle to 0.85 w at the outer members' axes; "
      "45-degree chamfers with 0.25 w = 0.089 C legs above and below both joins; the unit fills C x 0.3561 C x C; "
      "V = 0.2200 C^3";
  g.source = "Melby and Turk (1994), US patent 5,441,362 (central member, two parallel outer members, octagonal "
             "sections tapering to the ends, chamfered joins, equal member lengths); V = 0.22 C^3 from the "
             "USACE/CLI guidance. Member width calibrated to that volume; taper and chamfer sizes are an "
             "approximation of published drawings, not the proprietary geometry";
  g.build = [](const ShapeParameterValues&) { return buildCoreLoc(kMemberWidth); };
  return g;
}

} // namespace armour::geometry::shapes
