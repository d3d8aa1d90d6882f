// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchReport.hpp"

#include "benchmarks/BenchClock.hpp"
#include "benchmarks/SolverBenchArmourLayer.hpp"
#include "benchmarks/SolverBenchCase.hpp"
#include "benchmarks/SolverBenchPile.hpp"
#include "core/BuildInfo.hpp"

#include <fmt/format.h>
#include <malloc.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

namespace armour::bench {
namespace {

/// Resident set size now (unit: bytes), from /proc/self/statm.
double residentBytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

/// Heap bytes in use (malloc'ed and not freed, including mmapped blocks): unlike the resident set,
/// it falls when memory is freed, so it accounts for one case even after others ran.
double heapBytes() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks) + static_cast<double>(m.hblkhd);
}

std::string commandLine;
int defaultThreads = 1; ///< OpenMP's thread count at start (OMP_NUM_THREADS or the cores)

/// Solidity_R (seed 000): a 1-hour storm on 242 Core-Loc units + 3436 rocks in 24 h on 20 threads.
constexpr double kSolidityBodies = 242.0 + 3436.0;
constexpr double kSolidityUnits = 242.0;
constexpr double kSolidityCoreSeconds = 24.0 * 3600.0 * 20.0;
constexpr double kSoliditySimulated = 3600.0;

} // namespace

// ---------------------------------------------------------------------------------------------
// Memory and load

MemoryMark memoryNow() { return {heapBytes(), residentBytes()}; }

double peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return 1024.0 * static_cast<double>(usage.ru_maxrss);
}

// ---------------------------------------------------------------------------------------------
// Headings and number formats

void recordInvocation(int argc, char** argv) {
  defaultThreads = omp_get_max_threads();
  for (int i = 0; i < argc; ++i) {
    // Appended piecewise: `"" + std::string` trips GCC 12's false -Wrestrict warning here.
    commandLine += i > 0 ? " " : "";
    commandLine += argv[i];
  }
}

void printHeader(const std::string& title) {
  omp_set_num_threads(defaultThreads); // the build line reports OpenMP's default, not the last window's
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M", std::localtime(&now));
  char host[128] = "?";
  gethostname(host, sizeof host - 1);
  fmt::print("\n### {}\n\n", title);
  fmt::print("Command: `{}` (thread counts per row; OpenMP default below)  \n", commandLine);
  const char* wait = std::getenv("OMP_WAIT_POLICY");
  fmt::print("Build: {}; OMP_WAIT_POLICY={}  \nMachine: {}, {} cores online, load average {:.2f} now, {}  \n",
             armour::core::buildInfo(), wait != nullptr ? wait : "(unset)", host, sysconf(_SC_NPROCESSORS_ONLN),
             loadAverage(), date);
}

std::string si(double v, int digits) {
  if (v == 0.0 || !std::isfinite(v)) {
    return fmt::format("{}", v);
  }
  const double a = std::abs(v);
  if (a >= 1e5 || a < 1e-3) {
    return fmt::format("{:.{}e}", v, digits - 1);
  }
  const int decimals = std::max(0, digits - 1 - static_cast<int>(std::floor(std::log10(a))));
  return fmt::format("{:.{}f}", v, decimals);
}

std::string group(double v) {
  auto n = static_cast<long long>(std::llround(v));
  std::string digits = std::to_string(std::llabs(n));
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) {
      out += ' ';
    }
    out += digits[i];
  }
  return (n < 0 ? "-" : "") + out;
}

// ---------------------------------------------------------------------------------------------
// Tables

