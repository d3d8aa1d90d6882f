// SPDX-License-Identifier: GPL-3.0-or-later
// Rigid against deformable on one Core-Loc (issue 26, "Measure seed 000's claim"): seed 000
// section 1 says that for a Core-Loc of about 2500 elements its rigid code (Solidity_R) is about
// 50 times faster than its deformable one (Solidity_D), because the rigid step follows the whole
// body and the deformable step the smallest element. This program measures that ratio for armour's
// own two models on the same unit, the same mesh size and the same impact:
//
//   bench_solidity [--elements 2500] [--volume 5] [--seconds 0.05] [--speed 0.5]
//
// The scene: one Core-Loc (V = --volume m^3, seed 000's 5 m^3 units), lying flat (the plane of
// its H horizontal), its lowest point on a rigid floor and moving down at --speed m/s (seed 002's
// 0.5 m/s drop), gravity on, for --seconds of simulated time, 1 thread. Rows:
// - deformable, 4-node tets (gmsh, about --elements of them; seed 002's concrete: E 26.6 GPa,
//   nu 0.205, rho 2340 kg/m^3; no viscosity; frictionless potential contact with the floor): the
//   explicit step at 0.9 of its stable limit (the smallest element and the contact);
// - deformable, 10-node tets with F-bar (seed 002's element), the same mesh;
// - rigid, fdem contact with the same number of contact elements per unit (Solidity_R's model:
//   Munjiza's potential on the unit's tets), penalty solver at its automatic step;
// - rigid, level-set contact (armour's default), penalty solver at its automatic step;
// - rigid, level-set contact, constraint solver (1/200 s, its defaults).
// Each row prints its step, steps, thread CPU time and CPU time per simulated second; the ratio
// column divides each deformable row's CPU per simulated second by the rigid fdem row's.

#include "benchmarks/BenchClock.hpp"
#include "core/BuildInfo.hpp"
#include "deformable/DeformableBody.hpp"
#include "deformable/QuasiStatic.hpp"
#include "deformable/TetElement.hpp"
#include "support/DeformableFixtures.hpp"
#include "deformable/StressFields.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "geometry/Tetrahedralizer.hpp"
#include "simulation/World.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <string>
#include <vector>

namespace {

using armour::bench::threadCpuNow;
namespace sim = armour::simulation;
namespace geo = armour::geometry;
namespace def = armour::deformable;
using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

struct Row {
  std::string model;
  std::size_t elements = 0; ///< tets of the deformable mesh, or contact elements of the rigid unit
  double dt = 0.0;          ///< (unit: s)
  std::uint64_t steps = 0;
  double cpu = 0.0;         ///< thread CPU time of the stepping (unit: s)
  double seconds = 0.0;     ///< simulated (unit: s)
  double lowest = 0.0;      ///< lowest z of the unit at the end (unit: m)
  std::string note;
};

/// The unit lying flat: the natural frame's y (normal to the plane of the H) turned to z.
Quat lyingFlat() { return Quat(Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Vec3::UnitX())); }

/// gmsh's mesh of the unit with about `elements` tets (the deformable rows' mesh).
geo::TetMesh meshUnit(const geo::TriangleMesh& surface, std::size_t elements) {
  geo::TetrahedralizeOptions options;
  options.targetTetCount = elements;
  options.keepSurface = false;
  options.source = "bench_solidity Core-Loc";
  return geo::tetrahedralize(surface, options);
}

