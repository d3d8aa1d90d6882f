// SPDX-License-Identifier: GPL-3.0-or-later
/// @file Antifer.cpp
/// The Antifer cube (Port of Antifer, France, 1970s): a slightly tapered square block with a
/// groove down the middle of each side face.
///
/// Construction: one horizontal section, a square of side b with a trapezoidal notch in the middle
/// of each side, is lofted linearly from the base (z = 0, scale 1) to the top (z = H, scale
/// `taper`). All sections are similar and centred on the z axis, so each side face is a planar
/// trapezoid (its edges meet at the common apex of the loft) and the unit is an exact polyhedron:
/// 20 side faces, two caps, 76 triangles, built directly without gmsh. The volume is that of a
/// frustum of similar sections, V = H/3 (A_b + sqrt(A_b A_t) + A_t) = A_b H (1 + k + k^2) / 3.
///
/// Dimensions (seed paper 003, section 2.1, the unit of its 319-unit packing): height 2.574 m, base
/// square 2.674 m (1.039 H), top square 2.475 m (0.9615 H), grooves 0.658 m wide (0.256 H) and
/// 0.232 m deep (0.09 H); 17 m^3 without the grooves, 16 m^3 with them. The paper replaced the
/// rounded grooves of the real unit "by small rectangular grooves of comparable cross-sectional
/// area"; here the groove is a trapezoid, its floor 0.47 of its mouth, which gives 16.0 m^3 at the
/// published size (a full rectangle 0.658 x 0.232 m would give 15.6 m^3).

#include "core/Error.hpp"
#include "geometry/shapes/Generators.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace armour::geometry::shapes {
namespace {

/// Height of the published unit (m): seed 003, section 2.1.
constexpr double kHeight = 2.574;

struct AntiferSection {
  double base = 0.0;        ///< side of the base square (m)
  double grooveWidth = 0.0; ///< groove width at the mouth, on the base (m)
  double grooveDepth = 0.0; ///< groove depth, on the base (m)
  double grooveFloor = 0.0; ///< floor width / mouth width (unit: -)
};

/// Corners of the base section, counter-clockwise seen from above: for each side, its first
/// corner, then the groove's mouth, floor and mouth again.
std::vector<std::array<double, 2>> sectionPolygon(const AntiferSection& s) {
  std::vector<std::array<double, 2>> polygon;
  const double half = 0.5 * s.base;
  const double mouth = 0.5 * s.grooveWidth;
  const double floor = 0.5 * s.grooveFloor * s.grooveWidth;
  const double inner = half - s.grooveDepth;
  const double normals[4][2] = {{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.0, -1.0}};
  for (const auto& n : normals) {
    const double t[2] = {-n[1], n[0]}; // e_z x n: the counter-clockwise direction along the side
    auto at = [&](double along, double out) -> std::array<double, 2> {
      return {out * n[0] + along * t[0], out * n[1] + along * t[1]};
    };
    polygon.push_back(at(-half, half));
    polygon.push_back(at(-mouth, half));
    polygon.push_back(at(-floor, inner));
    polygon.push_back(at(floor, inner));
    polygon.push_back(at(mouth, half));
  }
  return polygon;
}

/// Ear-clipping triangulation of a simple counter-clockwise polygon (no three consecutive corners
/// collinear); returns index triples, counter-clockwise. The grooved section is not star-shaped
/// about its centre when the grooves are nearly rectangular, so a fan would fold over.
std::vector<std::array<int, 3>> triangulatePolygon(const std::vector<std::array<double, 2>>& p) {
  auto cross = [&](int a, int b, int c) {
    return (p[b][0] - p[a][0]) * (p[c][1] - p[a][1]) - (p[b][1] - p[a][1]) * (p[c][0] - p[a][0]);
  };
  std::vector<int> remaining(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    remaining[i] = static_cast<int>(i);
  }
  std::vector<std::array<int, 3>> triangles;
  while (remaining.size() > 3) {
    const std::size_t n = remaining.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const int a = remaining[(i + n - 1) % n];
      const int b = remaining[i];
      const int c = remaining[(i + 1) % n];
      if (cross(a, b, c) <= 0.0) {
        continue; // reflex corner: not an ear
      }
      bool empty = true;
      for (int q : remaining) {
        if (q != a && q != b && q != c && cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0) {
          empty = false;
          break;
        }
      }
      if (empty) {
        triangles.push_back({a, b, c});
        remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    if (!clipped) {
      core::failInput("shape antifer", "the grooved section is not a simple polygon; reduce groove_depth or "
                      "groove_width");
    }
  }
  triangles.push_back({remaining[0], remaining[1], remaining[2]});
  return triangles;
}

/// The Antifer of height `height` (m); `taper` = top side / base side (unit: -).
TriangleMesh buildAntifer(double height, const AntiferSection& section, double taper) {
  const auto polygon = sectionPolygon(section);
  const auto n = static_cast<std::int32_t>(polygon.size());
  TriangleMesh mesh;
  for (const auto& q : polygon) {
    mesh.vertices.emplace_back(q[0], q[1], 0.0); // base: 0 .. n-1
  }
  for (const auto& q : polygon) {
    mesh.vertices.emplace_back(taper * q[0], taper * q[1], height); // top: n .. 2n-1
  }
  // Side faces: the planar trapezoid between corresponding edges, outward because the base runs
  // counter-clockwise seen from above.
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t j = (i + 1) % n;
    mesh.triangles.push_back({i, j, n + j});
    mesh.triangles.push_back({i, n + j, n + i});
  }
  for (const auto& t : triangulatePolygon(polygon)) {
    mesh.triangles.push_back({n + t[0], n + t[1], n + t[2]}); // top, seen from above
    mesh.triangles.push_back({t[0], t[2], t[1]});             // base, seen from below
  }
  return mesh;
}

} // namespace

