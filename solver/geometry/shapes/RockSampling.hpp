// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RockSampling.hpp
/// Portable random sampling for the rock generators (Rock.cpp, VoronoiRock.cpp).
///
/// A seed must give the same rock on every platform. std::mt19937_64 is fully specified by the
/// C++ standard, but std::uniform_real_distribution and std::normal_distribution are not (each
/// standard library maps the engine's bits differently), and sin/cos/exp/pow may differ in the
/// last bit between maths libraries. So everything here uses the engine's raw 64-bit output and
/// only + - * / and sqrt, which IEEE 754 rounds identically everywhere.

#include "geometry/TriangleMesh.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace armour::geometry::shapes::rocks {

/// Uniform double in [0, 1): the top 53 bits of one engine draw, scaled by 2^-53 (exact).
inline double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// Uniform double in [lo, hi).
inline double uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * uniform01(rng); }

/// Uniformly distributed unit vector: rejection sampling in the cube [-1, 1]^3 (points outside the
/// unit ball, or too near its centre to normalise accurately, are drawn again). No trigonometry.
inline Vec3 randomDirection(std::mt19937_64& rng) {
  for (;;) {
    const Vec3 v(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    const double r2 = v.squaredNorm();
    if (r2 <= 1.0 && r2 > 1e-6) {
      return v / std::sqrt(r2);
    }
  }
}

/// Approximate surface area of the ellipsoid with semi-axes a, b, c (m^2): 4 pi (ab + bc + ca) / 3,
/// the p = 1 member of the Knud Thomsen family. Exact for a sphere, about 5 % low for 1 : 0.75 : 0.55;
/// used only to space sample points, where that is plenty, and free of pow().
inline double ellipsoidAreaEstimate(double a, double b, double c) {
  return 4.0 * 3.14159265358979323846 * (a * b + b * c + c * a) / 3.0;
}

/// "Blue-noise" sample: draws candidates with `draw` and keeps those at least `minDistance` from
/// every kept one (dart throwing), so neighbouring points are never very close and the hull has no
/// needle-shaped facets. When 30 x count candidates in a row are rejected the spacing is relaxed by
/// 10 %, so the loop always ends. Deterministic for a given engine state.
inline std::vector<Vec3> spacedSample(std::mt19937_64& rng, std::size_t count, double minDistance,
                                      const std::function<Vec3(std::mt19937_64&)>& draw) {
  std::vector<Vec3> kept;
  kept.reserve(count);
  double d2 = minDistance * minDistance;
  std::size_t misses = 0;
  while (kept.size() < count) {
    const Vec3 p = draw(rng);
    bool farEnough = true;
    for (const auto& q : kept) {
      if ((p - q).squaredNorm() < d2) {
        farEnough = false;
        break;
      }
    }
    if (farEnough) {
      kept.push_back(p);
      misses = 0;
    } else if (++misses > 30 * count) {
      d2 *= 0.81;
      misses = 0;
    }
  }
  return kept;
}

/// Stretch `vertices` along x, y and z (about the box centre) so that their bounding box has the
/// proportions of `axes` exactly. A per-axis scaling maps planes to planes, so a convex polyhedron
/// stays convex with flat faces; it removes the few-percent bias between a random polyhedron's
/// extents and the ellipsoid it was built on, so the aspect parameters are met exactly in the box
/// (the caliper measure behind LT).
inline void stretchToBox(std::vector<Vec3>& vertices, const Vec3& axes) {
  Box3 box;
  for (const auto& v : vertices) {
    box.extend(v);
  }
  const Vec3 centre = box.centre();
  const Vec3 factor = axes.cwiseQuotient(box.size());
  for (auto& v : vertices) {
    v = centre + (v - centre).cwiseProduct(factor);
  }
}

} // namespace armour::geometry::shapes::rocks
