// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/BroadPhase.hpp"

#include <algorithm>
#include <cmath>

namespace armour::contact {
namespace {

bool overlapYZ(const geometry::Box3& a, const geometry::Box3& b) {
  return a.min.y() <= b.max.y() && b.min.y() <= a.max.y() && a.min.z() <= b.max.z() && b.min.z() <= a.max.z();
}

bool overlapXYZ(const geometry::Box3& a, const geometry::Box3& b) {
  return a.min.x() <= b.max.x() && b.min.x() <= a.max.x() && overlapYZ(a, b);
}

bool contains(const geometry::Box3& outer, const geometry::Box3& inner) {
  return (outer.min.array() <= inner.min.array()).all() && (inner.max.array() <= outer.max.array()).all();
}

} // namespace

void BroadPhase::buildResting(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active) {
  ++restingBuilds_;
  const auto n = static_cast<std::uint32_t>(boxes.size());
  std::vector<std::uint32_t> resting;
  std::vector<double> extents;
  geometry::Box3 bounds;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!active[i] && !boxes[i].empty()) {
      resting.push_back(i);
      extents.push_back(std::max(boxes[i].max.x() - boxes[i].min.x(), boxes[i].max.y() - boxes[i].min.y()));
    }
  }
  large_.clear();
  cellStart_.assign(1, 0);
  cellItems_.clear();
  nx_ = ny_ = 0;
  if (resting.empty()) {
    return;
  }
  // Cell size: the median box extent, so a typical box covers 1 to 4 cells.
  std::vector<double> sorted = extents;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
  cell_ = std::max(sorted[sorted.size() / 2], 1e-6);
  std::vector<std::uint32_t> gridded;
  for (std::size_t k = 0; k < resting.size(); ++k) {
    if (extents[k] > 4.0 * cell_) {
      large_.push_back(resting[k]);
    } else {
      gridded.push_back(resting[k]);
      bounds.extend(boxes[resting[k]].min);
      bounds.extend(boxes[resting[k]].max);
    }
  }
  if (gridded.empty()) {
    return;
  }
  // At most about four cells per gridded box: coarser cells for sparse scenes.
  const double maxCells = 4.0 * static_cast<double>(gridded.size()) + 16.0;
  const double area = std::max(bounds.size().x(), cell_) * std::max(bounds.size().y(), cell_);
  cell_ = std::max(cell_, std::sqrt(area / maxCells));
  gridX0_ = bounds.min.x();
  gridY0_ = bounds.min.y();
  nx_ = static_cast<int>(std::floor(bounds.size().x() / cell_)) + 1;
  ny_ = static_cast<int>(std::floor(bounds.size().y() / cell_)) + 1;
  const auto cellRange = [&](const geometry::Box3& b, int& x0, int& x1, int& y0, int& y1) {
    x0 = std::clamp(static_cast<int>(std::floor((b.min.x() - gridX0_) / cell_)), 0, nx_ - 1);
    x1 = std::clamp(static_cast<int>(std::floor((b.max.x() - gridX0_) / cell_)), 0, nx_ - 1);
    y0 = std::clamp(static_cast<int>(std::floor((b.min.y() - gridY0_) / cell_)), 0, ny_ - 1);
    y1 = std::clamp(static_cast<int>(std::floor((b.max.y() - gridY0_) / cell_)), 0, ny_ - 1);
  };
  // Counting sort of (cell, box) entries into CSR form.
  cellStart_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
  for (const std::uint32_t i : gridded) {
    int x0, x1, y0, y1;
    cellRange(boxes[i], x0, x1, y0, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        ++cellStart_[static_cast<std::size_t>(x + nx_ * y) + 1];
      }
    }
  }
  for (std::size_t c = 1; c < cellStart_.size(); ++c) {
    cellStart_[c] += cellStart_[c - 1];
  }
  cellItems_.resize(cellStart_.back());
  std::vector<std::uint32_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (const std::uint32_t i : gridded) {
    int x0, x1, y0, y1;
    cellRange(boxes[i], x0, x1, y0, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        cellItems_[fill[static_cast<std::size_t>(x + nx_ * y)]++] = i;
      }
    }
  }
}