Row deformableRow(const geo::TriangleMesh& surface, std::size_t elements, def::ElementOrder order, double seconds,
                  double speed, double massScaling) {
  geo::TetMesh tets = meshUnit(surface, elements);
  const Quat q = lyingFlat();
  double lowest = 1e30;
  for (auto& p : tets.vertices) {
    p = q * p;
    lowest = std::min(lowest, p.z());
  }
  def::DeformableSettings settings; // seed 002's concrete, no viscosity
  settings.halfSpaces = {def::HalfSpace{Vec3(0.0, 0.0, lowest), Vec3::UnitZ()}};
  settings.massScaling = massScaling;
  def::DeformableBody body(def::makeDeformableMesh(tets, order, "bench_solidity Core-Loc"), settings,
                           "bench_solidity Core-Loc");
  body.setVelocities(std::vector<Vec3>(body.nodeCount(), Vec3(0.0, 0.0, -speed)));
  Row row;
  row.model = order == def::ElementOrder::Linear ? "deformable, tet4" : "deformable, tet10 (F-bar)";
  if (massScaling > 0.0) row.model += fmt::format(", mass scaling {} ({:.3g} % added to {} elements)", massScaling,
                                                  100.0 * body.massScaling().addedMass / body.massScaling().mass,
                                                  body.massScaling().scaled);
  row.elements = body.mesh().elementCount();
  row.dt = body.stableStep().dt;
  const geo::TetMeshQuality quality = geo::tetMeshQuality(tets);
  double shortest = 1e30; // shortest edge of the tets (unit: m)
  for (const geo::Tet& t : tets.tets) {
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, (tets.vertices[t[i]] - tets.vertices[t[j]]).norm());
    }
  }
  row.note = fmt::format("{} nodes, smallest element length {:.3f} m, shortest edge {:.3f} m, dihedral angles "
                         "{:.1f}-{:.1f} deg, radius ratio min {:.3f} mean {:.3f}, contact frequency {:.3g} rad/s",
                         body.nodeCount(), body.stableStep().lengthMin, shortest, quality.minDihedralDeg,
                         quality.maxDihedralDeg, quality.minRadiusRatio, quality.meanRadiusRatio,
                         body.stableStep().contactFrequency);
  const double cpu0 = threadCpuNow();
  while (body.time() < seconds) {
    body.step(row.dt);
    ++row.steps;
  }
  row.cpu = threadCpuNow() - cpu0;
  row.seconds = body.time();
  row.lowest = 1e30;
  for (const Vec3& p : body.positions()) row.lowest = std::min(row.lowest, p.z());
  row.lowest -= lowest;
  return row;
}

Row rigidRow(const geo::TriangleMesh& surface, sim::ContactModel model, sim::ContactSolverKind solver,
             std::size_t elements, double seconds, double speed) {
  sim::WorldSettings ws;
  ws.contactModel = model;
  ws.solver = solver;
  ws.fdem.elementsPerUnit = elements;
  ws.sleep.enabled = false;
  sim::World world(ws);
  sim::Material m;
  m.name = "concrete";
  m.density = 2340.0; // seed 002 Table 2
  const auto material = world.addMaterial(m);
  const auto shape = world.addShape("coreloc", surface);
  const Quat q = lyingFlat();
  double lowest = 1e30;
  for (const auto& p : surface.vertices) lowest = std::min(lowest, (q * p).z());
  world.addPlane({"floor", Vec3(0.0, 0.0, lowest), Vec3::UnitZ(), material});
  sim::BodySpec b;
  b.shape = shape;
  b.material = material;
  b.orientation = q;
  b.velocity = Vec3(0.0, 0.0, -speed);
  const auto body = world.addBody(b);
  Row row;
  row.model = fmt::format("rigid, {}, {} solver", model == sim::ContactModel::Fdem ? "fdem contact" : "level-set contact",
                          solver == sim::ContactSolverKind::Penalty ? "penalty" : "constraint");
  row.elements = model == sim::ContactModel::Fdem ? world.shape(shape).fdem->elements().size() : 0;
  row.dt = world.timeStep();
  row.note = model == sim::ContactModel::Fdem ? fmt::format("{} contact elements kept of about {} (the deep ones dropped)",
                                                            row.elements, elements)
                                              : "level set 24 cells per Dn, samples 0.1 Dn";
  const double cpu0 = threadCpuNow();
  while (world.time() < seconds) {
    world.step();
    ++row.steps;
  }
  row.cpu = threadCpuNow() - cpu0;
  row.seconds = world.time();
  const Vec3 x = world.bodies().position(body);
  double low = 1e30;
  for (const auto& p : surface.vertices) low = std::min(low, (world.naturalOrientation(body) * p + x).z());
  row.lowest = low - lowest;
  return row;
}

