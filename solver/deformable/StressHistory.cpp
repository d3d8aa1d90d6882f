// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/StressHistory.hpp"

#include "core/AtomicFile.hpp"
#include "deformable/StressFields.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <limits>

namespace armour::deformable {
namespace {

Vec3 currentCentroid(const DeformableBody& body, std::size_t e) {
  Vec3 sum = Vec3::Zero();
  for (int a = 0; a < 4; ++a) {
    sum += body.positions()[static_cast<std::size_t>(body.mesh().element(e)[a])];
  }
  return 0.25 * sum;
}

void keepLarger(StressPeak& best, const StressPeak& candidate) {
  if (candidate.value > best.value) {
    best = candidate;
  }
}

} // namespace

StressSample sampleStressPeaks(const DeformableBody& body) {
  const auto stresses = body.elementStresses();
  StressSample out;
  const double lowest = -std::numeric_limits<double>::infinity();
  out.tension.value = out.differential.value = out.vonMises.value = lowest;
  for (std::size_t e = 0; e < stresses.size(); ++e) {
    const auto s = summarizeStress(stresses[e]);
    const double values[3] = {s.principal[0], s.differential, s.vonMises};
    StressPeak* peaks[3] = {&out.tension, &out.differential, &out.vonMises};
    for (int k = 0; k < 3; ++k) {
      if (values[k] > peaks[k]->value) {
        peaks[k]->value = values[k];
        peaks[k]->element = e;
      }
    }
  }
  for (StressPeak* peak : {&out.tension, &out.differential, &out.vonMises}) {
    peak->location = currentCentroid(body, peak->element);
    peak->time = body.time();
  }
  return out;
}

void StressHistory::record(const DeformableBody& body) {
  const auto sample = sampleStressPeaks(body);
  if (samples_.empty()) {
    extremes_ = sample;
  } else {
    keepLarger(extremes_.tension, sample.tension);
    keepLarger(extremes_.differential, sample.differential);
    keepLarger(extremes_.vonMises, sample.vonMises);
  }
  samples_.push_back(sample);
}

void StressHistory::writeCsv(const std::filesystem::path& path) const {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "time_s";
    for (const char* name : {"tension", "differential", "von_mises"}) {
      fmt::print(out, ",{0}_Pa,{0}_element,{0}_x_m,{0}_y_m,{0}_z_m", name);
    }
    out << "\n";
    for (const auto& s : samples_) {
      fmt::print(out, "{}", s.tension.time);
      for (const StressPeak* p : {&s.tension, &s.differential, &s.vonMises}) {
        fmt::print(out, ",{},{},{},{},{}", p->value, p->element, p->location.x(), p->location.y(), p->location.z());
      }
      out << "\n";
    }
  });
}

} // namespace armour::deformable
