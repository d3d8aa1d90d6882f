// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/SampleBuckets.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace armour::contact {

SampleBuckets buildBuckets(const SurfaceSamples& samples, const Box3& box) {
  constexpr int kBuckets = SampleBuckets::kCells;
  SampleBuckets b;
  b.bounds = box;
  b.origin = box.min;
  b.cell = (box.size() / kBuckets).cwiseMax(Vec3::Constant(1e-12));
  const auto& positions = samples.positions();
  std::vector<std::uint32_t> cellOf(positions.size());
  b.start.assign(kBuckets * kBuckets * kBuckets + 1, 0);
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    const auto c = bucketOf(b, positions[i]);
    cellOf[i] = static_cast<std::uint32_t>(c[0] + kBuckets * (c[1] + kBuckets * c[2]));
    ++b.start[cellOf[i] + 1];
  }
  for (std::size_t k = 1; k < b.start.size(); ++k) {
    b.start[k] += b.start[k - 1];
  }
  b.samples.resize(positions.size());
  std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    b.samples[fill[cellOf[i]]++] = i;
  }
  // A sphere around each bucket's samples: surface samples fill a thin patch of their bucket, so
  // the sphere is the tighter bound for culling a whole bucket against another body's level set.
  const int cells = kBuckets * kBuckets * kBuckets;
  b.sphereCentre.assign(cells, Vec3::Zero());
  b.sphereRadius.assign(cells, 0.0);
  for (int c = 0; c < cells; ++c) {
    if (b.start[c] == b.start[c + 1]) {
      continue;
    }
    geometry::Box3 tight;
    for (std::uint32_t j = b.start[c]; j < b.start[c + 1]; ++j) {
      tight.extend(positions[b.samples[j]]);
    }
    b.sphereCentre[c] = tight.centre();
    for (std::uint32_t j = b.start[c]; j < b.start[c + 1]; ++j) {
      b.sphereRadius[c] = std::max(b.sphereRadius[c], (positions[b.samples[j]] - tight.centre()).norm());
    }
  }
  return b;
}

} // namespace armour::contact
