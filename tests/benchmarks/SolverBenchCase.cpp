// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/SolverBenchCase.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <set>
#include <utility>

namespace armour::bench {

Window runWindow(World& world, int threads, std::uint64_t steps, double untilTime, bool capture) {
  omp_set_num_threads(threads);
  Window w;
  w.threads = threads;
  const double t0 = world.time();
  const double wall0 = wallNow(), cpu0 = cpuNow();
  const auto more = [&] { return steps > 0 ? w.steps < steps : world.time() < untilTime; };
  while (more()) {
    world.step();
    ++w.steps;
    const auto& s = world.lastStep();
    w.awakeSum += static_cast<double>(s.awakeBodies);
    w.pairSum += static_cast<double>(s.candidatePairs);
    w.pointSum += static_cast<double>(s.contactPoints);
    w.listReuseSum += static_cast<double>(s.sampleListReuses);
    w.listSearchSum += static_cast<double>(s.sampleSearches);
    w.listLookupSum += static_cast<double>(s.sampleListLookups);
    w.maxOverlap = std::max(w.maxOverlap, s.maxOverlap);
  }
  w.wall = wallNow() - wall0;
  w.cpu = cpuNow() - cpu0;
  w.simulated = world.time() - t0;
  if (capture) {
    w.end = world.captureState();
  }
  return w;
}

long firstDifference(const WorldState& a, const WorldState& b) {
  if (a.bodies.size() != b.bodies.size()) {
    return 0;
  }
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const auto& x = a.bodies[i];
    const auto& y = b.bodies[i];
    if (x.motion != y.motion || x.position != y.position || !(x.orientation.coeffs() == y.orientation.coeffs()) ||
        x.velocity != y.velocity || x.angularMomentum != y.angularMomentum) {
      return static_cast<long>(i);
    }
  }
  return -1;
}

ContactCensus census(const World& world, const WorldState& state) {
  ContactCensus c;
  const auto& bodies = world.bodies();
  const auto n = static_cast<std::uint32_t>(bodies.size());
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (const auto& p : state.contacts) {
    pairs.emplace(p.first, p.second);
  }
  double ends = 0.0;
  for (const auto& [a, b] : pairs) {
    if (b >= n) {
      ++c.unitStatic;
      ends += 1.0;
    } else if (bodies.motionType(a) == dyn::MotionType::Static || bodies.motionType(b) == dyn::MotionType::Static) {
      ++c.unitFixed;
      ends += 1.0;
    } else {
      ++c.unitUnit;
      ends += 2.0;
    }
  }
  std::size_t dynamic = 0, touching = 0;
  double points = 0.0;
  for (std::uint32_t b = 0; b < n; ++b) {
    if (bodies.motionType(b) == dyn::MotionType::Static) {
      continue;
    }
    ++dynamic;
    points += world.contactCount(b);
    touching += world.contactCount(b) > 0 ? 1 : 0;
  }
  if (dynamic > 0) {
    c.pointsPerUnit = points / static_cast<double>(dynamic);
    c.pairsPerUnit = ends / static_cast<double>(dynamic);
    c.touchingFraction = static_cast<double>(touching) / static_cast<double>(dynamic);
  }
  return c;
}

Motion motion(const World& world) {
  Motion m;
  const auto& bodies = world.bodies();
  for (dyn::BodyId b = 0; b < bodies.size(); ++b) {
    if (bodies.motionType(b) == dyn::MotionType::Static) {
      continue;
    }
    ++m.dynamic;
    m.awake += bodies.isAwake(b) ? 1 : 0;
    const double v = bodies.velocity(b).norm();
    m.mean += v;
    m.max = std::max(m.max, v);
    m.meanZ += bodies.position(b).z();
  }
  if (m.dynamic > 0) {
    m.mean /= static_cast<double>(m.dynamic);
    m.meanZ /= static_cast<double>(m.dynamic);
  }
  return m;
}

Window settleWorld(World& world, int threads, double until, double traceEvery) {
  if (!(traceEvery > 0.0)) {
    return runWindow(world, threads, 0, until, false);
  }
  Window total;
  total.threads = threads;
  fmt::print(stderr, "  {:>7} {:>9} {:>7} {:>9} {:>11} {:>9} {:>9} {:>10} {:>8}\n", "t (s)", "steps/s", "awake",
             "pairs", "points", "pts/unit", "touching", "speed m/s", "mean z");
  while (world.time() < until) {
    const Window w = runWindow(world, threads, 0, std::min(until, world.time() + traceEvery), false);
    total.steps += w.steps;
    total.wall += w.wall;
    total.cpu += w.cpu;
    total.simulated += w.simulated;
    total.awakeSum += w.awakeSum;
    total.pairSum += w.pairSum;
    total.pointSum += w.pointSum;
    total.maxOverlap = std::max(total.maxOverlap, w.maxOverlap);
    const Motion m = motion(world);
    std::size_t touching = 0;
    for (dyn::BodyId b = 0; b < world.bodies().size(); ++b) {
      touching += world.bodies().motionType(b) != dyn::MotionType::Static && world.contactCount(b) > 0 ? 1 : 0;
    }
    fmt::print(stderr, "  {:7.3f} {:9.0f} {:7.0f} {:9.0f} {:11.0f} {:9.1f} {:8.0f}% {:10.3f} {:8.3f}\n", world.time(),
               w.stepsPerSecond(), w.perStep(w.awakeSum), w.perStep(w.pairSum), w.perStep(w.pointSum),
               w.perStep(w.pointSum) / static_cast<double>(std::max<std::size_t>(1, m.dynamic)),
               100.0 * static_cast<double>(touching) / static_cast<double>(std::max<std::size_t>(1, m.dynamic)), m.mean,
               m.meanZ);
  }
  return total;
}

void measureWindows(World& world, CaseResult& r, std::uint64_t steps, double seconds, const std::vector<int>& threads) {
  const WorldState start = world.captureState();
  r.load = loadAverage();
  for (const int t : threads) {
    world.restoreState(start);
    const std::uint64_t k = steps > 0 ? steps : 0;
    const double until = start.time + seconds;
    fmt::print(stderr, "  measuring {} on {} thread(s) ...\n", r.name, t);
    r.windows.push_back(runWindow(world, t, k, until, true));
    if (r.windows.back().wall <= 0.0 || r.windows.back().steps == 0) {
      throw InvalidCase(r.name + ": empty measurement window");
    }
  }
  for (std::size_t i = 1; i < r.windows.size(); ++i) {
    const long d = firstDifference(r.windows[0].end, r.windows[i].end);
    if (d >= 0) {
      r.deterministic = false;
      r.notes += fmt::format(" NOT DETERMINISTIC: body {} differs between {} and {} threads.", d,
                             r.windows[0].threads, r.windows[i].threads);
    }
  }
  for (auto& w : r.windows) {
    w.end = {}; // release the copies
  }
}

} // namespace armour::bench
