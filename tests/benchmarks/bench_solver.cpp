// SPDX-License-Identifier: GPL-3.0-or-later
// Rigid-solver benchmark (issue 3): piles of 100 to 4000 units in a walled box, and a Core-Loc
// armour layer on a static rock underlayer compared with Solidity_R.
//
//   bench_solver pile --shape cube|rock|coreloc --count N [--threads 1,2] [--settle S] [--steps K]
//   bench_solver armour-layer [--units 242] [--rocks 3436] [--threads 1,2] [--seconds S]
//   bench_solver all [--quick]     (the whole matrix as markdown tables; scripts/bench-solver)
//   bench_solver contact-models [--pile N] [--seconds S]   (level set vs fdem, docs/fidelity.md)
//   bench_solver at-rest [--shape dolos] [--units 3] [--scenes 8]   (do small piles come to rest?)
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
#include "benchmarks/SolverBenchAtRest.hpp"
#include "benchmarks/SolverBenchCase.hpp"
#include "benchmarks/SolverBenchPile.hpp"
#include "benchmarks/SolverBenchReport.hpp"

#include "geometry/ShapeLibrary.hpp"
#include "simulation/World.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using armour::bench::AtRestOptions;
using armour::bench::CaseResult;
using armour::bench::InvalidCase;
using armour::bench::LayerOptions;
using armour::bench::PileOptions;
using armour::bench::printHeader;
using armour::bench::printLayerTable;
using armour::bench::printLinearity;
using armour::bench::printPileSettings;
using armour::bench::printPileTable;
using armour::bench::runAtRest;
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

// ---------------------------------------------------------------------------------------------
// contact-models: the same scenes under the level-set and the fdem contact (docs/fidelity.md)
// ---------------------------------------------------------------------------------------------

using armour::simulation::BodyId;
using armour::simulation::ContactModel;
using armour::simulation::Quat;
using armour::simulation::Vec3;

/// One run of a scene under one model and resolution.
struct ModelRun {
  std::string label;
  double buildSeconds = 0.0; ///< shapes (level sets, samples or tetrahedra) (s)
  double runSeconds = 0.0;   ///< stepping (s)
  std::uint64_t steps = 0;
  double peakOverlap = 0.0;  ///< deepest overlap seen, / Dn (unit: -)
  std::vector<Vec3> positions;
  std::vector<Quat> orientations;
  std::string error;         ///< a guard rail that stopped the run
};

