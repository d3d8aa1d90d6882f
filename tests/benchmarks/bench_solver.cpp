// SPDX-License-Identifier: GPL-3.0-or-later
// Rigid-solver benchmark (issue 3): piles of 100 to 4000 units in a walled box, and a Core-Loc
// armour layer on a static rock underlayer compared with Solidity_R.
//
//   bench_solver pile --shape cube|rock|coreloc --count N [--threads 1,2] [--settle S] [--steps K]
//   bench_solver armour-layer [--units 242] [--rocks 3436] [--threads 1,2] [--seconds S]
//   bench_solver all [--quick]     (the whole matrix as markdown tables; scripts/bench-solver)
//
// A pile is deposited in place (a loose random pile built geometrically, unit by unit, so that it
// forms in 0.1 s of simulated time instead of the seconds a drop through metres needs: 4000 units
// would otherwise take most of an hour) or, with --placement drop, released from a grid above.
// Every case is built, released and run to the measurement point (the settle) on the largest
// thread count; its state is captured there, and the measured window is run from that same state
// once per thread count, so 1 and 2 threads time identical work. The World promises
// bit-identical results for any thread count: the states at the end of the windows are compared
// and a difference fails the case. A case whose physics is wrong (guard rail, non-finite state,
// units out of the box, no pile formed) prints INVALID and the program exits with status 2:
// timing a wrong result is worthless. Figures go to docs/benchmarks.md with the printed command.
//
// Files: SolverBenchPile and SolverBenchArmourLayer build and run the two scenes, from the shapes
// and settings of SolverBenchScene and the deposit of SolverBenchDeposit; SolverBenchCase times
// the windows and checks determinism; SolverBenchReport prints the tables (and records memory and
// load). This file holds the command line.

#include "benchmarks/SolverBenchArmourLayer.hpp"
#include "benchmarks/SolverBenchCase.hpp"
#include "benchmarks/SolverBenchPile.hpp"
#include "benchmarks/SolverBenchReport.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using armour::bench::CaseResult;
using armour::bench::InvalidCase;
using armour::bench::LayerOptions;
using armour::bench::PileOptions;
using armour::bench::printHeader;
using armour::bench::printLayerTable;
using armour::bench::printLinearity;
using armour::bench::printPileSettings;
using armour::bench::printPileTable;
using armour::bench::runLayer;
using armour::bench::runPile;
using armour::bench::wallNow;

std::vector<int> parseThreads(const std::vector<int>& threads) {
  for (const int t : threads) {
    if (t < 1) {
      throw std::invalid_argument(fmt::format("--threads {}: give positive thread counts, e.g. --threads 1,2", t));
    }
  }
  return threads;
}

} // namespace

