// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Tetrapod.cpp
/// The Tetrapod (Danel, Sogreah 1950): four legs, each a truncated cone, on the four tetrahedral
/// axes from a common centre (109.47 degrees between any two), flat circular tips.
///
/// Natural frame (overall height H = 1 m): standing on three legs with the fourth along +z, the
/// centre at the origin. A leg's axis runs from the centre to the middle of its tip face, length L;
/// its section shrinks linearly from the base diameter at the centre to the tip diameter. The unit
/// stands on the lowest rim points of the three lower tips, so
///     H = L + L/3 + (2 sqrt(2)/3) R_tip,
/// which fixes L once H and the tip diameter are given.
///
/// The cones are faceted (regular `facets`-gons with their corners on the circles), built as
/// plane-faced frustums and fused with OpenCASCADE. Planar faces make the triangle mesh exact
/// (volume and inertia do not depend on the triangulation), and each lower tip has a corner at its
/// lowest point, so the unit stands on exactly three vertices and its height is exactly H.
///
/// Limitation: each cone starts with a flat root polygon at the centre. With the default
/// proportions (and any at least as slender: tip close to root diameter) the neighbouring legs
/// bury those roots; for strongly tapered legs (root - tip diameter above about 0.25 H) parts of
/// the root polygons show as small flat facets in the crotches, as they would for ideal round
/// cones. The real unit's blended leg roots are not modelled.

#include "core/Error.hpp"
#include "geometry/GmshSession.hpp"
#include "geometry/shapes/Generators.hpp"

#include <gmsh.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Height of the natural-scale unit (m); makeShape rescales to the requested volume.
constexpr double kHeight = 1.0;

/// Corners of a regular polygon of `facets` sides, circumradius `radius` (m), centred at `centre`
/// in the plane spanned by unit vectors e1, e2; the first corner lies along e1.
std::vector<Vec3> regularPolygon(const Vec3& centre, const Vec3& e1, const Vec3& e2, double radius, int facets) {
  std::vector<Vec3> corners;
  for (int i = 0; i < facets; ++i) {
    const double psi = 2.0 * std::numbers::pi * i / facets;
    corners.push_back(centre + radius * (std::cos(psi) * e1 + std::sin(psi) * e2));
  }
  return corners;
}

/// Convex frustum between two polygons whose corners correspond (similar and parallel, so each side
/// is a planar trapezoid), built face by face from plane surfaces. Plane faces keep the fusion fast
/// and exact: OpenCASCADE fuses them ~30 times faster than the same solid lofted by ThruSections,
/// whose ruled faces it treats as general surfaces.
GmshEntity addFrustum(const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
  const std::size_t n = from.size();
  std::vector<int> pointsFrom, pointsTo;
  for (std::size_t i = 0; i < n; ++i) {
    pointsFrom.push_back(gmsh::model::occ::addPoint(from[i].x(), from[i].y(), from[i].z()));
    pointsTo.push_back(gmsh::model::occ::addPoint(to[i].x(), to[i].y(), to[i].z()));
  }
  std::vector<int> edgesFrom, edgesTo, edgesSide;
  for (std::size_t i = 0; i < n; ++i) {
    edgesFrom.push_back(gmsh::model::occ::addLine(pointsFrom[i], pointsFrom[(i + 1) % n]));
    edgesTo.push_back(gmsh::model::occ::addLine(pointsTo[i], pointsTo[(i + 1) % n]));
    edgesSide.push_back(gmsh::model::occ::addLine(pointsFrom[i], pointsTo[i]));
  }
  std::vector<int> faces{gmsh::model::occ::addPlaneSurface({gmsh::model::occ::addCurveLoop(edgesFrom)}),
                         gmsh::model::occ::addPlaneSurface({gmsh::model::occ::addCurveLoop(edgesTo)})};
  for (std::size_t i = 0; i < n; ++i) {
    const int loop = gmsh::model::occ::addCurveLoop(
        {edgesFrom[i], edgesSide[(i + 1) % n], -edgesTo[i], -edgesSide[i]});
    faces.push_back(gmsh::model::occ::addPlaneSurface({loop}));
  }
  const int shell = gmsh::model::occ::addSurfaceLoop(faces, -1, true);
  return {3, gmsh::model::occ::addVolume({shell})};
}

struct TetrapodSize {
  double height = kHeight;  ///< overall height standing on three legs (m)
  double tipDiameter = 0.0; ///< leg tip diameter (m)
  double baseDiameter = 0.0; ///< leg cone diameter at the centre (m)
  int facets = 24;          ///< sides of each leg's polygonal section (unit: -)
};