/// The cost of the quasi-static stage of `armour stress` on this unit: the stiffness assembled
/// and factored once, then load cases (two opposite point forces at the ends of the unit's long
/// axis and one across it, spread over 0.1 m), each a back substitution and the element stresses.
void quasiStaticRow(const geo::TriangleMesh& surface, std::size_t elements, def::ElementOrder order, int cases) {
  geo::TetMesh tets = meshUnit(surface, elements);
  def::DeformableSettings settings;
  const def::DeformableBody body(def::makeDeformableMesh(tets, order, "Core-Loc"), settings, "Core-Loc");
  const double cpu0 = threadCpuNow();
  const def::QuasiStaticUnit unit(body);
  const double factorCpu = threadCpuNow() - cpu0;
  Vec3 lo = body.mesh().nodes.front(), hi = lo;
  for (const auto& p : body.mesh().nodes) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 c = 0.5 * (lo + hi);
  double largest = 0.0;
  const double cpu1 = threadCpuNow();
  for (int k = 0; k < cases; ++k) {
    const double F = 1e5 * (1.0 + 0.01 * k);
    const std::vector<def::PointLoad> loads{{Vec3(lo.x(), c.y(), c.z()), Vec3(F, 0.0, 0.0)},
                                            {Vec3(hi.x(), c.y(), c.z()), Vec3(-F, 0.0, 0.3 * F)}};
    const auto r = unit.solve(loads, Vec3::Zero(), 0.1);
    for (const auto& s : r.stress) largest = std::max(largest, def::summarizeStress(s).principal.x());
  }
  const double solveCpu = (threadCpuNow() - cpu1) / cases;
  fmt::print("| quasi-static, {} | {} | {} | {:.3f} | {:.2f} | {:.0f} | {:.3g} MPa |\n",
             order == def::ElementOrder::Linear ? "tet4" : "tet10 (F-bar)", body.mesh().elementCount(),
             3 * body.nodeCount(), factorCpu, 1e3 * solveCpu, 60.0 / 0.01 * solveCpu, 1e-6 * largest);
}