void printPileSettings(const PileOptions& o) {
  const std::string placement =
      o.placement == "drop"
          ? fmt::format("dropped from a grid of {} layers (bounding spheres {} Dn apart), measured {}", o.layers,
                        2 * o.gap,
                        o.settle >= 0.0 ? fmt::format("{} s after release", o.settle)
                                        : std::string("0.3 s after the top layer's free fall"))
          : fmt::format("deposited in place (box of a {}-layer drop grid; best of {} poses, then downhill until {} "
                        "moves fail; released {} Dn clear), measured {} s after release",
                        o.layers, o.tries, o.moves, o.clearance, o.settle >= 0.0 ? o.settle : 0.1);
  fmt::print("Settings: Dn = {} m, concrete 2400 kg/m^3, friction {}, restitution {}, penalty modulus 1e9 Pa, "
             "auto time step (0.2 x stability limit), level set 24 cells/Dn, samples 0.1 Dn, sleep {}, energy guard "
             "on; rocks from {} seeded shapes (volume +-30 %); {}; seed {}.\n\n",
             o.dn, o.friction, o.restitution, o.sleep ? "on" : "off", o.rockShapes, placement, o.seed);
}

void printPileTable(const std::vector<CaseResult>& results) {
  fmt::print("| case | dt (s) | measured from t (s) | mean / max speed (m/s) | threads | steps/s | body-steps/core-s | "
             "cpu/wall | awake | cand. pairs | contact pts | pts/unit | touching pairs/unit | core-us per pt-step | "
             "core-us per pair-step |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& r : results) {
    if (!r.invalid.empty()) {
      fmt::print("| {} | INVALID: {} |||||||||||||\n", r.name, r.invalid);
    }
    for (const auto& w : r.windows) {
      fmt::print(
          "| {} | {} | {:.2f} (landing {:.2f}) | {} / {} | {} | {} | {} | {:.2f} | {} | {} | {} | {:.1f} | {:.2f} | "
          "{} | {} |\n",
          r.name, si(r.dt), r.settle.simulated, r.landing, si(r.atStart.mean, 2), si(r.atStart.max, 2), w.threads,
          group(w.stepsPerSecond()), group(w.bodyStepsPerCoreSecond()), w.cpu / w.wall, group(w.perStep(w.awakeSum)),
          group(w.perStep(w.pairSum)), group(w.perStep(w.pointSum)),
          w.perStep(w.pointSum) / static_cast<double>(r.dynamic), r.contacts.pairsPerUnit, si(1e6 * w.corePerPoint()),
          si(1e6 * w.corePerPair()));
    }
  }
  fmt::print("\n| case | build shapes (s) | build bodies (s) | settle: steps, wall (s), steps/s | shapes (MiB) | "
             "bodies: KiB/body at add | KiB/body running | RSS running (MiB) | peak RSS (MiB) | 1 = N threads | "
             "load avg |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& r : results) {
    if (!r.invalid.empty()) {
      continue;
    }
    const double n = static_cast<double>(r.dynamic + r.fixed);
    fmt::print("| {} | {} | {} | {}, {}, {} | {} | {} | {} | {} | {} | {} | {:.2f} |\n", r.name, si(r.buildShapes),
               si(r.buildBodies), group(static_cast<double>(r.settle.steps)), si(r.settle.wall),
               group(r.settle.stepsPerSecond()), si((r.memShapes.heap - r.memBase.heap) / kMiB),
               si((r.memBodies.heap - r.memShapes.heap) / 1024.0 / n),
               si((r.memRunning.heap - r.memShapes.heap) / 1024.0 / n), si(r.memRunning.resident / kMiB),
               si(peakResidentBytes() / kMiB),
               r.deterministic ? "yes" : "NO", r.load);
  }
  fmt::print("\n");
  for (const auto& r : results) {
    fmt::print("- {}:{}\n", r.name, r.notes);
  }
  fmt::print("\nColumns: steps/s and body-steps/core-s (awake bodies x steps / (wall x threads)) over the measured "
             "window; cand. pairs = broad-phase pairs incl. body-plane, contact pts = engaged sample points, both "
             "per step; pts/unit = contact points per unit; touching pairs/unit at the window's start; core-us per "
             "pt-step (pair-step) = wall x threads / (contact points (pairs) x steps); cpu/wall = process "
             "CPU time over wall time (below the thread count: the machine was busy with other work). Memory "
             "from the heap in use (mallinfo2): shapes = level sets, samples and meshes; KiB/body at add = after "
             "adding the bodies, running = after the settle (adds pairs, friction history, work lists); RSS "
             "running = resident set of the process after the settle (/proc/self/statm). The window is run from the "
             "same captured state for each thread "
             "count; 1 = N threads: final states bit-identical.\n");
}

