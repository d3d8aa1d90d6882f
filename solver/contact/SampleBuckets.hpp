// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file SampleBuckets.hpp
/// A shape's surface samples (SurfaceSamples) filed on a coarse grid over the shape's bounds, so
/// that the narrow phase (NarrowPhase.hpp) visits only the samples near the overlap of two boxes
/// (a face contact touches a sixth of a cube's samples). Built once per shape; shared by every
/// body of the shape.

#include "contact/SurfaceSamples.hpp"
#include "geometry/TriangleMesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace armour::contact {

using geometry::Box3;
using geometry::Vec3;

struct SampleBuckets {
  static constexpr int kCells = 6;           ///< buckets per axis (unit: -)
  Vec3 origin = Vec3::Zero();                ///< lower corner (unit: m, body frame, unscaled)
  Vec3 cell = Vec3::Ones();                  ///< bucket size (unit: m)
  Box3 bounds;                               ///< the shape's bounds the grid covers (unit: m, body frame)
  std::vector<std::uint32_t> start;          ///< kCells^3 + 1 offsets into `samples`
  std::vector<std::uint32_t> samples;        ///< sample indices grouped by bucket
  std::vector<Vec3> sphereCentre;            ///< per bucket: centre of the smallest box of its samples (m)
  std::vector<double> sphereRadius;          ///< per bucket: radius about that centre holding its samples (m)
};

/// Counting sort of the samples into buckets over `bounds` (the shape's mesh bounds, body frame).
SampleBuckets buildBuckets(const SurfaceSamples& samples, const Box3& bounds);

/// The bucket (x, y, z) holding the point p (body frame, unscaled), clamped to the grid.
inline std::array<int, 3> bucketOf(const SampleBuckets& b, const Vec3& p) {
  constexpr int n = SampleBuckets::kCells;
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k) {
    c[k] = std::clamp(static_cast<int>(std::floor((p[k] - b.origin[k]) / b.cell[k])), 0, n - 1);
  }
  return c;
}

/// Call f(cell, lowCorner) for every non-empty bucket that overlaps the local box [lo, hi] (body
/// frame of the shape, unscaled).
template <typename F>
void forBucketsNear(const SampleBuckets& b, const Vec3& lo, const Vec3& hi, F&& f) {
  constexpr int n = SampleBuckets::kCells;
  if ((hi.array() < b.bounds.min.array()).any() || (lo.array() > b.bounds.max.array()).any()) {
    return;
  }
  const auto c0 = bucketOf(b, lo);
  const auto c1 = bucketOf(b, hi);
  for (int z = c0[2]; z <= c1[2]; ++z) {
    for (int y = c0[1]; y <= c1[1]; ++y) {
      for (int x = c0[0]; x <= c1[0]; ++x) {
        const int cell = x + n * (y + n * z);
        if (b.start[cell] != b.start[cell + 1]) {
          f(cell, Vec3(b.origin + b.cell.cwiseProduct(Vec3(x, y, z))));
        }
      }
    }
  }
}

} // namespace armour::contact