/// Leg length L from the centre to the middle of a tip face (m), from H = 4L/3 + (2 sqrt 2 / 3) R_tip.
double legLength(const TetrapodSize& s) {
  return 0.75 * (s.height - 2.0 * std::numbers::sqrt2 / 3.0 * 0.5 * s.tipDiameter);
}

TriangleMesh buildTetrapod(const TetrapodSize& s) {
  GmshSession session("tetrapod");
  const double length = legLength(s);
  const double sinTilt = 2.0 * std::numbers::sqrt2 / 3.0; // lower legs: 19.47 degrees below horizontal
  std::vector<Vec3> axes{Vec3::UnitZ()};
  for (int k = 0; k < 3; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / 3.0;
    axes.emplace_back(sinTilt * std::cos(phi), sinTilt * std::sin(phi), -1.0 / 3.0);
  }
  std::vector<GmshEntity> legs;
  for (const Vec3& d : axes) {
    // First corner along the steepest descent within the section plane (for the upper leg, whose
    // sections are horizontal, any direction): the lowest point of each lower tip is a corner.
    Vec3 e1 = Vec3::UnitX();
    if (d.z() < 0.0) {
      e1 = -(Vec3::UnitZ() - d.z() * d).normalized();
    }
    const Vec3 e2 = d.cross(e1);
    legs.push_back(addFrustum(regularPolygon(Vec3::Zero(), e1, e2, 0.5 * s.baseDiameter, s.facets),
                                regularPolygon(length * d, e1, e2, 0.5 * s.tipDiameter, s.facets)));
  }
  session.fuse({legs.front()}, {legs.begin() + 1, legs.end()});
  // Planar faces only; a quarter of the height keeps the long leg facets to a few triangles.
  return session.meshSurface(0.25 * s.height, 0);
}

} // namespace

ShapeGenerator tetrapodGenerator() {
  ShapeGenerator g;
  g.name = "tetrapod";
  g.summary = "Tetrapod: four truncated-cone legs on the tetrahedral axes (Sogreah, Danel 1950)";
  g.proportions =
      "height H standing on three legs (fourth leg vertical, up); legs on the tetrahedral axes, centre to tip-face "
      "centre L = 0.643 H; tip diameter 0.302 H; cone diameter at the centre 0.5353 H; each leg a regular 24-gon "
      "frustum (planar facets, corners on the circles); V = 0.280 H^3 (Dn = 0.654 H); built at H = 1 m";
  g.source = "Danel (1953), Sogreah Tetrapod. Tip diameter 0.302 H (A) and leg length 0.644 H (F; 0.643 H here, from H) follow the dimension table "
             "of the Tetrapod drawing reproduced in the Shore Protection Manual (1984), quoted from memory and not "
             "checked against the original; the centre diameter is calibrated here to the quoted V = 0.280 H^3. "
             "The real unit's blended leg roots are not modelled";
  g.parameters = {
      {"tip_diameter", 0.302, 0.05, 0.6, "-", "leg tip diameter / overall height H"},
      {"base_diameter", 0.5353, 0.1, 0.9, "-", "leg cone diameter at the unit's centre / overall height H"},
      {"facets", 24.0, 16.0, 96.0, "-", "sides of each leg's polygonal section (the cone is faceted)"},
  };
  g.build = [](const ShapeParameterValues& p) {
    TetrapodSize s;
    s.tipDiameter = p.get("tip_diameter") * s.height;
    s.baseDiameter = p.get("base_diameter") * s.height;
    s.facets = static_cast<int>(std::lround(p.get("facets")));
    if (!(s.baseDiameter >= s.tipDiameter)) {
      core::failInput("shape tetrapod", "base_diameter = {} is smaller than tip_diameter = {}: the legs must taper "
                      "towards their tips; raise base_diameter", p.get("base_diameter"), p.get("tip_diameter"));
    }
    // The lowest point of a lower leg must be its tip (not its root at the centre), or the unit
    // would not stand on its three tips and its height would not be H: the underside of a lower
    // leg falls by L/3 along the leg and rises by (2 sqrt 2 / 3)(R_base - R_tip).
    if (!(std::numbers::sqrt2 * (s.baseDiameter - s.tipDiameter) < legLength(s))) {
      core::failInput("shape tetrapod",
                      "base_diameter = {} with tip_diameter = {}: the legs taper so much that the unit would not "
                      "stand on its tips; keep base_diameter - tip_diameter below {:.4f} (leg length / sqrt 2)",
                      p.get("base_diameter"), p.get("tip_diameter"), legLength(s) / std::numbers::sqrt2 / s.height);
    }
    return buildTetrapod(s);
  };
  return g;
}

} // namespace armour::geometry::shapes