void printLinearity(const std::vector<CaseResult>& results) {
  std::vector<std::string> shapes;
  for (const auto& r : results) {
    const std::string shape = r.name.substr(0, r.name.find(' '));
    if (r.invalid.empty() && std::find(shapes.begin(), shapes.end(), shape) == shapes.end()) {
      shapes.push_back(shape);
    }
  }
  fmt::print("\nLinear in contacts? CPU time per step on 1 thread, per item:\n\n");
  fmt::print("| shape | units | CPU ms/step | CPU us per body-step | CPU us per pair-step | CPU us per pt-step | "
             "pairs/unit | pts/unit |\n");
  fmt::print("|---|---|---|---|---|---|---|---|\n");
  for (const auto& shape : shapes) {
    const Window* first = nullptr;
    const Window* last = nullptr;
    for (const auto& r : results) {
      if (!r.invalid.empty() || r.name.substr(0, r.name.find(' ')) != shape) {
        continue;
      }
      for (const auto& w : r.windows) {
        if (w.threads != 1) {
          continue;
        }
        const double cpu = w.perStep(w.cpu);
        fmt::print("| {} | {} | {} | {} | {} | {} | {:.1f} | {:.1f} |\n", shape, group(static_cast<double>(r.dynamic)),
                   si(1e3 * cpu), si(1e6 * cpu / w.perStep(w.awakeSum)), si(1e6 * cpu / w.perStep(w.pairSum)),
                   si(1e6 * cpu / w.perStep(w.pointSum)), w.perStep(w.pairSum) / static_cast<double>(r.dynamic),
                   w.perStep(w.pointSum) / static_cast<double>(r.dynamic));
        first = first == nullptr ? &w : first;
        last = &w;
      }
    }
    if (first != nullptr && last != first) {
      const auto ratio = [&](double Window::*sum) {
        return (last->cpu / (last->*sum)) / (first->cpu / (first->*sum));
      };
      fmt::print("| {} | largest / smallest | | {:.2f} | {:.2f} | {:.2f} | | |\n", shape, ratio(&Window::awakeSum),
                 ratio(&Window::pairSum), ratio(&Window::pointSum));
    }
  }
}

