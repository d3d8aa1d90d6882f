// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file BenchClock.hpp
/// The clocks and the machine load every benchmark program reports (docs/benchmarks.md asks for the
/// load beside each figure).

#include <fmt/format.h>

#include <chrono>
#include <ctime>
#include <fstream>
#include <string>

namespace armour::bench {

/// Wall-clock time since an arbitrary epoch (unit: s): for intervals.
inline double wallNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// CPU time of the whole process, all threads (unit: s): cpu / wall shows how busy the threads were.
inline double cpuNow() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// The 1, 5 and 15 minute load averages of /proc/loadavg, e.g. "2.01 1.87 1.52", or "unknown".
inline std::string loadAverages() {
  std::ifstream in("/proc/loadavg");
  double a = 0.0, b = 0.0, c = 0.0;
  if (!(in >> a >> b >> c)) return "unknown";
  return fmt::format("{:.2f} {:.2f} {:.2f}", a, b, c);
}

} // namespace armour::bench
