// SPDX-License-Identifier: GPL-3.0-or-later
// Geometry benchmarks: shape generation, mass properties, refinement, tetrahedralisation.
// Run: build/bin/bench_geometry  (figures recorded in docs/benchmarks.md)

#include "geometry/MassProperties.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "geometry/SurfaceRefinement.hpp"
#include "geometry/Tetrahedralizer.hpp"

#include <benchmark/benchmark.h>

#include <cmath>

using namespace armour::geometry;

namespace {

/// A benchmark of a wrong result is worthless: stop the run with the reason.
void failUnless(benchmark::State& state, bool ok, const char* what) {
  if (!ok) {
    state.SkipWithError(what);
  }
}

void BM_MakeShape(benchmark::State& state, const std::string& name) {
  ShapeRequest request;
  request.volume = 5.0;
  std::size_t triangles = 0;
  for (auto _ : state) {
    TriangleMesh mesh = makeShape(name, request);
    triangles = mesh.triangleCount();
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  failUnless(state, std::abs(computeMassProperties(makeShape(name, request)).volume - 5.0) < 1e-9 * 5.0,
             "makeShape missed the requested volume");
}

void BM_MassProperties(benchmark::State& state) {
  ShapeRequest request;
  request.volume = 5.0;
  const TriangleMesh coarse = makeShape("coreloc", request);
  const TriangleMesh mesh = refineToCount(coarse, static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(computeMassProperties(mesh));
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(mesh.triangleCount()));
}

void BM_RefineSurface(benchmark::State& state) {
  ShapeRequest request;
  request.volume = 5.0;
  const TriangleMesh coarse = makeShape("coreloc", request);
  const double h = 1.71 / static_cast<double>(state.range(0)); // Dn / n
  std::size_t triangles = 0;
  for (auto _ : state) {
    TriangleMesh fine = refineSurface(coarse, h);
    triangles = fine.triangleCount();
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}

void BM_Tetrahedralize(benchmark::State& state) {
  ShapeRequest request;
  request.volume = 5.0;
  const TriangleMesh surface = makeShape("coreloc", request);
  TetrahedralizeOptions options;
  options.targetTetCount = static_cast<std::size_t>(state.range(0));
  std::size_t tets = 0;
  for (auto _ : state) {
    TetMesh mesh = tetrahedralize(surface, options);
    tets = mesh.tets.size();
    failUnless(state, std::abs(mesh.totalVolume() - 5.0) < 5e-3 * 5.0, "tet volumes do not add up to the surface volume");
  }
  state.counters["tets"] = static_cast<double>(tets);
}

} // namespace

int main(int argc, char** argv) {
  for (const auto& g : shapeGenerators()) {
    benchmark::RegisterBenchmark(("BM_MakeShape/" + g.name).c_str(), BM_MakeShape, g.name)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("BM_MassProperties", BM_MassProperties)->Arg(4000)->Arg(100000)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_RefineSurface", BM_RefineSurface)->Arg(10)->Arg(40)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_Tetrahedralize", BM_Tetrahedralize)->Arg(2500)->Arg(20000)->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