void printLayerTable(const LayerOptions& o, const CaseResult& r) {
  fmt::print("Settings: {} Core-Loc units of {} m^3 (Dn = {:.3f} m, concrete 2400 kg/m^3) on {} fixed rocks of {} m^3 "
             "(Dn = {:.3f} m, 2650 kg/m^3, {} seeded shapes, volume +-30 %), friction {}, restitution {}, penalty "
             "modulus 1e9 Pa, auto time step (0.2 x stability limit) = {:.4g} s, level set 24 cells/Dn, samples "
             "0.1 Dn, sleep {}, seed {}; measured from t = {} s for {} s of simulated time.\n\n",
             o.units, o.unitVolume, std::cbrt(o.unitVolume), o.rocks, o.rockVolume, std::cbrt(o.rockVolume),
             o.rockShapes, o.friction, o.restitution, r.dt, o.sleep ? "on" : "off (a storm keeps units awake)",
             o.seed, o.settle, o.seconds);
  if (!r.invalid.empty()) {
    fmt::print("INVALID: {}\n", r.invalid);
    return;
  }
  const double solidityAll = kSolidityBodies * kSoliditySimulated / kSolidityCoreSeconds;
  const double solidityUnits = kSolidityUnits * kSoliditySimulated / kSolidityCoreSeconds;
  const double solidityCoreSecondsPerSecond = kSolidityCoreSeconds / kSoliditySimulated;
  fmt::print("| code | threads | steps/s | cpu/wall | simulated s per wall s | core-s per simulated s | "
             "unit-simulated-s per core-s | body-simulated-s per core-s (rocks counted) | 1-h storm on 20 such "
             "cores |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|\n");
  fmt::print("| Solidity_R (seed 000, Xeon E5-2667 v3) | 20 | ? | | {} | {} | {} | {} | 24 h |\n",
             si(kSoliditySimulated / (24.0 * 3600.0)), group(solidityCoreSecondsPerSecond), si(solidityUnits),
             si(solidityAll));
  for (const auto& w : r.windows) {
    const double simPerWall = w.simulated / w.wall;
    const double coreSecondsPerSecond = w.wall * w.threads / w.simulated;
    const double units = static_cast<double>(r.dynamic) * w.simulated / (w.wall * w.threads);
    const double all = static_cast<double>(r.dynamic + r.fixed) * w.simulated / (w.wall * w.threads);
    const double storm = kSoliditySimulated * coreSecondsPerSecond / 20.0 / 3600.0; // hours on 20 cores, ideal scaling
    fmt::print("| armour | {} | {} | {:.2f} | {} | {} | {} | {} | {:.1f} h |\n", w.threads, group(w.stepsPerSecond()),
               w.cpu / w.wall, si(simPerWall), group(coreSecondsPerSecond), si(units), si(all), storm);
  }
  fmt::print(
      "\n| dt (s) | mean / max unit speed at start (m/s) | awake | cand. pairs | contact pts | unit-unit / unit-rock / "
      "unit-plane pairs | pts/unit | core-us per pt-step | core-us per pair-step | build (s) | settle: steps, wall (s) "
      "| "
      "KiB/body running | peak RSS (MiB) | 1 = N threads | load avg |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const Window& w = r.windows.front();
  const double n = static_cast<double>(r.dynamic + r.fixed);
  fmt::print(
      "| {:.4g} | {} / {} | {} | {} | {} | {} / {} / {} | {:.1f} | {} | {} | {} | {}, {} | {} | {} | {} | {:.2f} |\n",
      r.dt, si(r.atStart.mean, 2), si(r.atStart.max, 2), group(w.perStep(w.awakeSum)), group(w.perStep(w.pairSum)),
      group(w.perStep(w.pointSum)), r.contacts.unitUnit, r.contacts.unitFixed, r.contacts.unitStatic,
      w.perStep(w.pointSum) / static_cast<double>(r.dynamic), si(1e6 * w.corePerPoint()), si(1e6 * w.corePerPair()),
      si(r.buildShapes + r.buildBodies), group(static_cast<double>(r.settle.steps)), si(r.settle.wall),
      si((r.memRunning.heap - r.memShapes.heap) / 1024.0 / n), si(peakResidentBytes() / kMiB),
      r.deterministic ? "yes" : "NO", r.load);
  const double directions = w.listReuseSum + w.listSearchSum;
  fmt::print("\nNear-sample lists (slack {} Dn): {:.1f} % of the body-pair directions past the pair cull were "
             "served from their list, {:.0f} full searches and {:.0f} listed samples looked up per step.\n",
             r.sampleListSlack, directions > 0.0 ? 100.0 * w.listReuseSum / directions : 0.0,
             w.perStep(w.listSearchSum), w.perStep(w.listLookupSum));
  fmt::print("\n- {}:{}\n\nSolidity_R's 7.7 counts its 3436 rocks as bodies (3678 x 3600 s / (24 h x 20 threads)); "
             "here the rocks are fixed and cost only through their pairs with units, so the fair per-body "
             "comparison is the unit column against {:.2f}, and the plainest one is core-seconds per simulated "
             "second of the same scene. Storm hours assume perfect scaling to 20 cores.\n",
             r.name, r.notes, solidityUnits);
}

} // namespace armour::bench
