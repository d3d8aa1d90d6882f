// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file WorldBuckets.hpp
/// Internal to the World (not installed): the coarse grid of surface samples of a shape
/// (SampleBuckets, World.hpp). World::addShape builds it once per shape; the narrow phase
/// (WorldContacts.cpp) visits only the buckets near the overlap of two boxes.

#include "simulation/World.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace armour::simulation::detail {

constexpr int kBuckets = SampleBuckets::kCells; ///< buckets per axis (unit: -)

/// The bucket (x, y, z) holding the point p (body frame, unscaled), clamped to the grid.
inline std::array<int, 3> bucketOf(const SampleBuckets& b, const Vec3& p) {
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k) {
    c[k] = std::clamp(static_cast<int>(std::floor((p[k] - b.origin[k]) / b.cell[k])), 0, kBuckets - 1);
  }
  return c;
}

/// Counting sort of the samples into buckets (WorldBuckets.cpp).
void buildBuckets(ShapeModel& shape);

/// Call f(cell, lowCorner) for every non-empty bucket of `shape` that overlaps the local box
/// [lo, hi] (body frame of the shape, unscaled).
template <typename F>
void forBucketsNear(const ShapeModel& shape, const Vec3& lo, const Vec3& hi, F&& f) {
  const SampleBuckets& b = shape.buckets;
  if ((hi.array() < shape.bounds.min.array()).any() || (lo.array() > shape.bounds.max.array()).any()) {
    return;
  }
  const auto c0 = bucketOf(b, lo);
  const auto c1 = bucketOf(b, hi);
  for (int z = c0[2]; z <= c1[2]; ++z) {
    for (int y = c0[1]; y <= c1[1]; ++y) {
      for (int x = c0[0]; x <= c1[0]; ++x) {
        const int cell = x + kBuckets * (y + kBuckets * z);
        if (b.start[cell] != b.start[cell + 1]) {
          f(cell, Vec3(b.origin + b.cell.cwiseProduct(Vec3(x, y, z))));
        }
      }
    }
  }
}

} // namespace armour::simulation::detail