/// scene "dolos-drop": one Dolos (Dn 1 m) dropped tilted from 0.3 m onto a floor; "coreloc-pile":
/// `count` Core-Locs released from a jittered grid into a walled box. resolution: fdem tetrahedra
/// per unit, or level-set cells per Dn (samples at 2.4 / cells Dn, the default ratio).
ModelRun runContactModel(const std::string& scene, ContactModel model, double resolution, int count, double seconds,
                         double penalty) {
  namespace sim = armour::simulation;
  ModelRun out;
  out.label = model == ContactModel::Fdem ? fmt::format("fdem {:.0f} tets/unit", resolution)
                                          : fmt::format("level set {:.0f} cells/Dn", resolution);
  sim::WorldSettings ws;
  ws.contactModel = model;
  ws.sleep.enabled = false;
  if (model == ContactModel::Fdem) {
    ws.fdem.elementsPerUnit = static_cast<std::size_t>(resolution);
  } else {
    ws.levelSet.cellsPerDn = resolution;
    ws.samples.spacingOverDn = 2.4 / resolution;
  }
  sim::World world(ws);
  sim::Material m;
  m.name = "concrete";
  m.restitution = 0.3;
  m.frictionStatic = m.frictionDynamic = 0.6;
  m.penaltyModulus = penalty;
  const auto material = world.addMaterial(m);
  armour::geometry::ShapeRequest request;
  request.volume = 1.0;
  const double t0 = wallNow();
  const auto shape = world.addShape(scene == "dolos-drop" ? "dolos" : "coreloc",
                                    armour::geometry::makeShape(scene == "dolos-drop" ? "dolos" : "coreloc", request));
  out.buildSeconds = wallNow() - t0;
  const double radius = world.shape(shape).radius;
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), material});
  std::vector<BodyId> bodies;
  const auto add = [&](const Vec3& x, const Quat& q) {
    sim::BodySpec b;
    b.shape = shape;
    b.material = material;
    b.position = x;
    b.orientation = q;
    bodies.push_back(world.addBody(b));
  };
  if (scene == "dolos-drop") {
    add(Vec3(0, 0, radius + 0.3), Quat(Eigen::AngleAxisd(0.6, Vec3(1, 2, 0.5).normalized())));
  } else {
    const int side = std::max(1, static_cast<int>(std::ceil(std::sqrt(count / 2.0))));
    const double pitch = 2.05 * radius;
    const double half = 0.5 * side * pitch + 0.2;
    world.addPlane({"x-", Vec3(-half, 0, 0), Vec3::UnitX(), material});
    world.addPlane({"x+", Vec3(half, 0, 0), -Vec3::UnitX(), material});
    world.addPlane({"y-", Vec3(0, -half, 0), Vec3::UnitY(), material});
    world.addPlane({"y+", Vec3(0, half, 0), -Vec3::UnitY(), material});
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < count; ++i) {
      const int ix = i % side, iy = (i / side) % side, iz = i / (side * side);
      const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
      add(Vec3((ix + 0.5) * pitch - 0.5 * side * pitch + 0.05 * u(rng), (iy + 0.5) * pitch - 0.5 * side * pitch,
               radius + 0.1 + iz * pitch),
          Quat(Eigen::AngleAxisd(3.14159 * u(rng), axis)));
    }
  }
  const double t1 = wallNow();
  try {
    while (world.time() < seconds) {
      world.step();
      out.peakOverlap = std::max(out.peakOverlap, world.lastStep().maxOverlap);
    }
  } catch (const sim::SimulationError& e) {
    out.error = e.what();
  }
  out.runSeconds = wallNow() - t1;
  out.steps = world.stepCount();
  for (BodyId b : bodies) {
    out.positions.push_back(world.bodies().position(b));
    out.orientations.push_back(world.naturalOrientation(b));
  }
  return out; // Dn = 1 m: overlaps and positions are already in Dn
}

/// Largest centroid distance and rotation angle between two runs' final states (Dn, degrees).
std::pair<double, double> difference(const ModelRun& a, const ModelRun& b) {
  double dx = 0.0, angle = 0.0;
  for (std::size_t i = 0; i < a.positions.size() && i < b.positions.size(); ++i) {
    dx = std::max(dx, (a.positions[i] - b.positions[i]).norm());
    angle = std::max(angle, a.orientations[i].angularDistance(b.orientations[i]) * 180.0 / 3.14159265358979);
  }
  return {dx, angle};
}

