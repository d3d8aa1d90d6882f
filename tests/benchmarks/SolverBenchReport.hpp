// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// bench_solver's reporting: the markdown tables that go to docs/benchmarks.md (SolverBenchReport.cpp
// prints them), the heading of each (command, build, machine, load average), the number formats,
// and the memory marks a case records while it is built and run.

#include <string>
#include <vector>

namespace armour::bench {

struct CaseResult;
struct LayerOptions;
struct PileOptions;

// ---------------------------------------------------------------------------------------------
// Memory and load

/// Memory at one point of a case (unit: bytes).
struct MemoryMark {
  double heap = 0.0;
  double resident = 0.0;
};
MemoryMark memoryNow();

/// Peak resident set size of the process so far (unit: bytes).
double peakResidentBytes();

constexpr double kMiB = 1024.0 * 1024.0;

// ---------------------------------------------------------------------------------------------
// Headings and number formats

/// Record the command line and OpenMP's thread count at start (OMP_NUM_THREADS or the cores) for
/// printHeader: call first thing in main, before a window sets its own thread count.
void recordInvocation(int argc, char** argv);

/// "### title", then the command, build, OpenMP settings, machine, load average and date.
void printHeader(const std::string& title);

/// `v` to `digits` significant digits; exponent form below 1e-3 and from 1e5 on.
std::string si(double v, int digits = 3);

/// Thousands separated by thin spaces, as in the rest of docs/benchmarks.md.
std::string group(double v);

// ---------------------------------------------------------------------------------------------
// Tables

/// The settings line above the pile tables.
void printPileSettings(const PileOptions& o);

/// The timing table of the piles (one row per thread count), then build, settle and memory.
void printPileTable(const std::vector<CaseResult>& results);

/// The linear-in-contacts check: per shape, the CPU time per step of the 1-thread windows (CPU
/// time, not wall: other work on a shared machine does not count) divided by awake bodies,
/// candidate pairs and contact points, from the smallest pile to the largest. A solver whose
/// cost is linear in the contacts keeps these flat as N grows.
void printLinearity(const std::vector<CaseResult>& results);

/// The armour layer against Solidity_R (seed 000), then its counters and memory.
void printLayerTable(const LayerOptions& o, const CaseResult& r);

} // namespace armour::bench