int main(int argc, char** argv) {
  armour::bench::recordInvocation(argc, argv);
  CLI::App app{"armour rigid-solver benchmark (issue 3): piles of units and a Core-Loc armour layer"};
  app.require_subcommand(1);

  PileOptions pile;
  auto* pileCmd = app.add_subcommand("pile", "N units dropped into a walled box; time K steps after landing");
  pileCmd->add_option("--shape", pile.shape, "cube, rock or coreloc")
      ->check(CLI::IsMember({"cube", "rock", "coreloc"}));
  pileCmd
      ->add_option("--placement", pile.placement,
                   "deposit (a loose pile built in place, default) or drop (a grid "
                   "released from above)")
      ->check(CLI::IsMember({"deposit", "drop"}));
  pileCmd->add_option("--count", pile.count, "number of units")->check(CLI::PositiveNumber);
  pileCmd->add_option("--threads", pile.threads, "thread counts to time, e.g. 1,2")->delimiter(',');
  pileCmd->add_option(
      "--settle", pile.settle,
      "simulated time before the window (s); default 0.1 (deposit), top layer's free fall + 0.3 (drop)");
  pileCmd->add_option("--steps", pile.steps, "measured steps per thread count")->check(CLI::PositiveNumber);
  pileCmd->add_option("--layers", pile.layers, "drop-grid layers (footprint side ceil(sqrt(N/layers)))");
  pileCmd->add_option("--dn", pile.dn, "nominal diameter V^(1/3) (m)");
  pileCmd->add_option("--gap", pile.gap, "clearance between bounding spheres at release / Dn");
  pileCmd->add_option("--friction", pile.friction, "Coulomb friction (-)");
  pileCmd->add_option("--restitution", pile.restitution, "coefficient of restitution (-)");
  pileCmd->add_flag("--sleep,!--no-sleep", pile.sleep, "let resting islands sleep (default on)");
  pileCmd->add_option("--rock-shapes", pile.rockShapes, "seeded rock shapes in the library");
  pileCmd->add_option("--tries", pile.tries, "deposit: candidate poses per unit, the lowest kept");
  pileCmd->add_option("--moves", pile.moves, "deposit: failed downhill moves in a row that end a unit's slide");
  pileCmd->add_option("--clearance", pile.clearance, "deposit: gap between units at release / Dn");
  pileCmd->add_option("--seed", pile.seed, "placement and rock seed");
  pileCmd->add_option("--trace", pile.trace, "print progress every this much simulated time while settling (s)");

  LayerOptions layer;
  auto* layerCmd = app.add_subcommand("armour-layer", "Core-Loc units on a static rock underlayer vs Solidity_R");
  layerCmd->add_option("--units", layer.units, "Core-Loc units")->check(CLI::PositiveNumber);
  layerCmd->add_option("--rocks", layer.rocks, "fixed underlayer rocks")->check(CLI::NonNegativeNumber);
  layerCmd->add_option("--threads", layer.threads, "thread counts to time, e.g. 1,2")->delimiter(',');
  layerCmd->add_option("--settle", layer.settle, "simulated time before the window (s)");
  layerCmd->add_option("--seconds", layer.seconds, "measured simulated time per thread count (s)");
  layerCmd->add_option("--unit-volume", layer.unitVolume, "unit volume (m^3)");
  layerCmd->add_option("--rock-volume", layer.rockVolume, "nominal rock volume (m^3)");
  layerCmd->add_option("--width", layer.width, "section width (m)");
  layerCmd->add_option("--slope", layer.slope, "cot(alpha), horizontal over vertical");
  layerCmd->add_option("--packing", layer.packing, "packing density N Dn^2 / A of the unit rows");
  layerCmd->add_option("--toe", layer.toe, "horizontal rock berm in front of the slope (m)");
  layerCmd->add_option("--tries", layer.tries, "orientations tried per unit, the lowest kept");
  layerCmd->add_option("--moves", layer.moves, "failed moves towards the slope in a row that end a unit's placement");
  layerCmd->add_option("--clearance", layer.clearance, "gap between units and rocks at release / Dn");
  layerCmd->add_option("--friction", layer.friction, "Coulomb friction (-)");
  layerCmd->add_option("--restitution", layer.restitution, "coefficient of restitution (-)");
  layerCmd->add_flag("--sleep,!--no-sleep", layer.sleep, "let resting islands sleep (default off)");
  layerCmd->add_option("--seed", layer.seed, "placement and rock seed");
  layerCmd->add_option("--trace", layer.trace, "print progress every this much simulated time while settling (s)");

  bool quick = false;
  std::vector<int> allThreads{1, 2};
  std::vector<int> allCounts;
  std::vector<std::string> allShapes{"cube", "rock", "coreloc"};
  bool allLayer = true;
  auto* allCmd = app.add_subcommand("all", "the whole matrix: cube, rock, coreloc x 100, 1000, 4000, and the armour "
                                           "layer (about 20 min on 2 idle cores; --quick: a few minutes)");
  allCmd->add_flag("--quick", quick, "100 and 1000 units, shorter windows");
  allCmd->add_option("--threads", allThreads, "thread counts to time, e.g. 1,2")->delimiter(',');
  allCmd->add_option("--counts", allCounts, "pile sizes (default 100,1000,4000; --quick 100,1000)")->delimiter(',');
  allCmd->add_option("--shapes", allShapes, "pile shapes (default cube,rock,coreloc)")
      ->delimiter(',')
      ->check(CLI::IsMember({"cube", "rock", "coreloc"}));
  allCmd->add_flag("--layer,!--no-layer", allLayer, "include the armour layer (default on)");

  CLI11_PARSE(app, argc, argv);

  try {
    if (pileCmd->parsed()) {
      pile.threads = parseThreads(pile.threads);
      const CaseResult r = runPile(pile);
      printHeader(fmt::format("Rigid solver: pile of {} x {}", pile.count, pile.shape));
      printPileSettings(pile);
      printPileTable({r});
      return r.deterministic ? 0 : 3;
    }
    if (layerCmd->parsed()) {
      layer.threads = parseThreads(layer.threads);
      const CaseResult r = runLayer(layer);
      printHeader("Rigid solver: Core-Loc armour layer on a rock underlayer");
      printLayerTable(layer, r);
      return r.deterministic ? 0 : 3;
    }
    if (allCmd->parsed()) {
      const double start = wallNow();
      const std::vector<int> threads = parseThreads(allThreads);
      if (allCounts.empty()) {
        allCounts = quick ? std::vector<int>{100, 1000} : std::vector<int>{100, 1000, 4000};
      }
      // Window lengths: enough steps for a stable rate (a second or more of wall time), few
      // enough that the whole run stays near 20 min on 2 idle cores; the settle to 0.1 s (1 375 to
      // 1 870 steps per pile) costs more than the windows. Estimated case times: docs/benchmarks.md.
      const auto stepsFor = [&](int n) -> std::uint64_t {
        if (quick) {
          return n <= 100 ? 200 : 50;
        }
        return n <= 100 ? 500 : n <= 1000 ? 100 : 30;
      };
      std::vector<CaseResult> piles;
      bool ok = true;
      for (const std::string& shape : allShapes) {
        for (const int n : allCounts) {
          PileOptions o;
          o.threads = threads;
          o.shape = shape;
          o.count = n;
          o.steps = stepsFor(n);
          const double caseStart = wallNow();
          try {
            piles.push_back(runPile(o));
          } catch (const std::exception& e) { // InvalidCase or the solver's SimulationError
            CaseResult bad;
            bad.name = fmt::format("{} {}", shape, n);
            bad.invalid = e.what();
            piles.push_back(bad);
            fmt::print(stderr, "INVALID: {}\n", e.what());
          }
          ok = ok && piles.back().invalid.empty() && piles.back().deterministic;
          fmt::print(stderr, "{} {}: {:.0f} s (whole run so far {:.0f} s)\n", shape, n, wallNow() - caseStart,
                     wallNow() - start);
        }
      }
      LayerOptions lo;
      lo.threads = threads;
      lo.seconds = quick ? 0.02 : 0.05;
      CaseResult lr;
      if (allLayer) {
        const double caseStart = wallNow();
        try {
          lr = runLayer(lo);
        } catch (const std::exception& e) {
          lr.name = "armour layer";
          lr.invalid = e.what();
          fmt::print(stderr, "INVALID: {}\n", e.what());
        }
        ok = ok && lr.invalid.empty() && lr.deterministic;
        fmt::print(stderr, "armour layer: {:.0f} s (whole run so far {:.0f} s)\n", wallNow() - caseStart,
                   wallNow() - start);
      }
      printHeader(fmt::format("Rigid solver: piles{}", quick ? " (quick)" : ""));
      printPileSettings(PileOptions{});
      std::string windows;
      for (const int n : allCounts) {
        windows += fmt::format("{}{} steps ({} units)", windows.empty() ? "" : ", ", stepsFor(n), n);
      }
      fmt::print("Measured windows: {}, each on {} thread(s).\n\n", windows, fmt::join(threads, " and "));
      printPileTable(piles);
      printLinearity(piles);
      if (allLayer) {
        printHeader("Rigid solver: Core-Loc armour layer on a rock underlayer");
        printLayerTable(lo, lr);
      }
      fmt::print("\nWhole run: {:.0f} s wall.\n", wallNow() - start);
      return ok ? 0 : 2;
    }
  } catch (const InvalidCase& e) {
    fmt::print("INVALID: {}\n", e.what());
    return 2;
  } catch (const armour::simulation::SimulationError& e) {
    fmt::print("INVALID (the solver stopped): {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  return 0;
}
