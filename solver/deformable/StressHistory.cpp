// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/StressHistory.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "deformable/StressFields.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

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

void StressHistory::record(const DeformableBody& body) { add(sampleStressPeaks(body)); }

void StressHistory::add(const StressSample& sample) {
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

void StressHistory::keepUpTo(double time) {
  std::vector<StressSample> all;
  all.swap(samples_);
  extremes_ = StressSample{};
  for (const StressSample& s : all) {
    if (s.tension.time <= time) add(s);
  }
}

StressHistory StressHistory::readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    core::failInput(path.string(), "cannot open the stress history; check the path");
  }
  std::string line;
  std::getline(in, line);
  if (line.rfind("time_s,tension_Pa", 0) != 0) {
    core::failInput(path.string(), "not a stress history (its first line is '{}'); give the stress_history.csv a "
                                   "run wrote", line);
  }
  StressHistory history;
  std::size_t row = 1;
  while (std::getline(in, line)) {
    ++row;
    std::istringstream fields(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(fields, cell, ',')) {
      char* end = nullptr;
      v.push_back(std::strtod(cell.c_str(), &end));
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v.back())) {
        core::failInput(path.string(), "line {}: '{}' is not a finite number; the file is damaged, use an earlier "
                                       "checkpoint's folder or start the run again", row, cell);
      }
    }
    if (v.size() != 16) {
      core::failInput(path.string(), "line {} has {} fields, a sample has 16; the file is damaged or truncated", row,
                      v.size());
    }
    StressSample s;
    StressPeak* peaks[3] = {&s.tension, &s.differential, &s.vonMises};
    for (int k = 0; k < 3; ++k) {
      peaks[k]->time = v[0];
      peaks[k]->value = v[1 + 5 * k];
      peaks[k]->element = static_cast<std::size_t>(v[2 + 5 * k]);
      peaks[k]->location = Vec3(v[3 + 5 * k], v[4 + 5 * k], v[5 + 5 * k]);
    }
    history.add(s);
  }
  return history;
}

} // namespace armour::deformable