ShapeGenerator antiferGenerator() {
  ShapeGenerator g;
  g.name = "antifer";
  g.summary = "Antifer cube: tapered square block with a vertical groove in each side (seed 003)";
  g.proportions =
      "height H; base square 1.039 H, top square 0.9615 H (taper 0.9254); on each side a trapezoidal groove "
      "top to bottom, 0.256 H wide at the mouth, 0.09 H deep, floor 0.47 of the mouth (dimensions on the base, "
      "tapering with the faces); built at H = 2.574 m: V = 16.00 m^3 (17.07 m^3 without grooves), "
      "V = 0.938 H^3; 76 triangles, faces exactly planar";
  g.source = "seed paper 003, section 2.1: H = 2.574 m, base 2.674 m, top 2.475 m, "
             "grooves 0.658 m x 0.232 m, 16 m^3 (17 m^3 without grooves). The paper approximates the real rounded "
             "grooves by rectangles of comparable area; the trapezoid floor ratio here is calibrated to the "
             "published 16 m^3";
  g.parameters = {
      {"base_width", 1.039, 0.5, 2.0, "-", "side of the base square / height H"},
      {"taper", 0.9615 / 1.039, 0.5, 1.0, "-", "top side / base side (1 = prism)"},
      {"groove_width", 0.256, 0.02, 0.8, "-", "groove width at the mouth, on the base / height H"},
      {"groove_depth", 0.09, 0.005, 0.4, "-", "groove depth on the base / height H"},
      {"groove_floor", 0.47, 0.05, 1.0, "-", "groove floor width / mouth width (1 = rectangular groove)"},
  };
  g.build = [](const ShapeParameterValues& p) {
    AntiferSection s;
    s.base = p.get("base_width") * kHeight;
    s.grooveWidth = p.get("groove_width") * kHeight;
    s.grooveDepth = p.get("groove_depth") * kHeight;
    s.grooveFloor = p.get("groove_floor");
    // Keep a solid corner beside each groove and a solid core between opposite groove floors.
    if (!(s.grooveWidth < 0.9 * s.base)) {
      core::failInput("shape antifer", "groove_width = {} is too wide for base_width = {}: keep groove_width "
                      "below 0.9 x base_width", p.get("groove_width"), p.get("base_width"));
    }
    if (!(s.grooveDepth < 0.4 * s.base)) {
      core::failInput("shape antifer", "groove_depth = {} is too deep for base_width = {}: keep groove_depth "
                      "below 0.4 x base_width", p.get("groove_depth"), p.get("base_width"));
    }
    return buildAntifer(kHeight, s, p.get("taper"));
  };
  return g;
}

} // namespace armour::geometry::shapes