/// The highest frequency of the unit's free mesh (lumped masses, tangent at rest) against the
/// bounds a stable step can rest on: the element bound that StableStep uses (2 c_d / l_min),
/// Gershgorin's row sums of M^-1 |K| (a bound on the assembled mesh), and power iteration on
/// M^-1 K (a lower estimate of the true omega_max, 400 iterations).
bool stepBoundsRow(const geo::TriangleMesh& surface, std::size_t elements, def::ElementOrder order, double massScaling) {
  geo::TetMesh tets = meshUnit(surface, elements);
  def::DeformableSettings settings;
  settings.massScaling = massScaling;
  const def::DeformableBody body(def::makeDeformableMesh(tets, order, "Core-Loc"), settings, "Core-Loc");
  const double omegaMax = def::test::highestFrequencyByPowerIteration(
      def::tangentAtRest(body.mesh(), body.geometry(), body.model()), body.masses(), 400);
  const double gershgorin = body.stableStep().meshFrequency; // StableStep's own bound, not computed again here
  const double c = def::dilatationalWaveSpeed(settings.material);
  const double omegaElement = 2.0 * c / body.massScaling().length;
  fmt::print("| {}{} | {} | {:.4g} | {:.4g} | {:.4g} | {:.3g} | {:.3g} |\n", order == def::ElementOrder::Linear ? "tet4" : "tet10 (F-bar)",
             massScaling > 0.0 ? fmt::format(", mass scaling {}", massScaling) : std::string(), body.mesh().elementCount(),
             omegaElement, gershgorin, omegaMax, omegaElement / omegaMax, gershgorin / omegaMax);
  // Both are bounds: a power-iteration estimate above either is a bug, not a figure.
  return omegaMax <= gershgorin && omegaMax <= omegaElement;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Rigid against deformable on one Core-Loc: seed 000's 'Solidity_R is about 50 times faster' (issue 26)"};
  std::size_t elements = 2500;
  double volume = 5.0, seconds = 0.05, speed = 0.5, massScaling = 0.0;
  app.add_option("--elements", elements, "tets of the deformable unit and contact elements of the rigid one (seed 000: ~2500)")
      ->check(CLI::Range(std::size_t{50}, std::size_t{200000}));
  app.add_option("--volume", volume, "unit volume (m^3; seed 000's units are 5 m^3)")->check(CLI::Range(0.01, 100.0));
  app.add_option("--seconds", seconds, "simulated time of every row (s)")->check(CLI::Range(1e-4, 10.0));
  app.add_option("--speed", speed, "downward speed at first touch (m/s; seed 002's drop: 0.5)")->check(CLI::Range(0.0, 10.0));
  int quasiStaticCases = 0;
  bool stepBounds = false;
  app.add_flag("--step-bounds", stepBounds, "also compare the stable-step bounds with the mesh's highest frequency");
  app.add_option("--quasi-static", quasiStaticCases, "also time this many load cases of the quasi-static stress stage")
      ->check(CLI::Range(0, 100000));
  app.add_option("--mass-scaling", massScaling, "also the deformable rows with this mass scaling (added mass / mass; 0 = none)")
      ->check(CLI::Range(0.0, 0.1));
  CLI11_PARSE(app, argc, argv);
  omp_set_num_threads(1);

  geo::ShapeRequest request;
  request.volume = volume;
  const geo::TriangleMesh surface = geo::makeShape("coreloc", request);
  double shortestSurface = 1e30, longestSurface = 0.0; // edges of the shape's own surface (unit: m)
  for (const auto& f : surface.triangles) {
    for (int i = 0; i < 3; ++i) {
      const double l = (surface.vertices[f[i]] - surface.vertices[f[(i + 1) % 3]]).norm();
      shortestSurface = std::min(shortestSurface, l);
      longestSurface = std::max(longestSurface, l);
    }
  }
  fmt::print("bench_solidity --elements {} --volume {} --seconds {} --speed {} --mass-scaling {}\nbuild: {}\nload before: {}\nthe Core-Loc's surface: {} "
             "triangles, edges {:.4f} to {:.3f} m\n\n", elements, volume, seconds, speed, massScaling, armour::core::buildInfo(), armour::bench::loadAverages(), surface.triangles.size(), shortestSurface,
             longestSurface);
  std::vector<Row> rows;
  rows.push_back(rigidRow(surface, sim::ContactModel::Fdem, sim::ContactSolverKind::Penalty, elements, seconds, speed));
  rows.push_back(rigidRow(surface, sim::ContactModel::LevelSet, sim::ContactSolverKind::Penalty, elements, seconds, speed));
  rows.push_back(rigidRow(surface, sim::ContactModel::LevelSet, sim::ContactSolverKind::Constraint, elements, seconds, speed));
  for (const double ms : massScaling > 0.0 ? std::vector<double>{0.0, massScaling} : std::vector<double>{0.0}) {
    rows.push_back(deformableRow(surface, elements, def::ElementOrder::Linear, seconds, speed, ms));
    rows.push_back(deformableRow(surface, elements, def::ElementOrder::Quadratic, seconds, speed, ms));
  }
  const double reference = rows.front().cpu / rows.front().seconds;
  fmt::print("| model | elements | step (s) | steps | thread CPU (s) | CPU per simulated s | / rigid fdem | lowest point at the "
             "end, from the floor (mm) | notes |\n|---|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const Row& r : rows) {
    fmt::print("| {} | {} | {:.3g} | {} | {:.3f} | {:.3g} | {:.3g} | {:.2f} | {} |\n", r.model, r.elements, r.dt, r.steps,
               r.cpu, r.cpu / r.seconds, r.cpu / r.seconds / reference, 1e3 * r.lowest, r.note);
  }
  if (stepBounds) {
    fmt::print("\n| mesh | elements | element bound 2 c_d / l_min (rad/s) | Gershgorin bound (rad/s) | power iteration, "
               "omega_max >= (rad/s) | element bound / omega_max | Gershgorin / omega_max |\n|---|---:|---:|---:|---:|---:|---:|\n");
    for (const double ms : {0.0, 0.01}) {
      for (const auto order : {def::ElementOrder::Linear, def::ElementOrder::Quadratic}) {
        if (!stepBoundsRow(surface, elements, order, ms)) {
          fmt::print(stderr, "bench_solidity: the power iteration exceeds a stable-step bound: the bound is wrong\n");
          return 1;
        }
      }
    }
  }
  if (quasiStaticCases > 0) {
    fmt::print("\n| stage | elements | unknowns | assemble and factor, CPU (s) | per load case, CPU (ms) | per storm minute at "
               "0.01 s records, CPU (s) | largest sigma_1 of the cases |\n|---|---:|---:|---:|---:|---:|---:|\n");
    quasiStaticRow(surface, elements, def::ElementOrder::Linear, quasiStaticCases);
    quasiStaticRow(surface, elements, def::ElementOrder::Quadratic, quasiStaticCases);
  }
  fmt::print("\nload after: {}\n", armour::bench::loadAverages());
  return 0;
}