int runContactModels(int pileCount, double seconds, double pileSeconds, double penalty) {
  struct Scene {
    std::string name;
    int count;
    double seconds;
    std::vector<double> fdemRes, levelSetRes;
  };
  const std::vector<Scene> scenes{{"dolos-drop", 1, seconds, {600, 2500, 10000}, {12, 24, 48}},
                                  {"coreloc-pile", pileCount, pileSeconds, {600, 2500}, {24}}};
  for (const Scene& sc : scenes) {
    fmt::print("\n### {} ({} unit{}, {} s simulated, E_p = {:.0e} Pa, 1 thread)\n\n", sc.name, sc.count,
               sc.count > 1 ? "s" : "", sc.seconds, penalty);
    fmt::print("| model | build (s) | run (s) | steps | steps/s | peak overlap (Dn) | final vs finest same model "
               "(Dn, deg) | final vs other model at default (Dn, deg) |\n|---|---|---|---|---|---|---|---|\n");
    std::vector<ModelRun> fdem, ls;
    for (double r : sc.fdemRes) fdem.push_back(runContactModel(sc.name, ContactModel::Fdem, r, sc.count, sc.seconds, penalty));
    for (double r : sc.levelSetRes) {
      ls.push_back(runContactModel(sc.name, ContactModel::LevelSet, r, sc.count, sc.seconds, penalty));
    }
    // The defaults: 2500 tets per unit, 24 cells per Dn.
    const ModelRun& fdemDefault = fdem[fdem.size() > 1 ? 1 : 0];
    const ModelRun& lsDefault = ls[ls.size() > 1 ? 1 : 0];
    const auto row = [&](const ModelRun& r, const ModelRun& finest, const ModelRun& other) {
      const auto [dxF, aF] = difference(r, finest);
      const auto [dxO, aO] = difference(r, other);
      fmt::print("| {} | {:.2f} | {:.2f} | {} | {:.0f} | {:.2e} | {:.2e}, {:.2f} | {:.2e}, {:.2f} |{}\n", r.label,
                 r.buildSeconds, r.runSeconds, r.steps, r.steps / std::max(r.runSeconds, 1e-9), r.peakOverlap, dxF, aF,
                 dxO, aO, r.error.empty() ? "" : " STOPPED: " + r.error);
      std::fflush(stdout);
    };
    for (const ModelRun& r : fdem) row(r, fdem.back(), lsDefault);
    for (const ModelRun& r : ls) row(r, ls.back(), fdemDefault);
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  armour::bench::recordInvocation(argc, argv);
  CLI::App app{"armour rigid-solver benchmark (issue 3): piles of units and a Core-Loc armour layer"};
  app.require_subcommand(1);
  std::string solver = "penalty";
  app.add_option("--solver", solver, "contact solver of every case: penalty or constraint (contact.solver)")
      ->check(CLI::IsMember({"penalty", "constraint"}));
  double sampleSlack = armour::simulation::WorldSettings{}.sampleListSlackPerDn;
  app.add_option("--sample-slack", sampleSlack,
                 "near-sample list slack per Dn (WorldSettings::sampleListSlackPerDn; 0 = no lists)");
  double margin = armour::simulation::WorldSettings{}.constraint.speculativeMargin;
  app.add_option("--speculative-margin", margin,
                 "constraint solver's speculative margin per Dn (contact.constraint.speculative_margin)")
      ->check(CLI::NonNegativeNumber);

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

  int modelsPile = 4;
  double modelsSeconds = 1.5, modelsPileSeconds = 1.0, modelsPenalty = 1e10;
  auto* modelsCmd = app.add_subcommand("contact-models", "level set vs fdem contact: a Dolos drop at three "
                                                         "resolutions each, and a small Core-Loc pile");
  modelsCmd->add_option("--pile", modelsPile, "Core-Locs in the pile (default 4)");
  modelsCmd->add_option("--seconds", modelsSeconds, "simulated seconds of the Dolos drop (default 1.5)");
  modelsCmd->add_option("--pile-seconds", modelsPileSeconds, "simulated seconds of the pile (default 1)");
  modelsCmd->add_option("--penalty", modelsPenalty,
                        "penalty modulus (Pa; default 1e10: at 1e9 the dropped pile's impacts reach the depth of the "
                        "fdem surface elements' centroids, the fdem guard rail)");

  AtRestOptions atRest;
  auto* restCmd = app.add_subcommand("at-rest", "small piles dropped on a floor: do they come to rest? (sleeping off)");
  restCmd->add_option("--shape", atRest.shape, "a shape of the library, e.g. dolos, coreloc, accropode, cube");
  restCmd->add_option("--units", atRest.units, "units per scene")->check(CLI::PositiveNumber);
  restCmd->add_option("--scenes", atRest.scenes, "scenes, each with its own seed")->check(CLI::PositiveNumber);
  restCmd->add_option("--settle", atRest.settle, "simulated time before the window (s)")->check(CLI::PositiveNumber);
  restCmd->add_option("--window", atRest.window, "measured simulated time (s)")->check(CLI::PositiveNumber);
  restCmd->add_option("--seed", atRest.seed, "scene k is seeded seed + k");
  restCmd->add_option("--friction", atRest.friction, "Coulomb friction (-)");
  restCmd->add_option("--restitution", atRest.restitution, "coefficient of restitution (-)");

  CLI11_PARSE(app, argc, argv);
  armour::bench::setBenchSolver(solver == "constraint" ? armour::simulation::ContactSolverKind::Constraint
                                                       : armour::simulation::ContactSolverKind::Penalty);
  armour::bench::setBenchSampleListSlack(sampleSlack);
  armour::bench::setBenchSpeculativeMargin(margin);
  std::printf("contact solver: %s, near-sample slack %g Dn, speculative margin %g Dn\n", solver.c_str(), sampleSlack,
              margin);

  try {
    if (modelsCmd->parsed()) {
      return runContactModels(modelsPile, modelsSeconds, modelsPileSeconds, modelsPenalty);
    }
    if (restCmd->parsed()) {
      return runAtRest(atRest) == 0 ? 0 : 4;
    }
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
