// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Dolos.cpp
/// The Dolos (Merrifield, CSIR; Merrifield and Zwamborn 1966): an anchor-like unit of three
/// octagonal members, a straight shank and two flukes, one across each end of the shank, the
/// flukes at 90 degrees to each other.
///
/// Natural frame (overall height C = 1): shank along z, centred at the origin; the upper fluke lies
/// along x, the lower one along y. Every member is C long over its outer faces, so the unit fills a
/// C x C x C box. Sections are regular octagons (flats normal to the frame axes) so every face is
/// planar: the surface mesh needs no curvature refinement.

#include "geometry/GmshSession.hpp"
#include "geometry/shapes/Generators.hpp"
#include "geometry/shapes/PlanarLoft.hpp"

#include <gmsh.h>

#include <cmath>
#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Fluke end width relative to the fluke root width B (unit: -). Calibrated (bisection on the
/// exact CAD volume, waist 0.32) so that this construction gives V = 0.160 C^3 at waist ratio 0.32,
/// the Shore Protection Manual (1984) volume of the standard Dolos; test_shapes_slender checks it.
constexpr double kFlukeEndRatio = 0.5562;

/// A fluke: octagonal, full width B over the middle length B (where the shank joins), tapering
/// linearly to endRatio x B at its flat ends, C = 1 long, along `axis` through `centre`.
GmshEntity addFluke(const Vec3& centre, const Vec3& axis, const Vec3& e1, const Vec3& e2, double waist,
                    double endRatio) {
  const double b = waist;
  return addPlanarLoft({octagonSection(centre - 0.5 * axis, e1, e2, endRatio * b), octagonSection(centre - 0.5 * b * axis, e1, e2, b),
                  octagonSection(centre + 0.5 * b * axis, e1, e2, b), octagonSection(centre + 0.5 * axis, e1, e2, endRatio * b)});
}

/// The Dolos at C = 1 for waist ratio `waist` = B / C and fluke end ratio `endRatio`.
TriangleMesh buildDolos(double waist, double endRatio, double* cadVolume = nullptr) {
  GmshSession session("dolos");
  const Vec3 ex = Vec3::UnitX();
  const Vec3 ey = Vec3::UnitY();
  const Vec3 ez = Vec3::UnitZ();
  // Fluke axes sit half a fluke width inside the overall height, so the fluke's outer face at the
  // shank is the unit's top (bottom) face and the shank's overall length equals C.
  const double zFluke = 0.5 * (1.0 - waist);
  const GmshEntity shank = addPlanarLoft({octagonSection(-zFluke * ez, ex, ey, waist), octagonSection(zFluke * ez, ex, ey, waist)});
  const GmshEntity upper = addFluke(zFluke * ez, ex, ey, ez, waist, endRatio);
  const GmshEntity lower = addFluke(-zFluke * ez, ey, ez, ex, waist, endRatio);
  const auto solid = session.fuse({shank}, {upper, lower});
  if (cadVolume != nullptr) {
    *cadVolume = session.occVolume(solid);
  }
  // Flat faces only: one element size of the unit's height keeps them to a few triangles each.
  return session.meshSurface(1.0, 0);
}

} // namespace

ShapeGenerator dolosGenerator() {
  ShapeGenerator g;
  g.name = "dolos";
  g.summary = "Dolos: octagonal shank with two tapered flukes at 90 degrees (Merrifield, CSIR)";
  g.proportions =
      "overall height C = fluke length = shank length over the fluke faces; shank a regular octagon "
      "B = waist x C across flats; flukes regular octagons B across flats over their middle length B (where "
      "the shank joins), tapering linearly to 0.5562 B at their flat ends; flukes perpendicular to the shank "
      "and to each other; the unit fills a C x C x C box. V/C^3 = 0.1600 at waist 0.32, 0.1691 at 0.33 "
      "(default), 0.1977 at 0.36, 0.2593 at 0.42";
  g.source = "Merrifield and Zwamborn (1966, ICCE, the CSIR Dolos): octagonal members, flat fluke ends. Waist "
             "ratio range: CSIR practice 0.32-0.36, extended to 0.42 after Burcharth and Liu (1992, ICCE), who "
             "varied it to trade strength for stability. Fluke taper calibrated to the Shore Protection Manual "
             "(1984) volume V = 0.16 C^3 at waist 0.32. An approximation of the published drawings (no fillets), "
             "not the CSIR drawing itself";
  g.parameters = {
      {"waist", 0.33, 0.32, 0.42, "-",
       "waist ratio r = shank width across flats / overall height C (CSIR standard about 0.33; a thicker "
       "waist is stronger but less stable per unit mass)"},
  };
  g.build = [](const ShapeParameterValues& p) { return buildDolos(p.get("waist"), kFlukeEndRatio); };
  return g;
}

} // namespace armour::geometry::shapes