void BroadPhase::findNeighbours(const std::vector<geometry::Box3>& boxes, Neighbours& n) {
  ++neighbourSearches_;
  n.resting.clear();
  n.valid = true;
  const geometry::Box3& g = n.grown;
  if (++query_ == 0) { // wrapped: clear the stamps
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  if (nx_ > 0) {
    const int x0 = std::clamp(static_cast<int>(std::floor((g.min.x() - gridX0_) / cell_)), 0, nx_ - 1);
    const int x1 = std::clamp(static_cast<int>(std::floor((g.max.x() - gridX0_) / cell_)), 0, nx_ - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor((g.min.y() - gridY0_) / cell_)), 0, ny_ - 1);
    const int y1 = std::clamp(static_cast<int>(std::floor((g.max.y() - gridY0_) / cell_)), 0, ny_ - 1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const auto c = static_cast<std::size_t>(x + nx_ * y);
        for (std::uint32_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
          const std::uint32_t j = cellItems_[k];
          if (stamp_[j] == query_) {
            continue;
          }
          stamp_[j] = query_;
          if (overlapXYZ(g, boxes[j])) {
            n.resting.push_back(j);
          }
        }
      }
    }
  }
  for (const std::uint32_t j : large_) {
    if (overlapXYZ(g, boxes[j])) {
      n.resting.push_back(j);
    }
  }
}

void BroadPhase::findPairs(const std::vector<geometry::Box3>& boxes, const std::vector<std::uint8_t>& active,
                           std::vector<BodyPair>& pairs) {
  pairs.clear();
  const auto n = static_cast<std::uint32_t>(boxes.size());
  const bool flagsChanged = activeCopy_.size() != n || !std::equal(activeCopy_.begin(), activeCopy_.end(), active.begin());
  if (flagsChanged || !restingValid_) {
    activeCopy_.assign(active.begin(), active.begin() + n);
    buildResting(boxes, active);
    restingValid_ = true;
    stamp_.assign(n, 0);
    query_ = 0;
    neighbours_.resize(n);
    for (Neighbours& near : neighbours_) near.valid = false; // the grid is new
    // The active set changed: start the sweep order again from the active boxes.
    order_.clear();
    for (std::uint32_t i = 0; i < n; ++i) {
      if (active[i] && !boxes[i].empty()) {
        order_.push_back(i);
      }
    }
    std::sort(order_.begin(), order_.end(), [&](std::uint32_t a, std::uint32_t b) {
      return boxes[a].min.x() < boxes[b].min.x() || (boxes[a].min.x() == boxes[b].min.x() && a < b);
    });
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
  // Active with active: sweep and prune.
  for (std::size_t a = 0; a < order_.size(); ++a) {
    const std::uint32_t i = order_[a];
    const auto& bi = boxes[i];
    for (std::size_t b = a + 1; b < order_.size(); ++b) {
      const std::uint32_t j = order_[b];
      const auto& bj = boxes[j];
      if (bj.min.x() > bi.max.x()) {
        break;
      }
      if (overlapYZ(bi, bj)) {
        pairs.emplace_back(std::min(i, j), std::max(i, j));
      }
    }
  }
  // Active with resting: each active box's neighbours (found again when it has left the grown box
  // they were found for), then the exact overlap test.
  for (const std::uint32_t i : order_) {
    const auto& bi = boxes[i];
    if (!bi.min.allFinite() || !bi.max.allFinite()) {
      continue; // a body with a non-finite state: the caller's guard rail names it
    }
    Neighbours& near = neighbours_[i];
    if (!near.valid || !contains(near.grown, bi)) {
      const double grow = kGrowth * bi.size().maxCoeff();
      near.grown.min = bi.min.array() - grow;
      near.grown.max = bi.max.array() + grow;
      findNeighbours(boxes, near);
    }
    for (const std::uint32_t j : near.resting) {
      if (overlapXYZ(bi, boxes[j])) {
        pairs.emplace_back(std::min(i, j), std::max(i, j));
      }
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
