// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/BroadPhase.hpp"

#include <algorithm>

namespace armour::contact {
namespace {

bool overlapYZ(const geometry::Box3& a, const geometry::Box3& b) {
  return a.min.y() <= b.max.y() && b.min.y() <= a.max.y() && a.min.z() <= b.max.z() && b.min.z() <= a.max.z();
}

} // namespace

void BroadPhase::findPairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active,
                           std::vector<BodyPair>& pairs) {
  pairs.clear();
  const auto n = static_cast<std::uint32_t>(boxes.size());
  if (order_.size() != n) {
    order_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      order_[i] = i;
    }
    std::sort(order_.begin(), order_.end(),
              [&](std::uint32_t a, std::uint32_t b) { return boxes[a].min.x() < boxes[b].min.x(); });
  } else {
    // Insertion sort: near-linear when the order changed little since the last step.
    for (std::size_t i = 1; i < order_.size(); ++i) {
      const std::uint32_t key = order_[i];
      const double x = boxes[key].min.x();
      std::size_t j = i;
      while (j > 0 && boxes[order_[j - 1]].min.x() > x) {
        order_[j] = order_[j - 1];
        --j;
      }
      order_[j] = key;
    }
  }
  for (std::size_t a = 0; a < order_.size(); ++a) {
    const std::uint32_t i = order_[a];
    const auto& bi = boxes[i];
    if (bi.empty()) {
      continue;
    }
    for (std::size_t b = a + 1; b < order_.size(); ++b) {
      const std::uint32_t j = order_[b];
      const auto& bj = boxes[j];
      if (bj.min.x() > bi.max.x()) {
        break;
      }
      if (bj.empty() || (!active[i] && !active[j]) || !overlapYZ(bi, bj)) {
        continue;
      }
      pairs.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

std::vector<BodyPair> bruteForcePairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active) {
  std::vector<BodyPair> pairs;
  for (std::uint32_t i = 0; i < boxes.size(); ++i) {
    for (std::uint32_t j = i + 1; j < boxes.size(); ++j) {
      const auto& a = boxes[i];
      const auto& b = boxes[j];
      if (a.empty() || b.empty() || (!active[i] && !active[j])) {
        continue;
      }
      if (a.min.x() <= b.max.x() && b.min.x() <= a.max.x() && overlapYZ(a, b)) {
        pairs.emplace_back(i, j);
      }
    }
  }
  return pairs;
}

} // namespace armour::contact
