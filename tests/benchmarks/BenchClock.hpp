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

/// CPU time of the calling thread (unit: s).
inline double threadCpuNow() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// The 1, 5 and 15 minute load averages of /proc/loadavg, or -1 each where it cannot be read.
struct LoadAverages {
  double one = -1.0, five = -1.0, fifteen = -1.0;
};
inline LoadAverages readLoadAverages() {
  std::ifstream in("/proc/loadavg");
  LoadAverages l;
  in >> l.one >> l.five >> l.fifteen;
  return l;
}

/// One-minute load average: a shared machine's other work shows here (and in cpu / wall).
inline double loadAverage() { return readLoadAverages().one; }

/// The three load averages as text, e.g. "2.01 1.87 1.52".
inline std::string loadAverages() {
  const LoadAverages l = readLoadAverages();
  return fmt::format("{:.2f} {:.2f} {:.2f}", l.one, l.five, l.fifteen);
}

} // namespace armour::bench
