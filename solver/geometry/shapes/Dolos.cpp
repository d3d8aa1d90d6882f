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

#include <gmsh.h>

#include <cmath>
#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Fluke end width relative to the fluke root width B (unit: -). Calibrated (bisection on the
/// exact CAD volume, waist 0.32) so that this construction gives V = 0.160 C^3 at waist ratio 0.32,
/// the Shore Protection Manual (1984) volume of the standard Dolos; test_shapes_slender checks it.
constexpr double kFlukeEndRatio = 0.5562;

/// Corners of a regular octagon, `width` across flats (m), in the plane through `centre` spanned by
/// the unit vectors e1, e2, with flats normal to e1 and e2; counter-clockwise about e1 x e2.
std::vector<Vec3> octagon(const Vec3& centre, const Vec3& e1, const Vec3& e2, double width) {
  const double h = 0.5 * width;
  const double q = h * (std::sqrt(2.0) - 1.0); // half side: the eight sides are equal
  const double a[8][2] = {{h, -q}, {h, q}, {q, h}, {-q, h}, {-h, q}, {-h, -q}, {-q, -h}, {q, -h}};
  std::vector<Vec3> corners;
  for (const auto& p : a) {
    corners.push_back(centre + p[0] * e1 + p[1] * e2);
  }
  return corners;
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

/// A fluke: octagonal, full width B over the middle length B (where the shank joins), tapering
/// linearly to endRatio x B at its flat ends, C = 1 long, along `axis` through `centre`.
GmshEntity addFluke(const Vec3& centre, const Vec3& axis, const Vec3& e1, const Vec3& e2, double waist,
                    double endRatio) {
  const double b = waist;
  return addLoft({octagon(centre - 0.5 * axis, e1, e2, endRatio * b), octagon(centre - 0.5 * b * axis, e1, e2, b),
                  octagon(centre + 0.5 * b * axis, e1, e2, b), octagon(centre + 0.5 * axis, e1, e2, endRatio * b)});
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
  const GmshEntity shank = addLoft({octagon(-zFluke * ez, ex, ey, waist), octagon(zFluke * ez, ex, ey, waist)});
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
